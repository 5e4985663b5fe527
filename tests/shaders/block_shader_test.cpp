// The block-shader entry point (shaders/block_shader.h) against the per-pixel oracle: random
// draws of shaders that have both entry points, rendered with SIMD blocks (the lean path calls
// shadeBlock) and without (every pixel through operator()), must give the same bytes, the same
// counters and the same per-pixel invocation counts.
#include <doctest/doctest.h>

#include <cstring>
#include <random>
#include <vector>

#include <tessera/raster/device.h>
#include <tessera/shaders/block_shader.h>

#include "support/surface_compare.h"
#include "support/test_draw.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::shaders_block_shader_test {

using namespace tessera;
using namespace tessera::test;

namespace {

// Target 0: the colour. Target 1: SV_Position (x, y, z, w), with w negated on back faces.
struct PositionPS {
    using Varyings = ColorVaryings;
    static constexpr int kTargetCount = 2;
    void operator()(const PixelInput<ColorVaryings>& in, PixelOutput<2>& out) const {
        out.target[0] = in.varyings.color;
        out.target[1] = glm::vec4(in.posWindow.x, in.posWindow.y, in.posWindow.z, in.isFrontFace ? in.posWindow.w : -in.posWindow.w);
    }
    void shadeBlock(const BlockInput& in, BlockOutput<2>& out) const {
        for (int c = 0; c < 4; ++c)
            std::memcpy(out.target[0] + c * kBlockLanes, in.varyings + c * kBlockLanes, kBlockLanes * sizeof(float));
        float* pos = out.target[1];
        for (int l = 0; l < kBlockLanes; ++l) {
            pos[l] = blockPosX(in, l);
            pos[kBlockLanes + l] = blockPosY(in, l);
            pos[2 * kBlockLanes + l] = in.zWindow[l];
            pos[3 * kBlockLanes + l] = in.isFrontFace ? in.wClip[l] : -in.wClip[l];
        }
    }
};

// Discards where alpha > 0.8 and writes coarse derivatives and arithmetic on the varyings.
struct DerivativePS {
    using Varyings = ColorVaryings;
    static constexpr int kTargetCount = 2;
    static constexpr bool kMayDiscard = true;
    void operator()(const PixelInput<ColorVaryings>& in, PixelOutput<2>& out) const {
        if (in.varyings.color.w > 0.8f) out.discard();
        const glm::vec4& c = in.varyings.color;
        out.target[0] = glm::vec4(c.x * c.y, c.y + c.z, c.z - c.x, c.w);
        out.target[1] = glm::vec4(in.ddx.color.x * 64.0f, in.ddy.color.y * 64.0f, in.ddx.color.w, in.ddy.color.z);
    }
    void shadeBlock(const BlockInput& in, BlockOutput<2>& out) const {
        const float* r = in.varyings;
        const float* g = r + kBlockLanes;
        const float* b = g + kBlockLanes;
        const float* a = b + kBlockLanes;
        float* o0 = out.target[0];
        float* o1 = out.target[1];
        for (int l = 0; l < kBlockLanes; ++l) {
            if (a[l] > 0.8f) out.discarded |= std::uint64_t(1) << l;
            o0[l] = r[l] * g[l];
            o0[kBlockLanes + l] = g[l] + b[l];
            o0[2 * kBlockLanes + l] = b[l] - r[l];
            o0[3 * kBlockLanes + l] = a[l];
            o1[l] = blockDdx(in, 0, l) * 64.0f;
            o1[kBlockLanes + l] = blockDdy(in, 1, l) * 64.0f;
            o1[2 * kBlockLanes + l] = blockDdx(in, 3, l);
            o1[3 * kBlockLanes + l] = blockDdy(in, 2, l);
        }
        out.discarded &= in.shade;
    }
};

static_assert(BlockPixelShader<PositionPS> && BlockPixelShader<DerivativePS>);
static_assert(!BlockPixelShader<ColorPS>, "a shader without shadeBlock keeps the per-pixel call");

struct Rendered {
    Surface color, extra, depth;
    DrawStats stats;
    ShadeCounts counts;
};

constexpr std::uint32_t kW = 141, kH = 99;  // odd: partial blocks and quads at the edges

Rendered renderRandomDraws(bool simd, Format colorFormat, Format depthFormat, std::uint32_t seed) {
    Rendered f{Surface({kW, kH, colorFormat, 1}), Surface({kW, kH, Format::R32G32B32A32_FLOAT, 1}),
               Surface({kW, kH, depthFormat, 1}), {}, ShadeCounts(kW, kH)};
    f.color.clearColor(glm::vec4(0.1f, 0.2f, 0.3f, 0.5f));
    f.extra.clearColor(glm::vec4(0.0f));
    f.depth.clearDepthStencil(true, 0.6f, true, 3);
    DeviceConfig config{16, 2};
    config.simdBlocks = simd;
    Device dev(config);
    dev.setShadeCounts(&f.counts);
    RenderTargets rt;
    rt.colors[0] = &f.color;
    rt.colors[1] = &f.extra;
    rt.depthStencil = &f.depth;
    std::mt19937 rng(seed);
    for (int draw = 0; draw < 16; ++draw) {
        const std::vector<ColorVertex> verts = randomLargeTriangles(rng, 8);
        DrawState st = cyclingDepthState(draw, f.color);  // its stencil draws take no block shader
        st.blend.renderTarget[0] = draw % 3 == 1 ? kAlphaBlend : RenderTargetBlendDesc{};
        st.blend.renderTarget[1] = draw % 4 == 2 ? kAdditiveBlend : RenderTargetBlendDesc{};
        st.blend.independentBlendEnable = true;
        st.rasterizer.scissorEnable = draw == 10;
        st.scissor = {13, 7, 120, 90};
        const std::span<const ColorVertex> vs(verts);
        f.stats += draw % 2 == 0 ? dev.draw(st, rt, vs, {}, PassThroughVS{}, PositionPS{})
                                 : dev.draw(st, rt, vs, {}, PassThroughVS{}, DerivativePS{});
    }
    return f;
}

} // namespace

TEST_CASE("block shaders give the per-pixel shader's bytes, counters and invocations: formats, depth, blend, discard, derivatives") {
    struct Case {
        Format color, depth;
    };
    const Case cases[] = {{Format::R8G8B8A8_UNORM, Format::D32_FLOAT},
                          {Format::R8G8B8A8_UNORM, Format::D24_UNORM_S8_UINT},
                          {Format::R8G8B8A8_UNORM_SRGB, Format::D32_FLOAT_S8X24_UINT},
                          {Format::R16G16B16A16_FLOAT, Format::D24_UNORM_S8_UINT}};
    for (const Case& k : cases) {
        for (const std::uint32_t seed : {1u, 2u, 3u}) {
            INFO("colour " << formatInfo(k.color).name << ", depth " << formatInfo(k.depth).name << ", seed " << seed);
            const Rendered block = renderRandomDraws(true, k.color, k.depth, seed);
            const Rendered pixel = renderRandomDraws(false, k.color, k.depth, seed);
            CHECK(sameBytes(block.color, pixel.color));
            CHECK(sameBytes(block.extra, pixel.extra));
            CHECK(sameBytes(block.depth, pixel.depth));
            CHECK(block.stats.quads == pixel.stats.quads);
            CHECK(block.stats.psInvocations == pixel.stats.psInvocations);
            CHECK(block.stats.samplesPassed == pixel.stats.samplesPassed);
            CHECK(block.counts.invocations == pixel.counts.invocations);
            // The comparison covers the block entry point, and only it differs between the two.
            CHECK(pixel.stats.blockShaderCalls == 0);
            CHECK(block.stats.blockShaderCalls > 100);
            CHECK(block.stats.blockShaderCalls <= block.stats.leanBlocks);
        }
    }
}

TEST_CASE("block derivative helpers take the quad's top row and left column, as the per-pixel path does") {
    // Varying 0 = 100 * row + column at each lane, varying 1 = its square: the derivative of a
    // lane is its quad's top-left neighbour difference, the same for all four lanes of the quad.
    std::vector<float> varyings(2 * kBlockLanes);
    for (int l = 0; l < kBlockLanes; ++l) {
        const float v = float(100 * (l / kBlockSide) + l % kBlockSide);
        varyings[std::size_t(l)] = v;
        varyings[std::size_t(kBlockLanes + l)] = v * v;
    }
    const BlockInput in{16, 24, ~std::uint64_t(0), varyings.data(), nullptr, nullptr, true};
    for (int l = 0; l < kBlockLanes; ++l) {
        INFO("lane " << l);
        const int row = l / kBlockSide, col = l % kBlockSide;
        const float tl = float(100 * (row & ~1) + (col & ~1));
        CHECK(blockDdx(in, 0, l) == 1.0f);
        CHECK(blockDdy(in, 0, l) == 100.0f);
        CHECK(blockDdx(in, 1, l) == (tl + 1.0f) * (tl + 1.0f) - tl * tl);
        CHECK(blockDdy(in, 1, l) == (tl + 100.0f) * (tl + 100.0f) - tl * tl);
        CHECK(blockPosX(in, l) == float(16 + col) + 0.5f);
        CHECK(blockPosY(in, l) == float(24 + row) + 0.5f);
    }
}

} // namespace tessera_test::shaders_block_shader_test
