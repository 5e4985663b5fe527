// Hand-derived cases for the 3dgep plane and frustum tests (culling/plane.h, culling/frustum.h;
// 3dgep article §4): ComputePlane, point / sphere / cone against a plane, sphere / cone against a frustum with
// its near and far range, and the concrete case in which the article's cone test (m not
// normalized) culls a cone that crosses the plane while the corrected test keeps it.
#include <doctest/doctest.h>

#include <cmath>

#include <tessera/culling/frustum.h>
#include <tessera/culling/plane.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::culling_plane_test {

using namespace tessera;

namespace {

constexpr float kTol = 1e-7f;  // a few ulp of values of size 1

bool near3(const glm::vec3& a, const glm::vec3& b, float tol = kTol) {
    return std::fabs(a.x - b.x) <= tol && std::fabs(a.y - b.y) <= tol && std::fabs(a.z - b.z) <= tol;
}

}  // namespace

TEST_CASE("computePlane: N = normalize(cross(p1 - p0, p2 - p0)), d = dot(N, p0) (3dgep article §4.1)") {
    // p0 = 0, p1 = x, p2 = y: cross((1,0,0), (0,1,0)) = (0,0,1), |.| = 1; d = dot(N, 0) = 0.
    const Plane xy = computePlane({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    CHECK(xy.N == glm::vec3(0, 0, 1));
    CHECK(xy.d == 0.0f);
    // Lifted to z = 5 and stretched: v0 = (2,0,0), v2 = (0,3,0), cross = (0,0,6) -> N = (0,0,1);
    // d = dot((0,0,1), (0,0,5)) = 5 (all exact in binary32).
    const Plane lifted = computePlane({0, 0, 5}, {2, 0, 5}, {0, 3, 5});
    CHECK(lifted.N == glm::vec3(0, 0, 1));
    CHECK(lifted.d == 5.0f);
    // Swapping p1 and p2 flips the normal (right-handed cross product): N = (0,0,-1), d = -5.
    const Plane flipped = computePlane({0, 0, 5}, {0, 3, 5}, {2, 0, 5});
    CHECK(flipped.N == glm::vec3(0, 0, -1));
    CHECK(flipped.d == -5.0f);
    // The unit triangle x + y + z = 1: v0 = (-1,1,0), v2 = (-1,0,1),
    // cross = (1*1 - 0*0, 0*(-1) - (-1)*1, (-1)*0 - 1*(-1)) = (1, 1, 1); N = (1,1,1)/sqrt(3)
    // = 0.577350269 each; d = dot(N, (1,0,0)) = 1/sqrt(3) = 0.577350269.
    const Plane diagonal = computePlane({1, 0, 0}, {0, 1, 0}, {0, 0, 1});
    CHECK(near3(diagonal.N, glm::vec3(0.577350269f)));
    CHECK(diagonal.d == doctest::Approx(0.577350269).epsilon(1e-7));
}

TEST_CASE("pointInsidePlane and sphereInsidePlane use the strict negative half-space") {
    const Plane p{glm::vec3(0, 0, 1), 5.0f};  // z = 5; dot(N, X) - d = z - 5
    CHECK(pointInsidePlane({0, 0, 4.5f}, p));    // -0.5 < 0
    CHECK_FALSE(pointInsidePlane({0, 0, 5}, p)); // 0 is not < 0
    CHECK_FALSE(pointInsidePlane({0, 0, 6}, p));
    // Sphere c = (0,0,3): distance -2. r = 1.5: -2 < -1.5 -> inside; r = 2: -2 < -2 false (touching
    // counts as intersecting); r = 3: false.
    CHECK(sphereInsidePlane({{0, 0, 3}, 1.5f}, p));
    CHECK_FALSE(sphereInsidePlane({{0, 0, 3}, 2.0f}, p));
    CHECK_FALSE(sphereInsidePlane({{0, 0, 3}, 3.0f}, p));
}

TEST_CASE("cone tests agree when the axis is parallel or perpendicular to N (|m| = 0 or 1)") {
    const Plane p{glm::vec3(1, 0, 0), 0.0f};  // x = 0, inside = x < 0
    // Axis along +x (parallel to N): N x d = 0, m = 0, Q = T + h d = (-2 + 1.5, 0, 0) = (-0.5, 0, 0):
    // inside (the base disc lies in the plane x = -0.5 whatever r is).
    const Cone parallel{{-2, 0, 0}, 1.5f, {1, 0, 0}, 10.0f};
    CHECK(coneInsidePlane(parallel, p));
    CHECK(coneInsidePlaneCorrected(parallel, p));
    // Axis along +z (perpendicular): N x d = (1,0,0) x (0,0,1) = (0,-1,0); m = (0,-1,0) x (0,0,1)
    // = (-1, 0, 0), unit already. Q = T + h d - r m = (-2 + r, 0, h). r = 1.9: Q.x = -0.1 inside;
    // r = 2.1: Q.x = 0.1 outside the half-space -> the cone crosses.
    const Cone perpInside{{-2, 0, 0}, 3.0f, {0, 0, 1}, 1.9f};
    const Cone perpCrossing{{-2, 0, 0}, 3.0f, {0, 0, 1}, 2.1f};
    CHECK(coneInsidePlane(perpInside, p));
    CHECK(coneInsidePlaneCorrected(perpInside, p));
    CHECK_FALSE(coneInsidePlane(perpCrossing, p));
    CHECK_FALSE(coneInsidePlaneCorrected(perpCrossing, p));
    // Tip on the positive side: never inside.
    const Cone tipOut{{0.5f, 0, 0}, 1.0f, {-1, 0, 0}, 0.1f};
    CHECK_FALSE(coneInsidePlane(tipOut, p));
    CHECK_FALSE(coneInsidePlaneCorrected(tipOut, p));
}

TEST_CASE("faithful 3dgep cone test culls a cone whose base rim crosses the plane (m not normalized)") {
    // Plane x = 0 (N = (1,0,0), d = 0), "inside" = x < 0. Cone: T = (-1.3, 0, 0), axis d at 45
    // degrees d = (s, 0, s), s = sqrt(1/2) = 0.70710677, h = 1, r = 1 (a 45-degree half angle).
    //   N x d = (0*s - 0*0, 0*s - 1*s, 1*0 - 0*s) = (0, -s, 0)
    //   m = (0, -s, 0) x (s, 0, s) = ((-s)s - 0, 0 - 0, 0 - (-s)s) = (-1/2, 0, 1/2), |m| = s, not 1.
    // Faithful: Q = T + d h - m r = (-1.3 + s + 0.5, 0, s - 0.5) = (-0.0929, 0, 0.2071): x < 0, and
    // T.x = -1.3 < 0, so the cone is reported entirely inside the plane (culled).
    // Truth: the base centre C = T + d = (-0.5929, 0, 0.7071); the rim point farthest along +x is
    // C + r u, u = (N - (N.d) d) / |N - (N.d) d| = (s, 0, -s), at x = -1.3 + 2s = +0.1142 > 0: the
    // cone crosses the plane. Corrected: Q = T + d h - r m/|m| = (-1.3 + 2s, 0, 0) = (0.1142, 0, 0).
    const float s = std::sqrt(0.5f);
    const Plane p{glm::vec3(1, 0, 0), 0.0f};
    const Cone cone{{-1.3f, 0, 0}, 1.0f, {s, 0, s}, 1.0f};
    const glm::vec3 m = cullmath::cross(cullmath::cross(p.N, cone.d), cone.d);
    CHECK(near3(m, glm::vec3(-0.5f, 0.0f, 0.5f)));
    const glm::vec3 qFaithful = (cone.T + cone.d * cone.h) - m * cone.r;
    CHECK(qFaithful.x == doctest::Approx(-1.3 + std::sqrt(0.5) + 0.5).epsilon(1e-6));  // -0.0929
    const glm::vec3 rimFarthest = cone.T + cone.d * cone.h + glm::vec3(s, 0, -s) * cone.r;
    CHECK(rimFarthest.x == doctest::Approx(-1.3 + 2.0 * std::sqrt(0.5)).epsilon(1e-6));  // +0.1142
    CHECK(rimFarthest.x > 0.0f);  // a point of the solid cone on the positive side

    CHECK(coneInsidePlane(cone, p));                 // faithful: wrongly "inside" -> culled
    CHECK_FALSE(coneInsidePlaneCorrected(cone, p));  // corrected: crossing -> kept

    // The same cone against a frustum whose left plane is x = 0 (other planes far away): the
    // faithful ConeInsideFrustum drops it, the corrected one keeps it.
    Frustum f;
    f.planes[0] = Plane{glm::vec3(1, 0, 0), 0.0f};       // left: x >= 0 inside the frustum
    f.planes[1] = Plane{glm::vec3(-1, 0, 0), -100.0f};   // right: x <= 100
    f.planes[2] = Plane{glm::vec3(0, -1, 0), -100.0f};   // top: y <= 100
    f.planes[3] = Plane{glm::vec3(0, 1, 0), -100.0f};    // bottom: y >= -100
    CHECK_FALSE(coneInsideFrustum(cone, f, 100.0f, -100.0f));
    CHECK(coneInsideFrustumCorrected(cone, f, 100.0f, -100.0f));
}

TEST_CASE("sphereInsideFrustum: the z slab [zFar, zNear] then the four planes (3dgep article §4.4.1)") {
    // A box-like "frustum" |x| <= 1, |y| <= 1 (normals inward), zNear = -1, zFar = -10 (RH).
    Frustum f;
    f.planes[0] = Plane{glm::vec3(1, 0, 0), -1.0f};   // left:   x - (-1) >= 0
    f.planes[1] = Plane{glm::vec3(-1, 0, 0), -1.0f};  // right: -x + 1 >= 0
    f.planes[2] = Plane{glm::vec3(0, -1, 0), -1.0f};  // top:   -y + 1 >= 0
    f.planes[3] = Plane{glm::vec3(0, 1, 0), -1.0f};   // bottom: y + 1 >= 0
    CHECK(sphereInsideFrustum({{0, 0, -5}, 0.5f}, f, -1.0f, -10.0f));
    // c.z - r > zNear: -0.4 - 0.5 = -0.9 > -1 -> entirely in front of the near plane: out.
    CHECK_FALSE(sphereInsideFrustum({{0, 0, -0.4f}, 0.5f}, f, -1.0f, -10.0f));
    // c.z - r = -0.5 - 0.5 = -1, not > -1: touching the near plane counts as in.
    CHECK(sphereInsideFrustum({{0, 0, -0.5f}, 0.5f}, f, -1.0f, -10.0f));
    // c.z + r < zFar: -11 + 0.5 = -10.5 < -10: beyond the far plane: out.
    CHECK_FALSE(sphereInsideFrustum({{0, 0, -11}, 0.5f}, f, -1.0f, -10.0f));
    // Right plane: distance -x + 1 at x = 2 is -1; r = 0.9: -1 < -0.9 -> out; r = 1.1: in.
    CHECK_FALSE(sphereInsideFrustum({{2, 0, -5}, 0.9f}, f, -1.0f, -10.0f));
    CHECK(sphereInsideFrustum({{2, 0, -5}, 1.1f}, f, -1.0f, -10.0f));
    // The corner false positive the per-plane test is known for: centre (1.8, 1.8), r = 1: each
    // plane alone is at distance -0.8 > -1 (kept), yet the nearest box point (1, 1) is at
    // sqrt(0.64 + 0.64) = 1.131 > r.
    CHECK(sphereInsideFrustum({{1.8f, 1.8f, -5}, 1.0f}, f, -1.0f, -10.0f));
}

TEST_CASE("coneInsideFrustum: near {(0,0,-1), -zNear} and far {(0,0,1), zFar} planes (3dgep article §4.4.2)") {
    const Plane nearP = nearPlane3dgep(-1.0f);
    const Plane farP = farPlane3dgep(-10.0f);
    CHECK(nearP.N == glm::vec3(0, 0, -1));
    CHECK(nearP.d == 1.0f);
    CHECK(farP.N == glm::vec3(0, 0, 1));
    CHECK(farP.d == -10.0f);
    // Inside the near plane: -z + zNear < 0 <=> z > zNear; inside the far plane: z < zFar.
    CHECK(pointInsidePlane({0, 0, -0.5f}, nearP));
    CHECK(pointInsidePlane({0, 0, -11.0f}, farP));

    Frustum f;  // the same box as above
    f.planes[0] = Plane{glm::vec3(1, 0, 0), -1.0f};
    f.planes[1] = Plane{glm::vec3(-1, 0, 0), -1.0f};
    f.planes[2] = Plane{glm::vec3(0, -1, 0), -1.0f};
    f.planes[3] = Plane{glm::vec3(0, 1, 0), -1.0f};
    // A cone pointing away from the frustum, entirely at z > -1 (behind the near plane): tip
    // (0,0,-0.5), axis +z, h = 2, r = 1: T and Q = (0, 0, 1.5) are both at z > -1 -> out.
    const Cone behind{{0, 0, -0.5f}, 2.0f, {0, 0, 1}, 1.0f};
    CHECK_FALSE(coneInsideFrustum(behind, f, -1.0f, -10.0f));
    CHECK_FALSE(coneInsideFrustumCorrected(behind, f, -1.0f, -10.0f));
    // The same tip pointing into the frustum: kept.
    const Cone into{{0, 0, -0.5f}, 2.0f, {0, 0, -1}, 1.0f};
    CHECK(coneInsideFrustum(into, f, -1.0f, -10.0f));
    CHECK(coneInsideFrustumCorrected(into, f, -1.0f, -10.0f));
}

} // namespace tessera_test::culling_plane_test
