// The Cookbook's tessellated light volumes (techniques/cookbook_volumes.h): domain-shader vertices
// against values worked from the recipes' formulas, outward winding, and containment of each
// light's region by the support function, with and without the enlargement.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <tessera/techniques/cookbook_volumes.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_cookbook_volumes_test {

using namespace tessera;

namespace {

void checkVec(const glm::vec3& got, const glm::vec3& want) {
    CHECK(got.x == doctest::Approx(want.x).epsilon(1e-5));
    CHECK(got.y == doctest::Approx(want.y).epsilon(1e-5));
    CHECK(got.z == doctest::Approx(want.z).epsilon(1e-5));
}

// Is p inside every non-degenerate face plane of the mesh (scaled by s about the origin)?
bool inside(const CookbookVolumeMesh& mesh, const glm::dvec3& p, double s = 1.0) {
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const glm::dvec3 a = s * glm::dvec3(mesh.positions[mesh.indices[t]]);
        const glm::dvec3 b = s * glm::dvec3(mesh.positions[mesh.indices[t + 1]]);
        const glm::dvec3 c = s * glm::dvec3(mesh.positions[mesh.indices[t + 2]]);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        if (glm::length(n) < 1e-6) continue;  // degenerate, or a float sliver on the spot axis
        if (glm::dot(glm::normalize(n), p - a) > 1e-9) return false;
    }
    return true;
}

std::vector<glm::dvec3> sphereDirections(int n) {
    std::vector<glm::dvec3> dirs;
    std::mt19937 rng(7);
    std::normal_distribution<double> g;
    for (int i = 0; i < n; ++i) dirs.push_back(glm::normalize(glm::dvec3(g(rng), g(rng), g(rng))));
    return dirs;
}

} // namespace

TEST_CASE("cookbook volumes: domain-shader vertices equal the recipes' formulas worked by hand") {
    // Point, factor 18, v = 0.5, HemiDir (1, 1, 1), u = k / 18: posClipSpace = (k/9 - 1, 0),
    // normalize(x, 0, |x| - 1): k 9 -> (0, 0, -1); k 10 -> (1/9, 0, -8/9)/|..| = (0.124035, 0, -0.992278);
    // k 12 -> (0.447214, 0, -0.894427); k 14 -> (0.780869, 0, -0.624695); k 18 -> (1, 0, 0).
    const glm::vec3 hemi0(1.0f, 1.0f, 1.0f), hemi1(-1.0f, 1.0f, -1.0f);
    checkVec(cookbookPointDomain({9.0f / 18.0f, 0.5f}, hemi0), {0.0f, 0.0f, -1.0f});
    checkVec(cookbookPointDomain({10.0f / 18.0f, 0.5f}, hemi0), {0.124035f, 0.0f, -0.992278f});
    checkVec(cookbookPointDomain({12.0f / 18.0f, 0.5f}, hemi0), {0.447214f, 0.0f, -0.894427f});
    checkVec(cookbookPointDomain({14.0f / 18.0f, 0.5f}, hemi0), {0.780869f, 0.0f, -0.624695f});
    checkVec(cookbookPointDomain({1.0f, 0.5f}, hemi0), {1.0f, 0.0f, 0.0f});
    checkVec(cookbookPointDomain({1.0f, 1.0f}, hemi0), {0.707107f, 0.707107f, 0.0f});
    checkVec(cookbookPointDomain({0.5f, 0.5f}, hemi1), {0.0f, 0.0f, 1.0f});  // the other hemisphere
    // Capsule, range 1, half segment 1, factor 12, v = 0.5, u = k / 12: k 6 -> (0, 0, -2) (the
    // pole, 1 + 1 below the centre); k 7 -> (0.266586, 0, -1.963811); k 9 -> (0.880471, 0, -1.474100);
    // k 10 -> (0.988372, 0, -1.152057); k 11: cylinderOffsetZ = (5/6 - 0.7) / 0.3 = 0.444445 ->
    // (1, 0, -0.555555); k 12 -> (1, 0, 0) (the rim at the centre plane).
    checkVec(cookbookCapsuleDomain({0.5f, 0.5f}, hemi0, 1.0f, 1.0f), {0.0f, 0.0f, -2.0f});
    checkVec(cookbookCapsuleDomain({7.0f / 12.0f, 0.5f}, hemi0, 1.0f, 1.0f), {0.266586f, 0.0f, -1.963811f});
    checkVec(cookbookCapsuleDomain({9.0f / 12.0f, 0.5f}, hemi0, 1.0f, 1.0f), {0.880471f, 0.0f, -1.474100f});
    checkVec(cookbookCapsuleDomain({10.0f / 12.0f, 0.5f}, hemi0, 1.0f, 1.0f), {0.988372f, 0.0f, -1.152057f});
    checkVec(cookbookCapsuleDomain({11.0f / 12.0f, 0.5f}, hemi0, 1.0f, 1.0f), {1.0f, 0.0f, -0.555555f});
    checkVec(cookbookCapsuleDomain({1.0f, 0.5f}, hemi0, 1.0f, 1.0f), {1.0f, 0.0f, 0.0f});
    // Spot, sin 0.5 / cos 30 deg, factor 12, v = 0.5: k 6 -> (0, 0, 1) (the base's pole); k 8 ->
    // (0.304997, 0, 0.952353); k 10 -> (0.488678, 0, 0.872464); k 11 -> (0.5, 0, 0.866025) (the
    // rim, at 30 deg); k 12 -> (0, 0, 0) (the apex).
    const float s = 0.5f, c = std::cos(std::numbers::pi_v<float> / 6.0f);
    checkVec(cookbookSpotDomain({0.5f, 0.5f}, s, c), {0.0f, 0.0f, 1.0f});
    checkVec(cookbookSpotDomain({8.0f / 12.0f, 0.5f}, s, c), {0.304997f, 0.0f, 0.952353f});
    checkVec(cookbookSpotDomain({10.0f / 12.0f, 0.5f}, s, c), {0.488678f, 0.0f, 0.872464f});
    const glm::vec3 rim = cookbookSpotDomain({11.0f / 12.0f, 0.5f}, s, c);
    CHECK(rim.x == doctest::Approx(0.5f).epsilon(1e-5));
    CHECK(rim.z == doctest::Approx(0.866025f).epsilon(1e-5));
    CHECK(glm::length(cookbookSpotDomain({1.0f, 0.5f}, s, c)) <= 1e-6f);
}

TEST_CASE("cookbook volumes: meshes are closed grids wound outward (D3D11's default front face)") {
    const CookbookVolumeMesh point = cookbookPointVolume();
    CHECK(point.positions.size() == 2 * 19 * 19);
    CHECK(point.indices.size() == 2 * 18 * 18 * 6);
    const CookbookVolumeMesh capsule = cookbookCapsuleVolume(1.0f, 1.0f);
    CHECK(capsule.indices.size() == 2 * 12 * 12 * 6);
    const CookbookVolumeMesh spot = cookbookSpotVolume(0.5f, std::cos(std::numbers::pi_v<float> / 6.0f));
    CHECK(spot.indices.size() == 12 * 12 * 6);
    // Outward: every non-degenerate face's (b - a) x (c - a) points away from an inside point,
    // checked against the region's own geometry rather than the generator's test point: the sphere's
    // centre, the capsule's nearest segment point, the spot's axis point at the face's height.
    const auto outward = [](const CookbookVolumeMesh& m, auto insidePoint) {
        int faces = 0;
        for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
            const glm::dvec3 a(m.positions[m.indices[t]]), b(m.positions[m.indices[t + 1]]), c(m.positions[m.indices[t + 2]]);
            const glm::dvec3 n = glm::cross(b - a, c - a);
            if (glm::length(n) < 1e-6) continue;  // degenerate, or a float sliver on the spot axis
            const glm::dvec3 centroid = (a + b + c) / 3.0;
            CHECK(glm::dot(n, centroid - insidePoint(centroid)) > 0.0);
            ++faces;
        }
        return faces;
    };
    CHECK(outward(point, [](glm::dvec3) { return glm::dvec3(0.0); }) > 600);
    CHECK(outward(capsule, [](glm::dvec3 p) { return glm::dvec3(0.0, 0.0, std::clamp(p.z, -1.0, 1.0)); }) > 200);
    CHECK(outward(spot, [](glm::dvec3 p) { return glm::dvec3(0.0, 0.0, std::max(p.z * 0.5, 1e-3)); }) > 100);
}

TEST_CASE("cookbook volumes: the enlarged volumes contain their light's region, the unenlarged ones do not") {
    const std::vector<glm::dvec3> dirs = sphereDirections(4000);
    // Point: the unit sphere, scale 1 (the demo: exactly the range) misses points between the
    // flat faces and the sphere; cookbookPointPadding() covers them, and is small.
    const CookbookVolumeMesh point = cookbookPointVolume();
    const double pad = cookbookPointPadding();
    CHECK(pad > 1.0);
    CHECK(pad < 1.02);  // factor 18: chords of at most ~10 deg cut ~0.5 % inside the sphere
    int missed = 0;
    for (const glm::dvec3& d : dirs) {
        missed += inside(point, d, 1.0) ? 0 : 1;
        CHECK(inside(point, d, pad));
    }
    CHECK(missed > 100);
    // Capsule: radius 2 around the segment z in [-3, 3].
    const float halfLen = 3.0f, range = 2.0f;
    const float padded = cookbookCapsulePaddedRange(halfLen, range);
    CHECK(padded > range);
    CHECK(padded < range * 1.05f);
    const CookbookVolumeMesh capsule = cookbookCapsuleVolume(halfLen, padded);
    const CookbookVolumeMesh capsuleTight = cookbookCapsuleVolume(halfLen, range);
    missed = 0;
    for (const glm::dvec3& d : dirs) {
        for (const double z : {-3.0, -1.0, 0.0, 2.5, 3.0}) {
            const glm::dvec3 p = glm::dvec3(0.0, 0.0, z) + double(range) * (std::abs(z) == 3.0 ? d : glm::dvec3(d.x, d.y, 0.0) / std::max(1e-9, glm::length(glm::dvec2(d))));
            CHECK(inside(capsule, p));
            missed += inside(capsuleTight, p) ? 0 : 1;
        }
    }
    CHECK(missed > 100);
    // Spot: the 30 deg cone cut by the unit sphere: its rim circle and its spherical cap.
    const float alpha = std::numbers::pi_v<float> / 6.0f;
    const CookbookSpotPadding sp = cookbookSpotPadding(alpha);
    CHECK(sp.halfAngle > alpha);
    CHECK(sp.halfAngle < alpha * 1.05f);
    const CookbookVolumeMesh spot = cookbookSpotVolume(std::sin(sp.halfAngle), std::cos(sp.halfAngle));
    const CookbookVolumeMesh spotTight = cookbookSpotVolume(std::sin(alpha), std::cos(alpha));
    missed = 0;
    for (int i = 0; i < 720; ++i) {
        const double phi = 2.0 * std::numbers::pi * i / 720.0;
        for (const double r : {0.25, 0.5, 1.0}) {  // along the cone's side, and on the rim
            const glm::dvec3 p = r * glm::dvec3(std::sin(alpha) * std::cos(phi), std::sin(alpha) * std::sin(phi), std::cos(alpha));
            CHECK(inside(spot, p, sp.scale));
            missed += inside(spotTight, p) ? 0 : 1;
        }
    }
    for (const glm::dvec3& d : dirs)
        if (d.z >= std::cos(alpha)) CHECK(inside(spot, d, sp.scale));  // the cap
    CHECK(missed > 100);
}

} // namespace tessera_test::techniques_cookbook_volumes_test
