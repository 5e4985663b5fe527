// Light-volume meshes and transforms of the 3dgep deferred pass (demo DeferredLightingPass.cpp):
// the assimp NFF sphere (tess 4) and cone (256 segments), their inscribed / circumscribed fit,
// the spot volume's placement, and the quaternion's antiparallel case.
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <random>
#include <stdexcept>
#include <utility>

#include <tessera/techniques/light_volumes.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_light_volumes_test {

using namespace tessera;

namespace {

// Every directed edge appears once and its reverse once: the mesh is closed and consistently
// oriented. Returns the number of undirected edges (0 on failure).
std::size_t checkClosedOriented(const VolumeMesh& mesh) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (std::size_t i = 0; i < mesh.indices.size(); i += 3)
        for (int e = 0; e < 3; ++e) ++directed[{mesh.indices[i + e], mesh.indices[i + (e + 1) % 3]}];
    for (const auto& [edge, count] : directed) {
        if (count != 1) return 0;
        const auto reverse = directed.find({edge.second, edge.first});
        if (reverse == directed.end() || reverse->second != 1) return 0;
    }
    return directed.size() / 2;
}

struct PlaneD {
    glm::dvec3 n;  // unit outward normal
    double offset; // n . p <= offset inside
};

std::vector<PlaneD> facePlanes(const VolumeMesh& mesh, const glm::dvec3& scale = glm::dvec3(1.0)) {
    std::vector<PlaneD> planes;
    for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
        const glm::dvec3 a = glm::dvec3(mesh.positions[mesh.indices[i]]) * scale;
        const glm::dvec3 b = glm::dvec3(mesh.positions[mesh.indices[i + 1]]) * scale;
        const glm::dvec3 c = glm::dvec3(mesh.positions[mesh.indices[i + 2]]) * scale;
        const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
        planes.push_back({n, glm::dot(n, a)});
    }
    return planes;
}

double maxPlaneExcess(const std::vector<PlaneD>& planes, const glm::dvec3& p) {
    double worst = -1e300;
    for (const PlaneD& pl : planes) worst = std::max(worst, glm::dot(pl.n, p) - pl.offset);
    return worst;
}

} // namespace

TEST_CASE("the demo's point volume: assimp MakeSphere(4) = icosahedron split 4 times, inscribed in the unit sphere") {
    const VolumeMesh sphere = makeIcosphere(kDemoSphereTessellation);
    // 20 * 4^4 triangles; V = 10 * 4^4 + 2 after joining identical positions.
    CHECK(sphere.triangleCount() == 5120);
    CHECK(sphere.positions.size() == 2562);
    const std::size_t edges = checkClosedOriented(sphere);
    CHECK(edges == 7680);
    CHECK(long(sphere.positions.size()) - long(edges) + long(sphere.triangleCount()) == 2);  // Euler: sphere
    // Every vertex on the unit sphere (to float precision): the polyhedron is inscribed.
    double worst = 0.0;
    for (const glm::vec3& p : sphere.positions) worst = std::max(worst, std::fabs(glm::length(glm::dvec3(p)) - 1.0));
    MESSAGE("icosphere tess 4: max | |v| - 1 | = " << worst);
    CHECK(worst < 4.0 / 16777216.0);
    // Outward, counter-clockwise seen from outside: every face normal points away from the origin.
    int inward = 0;
    for (const PlaneD& pl : facePlanes(sphere)) inward += pl.offset <= 0.0;
    CHECK(inward == 0);
    // Smaller tessellations follow the same counts.
    for (unsigned s = 0; s <= 3; ++s) {
        const VolumeMesh m = makeIcosphere(s);
        CHECK(m.triangleCount() == std::size_t(20) << (2 * s));
        CHECK(m.positions.size() == (std::size_t(10) << (2 * s)) + 2);
        CHECK(checkClosedOriented(m) == std::size_t(30) << (2 * s));
    }
    CHECK_THROWS_AS(makeIcosphere(9), std::invalid_argument);
}

TEST_CASE("inscribed sphere volumes lose the rim, the circumscribed scale contains the unit sphere") {
    const LightVolumes volumes;
    const VolumeMesh& sphere = volumes.sphere();
    const auto inscribed = facePlanes(sphere);
    const float scale = volumes.sphereCircumscribeScale();
    // tess 4: the face planes come within 1 / scale of the centre; the gap is ~0.1 % of Range.
    MESSAGE("icosphere tess 4: min face-plane distance = " << 1.0 / scale << ", circumscribe scale = " << scale);
    CHECK(scale > 1.0f);
    CHECK(scale < 1.002f);
    const auto circumscribed = facePlanes(sphere, glm::dvec3(scale));
    std::mt19937_64 rng(7);
    std::normal_distribution<double> gauss;
    int outsideInscribed = 0, outsideCircumscribed = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        const glm::dvec3 onSphere = glm::normalize(glm::dvec3(gauss(rng), gauss(rng), gauss(rng)));
        outsideInscribed += maxPlaneExcess(inscribed, onSphere) > 0.0;
        outsideCircumscribed += maxPlaneExcess(circumscribed, onSphere) > 0.0;
    }
    // Points of the light's sphere almost all lie outside the inscribed polyhedron (only its
    // vertices touch the sphere): that shell is what the faithful volume does not shade.
    CHECK(outsideInscribed > n * 9 / 10);
    CHECK(outsideCircumscribed == 0);
    // The tangent points (face-normal directions) too, to the rounding of the scale.
    double worstTangent = -1.0;
    for (const PlaneD& pl : inscribed) worstTangent = std::max(worstTangent, maxPlaneExcess(circumscribed, pl.n));
    CHECK(worstTangent <= 1e-12);
}

TEST_CASE("the demo's spot volume: CreateCylinder(0, 1, 1, +Z) = a 256-segment closed cone, apex at the origin") {
    const VolumeMesh cone = makeUnitCone(kDemoConeSlices);
    CHECK(kDemoConeSlices == 256);
    CHECK(cone.positions.size() == 258);
    CHECK(cone.triangleCount() == 512);
    CHECK(checkClosedOriented(cone) == 768);
    CHECK(cone.positions[0] == glm::vec3(0.0f));
    CHECK(cone.positions[1] == glm::vec3(0.0f, 0.0f, 1.0f));
    // Rim: radius 1 at z = 1, first vertex at +X, then clockwise seen from +Z (assimp's +Y cone
    // after the NFF node's Y -> Z rotation).
    double worstRadius = 0.0;
    for (std::size_t k = 2; k < cone.positions.size(); ++k) {
        const glm::dvec3 p(cone.positions[k]);
        CHECK(p.z == 1.0);
        worstRadius = std::max(worstRadius, std::fabs(std::hypot(p.x, p.y) - 1.0));
    }
    CHECK(worstRadius < 2.0 / 16777216.0);
    CHECK(cone.positions[2] == glm::vec3(1.0f, 0.0f, 1.0f));
    CHECK(cone.positions[2 + 64] == glm::vec3(0.0f, -1.0f, 1.0f));  // a quarter turn: (cos 90, -sin 90)
    CHECK(cone.positions[3].y < 0.0f);
    // Outward faces: an interior point lies strictly inside every face plane.
    const glm::dvec3 interior(0.0, 0.0, 0.5);
    int inward = 0;
    for (const PlaneD& pl : facePlanes(cone)) inward += glm::dot(pl.n, interior) >= pl.offset;
    CHECK(inward == 0);
    CHECK_THROWS_AS(makeUnitCone(2), std::invalid_argument);
}

TEST_CASE("the circumscribed cone (XY x 1/cos(pi/256)) contains the circular cone, the inscribed one does not") {
    const float radial = circumscribedConeRadialScale(kDemoConeSlices);
    CHECK(double(radial) >= 1.0 / std::cos(3.14159265358979323846 / 256.0));
    CHECK(double(radial) == doctest::Approx(1.0 / std::cos(3.14159265358979323846 / 256.0)).epsilon(1e-7));
    const VolumeMesh cone = makeUnitCone(kDemoConeSlices);
    const auto inscribed = facePlanes(cone);
    const auto circumscribed = facePlanes(cone, glm::dvec3(radial, radial, 1.0));
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int outsideInscribed = 0, outsideCircumscribed = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        // Points on the lateral surface r = z of the true cone (the worst case for containment).
        const double z = unit(rng), angle = unit(rng) * 2.0 * 3.14159265358979323846;
        const glm::dvec3 p(z * std::cos(angle), z * std::sin(angle), z);
        outsideInscribed += maxPlaneExcess(inscribed, p) > 1e-12;
        outsideCircumscribed += maxPlaneExcess(circumscribed, p) > 1e-12;
    }
    CHECK(outsideInscribed > n * 9 / 10);
    CHECK(outsideCircumscribed == 0);
}

TEST_CASE("spot volume transform: apex at the light, axis along its direction, base radius tan(angle) * Range") {
    const LightVolumes volumes;
    Light spot;
    spot.type = LightType::Spot;
    spot.positionWorld = glm::vec3(3.0f, -2.0f, 5.0f);
    spot.directionWorld = glm::normalize(glm::vec3(0.3f, -0.8f, 0.2f));
    spot.range = 7.5f;
    spot.spotHalfAngleDeg = 40.0f;
    const glm::dvec3 dir(spot.directionWorld), pos(spot.positionWorld);
    for (const VolumeRotation rotation : {VolumeRotation::Glm096, VolumeRotation::Robust}) {
        const glm::dmat4 m(volumes.worldFromObject(spot, {VolumeFit::Inscribed, rotation}));
        const glm::dvec3 apex(m * glm::dvec4(0.0, 0.0, 0.0, 1.0));
        const glm::dvec3 baseCentre(m * glm::dvec4(0.0, 0.0, 1.0, 1.0));
        CHECK(glm::length(apex - pos) < 1e-6);
        CHECK(glm::length(baseCentre - (pos + dir * double(spot.range))) < 1e-5);
        const double baseRadius = std::tan(glm::radians(40.0)) * 7.5;
        for (std::size_t k = 2; k < volumes.cone().positions.size(); k += 37) {
            const glm::dvec3 rim(m * glm::dvec4(glm::dvec3(volumes.cone().positions[k]), 1.0));
            CHECK(std::fabs(glm::dot(rim - baseCentre, dir)) < 1e-5);                 // in the base plane
            CHECK(glm::length(rim - baseCentre) == doctest::Approx(baseRadius).epsilon(1e-6));  // on the rim
        }
    }
    // Circumscribed: the rim radius grows by 1/cos(pi/256), the axis length stays Range.
    const glm::dmat4 mc(volumes.worldFromObject(spot, {VolumeFit::Circumscribed, VolumeRotation::Robust}));
    const glm::dvec3 rim(mc * glm::dvec4(glm::dvec3(volumes.cone().positions[2]), 1.0));
    const glm::dvec3 baseCentre(mc * glm::dvec4(0.0, 0.0, 1.0, 1.0));
    CHECK(glm::length(rim - baseCentre) ==
          doctest::Approx(std::tan(glm::radians(40.0)) * 7.5 * volumes.coneCircumscribeRadialScale()).epsilon(1e-6));
    CHECK(glm::length(baseCentre - pos) == doctest::Approx(7.5).epsilon(1e-6));
}

TEST_CASE("point volume transform: centre at the light, vertices at Range (inscribed) or containing the sphere") {
    const LightVolumes volumes;
    Light point;
    point.type = LightType::Point;
    point.positionWorld = glm::vec3(-1.0f, 4.0f, 2.0f);
    point.range = 5.0f;
    const glm::dmat4 m(volumes.worldFromObject(point));
    double worst = 0.0;
    for (const glm::vec3& p : volumes.sphere().positions) {
        const glm::dvec3 w(m * glm::dvec4(glm::dvec3(p), 1.0));
        worst = std::max(worst, std::fabs(glm::length(w - glm::dvec3(point.positionWorld)) - 5.0));
    }
    CHECK(worst < 1e-5);
    const glm::dmat4 mc(volumes.worldFromObject(point, {VolumeFit::Circumscribed, VolumeRotation::Glm096}));
    CHECK(glm::length(glm::dvec3(mc[0])) == doctest::Approx(5.0 * volumes.sphereCircumscribeScale()).epsilon(1e-6));
    Light directional;
    directional.type = LightType::Directional;
    CHECK_THROWS_AS(volumes.worldFromObject(directional), std::invalid_argument);
    CHECK_THROWS_AS(volumes.meshFor(LightType::Directional), std::invalid_argument);
    CHECK(&volumes.meshFor(LightType::Point) == &volumes.sphere());
    CHECK(&volumes.meshFor(LightType::Spot) == &volumes.cone());
}

TEST_CASE("quaternion from +Z to the light direction, including the antiparallel case") {
    const glm::vec3 z(0.0f, 0.0f, 1.0f);
    // General directions: both modes rotate +Z onto the direction.
    for (const glm::vec3 to : {glm::vec3(1, 0, 0), glm::normalize(glm::vec3(1, 2, 3)), glm::normalize(glm::vec3(-0.2f, 0.1f, -0.97f)),
                               glm::vec3(0, 0, 1)}) {
        for (const VolumeRotation mode : {VolumeRotation::Glm096, VolumeRotation::Robust}) {
            const glm::quat q = rotationBetween(z, to, mode);
            const glm::vec3 got = q * z;
            CHECK(glm::length(got - to) < 1e-6f);
            CHECK(std::fabs(glm::length(q) - 1.0f) < 1e-6f);
        }
    }
    // Antiparallel (a spot aimed straight down -Z; also every point light with the default
    // DirectionWS (0,0,-1)): glm 0.9.6 builds q = (1 + dot, cross) = 0 and its normalize returns
    // identity, so the faithful volume still points along +Z.
    const glm::vec3 minusZ(0.0f, 0.0f, -1.0f);
    const glm::quat faithful = rotationBetween(z, minusZ, VolumeRotation::Glm096);
    CHECK(faithful == glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
    CHECK(faithful * z == z);
    // Corrected: 180 degrees about an axis orthogonal to +Z (the demo's RotationFromTwoVectors
    // picks (0, -u.z, u.y) = (0, -1, 0)).
    const glm::quat robust = rotationBetween(z, minusZ, VolumeRotation::Robust);
    CHECK(glm::length(robust * z - minusZ) < 1e-6f);
    CHECK(std::fabs(robust.w) < 1e-7f);
    CHECK(glm::length(glm::vec3(robust.x, robust.y, robust.z) - glm::vec3(0.0f, -1.0f, 0.0f)) < 1e-6f);
    // The spot volume: faithful apex-to-base axis goes +Z (wrong), corrected goes -Z.
    const LightVolumes volumes(1, 8);
    Light spot;
    spot.type = LightType::Spot;
    spot.directionWorld = minusZ;
    spot.range = 2.0f;
    const glm::vec4 baseFaithful = volumes.worldFromObject(spot, {VolumeFit::Inscribed, VolumeRotation::Glm096}) * glm::vec4(0, 0, 1, 1);
    const glm::vec4 baseRobust = volumes.worldFromObject(spot, {VolumeFit::Inscribed, VolumeRotation::Robust}) * glm::vec4(0, 0, 1, 1);
    CHECK(baseFaithful.z == doctest::Approx(2.0f));
    CHECK(baseRobust.z == doctest::Approx(-2.0f));
    // Nearly antiparallel still works in both modes (the quaternion is tiny but normalizable).
    const glm::vec3 almost = glm::normalize(glm::vec3(1e-3f, 0.0f, -1.0f));
    CHECK(glm::length(rotationBetween(z, almost, VolumeRotation::Glm096) * z - almost) < 1e-3f);
    CHECK(glm::length(rotationBetween(z, almost, VolumeRotation::Robust) * z - almost) < 1e-3f);
}

} // namespace tessera_test::techniques_light_volumes_test
