// The block-shader entry point: a pixel shader may also shade one triangle's lanes of an 8x8
// block in a single call, over structure-of-arrays lanes, so that its per-lane work runs in
// vectors and the rasterizer makes one call per block instead of one per pixel. The per-pixel
// operator() stays the definition (and the tests' oracle): shadeBlock must give its bits.
#pragma once

#include <array>
#include <concepts>
#include <cstdint>

#include <tessera/shaders/shader_stages.h>

namespace tessera {

inline constexpr int kBlockSide = 8;                        // px per block side
inline constexpr int kBlockLanes = kBlockSide * kBlockSide;  // lane = row * kBlockSide + column

// One triangle's part of one 8x8 block, single-sampled, at pixel centres.
struct BlockInput {
    std::int32_t x0, y0;    // the block's top-left pixel, window px (lane l is x0 + l % 8, y0 + l / 8)
    std::uint64_t shade;    // the lanes to shade (bit l): exactly the pixels operator() would run on
    // Float j of the varyings of lane l at varyings[j * kBlockLanes + l], perspective-correct at
    // the pixel centre. Every lane holds a value, helper lanes outside the triangle included, so
    // that coarse derivatives can be taken as the per-pixel path takes them: ddx = lane
    // (top-left of its quad) + 1 minus the top-left lane, ddy = top-left + 8 minus top-left
    // (blockDdx / blockDdy below).
    const float* varyings;
    const float* zWindow;   // SV_Position.z per lane, clamped to the viewport's depth range (shaded lanes)
    const float* wClip;     // SV_Position.w per lane
    bool isFrontFace;       // SV_IsFrontFace (one triangle per call); SV_Coverage is 1, SV_SampleIndex 0
};

// Where a block shader writes. Channel c of target rt for lane l goes to
// target[rt][c * kBlockLanes + l]. A shaded lane that is not discarded must have all four
// channels of every target written (operator()'s PixelOutput starts at zero, so a shader that
// leaves a target unwritten writes 0 there); lanes outside `shade` may be written and are ignored.
template <int N>
struct BlockOutput {
    std::array<float*, (N > 0 ? N : 1)> target{};
    std::uint64_t discarded = 0;  // lanes that discarded (a subset of `shade`); only if kMayDiscard
};

// SV_Position.x / .y of lane l: the pixel centre.
inline float blockPosX(const BlockInput& in, int lane) { return float(in.x0 + lane % kBlockSide) + 0.5f; }
inline float blockPosY(const BlockInput& in, int lane) { return float(in.y0 + lane / kBlockSide) + 0.5f; }

// The per-pixel path's coarse derivative of varying float j at lane l: taken in the quad's top
// row (right minus left) and left column (bottom minus top), one float subtraction each.
inline int blockQuadOrigin(int lane) { return lane & ~(kBlockSide + 1); }  // clears the column's and row's low bit
inline float blockDdx(const BlockInput& in, std::uint32_t j, int lane) {
    const float* v = in.varyings + std::size_t(j) * kBlockLanes;
    const int tl = blockQuadOrigin(lane);
    return v[tl + 1] - v[tl];
}
inline float blockDdy(const BlockInput& in, std::uint32_t j, int lane) {
    const float* v = in.varyings + std::size_t(j) * kBlockLanes;
    const int tl = blockQuadOrigin(lane);
    return v[tl + kBlockSide] - v[tl];
}

// A pixel shader with a block entry point:
//   void shadeBlock(const BlockInput&, BlockOutput<kTargetCount>&) const
// Used by single-sampled draws on the lean SIMD-block path (raster/detail/draw_impl.h) when
// DeviceConfig::simdBlocks is on; per-sample and depth-writing shaders never get it.
template <class PS>
concept BlockPixelShader = PixelShader<PS> && requires(const PS& ps, const BlockInput& in, BlockOutput<PS::kTargetCount>& out) {
    ps.shadeBlock(in, out);
};

} // namespace tessera
