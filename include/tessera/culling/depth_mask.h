// Depth-direction culling of AMD Forward+: GPU Pro 4's 2.5D culling (ch. 5 §5.6.1: a 32-cell
// occupancy mask per tile built from its pixels' view z, a light's depth extent as a mask, keep
// iff the AND is non-zero) and TiledLighting11's half-Z split (two depth ranges per tile split at
// the midpoint, TiledLighting11 DoLightCulling). Callers: the forward-plus-amd culling kernel
// (techniques/amd_light_culling.h) and tests/culling/depth_mask_test.cpp.
#pragma once

#include <cstdint>
#include <limits>
#include <span>

#include <glm/glm.hpp>

#include <tessera/culling/tile_depth_range.h>

namespace tessera {

// ===== 2.5D culling (GPU Pro 4 §5.6.1) ===========================================================
// All depths are AMD's LEFT-handed view z (> 0 in front of the eye), as tile_depth_range.h's AMD
// variants produce them. The chapter gives the algorithm but not the arithmetic; the forms below are
// tessera's reading of its text (quoted in parentheses), written as HLSL would evaluate them:
//   pitch   = (maxZ - minZ) / 32                      ("the pitch of a cell is calculated from the extent")
//   cell(z) = clamp((int)((z - minZ) / pitch), 0, 31)  (HLSL float -> int: NaN -> 0, out of range saturates)
//   light   = (0xffffffff << cell(c.z - r)) & (0xffffffff >> (31 - cell(c.z + r)))
//             ("two bit-shift operations and a bit-and")
// cell() is monotone non-decreasing in z (every step is), so a pixel at z inside [c.z - r, c.z + r]
// lands in a cell between the light's two end cells: the test never drops a light whose depth
// extent contains a pixel of the tile (tested against geometric truth). pitch = 0 (minZ == maxZ)
// needs no special case: (z - minZ) / 0 is +-inf or NaN, which the conversion maps to INT_MAX,
// INT_MIN or 0, and the clamp to 31 / 0 / 0; every pixel of such a tile sets cell 0 (0/0 = NaN)
// and every light whose extent reaches minZ covers cell 0.
inline constexpr std::uint32_t kDepthMaskCells = 32;  // cells per tile: one bit each of a uint

// D3D11.3 §3.2.3 float -> signed integer conversion (ftoi): NaN -> 0, truncation toward zero,
// values beyond the int32 range saturate to INT_MIN / INT_MAX.
inline std::int32_t ftoiD3D(float x) {
    if (x != x) return 0;
    if (x >= 2147483648.0f) return std::numeric_limits<std::int32_t>::max();
    if (x <= -2147483648.0f) return std::numeric_limits<std::int32_t>::min();
    return static_cast<std::int32_t>(x);
}

// pitch = (maxZ - minZ) / 32: view-z units per cell.
inline float depthMaskPitch(float minZ, float maxZ) { return (maxZ - minZ) / static_cast<float>(kDepthMaskCells); }

// The cell (0..31) holding view z: clamp((int)((z - minZ) / pitch), 0, 31).
inline std::uint32_t depthMaskCell(float viewZ, float minZ, float pitch) {
    const std::int32_t cell = ftoiD3D((viewZ - minZ) / pitch);
    return static_cast<std::uint32_t>(cell < 0 ? 0 : (cell > 31 ? 31 : cell));
}

// The flag one pixel ORs into the tile mask: 1 << cell.
inline std::uint32_t depthMaskBit(float viewZ, float minZ, float pitch) { return 1u << depthMaskCell(viewZ, minZ, pitch); }

// A depth extent [zLo, zHi] (zLo <= zHi) as a mask: cells cell(zLo) .. cell(zHi) set.
inline std::uint32_t depthMaskOfRange(float zLoView, float zHiView, float minZ, float pitch) {
    const std::uint32_t cellLo = depthMaskCell(zLoView, minZ, pitch);
    const std::uint32_t cellHi = depthMaskCell(zHiView, minZ, pitch);
    return (0xFFFFFFFFu << cellLo) & (0xFFFFFFFFu >> (31u - cellHi));
}

// A sphere's depth extent [c.z - r, c.z + r] as a mask (GPU Pro 4 §5.6.1: "the minimum and maximum depth
// values of the geometry are calculated and converted to cell indices").
inline std::uint32_t lightDepthMask(float centerZView, float radius, float minZ, float pitch) {
    return depthMaskOfRange(centerZView - radius, centerZView + radius, minZ, pitch);
}

// The 2.5D verdict for a light that already passed the frustum test.
inline bool depthMasksOverlap(std::uint32_t lightMask, std::uint32_t tileMask) { return (lightMask & tileMask) != 0u; }

// A tile's mask from its pixels' view z (the atomic OR over the tile: order-independent).
inline std::uint32_t tileDepthMaskFromViewZ(std::span<const float> viewZs, float minZ, float maxZ) {
    const float pitch = depthMaskPitch(minZ, maxZ);
    std::uint32_t mask = 0;
    for (float z : viewZs) mask |= depthMaskBit(z, minZ, pitch);
    return mask;
}

// The tile mask exactly as the GPU Pro 4 kernel builds it (§5.3.1 + §5.6.1), for the pixels
// that entered tileViewZBitsAmdGpuPro4's min/max: depth != 1.0 (cleared pixels set no bit); a
// thread past the screen edge loads depth 0 and sets the near plane's cell, as it entered minZ.
// minZ / maxZ: asfloat of that function's bits. An all-cleared tile gives mask 0.
inline std::uint32_t tileDepthMaskAmdGpuPro4(const DepthImageView& image, glm::uvec2 groupId, std::uint32_t tileSizePx,
                                             const glm::mat4& inverseProjection, float minZ, float maxZ) {
    const float pitch = depthMaskPitch(minZ, maxZ);
    std::uint32_t mask = 0;
    for (std::uint32_t y = 0; y < tileSizePx; ++y) {
        for (std::uint32_t x = 0; x < tileSizePx; ++x) {
            const float depth = image.load(groupId.x * tileSizePx + x, groupId.y * tileSizePx + y);
            if (depth == 1.0f) continue;
            const float viewZ = clipToView(glm::vec4(0.0f, 0.0f, depth, 1.0f), inverseProjection).z;
            mask |= depthMaskBit(viewZ, minZ, pitch);
        }
    }
    return mask;
}

// ===== Half-Z (TiledLighting11, TilingCommonHeader.h DoLightCulling) ============================
// fHalfZ = (minZ + maxZ) / 2.0f; two lists per tile:
//   A (near half): -c.z + minZ  < r && c.z - fHalfZ < r
//   B (far half):  -c.z + fHalfZ < r && c.z - maxZ  < r
// A pixel reads list A iff its view z < fHalfZ, else list B (TilingForward.hlsl). The union of
// the halves is the plain min/max slab; the gain is per pixel (a pixel sees only its half's list).
inline float halfZAmd(float minZ, float maxZ) { return (minZ + maxZ) / 2.0f; }

// AMD's depth-slab test, `-c.z + zNear < r && c.z - zFar < r`, evaluated left to right.
inline bool sphereOverlapsDepthSlabAmd(float centerZView, float radius, float zNearView, float zFarView) {
    return -centerZView + zNearView < radius && centerZView - zFarView < radius;
}

struct HalfZOverlap {
    bool nearHalf = false;  // list A
    bool farHalf = false;   // list B
};

inline HalfZOverlap sphereOverlapsHalfZAmd(float centerZView, float radius, float minZ, float maxZ) {
    const float halfZ = halfZAmd(minZ, maxZ);
    return {sphereOverlapsDepthSlabAmd(centerZView, radius, minZ, halfZ),
            sphereOverlapsDepthSlabAmd(centerZView, radius, halfZ, maxZ)};
}

// The list a pixel at view z shades with: true = A (near half).
inline bool pixelUsesNearHalfAmd(float viewZ, float halfZ) { return viewZ < halfZ; }

}  // namespace tessera
