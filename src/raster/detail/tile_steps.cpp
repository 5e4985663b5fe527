// The shader-independent steps of the tile loop (include/tessera/raster/detail/tile_steps.h):
// edge stepping per triangle, SIMD block coverage and the RGBA8 colour stash's store. Moved out
// of the rasterizer's template so that they are compiled once, not per pixel shader.
#include <tessera/raster/detail/tile_steps.h>

#include <algorithm>
#include <bit>
#include <cstring>

#include <tessera/buffers/surface.h>
#include <tessera/raster/fixed_point.h>

namespace tessera::detail {

void triangleEdges(const SetupTriangle& t, const PixelRect& r, std::span<const SampleOffset> samples,
                   std::uint32_t sampleCount, TriangleEdges& out) {
    out.qx0 = r.minX & ~1;
    out.qy0 = r.minY & ~1;
    for (int i = 0; i < 3; ++i) {
        out.stepX[i] = std::int64_t(t.a[i]) * fixed::kOne;
        out.stepY[i] = std::int64_t(t.b[i]) * fixed::kOne;
        const std::int64_t X = std::int64_t(out.qx0) * fixed::kOne + fixed::kHalf;
        const std::int64_t Y = std::int64_t(out.qy0) * fixed::kOne + fixed::kHalf;
        out.eOrigin[i] = std::int64_t(t.a[i]) * (X - t.edgeX[i]) + std::int64_t(t.b[i]) * (Y - t.edgeY[i]);
        for (std::uint32_t s = 0; s < sampleCount; ++s)
            out.sampleDelta[s][i] = std::int64_t(t.a[i]) * (samples[s].x * 16) + std::int64_t(t.b[i]) * (samples[s].y * 16);
    }
    constexpr std::int32_t kBlock = QuadBlock::kSide;  // px
    for (int i = 0; i < 3; ++i) {
        std::int64_t maxDelta = out.sampleDelta[0][i];
        for (std::uint32_t s = 1; s < sampleCount; ++s) maxDelta = std::max(maxDelta, out.sampleDelta[s][i]);
        out.blockReach[i] = std::max<std::int64_t>(0, (kBlock - 1) * out.stepX[i]) +
                            std::max<std::int64_t>(0, (kBlock - 1) * out.stepY[i]) + maxDelta;
    }
    for (int i = 0; i < 3; ++i)
        out.blockLow[i] = std::min<std::int64_t>(0, (kBlock - 1) * out.stepX[i]) + std::min<std::int64_t>(0, (kBlock - 1) * out.stepY[i]);
}

std::uint64_t simdBlockCoverage(const SetupTriangle& t, const TriangleEdges& e, const QuadBlock::Edges& edges,
                                const PixelRect& r, std::int32_t bx, std::int32_t by) {
    constexpr std::int32_t kBlock = QuadBlock::kSide;  // px
    std::uint8_t columns = 0, rows = 0;
    for (std::int32_t c = 0; c < kBlock; ++c) {
        if (bx + c >= r.minX && bx + c < r.maxX) columns = std::uint8_t(columns | (1u << c));
        if (by + c >= r.minY && by + c < r.maxY) rows = std::uint8_t(rows | (1u << c));
    }
    // Trivially covered when every edge is at or above its bias at the block's
    // lowest corner (E_i is linear; the same exact integer bound as blockReach).
    bool inside = true;
    for (int i = 0; i < 3; ++i) inside = inside && edges.origin[i] + e.blockLow[i] >= t.bias[i];
    std::uint64_t covered = 0;
    if (inside) {
        for (std::int32_t y = 0; y < kBlock; ++y)
            if ((rows >> y) & 1u) covered |= std::uint64_t(columns) << (y * kBlock);
    } else {
        covered = quadBlockCoverage(t, edges, columns, rows);
    }
    return covered;
}

void storeStashedRgba8(Surface& target, float* rgba, std::uint64_t pending, bool blend,
                       const RenderTargetBlendDesc& blendDesc, const glm::vec4& blendFactor, bool fast,
                       std::int32_t bx, std::int32_t by) {
    constexpr std::int32_t kBlock = QuadBlock::kSide;  // px
    if (blend) {
        alignas(64) std::uint32_t dstCodes[QuadBlock::kPixels] = {};
        for (std::uint64_t m = pending; m != 0; m &= m - 1) {
            const int lane = std::countr_zero(m);
            std::memcpy(&dstCodes[lane], target.texel(std::uint32_t(bx + lane % kBlock), std::uint32_t(by + lane / kBlock)), 4);
        }
        quadBlockBlendRgba8(rgba, dstCodes, blendDesc, blendFactor);
    }
    // writeColorSample encodes blends exactly in every precision mode.
    alignas(64) std::uint32_t codes[QuadBlock::kPixels];
    quadBlockEncodeRgba8(rgba, fast && !blend, codes);
    for (int row = 0; row < kBlock; ++row) {
        auto rowBits = std::uint32_t((pending >> (row * kBlock)) & 0xFFu);
        if (rowBits == 0) continue;
        // A row's texels are contiguous (single-sampled): one copy when all
        // eight are written, else texel by texel.
        std::byte* rowTexels = target.texel(std::uint32_t(bx), std::uint32_t(by + row));
        if (rowBits == 0xFFu) {
            std::memcpy(rowTexels, &codes[row * kBlock], 4 * kBlock);
            continue;
        }
        for (; rowBits != 0; rowBits &= rowBits - 1) {
            const int column = std::countr_zero(rowBits);
            std::memcpy(rowTexels + 4 * column, &codes[row * kBlock + column], 4);
        }
    }
}

}  // namespace tessera::detail
