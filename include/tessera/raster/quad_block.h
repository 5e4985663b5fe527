// The per-pixel values of one 8x8 pixel block of a triangle (coverage, barycentrics, depth,
// clip w and the perspective-correct varyings), computed 2 to 16 lanes at a time through
// Highway's runtime dispatch. Each lane performs exactly the operations of the scalar per-quad
// path (detail::quadCentres in draw_impl.h), in the same order, so it equals it bit for bit.
#pragma once

#include <cstdint>

#include <glm/vec4.hpp>

#include <tessera/raster/triangle_setup.h>
#include <tessera/state/blend_state.h>
#include <tessera/state/comparison.h>

namespace tessera {

struct QuadBlock {
    static constexpr int kSide = 8;                  // px
    static constexpr int kPixels = kSide * kSide;    // lane = row * kSide + column
    static constexpr std::uint32_t kMaxVaryings = 64;  // floats per vertex the block holds

    // The block: E_i at the centre of its top-left pixel, and E_i's change per pixel in x and y
    // (A_i * 256, B_i * 256: fixed_point.h). Pixels of the block lie inside the guard band.
    struct Edges {
        std::int64_t origin[3], stepX[3], stepY[3];
    };

    alignas(64) float l[3][kPixels];  // barycentrics, float(double(E_i) * invArea2)
    alignas(64) float z[kPixels];     // depth at the centre, not clamped
    alignas(64) float posW[kPixels];  // clip w (1 / sum(l_i / w_i)); only with varyings
    // Varying k of lane p at varyings[k * kPixels + p]; only with varyings.
    alignas(64) float varyings[kMaxVaryings * kPixels];
};

// Bit (row * 8 + column) set where the pixel centre is covered (E_i >= bias_i for every edge,
// D3D11.3 §15.14's top-left rule as encoded in SetupTriangle::bias) and the column's bit is
// set in `columns` and the row's in `rows` (the block's part of the rasterized rectangle).
std::uint64_t quadBlockCoverage(const SetupTriangle& t, const QuadBlock::Edges& e, std::uint8_t columns,
                                std::uint8_t rows);

// Fills barycentrics and depth for all 64 pixels (covered or not: helper pixels need them),
// and with `varyingCount` > 0 also posW and the varyings (`vertexVaryings`: the triangle's
// 3 * varyingCount floats, premultiplied by 1/w, vertex after vertex; varyingCount <=
// kMaxVaryings). fastBarycentrics: float(double(E_i)) * float(invArea2), precision fast.
void quadBlockCentres(const SetupTriangle& t, const QuadBlock::Edges& e, const float* vertexVaryings,
                      std::uint32_t varyingCount, bool wantPosW, bool fastBarycentrics, QuadBlock& out);

// R8G8B8A8_UNORM texels of 64 colours (rgba[c * 64 + lane], c = R, G, B, A): the clamp to [0, 1]
// (NaN -> 0) and the rounding of writeColorRgba8Unorm (output_merger.h), same operations in the
// same order (x * 255 in double, truncate, add 1 where the fraction is >= 0.5); with `fast`,
// writeColorRgba8UnormFast's float x * 255 + 0.5 truncated. codes[lane] holds the four bytes
// in memory order (R first), ready to copy into the texel.
void quadBlockEncodeRgba8(const float* rgba, bool fast, std::uint32_t* codes);

// writeColorSample's blend for R8G8B8A8_UNORM (output_merger.cpp) on 64 pixels, up to the
// encode: rgba (c * 64 + lane) holds the shader's colours and receives the values encodeTexel
// then rounds (quadBlockEncodeRgba8 with fast = false); dstCodes[lane] the texel's four bytes.
// The source and the blend factor clamped to [0, 1] (NaN -> 0), the destination decoded as
// code / 255, factors and ops of D3D11_BLEND / D3D11_BLEND_OP in the scalar code's operation order, channels
// outside the write mask keep the destination. Every lane is computed; callers store only theirs.
void quadBlockBlendRgba8(float* rgba, const std::uint32_t* dstCodes, const RenderTargetBlendDesc& blend,
                         const glm::vec4& blendFactor);

// The depth test of DepthPath D32 / D24 (output_merger.h: stencil inactive) for the lanes in
// `lanes`: z clamped to [minDepth, maxDepth] (NaN -> minDepth) as the scalar clampDepth, and for
// d24 converted by convert::depthToD24's operations, then `incoming OP stored` with stored[lane]
// the texel's depth (D32: the float's bits; D24: the 24-bit code). Returns the passing lanes
// (a subset of `lanes`); zClamped[lane] receives the clamped depth and incoming[lane] the value a
// passing sample stores (the float's bits or the code). Lanes outside `lanes` are computed from
// whatever the arrays hold and must be ignored.
std::uint64_t quadBlockDepthTest(const float* z, const std::uint32_t* stored, std::uint64_t lanes, bool d24,
                                 ComparisonFunc func, float minDepth, float maxDepth, float* zClamped,
                                 std::uint32_t* incoming);

// The SIMD target these run on ("AVX3", "AVX2", "SSE4", "EMU128", ...), for --stats and benchmarks.
const char* quadBlockTarget();

} // namespace tessera
