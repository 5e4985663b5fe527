// The G-buffer math of Practical Rendering and Computation with Direct3D 11 (Zink, Pettineo, Hoxley
// 2011), ch. 11 "Deferred Rendering": the sphere-map normal codec (Listing 11.8), the xy + rebuilt z
// normal (Eq. 11.3), linear depth from the hardware depth with ProjectionA / ProjectionB (Listing
// 11.12) and the point light's scissor rectangle (Listing 11.14). Left-handed view space (+z
// forward) as the chapter; float, in the listings' operation order. Tested against values worked
// from the printed code in tests/gbuffer/prc_gbuffer_test.cpp; the building blocks of the planned
// `deferred-classic` and `light-prepass` techniques.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace tessera {

// SpheremapEncode: normalize(n.xy) * sqrt(-n.z * 0.5 + 0.5). The result lies in the unit disc
// (|e|^2 = (1 - n.z) / 2). n = (0, 0, +-1) normalizes (0, 0): NaN (as the HLSL would; the
// chapter does not handle it, tests/gbuffer/prc_gbuffer_test.cpp shows it).
glm::vec2 prcSpheremapEncode(const glm::vec3& normal);
// The same encoding defined at the poles (ERRATA #29): n.xy = 0 encodes as (0, 0) for z > 0 and
// (1, 0) for z < 0 (|e| = 1 is the whole circle for z = -1; any point on it decodes to (0, 0, -1)).
// The listing's NaN stored to SNORM becomes 0, which decodes as (0, 0, +1): a normal facing the
// camera head-on comes back facing away.
glm::vec2 prcSpheremapEncodeSafe(const glm::vec3& normal);
// SpheremapDecode with l = 1 - |e|^2 clamped to >= 0 (ERRATA #29): near z = -1 (in the chapter's
// left-handed view space, a surface facing the camera) |e| -> 1, and rounding the code to a 16-bit
// SNORM can push |e|^2 past 1, where the listing's sqrt(l) is NaN and the pixel goes black.
glm::vec3 prcSpheremapDecodeSafe(const glm::vec2& encoded);
// SpheremapDecode: nn = (e, 1, -1); l = dot(nn.xyz, -nn.xyw) = 1 - dot(e, e); nn.z = l;
// nn.xy *= sqrt(l); return nn.xyz * 2 + (0, 0, -1).
glm::vec3 prcSpheremapDecode(const glm::vec2& encoded);

// Eq. 11.3: z = +-sqrt(1 - (x^2 + y^2)), the sign chosen by the caller (the chapter: store it in x
// or y; assuming z < 0 in view space is wrong, Fig. 11.5). max(0, ...) keeps rounding from a NaN.
glm::vec3 prcNormalFromXy(const glm::vec2& xy, bool positiveZ);

// Listing 11.12: ProjectionA = Far / (Far - Near), ProjectionB = (-Far * Near) / (Far - Near);
// linear (view) depth = ProjectionB / (depth - ProjectionA): depth 0 -> Near, 1 -> Far.
struct PrcProjectionAB {
    float a = 1.0f, b = 0.0f;
};
PrcProjectionAB prcProjectionAB(float nearZ, float farZ);
float prcLinearDepth(float depth, const PrcProjectionAB& ab);

// The chapter's other ways to rebuild a position from one stored value (§11.4.1), each with the
// ray its light volume or quad hands the pixel shader, left-handed view space:
//   (a) Listings 11.9/11.10: the G-buffer stores length(positionVS); the light pass walks that
//       distance along normalize(viewRay) from the camera.
glm::vec3 prcPositionFromDistance(const glm::vec3& cameraPos, const glm::vec3& viewRay, float distance);
//   (b) Listing 11.11: the G-buffer stores positionVS.z / Far; a volume's ray is scaled to the far
//       plane, viewRay = (p.xy * (Far / p.z), Far), and the position is viewRay * stored.
glm::vec3 prcPositionFromNormalizedDepth(const glm::vec3& volumePositionVS, float farZ, float storedDepth);
//   (d) Listing 11.13: any space: the linear depth divided by the ray's cosine with the eye's z
//       axis, along the normalized ray from the camera.
glm::vec3 prcPositionAnySpace(const glm::vec3& cameraPos, const glm::vec3& eyeZAxis, const glm::vec3& viewRay, float linearDepth);

// Listing 11.14: the screen rectangle of a point light's sphere (view-space centre, radius) for a
// symmetric perspective projection with P(0, 0), P(1, 1), near / far clip distances and a
// width x height viewport: the sphere's left/right/top/bottom points pushed towards or away from
// the eye by the radius, clamped to [near, far], projected, clamped to [-1, 1], mapped to pixels
// (top and bottom flipped) and truncated (static_cast<LONG>), then clamped to the viewport.
// roundOut: the right and bottom edges rounded up instead (truncating them drops the last partly
// covered column and row, ERRATA #28).
struct PrcScissorRect {
    std::int32_t left = 0, top = 0, right = 0, bottom = 0;
};
PrcScissorRect prcPointLightScissor(const glm::vec3& centerView, float radius, float proj00, float proj11, float nearZ,
                                    float farZ, std::uint32_t widthPx, std::uint32_t heightPx, bool roundOut = false);

} // namespace tessera
