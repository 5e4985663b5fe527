// The steps of the tile loop (draw_impl.h's TileRasterizer) that do not depend on the pixel
// shader, compiled once in src/raster/detail/tile_steps.cpp instead of once per shader and depth
// kernel: a triangle's edge stepping over its rectangle in a tile, the SIMD block's coverage, and
// storing a block's stashed RGBA8 colours. Not a public header.
#pragma once

#include <cstdint>
#include <span>

#include <tessera/raster/quad_block.h>
#include <tessera/raster/sample_pattern.h>
#include <tessera/raster/triangle_setup.h>

namespace tessera {
class Surface;
}  // namespace tessera

namespace tessera::detail {

// One triangle's edge functions over its rectangle r in a tile (units^2, fixed_point.h). Edge
// functions are stepped, not re-multiplied: E_i at the top-left pixel centre of the first quad
// (qx0, qy0) is evaluated once as A_i (X - X_i) + B_i (Y - Y_i), then moves by A_i * 256 per pixel
// in x and B_i * 256 per pixel in y, and a sample adds A_i * dx + B_i * dy for its offset.
struct TriangleEdges {
    std::int64_t stepX[3], stepY[3];
    std::int64_t sampleDelta[8][3];  // [s][i]; only s < sampleCount is set
    std::int32_t qx0, qy0;           // px: r's top-left, rounded down to whole quads
    std::int64_t eOrigin[3];         // E_i at the centre of pixel (qx0, qy0)
    // Blocks of QuadBlock::kSide x kSide pixels (whole quads, from (qx0, qy0)) where some edge
    // function is below its bias at every sample point are skipped. E_i is linear, so its
    // maximum over the block's sample points is E_i at the block's first pixel centre plus
    // blockReach[i] (the largest pixel step in x and in y, plus the largest sample offset):
    // an exact integer bound, so a skipped block holds no covered sample. The points are
    // at most kSide px outside the target, inside the guard band: |E| <= 2^61 still holds.
    std::int64_t blockReach[3];
    // The minimum of E_i over a block's pixel centres, relative to its first: the SIMD block
    // path (single-sampled) treats a block whose minimum is at or above the bias as covered.
    std::int64_t blockLow[3];
};
void triangleEdges(const SetupTriangle& t, const PixelRect& r, std::span<const SampleOffset> samples,
                   std::uint32_t sampleCount, TriangleEdges& out);

// The covered pixel centres of the SIMD block at (bx, by) (bit row * 8 + column), limited to r:
// every pixel of r when the block's lowest edge values are at or above the biases (trivially
// covered: the same exact integer bound as blockReach), else quadBlockCoverage.
std::uint64_t simdBlockCoverage(const SetupTriangle& t, const TriangleEdges& e, const QuadBlock::Edges& edges,
                                const PixelRect& r, std::int32_t bx, std::int32_t by);

// Stores the RGBA8 colours of one triangle's block for one target (rgba: colour c of lane p at
// rgba[c * 64 + p]; `pending`: the lanes to write), blended with the texels first when `blend`,
// encoded 64 at a time. The block's top-left pixel is (bx, by); the target is single-sampled.
void storeStashedRgba8(Surface& target, float* rgba, std::uint64_t pending, bool blend,
                       const RenderTargetBlendDesc& blendDesc, const glm::vec4& blendFactor, bool fast,
                       std::int32_t bx, std::int32_t by);

}  // namespace tessera::detail
