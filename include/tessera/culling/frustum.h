// The 3dgep tile frustum (four side planes) and its sphere and cone tests with a near/far depth
// range (3dgep article §4.1, §4.4; demo CommonInclude.hlsl), binary32 in the
// HLSL order. View space is right-handed, the camera looks down -z, plane normals point INTO the
// frustum, so "inside a plane" (negative half-space) means outside the frustum.
#pragma once

#include <array>
#include <cstddef>

#include <tessera/culling/plane.h>

namespace tessera {

// 3dgep article §4.1 Frustum: planes[0..3] = left, right, top, bottom (CS_ComputeFrustums' order).
struct Frustum {
    std::array<Plane, 4> planes{};
};

// 3dgep article §4.4.1 SphereInsideFrustum: false if `c.z - r > zNear || c.z + r < zFar`, else false if
// SphereInsidePlane for any of the 4 planes, else true. "Inside" = intersecting or contained.
// zNear > zFar are view z values (negative in front of the camera; right-handed, article §4.4.1:
// swap them for a left-handed system). The kernel passes (nearClipVS, maxDepthVS) for the
// transparent list and the opaque list additionally requires !SphereInsidePlane(minPlane).
inline bool sphereInsideFrustum(const Sphere& sphere, const Frustum& frustum, float zNear, float zFar) {
    bool result = true;
    if (sphere.c.z - sphere.r > zNear || sphere.c.z + sphere.r < zFar) result = false;
    for (int i = 0; i < 4 && result; ++i) {
        if (sphereInsidePlane(sphere, frustum.planes[static_cast<std::size_t>(i)])) result = false;
    }
    return result;
}

// 3dgep article §4.4.2: the near and far planes ConeInsideFrustum builds, normals pointing OUT of the
// depth range: nearPlane = {(0,0,-1), -zNear} (inside it: z > zNear), farPlane = {(0,0,1), zFar}
// (inside it: z < zFar). nearPlane3dgep(minDepthVS) is also CS_main's opaque-list
// `minPlane = { float3(0,0,-1), -minDepthVS }` (demo ForwardPlusRendering.hlsl).
inline Plane nearPlane3dgep(float zNear) { return Plane{glm::vec3(0.0f, 0.0f, -1.0f), -zNear}; }
inline Plane farPlane3dgep(float zFar) { return Plane{glm::vec3(0.0f, 0.0f, 1.0f), zFar}; }

// 3dgep article §4.4.2 ConeInsideFrustum, FAITHFUL: false if ConeInsidePlane(near) || ConeInsidePlane(far),
// else false if ConeInsidePlane for any of the 4 planes. Inherits coneInsidePlane's erratum (m not
// normalized): it can report "outside" for a cone that intersects the frustum.
inline bool coneInsideFrustum(const Cone& cone, const Frustum& frustum, float zNear, float zFar) {
    bool result = true;
    if (coneInsidePlane(cone, nearPlane3dgep(zNear)) || coneInsidePlane(cone, farPlane3dgep(zFar))) result = false;
    for (int i = 0; i < 4 && result; ++i) {
        if (coneInsidePlane(cone, frustum.planes[static_cast<std::size_t>(i)])) result = false;
    }
    return result;
}

// CORRECTED ConeInsideFrustum (tessera): the same structure with coneInsidePlaneCorrected.
// Conservative: it never reports "outside" for a cone that intersects the frustum (beyond
// rounding); see tests/culling/culling_property_test.cpp.
inline bool coneInsideFrustumCorrected(const Cone& cone, const Frustum& frustum, float zNear, float zFar) {
    bool result = true;
    if (coneInsidePlaneCorrected(cone, nearPlane3dgep(zNear)) || coneInsidePlaneCorrected(cone, farPlane3dgep(zFar)))
        result = false;
    for (int i = 0; i < 4 && result; ++i) {
        if (coneInsidePlaneCorrected(cone, frustum.planes[static_cast<std::size_t>(i)])) result = false;
    }
    return result;
}

}  // namespace tessera
