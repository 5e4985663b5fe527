// Planes and the point / sphere / cone against plane tests of the 3dgep Forward+ light culling
// (3dgep article §4.1, §4.4; the demo's CommonInclude.hlsl), binary32 with
// the HLSL operation order, plus the corrected cone test (the article's m is not normalized).
// Callers: frustum.h, tile_frustum.h, the Forward+ culling kernels and their tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>

namespace tessera {

// ----- Structs of CommonInclude.hlsl (3dgep article §4.1, §4.4, field order as there) ------------
// Plane `dot(N, X) - d = 0` (the article: "ax + by + cz - d = 0"), N unit when made by
// computePlane. Which side is "inside" is the caller's business; the tests below call the
// NEGATIVE half-space `dot(N, X) - d < 0` "inside the plane".
struct Plane {
    glm::vec3 N{0.0f};  // normal (view space for every caller in tessera)
    float d = 0.0f;     // distance of the plane from the origin along N, in view units
};

// Sphere (a point light): centre c, radius r (view units).
struct Sphere {
    glm::vec3 c{0.0f};
    float r = 0.0f;
};

// Cone (a spot light): tip T, height h, unit axis d (from the tip to the base), base radius r.
// The 3dgep culling kernel fills it as { PositionVS, Range, DirectionVS, tan(radians(angle)) *
// Range } (3dgep demo ForwardPlusRendering.hlsl CS_main).
struct Cone {
    glm::vec3 T{0.0f};
    float h = 0.0f;
    glm::vec3 d{0.0f, 0.0f, -1.0f};
    float r = 0.0f;
};

// ----- HLSL vector intrinsics with the order of operations tessera fixes ------------------------
// (the same choices as hlsl:: in shading/phong_lighting.h: dot summed left to right, normalize
// as v / sqrt(dot(v, v)), correctly rounded, instead of the hardware's approximate rsq).
namespace cullmath {

inline float dot(const glm::vec3& a, const glm::vec3& b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }

inline glm::vec3 cross(const glm::vec3& a, const glm::vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

inline float length(const glm::vec3& v) { return std::sqrt(dot(v, v)); }

inline glm::vec3 normalize(const glm::vec3& v) {
    const float len = std::sqrt(dot(v, v));
    return {v.x / len, v.y / len, v.z / len};
}

// normalize(cross(a, b)) as every plane construction spells it, with one rescue: where the cross
// product's squared length leaves binary32's normal range (under- or overflow: the tile corners of
// a camera with near 1e-21 or of a world scaled by 1e-15 lie ~1e-21 from the eye, and their
// cross product squared is ~1e-84), a and b are first scaled by powers of two so that their
// largest components lie in [0.5, 1). The scaling is exact, so the normal is the same direction
// the real numbers give; where the plain squared length is a normal float the bits are its own.
inline glm::vec3 unitCross(const glm::vec3& a, const glm::vec3& b) {
    const glm::vec3 c = cross(a, b);
    const float lengthSquared = dot(c, c);
    if (std::isfinite(lengthSquared) && lengthSquared >= std::numeric_limits<float>::min()) return normalize(c);
    const auto powerOfTwoScaled = [](const glm::vec3& v) {
        const float largest = std::max(std::max(std::fabs(v.x), std::fabs(v.y)), std::fabs(v.z));
        if (!(largest > 0.0f) || !std::isfinite(largest)) return v;
        int exponent = 0;
        (void)std::frexp(largest, &exponent);
        return glm::vec3(std::ldexp(v.x, -exponent), std::ldexp(v.y, -exponent), std::ldexp(v.z, -exponent));
    };
    return normalize(cross(powerOfTwoScaled(a), powerOfTwoScaled(b)));
}

}  // namespace cullmath

// Signed distance `dot(N, p) - d` (view units when N is unit). Every test below compares it.
inline float signedDistance(const Plane& plane, const glm::vec3& p) { return cullmath::dot(plane.N, p) - plane.d; }

// 3dgep article §4.1 ComputePlane: v0 = p1 - p0; v2 = p2 - p0; N = normalize(cross(v0, v2));
// d = dot(N, p0). With p0, p1, p2 counter-clockwise as seen from the side N points to (right-
// handed cross product).
inline Plane computePlane(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2) {
    const glm::vec3 v0 = p1 - p0;
    const glm::vec3 v2 = p2 - p0;
    Plane plane;
    plane.N = cullmath::unitCross(v0, v2);
    plane.d = cullmath::dot(plane.N, p0);
    return plane;
}

// 3dgep article §4.4.2 PointInsidePlane: `dot(plane.N, p) - plane.d < 0` (strictly in the negative
// half-space).
inline bool pointInsidePlane(const glm::vec3& p, const Plane& plane) { return signedDistance(plane, p) < 0.0f; }

// 3dgep article §4.4.1 SphereInsidePlane (Ericson): `dot(plane.N, sphere.c) - plane.d < -sphere.r`, the
// whole sphere strictly in the negative half-space. Exact for unit N (up to rounding).
inline bool sphereInsidePlane(const Sphere& sphere, const Plane& plane) {
    return signedDistance(plane, sphere.c) < -sphere.r;
}

// 3dgep article §4.4.2 ConeInsidePlane, FAITHFUL (article and demo): m = cross(cross(N, d), d);
// Q = T + d * h - m * r; inside iff PointInsidePlane(T) && PointInsidePlane(Q).
// ERRATUM: for unit N and d, cross(cross(N, d), d) = (N.d) d - N has length sin(theta) (theta the
// angle between N and d), not 1, so Q lies only r * sin(theta) from the base centre instead of r:
// it is not the base point farthest along N. A cone whose base rim crosses the plane can then be
// reported inside (and culled). The error is 0 when d is parallel or perpendicular to N and
// largest in between (r (1 - sin theta) short). See coneInsidePlaneCorrected and the test
// "faithful 3dgep cone test culls a cone whose base rim crosses the plane".
// The point Q ConeInsidePlane tests beside T, for a plane with normal N (it does not depend on
// the plane's d): Q = T + d h - m r, m = cross(cross(N, d), d).
inline glm::vec3 coneTestPoint(const Cone& cone, const glm::vec3& N) {
    const glm::vec3 m = cullmath::cross(cullmath::cross(N, cone.d), cone.d);
    return (cone.T + cone.d * cone.h) - m * cone.r;
}

inline bool coneInsidePlane(const Cone& cone, const Plane& plane) {
    const glm::vec3 Q = coneTestPoint(cone, plane.N);
    return pointInsidePlane(cone.T, plane) && pointInsidePlane(Q, plane);
}

// CORRECTED ConeInsidePlane (tessera): the same test with m normalized, so Q is the base-rim
// point farthest along N (the article's formula with the unit vector it intends: Q = T + h d -
// r m / |m|, m = (N x d) x d = (N.d) d - N). When N is parallel to d, m = 0 and Q is the base
// centre (every rim point is equally far). The solid cone
// is the convex hull of T and the base disc, so {T, Q} contains its maximum of dot(N, X): the
// test is exact up to rounding.
// Its Q, for a plane with normal N: T + d h - r m / |m| (m = 0: the base centre).
inline glm::vec3 coneTestPointCorrected(const Cone& cone, const glm::vec3& N) {
    const glm::vec3 m = cullmath::cross(cullmath::cross(N, cone.d), cone.d);
    const float mLength = cullmath::length(m);
    const glm::vec3 mUnit = mLength > 0.0f ? glm::vec3(m.x / mLength, m.y / mLength, m.z / mLength) : glm::vec3(0.0f);
    return (cone.T + cone.d * cone.h) - mUnit * cone.r;
}

inline bool coneInsidePlaneCorrected(const Cone& cone, const Plane& plane) {
    const glm::vec3 Q = coneTestPointCorrected(cone, plane.N);
    return pointInsidePlane(cone.T, plane) && pointInsidePlane(Q, plane);
}

}  // namespace tessera
