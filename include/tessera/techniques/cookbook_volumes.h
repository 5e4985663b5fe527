// The HLSL Development Cookbook's light volumes (Feinstein 2013, ch. 2, recipes "Point light",
// "Capsule light", "Spot light"), generated on the CPU the way the recipes' hull and domain shaders
// tessellate them: a quad-domain patch with integer partitioning at a uniform factor (point 18,
// capsule and spot 12), every domain point (u, v) = (i, j) / factor mapped by the recipe's domain
// shader, in float and in the shader's operation order. Local space is left-handed like the book's
// (point: view axes; spot: +z along the light, apex at the origin; capsule: +z along the segment,
// centre at the origin). tests/techniques/cookbook_volumes_test.cpp checks vertices against the formulas'
// worked values, the winding, and that each volume contains its light's region.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace tessera {

// Tessellation factors of the recipes' constant hull shaders (edges and inside alike).
inline constexpr std::uint32_t kCookbookPointTessFactor = 18;
inline constexpr std::uint32_t kCookbookCapsuleTessFactor = 12;
inline constexpr std::uint32_t kCookbookSpotTessFactor = 12;

// PointLightDS: posClipSpace = UV * 2 - 1; maxLen = max(|x|, |y|);
// normDir = normalize(float3(posClipSpace, maxLen - 1) * HemiDir). HemiDir (1, 1, 1) is patch 0
// (the -z hemisphere), (-1, 1, -1) patch 1.
glm::vec3 cookbookPointDomain(glm::vec2 uv, glm::vec3 hemiDir);

// CapsuleLightDS (CylinderPortion 0.3, SpherePortion 0.7, ExpendAmount 1.3): one half capsule
// spanning local z in [-(halfSegmentLen + capsuleRange), 0], mirrored by CapsuleDir (-1, 1, -1, 1).
glm::vec3 cookbookCapsuleDomain(glm::vec2 uv, glm::vec3 capsuleDir, float halfSegmentLen, float capsuleRange);

// SpotLightDS (CylinderPortion 0.2, ExpendAmount 1.2): the cone with its rounded base on the unit
// sphere around the apex, half angle given by sinAngle / cosAngle (the demo passes the outer
// angle's), the UV's y flipped (posClipSpace = UV * (2, -2) + (-1, 1)).
glm::vec3 cookbookSpotDomain(glm::vec2 uv, float sinAngle, float cosAngle);

// A volume mesh in local space: triangle list, every triangle outward-facing as D3D11's default
// front face (clockwise on screen seen from outside), so that CULL_FRONT draws the far side.
struct CookbookVolumeMesh {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
};

// The patch grid of the tessellator: (factor + 1)^2 domain points, two triangles per cell, the
// diagonals radiating from the patch centre (the D3D11 tessellator's exact triangulation of the
// quad domain is not given by the recipes, the vertex positions are), in the winding above.
CookbookVolumeMesh cookbookPointVolume();                                     // 2 patches, factor 18
CookbookVolumeMesh cookbookCapsuleVolume(float halfSegmentLen, float capsuleRange);  // 2 patches, factor 12
CookbookVolumeMesh cookbookSpotVolume(float sinAngle, float cosAngle);          // 1 patch, factor 12

// The smallest enlargement that makes a volume contain its light's region (the book: the range
// "plus a small value", since straight tessellation edges cut inside the sphere). Exact by the
// support function: a mesh whose faces are planes n.x <= d contains a convex set S when every
// face has h_S(n) <= d.
//   point: the scale s of the unit sphere mesh so that it contains the unit ball (s = 1 / min d).
float cookbookPointPadding();
//   capsule: the capsuleRange to pass so the mesh contains the capsule of radius `range` around
//   the segment [-halfSegmentLen, halfSegmentLen] on z (found by bisection to 1e-6 relative).
float cookbookCapsulePaddedRange(float halfSegmentLen, float range);
//   spot: the half angle (radians) to pass and the scale about the apex, so the mesh contains the
//   cone of half angle `halfAngle` truncated by the unit sphere.
struct CookbookSpotPadding {
    float halfAngle = 0.0f;  // radians, >= the light's
    float scale = 1.0f;      // x the range
};
CookbookSpotPadding cookbookSpotPadding(float halfAngle);

} // namespace tessera
