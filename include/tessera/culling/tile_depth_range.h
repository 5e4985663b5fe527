// The per-tile depth range of the tiled culling kernels, computed from a depth buffer exactly as
// each kernel does it: 3dgep (demo CS_main), AMD (GPU Pro 4 §5.3.1 and ForwardPlus11) and Intel
// (2010 sample): uint atomic min/max over float bits, each kernel's value, skip rule and initial
// values, and the D3D11 rule that an out-of-range Load returns 0 for threads past the screen edge.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include <tessera/gbuffer/screen_to_view.h>

namespace tessera {

// A depth buffer as a shader's Load sees it: row-major, row 0 at the top, one float per pixel
// (D32_FLOAT as stored, or D24 decoded to code / (2^24 - 1)). Load out of range returns 0 in
// every component (D3D11.3 §22, ld; compute/resources.h): a thread of a partial edge tile that
// loads past the screen reads depth 0.
struct DepthImageView {
    std::span<const float> depth;
    std::uint32_t width = 0, height = 0;  // px

    float load(std::uint32_t pxX, std::uint32_t pxY) const {
        return pxX < width && pxY < height ? depth[std::size_t{pxY} * width + pxX] : 0.0f;
    }
};

// The two group-shared uints after the reduction (InterlockedMin / InterlockedMax over asuint).
// For non-negative floats the uint order is the float order; -0.0 (0x80000000) and NaNs are not.
struct TileDepthBits {
    std::uint32_t minBits = 0, maxBits = 0;
    float minValue() const { return std::bit_cast<float>(minBits); }  // asfloat
    float maxValue() const { return std::bit_cast<float>(maxBits); }
};

// Every kernel below runs one group of tileSize x tileSize threads per tile, one pixel each, and
// only commutative uint min/max reach the shared values, so a plain loop over the tile's pixels
// gives the bits any thread order gives (checked against compute::dispatch in
// tests/culling/tile_depth_range_test.cpp). groupId: SV_GroupID.xy (tile column, row from the top).
namespace tiledepth_detail {

template <class ValueFn>
TileDepthBits reduce(const DepthImageView& image, glm::uvec2 groupId, std::uint32_t tileSizePx,
                     std::uint32_t initMin, std::uint32_t initMax, ValueFn&& valueFn) {
    TileDepthBits bits{initMin, initMax};
    for (std::uint32_t y = 0; y < tileSizePx; ++y) {
        for (std::uint32_t x = 0; x < tileSizePx; ++x) {
            float value = 0.0f;
            if (valueFn(image.load(groupId.x * tileSizePx + x, groupId.y * tileSizePx + y), value)) {
                const std::uint32_t u = std::bit_cast<std::uint32_t>(value);
                if (u < bits.minBits) bits.minBits = u;
                if (u > bits.maxBits) bits.maxBits = u;
            }
        }
    }
    return bits;
}

}  // namespace tiledepth_detail

// ----- 3dgep (demo ForwardPlusRendering.hlsl CS_main) -------------------------------------------
// uDepth = asuint(DepthTextureVS.Load(int3(texCoord, 0)).r) for EVERY thread (cleared 1.0 pixels
// included); uMinDepth = 0xffffffff, uMaxDepth = 0; InterlockedMin / InterlockedMax.
// Edge tiles: threads past the screen load 0, so the tile's minimum depth becomes 0 and
// minDepthVS = nearClipVS (the demo's CS_main, ERRATA #14): the opaque list of a partial tile gets no
// near-side culling at all.
inline TileDepthBits tileDepthBits3dgep(const DepthImageView& image, glm::uvec2 groupId, std::uint32_t blockSizePx) {
    return tiledepth_detail::reduce(image, groupId, blockSizePx, 0xFFFFFFFFu, 0u, [](float depth, float& value) {
        value = depth;
        return true;
    });
}

struct TileDepthRange3dgep {
    float minDepth = 0.0f, maxDepth = 0.0f;  // depth-buffer values: asfloat(uMinDepth), asfloat(uMaxDepth)
    float minDepthVS = 0.0f;                 // ScreenToView(float4(0, 0, fMinDepth, 1)).z (RH, < 0)
    float maxDepthVS = 0.0f;                 // ScreenToView(float4(0, 0, fMaxDepth, 1)).z
    float nearClipVS = 0.0f;                 // ScreenToView(float4(0, 0, 0, 1)).z
};

// The kernel's view-space bounds: the culling then uses (nearClipVS, maxDepthVS) for the
// transparent list and additionally minPlane = {(0, 0, -1), -minDepthVS} for the opaque list.
// MSAA: one image per sample, every sample's depth in the min / max (the demo has no MSAA; the
// bounds then hold every surface a sample of the tile shows).
inline TileDepthRange3dgep tileDepthRange3dgep(std::span<const DepthImageView> samples, glm::uvec2 groupId, std::uint32_t blockSizePx,
                                               const glm::vec2& screenDimensions, const glm::mat4& inverseProjection) {
    TileDepthBits bits = tileDepthBits3dgep(samples[0], groupId, blockSizePx);
    for (std::size_t i = 1; i < samples.size(); ++i) {
        const TileDepthBits b = tileDepthBits3dgep(samples[i], groupId, blockSizePx);
        bits.minBits = std::min(bits.minBits, b.minBits);
        bits.maxBits = std::max(bits.maxBits, b.maxBits);
    }
    TileDepthRange3dgep range;
    range.minDepth = bits.minValue();
    range.maxDepth = bits.maxValue();
    range.minDepthVS = screenToView(glm::vec4(0.0f, 0.0f, range.minDepth, 1.0f), screenDimensions, inverseProjection).z;
    range.maxDepthVS = screenToView(glm::vec4(0.0f, 0.0f, range.maxDepth, 1.0f), screenDimensions, inverseProjection).z;
    range.nearClipVS = screenToView(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f), screenDimensions, inverseProjection).z;
    return range;
}

inline TileDepthRange3dgep tileDepthRange3dgep(const DepthImageView& image, glm::uvec2 groupId, std::uint32_t blockSizePx,
                                               const glm::vec2& screenDimensions, const glm::mat4& inverseProjection) {
    return tileDepthRange3dgep(std::span<const DepthImageView>(&image, 1), groupId, blockSizePx, screenDimensions, inverseProjection);
}

// ----- AMD, GPU Pro 4 chapter (ch. 5 §5.3.1) ----------------------------------------------------
// viewPos = projToView(x, y, depth); z = asuint(viewPos.z); if (depth != 1.f) { AtomMax; AtomMin }
// with ldsZMax = 0, ldsZMin = 0xffffffff: LEFT-handed view z (> 0), cleared 1.0 pixels skipped.
// projToView is not given; its z is taken as clipToView(float4(0, 0, depth, 1), invProj).z (for
// a perspective inverse the z does not depend on x, y). Edge tiles: an out-of-range load gives
// depth 0 (!= 1), the near plane's view z, which enters the MINIMUM. An all-cleared tile keeps
// the initial values: maxZ = +0.0, minZ = asfloat(0xffffffff), a NaN (GPU Pro 4 §5.3.1 leaves this open).
inline TileDepthBits tileViewZBitsAmdGpuPro4(const DepthImageView& image, glm::uvec2 groupId, std::uint32_t tileSizePx,
                                              const glm::mat4& inverseProjection) {
    return tiledepth_detail::reduce(image, groupId, tileSizePx, 0xFFFFFFFFu, 0u, [&](float depth, float& value) {
        value = clipToView(glm::vec4(0.0f, 0.0f, depth, 1.0f), inverseProjection).z;
        return depth != 1.0f;
    });
}

// ----- AMD ForwardPlus11 (CalculateMinMaxDepthInLds) --------------------------------------------
// Reversed depth (cleared to 0, near = 1): viewPosZ = 1.f / (depth * g_mProjectionInv._34 +
// g_mProjectionInv._44) with _34 = m[2][3], _44 = m[3][3] of the glm inverse; if (depth != 0.f)
// InterlockedMax / InterlockedMin; ldsZMin = 0x7f7fffff (FLT_MAX), ldsZMax = 0.
// Edge tiles: the out-of-range load's 0 is the cleared value and is skipped, so partial tiles
// bound only their on-screen pixels. An empty tile keeps (FLT_MAX, 0): every light fails
// `-c.z + minZ < r`.
inline TileDepthBits tileViewZBitsAmdForwardPlus11(const DepthImageView& image, glm::uvec2 groupId, std::uint32_t tileRes,
                                                    const glm::mat4& inverseProjection) {
    const float inv34 = inverseProjection[2][3], inv44 = inverseProjection[3][3];
    return tiledepth_detail::reduce(image, groupId, tileRes, 0x7F7FFFFFu, 0u, [&](float depth, float& value) {
        value = 1.0f / (depth * inv34 + inv44);
        return depth != 0.0f;
    });
}

// ----- Intel 2010 tiled deferred (Intel 2010 sample, ComputeShaderTile.hlsl) -------------------
// Per pixel viewSpaceZ = mCameraProj._43 / (zBuffer - mCameraProj._33) (GBuffer.hlsl, the 2010
// lines; _43 = m[3][2], _33 = m[2][2] of the glm projection), valid iff
// `viewSpaceZ >= mCameraNearFar.x && viewSpaceZ < mCameraNearFar.y`; only valid samples reach
// InterlockedMin / InterlockedMax(asuint), initialised to 0x7F7FFFFF (FLT_MAX) / 0. LEFT-handed z.
// Edge tiles: the G-buffer load past the screen returns zBuffer = 0. With the sample's
// complementary Z (SetProjParams(pi/4, aspect, 300, 0.05), mCameraNearFar = (0.05, 300)) depth
// 0 gives _43 / (0 - _33) = 300.0f exactly in binary32, which fails `< far`: off-screen threads
// are invalid and edge tiles are bounded by their own pixels (tests/culling/tile_depth_range_test.cpp).
// With another projection the rounded value could land below far and enter the maximum.
inline TileDepthBits tileViewZBitsIntel(const DepthImageView& image, glm::uvec2 groupId, std::uint32_t tileDim,
                                        const glm::mat4& projection, float cameraNear, float cameraFar) {
    const float proj43 = projection[3][2], proj33 = projection[2][2];
    return tiledepth_detail::reduce(image, groupId, tileDim, 0x7F7FFFFFu, 0u, [&](float zBuffer, float& value) {
        value = proj43 / (zBuffer - proj33);
        return value >= cameraNear && value < cameraFar;
    });
}

}  // namespace tessera
