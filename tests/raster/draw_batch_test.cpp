// DrawBatch (raster/draw_batch.h) against the draws it bins, run one at a time by Device::draw:
// random frames of large and small, indexed and listed triangles through every depth, stencil,
// blend and discard path, single-sampled and 4x, at 1, 2 and 7 threads and tiles of 8, 16 and 64
// px, must leave the same bytes in every target and the same counters. Also the batch's own
// contract: what it runs at once, what it discards, how it fails.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <tessera/raster/draw_batch.h>

#include "support/surface_compare.h"
#include "support/test_draw.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::raster_draw_batch_test {

using namespace tessera;
using namespace tessera::test;

namespace {

// Scales the colour by a factor held in data the batch keeps (DrawBatch::keep), discards some
// pixels, and writes derivatives, SV_Position and the facing into a second target.
struct Tint {
    glm::vec4 scale;
};
struct KeptDataPS {
    using Varyings = ColorVaryings;
    static constexpr int kTargetCount = 2;
    static constexpr bool kMayDiscard = true;
    const Tint* tint = nullptr;
    void operator()(const PixelInput<ColorVaryings>& in, PixelOutput<2>& out) const {
        if (in.varyings.color.y > 0.9f) out.discard();
        out.target[0] = in.varyings.color * tint->scale;
        out.target[1] = glm::vec4(in.posWindow.z, in.posWindow.w, in.ddx.color.x * 64.0f, in.isFrontFace ? 1.0f : -1.0f);
    }
};
struct DepthOutPS {  // writes SV_Depth
    using Varyings = ColorVaryings;
    static constexpr int kTargetCount = 1;
    static constexpr bool kWritesDepth = true;
    void operator()(const PixelInput<ColorVaryings>& in, PixelOutput<1>& out) const {
        out.target[0] = in.varyings.color;
        out.depth = in.varyings.color.z;
    }
};
struct PerSamplePS {  // runs per sample (DrawStats::psPerSample)
    using Varyings = ColorVaryings;
    static constexpr int kTargetCount = 1;
    static constexpr bool kPerSample = true;
    void operator()(const PixelInput<ColorVaryings>& in, PixelOutput<1>& out) const {
        out.target[0] = in.varyings.color * (1.0f + 0.25f * float(in.sampleIndex));
    }
};

struct Frame {
    Surface color, extra, depth;
    DrawStats stats;
};

constexpr std::uint32_t kW = 141, kH = 99;  // odd: partial tiles, blocks and quads at the edges

Frame makeFrame(std::uint32_t samples) {
    Frame f{Surface({kW, kH, Format::R8G8B8A8_UNORM, samples}), Surface({kW, kH, Format::R32G32B32A32_FLOAT, samples}),
            Surface({kW, kH, Format::D24_UNORM_S8_UINT, samples}), {}};
    f.color.clearColor(glm::vec4(0.1f, 0.2f, 0.3f, 0.5f));
    f.extra.clearColor(glm::vec4(0.0f));
    f.depth.clearDepthStencil(true, 0.6f, true, 3);
    return f;
}

// The draws of one random frame, issued through `issue(state, vertices, indices, shaderKind)`.
template <class Issue>
void randomDraws(std::uint32_t seed, std::uint32_t samples, Issue&& issue) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.3f, 1.3f), zr(-0.2f, 1.2f), wr(0.5f, 2.5f), c(-0.1f, 1.1f), small(-0.04f, 0.04f);
    for (int draw = 0; draw < 20; ++draw) {
        std::vector<ColorVertex> verts;
        std::vector<std::uint32_t> indices;
        if (draw % 2 == 0) {  // a few large triangles: whole 8x8 blocks, many tiles
            for (int i = 0; i < 3 * 6; ++i) {
                const float w = wr(rng);
                verts.push_back({glm::vec4(u(rng) * w, u(rng) * w, zr(rng) * w, w), glm::vec4(c(rng), c(rng), c(rng), c(rng))});
            }
        } else {  // many small indexed triangles (a few px each), one index past the vertex count
            for (int i = 0; i < 300; ++i) {
                const float x = u(rng), y = u(rng), z = zr(rng);
                for (int k = 0; k < 3; ++k)
                    verts.push_back({glm::vec4(x + small(rng), y + small(rng), z, 1.0f), glm::vec4(c(rng), c(rng), c(rng), c(rng))});
            }
            for (std::uint32_t i = 0; i < verts.size(); ++i) indices.push_back(i);
            indices[indices.size() / 2] = std::uint32_t(verts.size()) + 5;  // fetches Vertex{}
        }
        DrawState st;
        st.viewport = Viewport{0.0f, 0.0f, float(kW), float(kH), draw % 5 == 2 ? 0.2f : 0.0f, draw % 5 == 3 ? 0.8f : 1.0f};
        st.rasterizer.cullMode = CullMode(1 + draw % 3);
        st.depthStencil.depthEnable = draw % 6 != 5;
        st.depthStencil.depthWriteEnable = draw % 4 != 3;
        // Draw 0 LessEqual (opaque), draw 1 Always (alpha-blended, SV_Depth) over it: the first two
        // draws overlap in an order-dependent way; Never at draws 4 and 12.
        st.depthStencil.depthFunc = ComparisonFunc(1 + (draw * 3 + 4) % 8);
        st.depthStencil.stencilEnable = draw % 3 == 1;
        st.depthStencil.frontFace = {StencilOp::IncrSat, StencilOp::Invert, StencilOp::Incr, ComparisonFunc::GreaterEqual};
        st.depthStencil.backFace = {StencilOp::Zero, StencilOp::DecrSat, StencilOp::Replace, ComparisonFunc::NotEqual};
        st.stencilRef = std::uint8_t(draw * 17);
        st.precision = draw % 8 == 4 ? Precision::Fast : Precision::Exact;
        st.blend.independentBlendEnable = true;
        st.blend.renderTarget[0] = draw % 3 == 0 ? RenderTargetBlendDesc{} : (draw % 3 == 1 ? kAlphaBlend : kAdditiveBlend);
        st.blend.renderTarget[1].renderTargetWriteMask = std::uint8_t(1 + draw % 15);
        st.rasterizer.scissorEnable = draw == 7;
        st.scissor = {13, 7, 120, 90};
        // Shaders: 0 kept data + discard, 1 SV_Depth, 2 none (depth/stencil only), 3 colour (per
        // sample when multisampled).
        const int kind = draw % 4;
        issue(st, verts, indices, kind, samples);
    }
}

// The random frame drawn one draw at a time (binned = false) or through one DrawBatch.
Frame render(bool binned, std::uint32_t threads, std::uint32_t tileSize, std::uint32_t samples, std::uint32_t seed) {
    Frame f = makeFrame(samples);
    DeviceConfig config{tileSize, threads};
    Device dev(config);
    RenderTargets rt;
    rt.colors[0] = &f.color;
    rt.colors[1] = &f.extra;
    rt.depthStencil = &f.depth;
    RenderTargets rtOne = rt;
    rtOne.colors[1] = nullptr;
    DrawBatch batch(dev);
    // Vertex data lives until the batch runs; shaders, states and tints are this loop's locals.
    std::vector<std::vector<ColorVertex>> keptVertices;
    std::vector<std::vector<std::uint32_t>> keptIndices;
    randomDraws(seed, samples, [&](const DrawState& st, std::vector<ColorVertex>& verts, std::vector<std::uint32_t>& indices,
                                   int kind, std::uint32_t sampleCount) {
        keptVertices.push_back(std::move(verts));
        keptIndices.push_back(std::move(indices));
        const std::span<const ColorVertex> v(keptVertices.back());
        const std::span<const std::uint32_t> idx(keptIndices.back());
        auto draw = [&](const RenderTargets& targets, const auto& ps) {
            if (binned) batch.draw(st, targets, v, idx, PassThroughVS{}, ps);
            else f.stats += dev.draw(st, targets, v, idx, PassThroughVS{}, ps);
        };
        switch (kind) {
        case 0: {
            const Tint tint{glm::vec4(0.5f + 0.1f * float(keptVertices.size() % 5), 1.0f, 0.75f, 1.0f)};
            draw(rt, KeptDataPS{binned ? &batch.keep(tint) : &tint});
            break;
        }
        case 1: draw(rtOne, DepthOutPS{}); break;
        case 2: draw(rt, NoPixelShader{}); break;
        default:
            if (sampleCount > 1) draw(rtOne, PerSamplePS{});
            else draw(rtOne, ColorPS{});
            break;
        }
    });
    if (binned) {
        CHECK(batch.pending() == 20);
        f.stats += batch.run();
        CHECK(batch.pending() == 0);
    }
    return f;
}

void checkSameStats(const DrawStats& a, const DrawStats& b) {
    CHECK(a.setup.trianglesIn == b.setup.trianglesIn);
    CHECK(a.setup.trianglesOut == b.setup.trianglesOut);
    CHECK(a.setup.culledFacing == b.setup.culledFacing);
    CHECK(a.setup.clipped == b.setup.clipped);
    CHECK(a.binnedTileTriangles == b.binnedTileTriangles);
    CHECK(a.quads == b.quads);
    CHECK(a.psInvocations == b.psInvocations);
    CHECK(a.psPerSample == b.psPerSample);
    CHECK(a.samplesPassed == b.samplesPassed);
    CHECK(a.simdBlocks == b.simdBlocks);
    CHECK(a.leanBlocks == b.leanBlocks);
    CHECK(a.paths == b.paths);
}

} // namespace

TEST_CASE("draw batch: a binned frame equals its draws one at a time, byte for byte, at 1, 2 and 7 threads and tiles of 8, 16 and 64 px") {
    for (const std::uint32_t samples : {1u, 4u}) {
        for (const std::uint32_t seed : {1u, 2u}) {
            const Frame ref16 = render(false, 1, 16, samples, seed);
            // The frame exercises what it compares: stencil written, pixels discarded and shaded per sample.
            int stencilSet = 0;
            for (std::uint32_t y = 0; y < kH; ++y)
                for (std::uint32_t x = 0; x < kW; ++x) stencilSet += ref16.depth.loadStencil(x, y) != 3;
            CHECK(stencilSet > 500);
            CHECK(ref16.stats.psInvocations > 5000);
            CHECK(ref16.stats.binnedDraws == 0);
            if (samples > 1) CHECK(ref16.stats.psPerSample > 1000);
            if (samples == 1) CHECK(ref16.stats.leanBlocks > 20);
            for (const std::uint32_t tile : {8u, 16u, 64u}) {
                // Tiles cut triangles and blocks: binning and block counters are compared at the same tile size.
                const DrawStats refStats = tile == 16 ? ref16.stats : render(false, 1, tile, samples, seed).stats;
                for (const std::uint32_t threads : {1u, 2u, 7u}) {
                    INFO("samples " << samples << ", seed " << seed << ", threads " << threads << ", tile " << tile);
                    const Frame f = render(true, threads, tile, samples, seed);
                    CHECK(sameBytes(f.color, ref16.color));
                    CHECK(sameBytes(f.extra, ref16.extra));
                    CHECK(sameBytes(f.depth, ref16.depth));
                    // Every draw went through one run's shared tile lists.
                    CHECK(f.stats.binnedDraws == 20);
                    CHECK(f.stats.binnedRuns == 1);
                    checkSameStats(f.stats, refStats);
                }
            }
        }
    }
}

TEST_CASE("draw batch: draws it cannot bin run at once, in order: binPasses off, other target sizes") {
    Surface small({32, 32, Format::R8G8B8A8_UNORM, 1}), large({48, 32, Format::R8G8B8A8_UNORM, 1});
    std::vector<ColorVertex> tri{{glm::vec4(-1, -1, 0.5f, 1), glm::vec4(0.25f, 0, 0, 1)},
                                 {glm::vec4(-1, 3, 0.5f, 1), glm::vec4(0.25f, 0, 0, 1)},
                                 {glm::vec4(3, -1, 0.5f, 1), glm::vec4(0.25f, 0, 0, 1)}};  // covers the target
    for (const bool binPasses : {true, false}) {
        INFO("binPasses " << binPasses);
        small.clearColor(glm::vec4(0.0f));
        large.clearColor(glm::vec4(0.0f));
        DeviceConfig config{16, 2};
        config.binPasses = binPasses;
        Device dev(config);
        DrawBatch batch(dev);
        RenderTargets a, b;
        a.colors[0] = &small;
        b.colors[0] = &large;
        DrawState st = countingState(small);  // additive: every draw adds 0.25 to red
        DrawState stLarge = countingState(large);
        const std::span<const ColorVertex> v(tri);
        batch.draw(st, a, v, {}, PassThroughVS{}, ColorPS{});
        batch.draw(st, a, v, {}, PassThroughVS{}, ColorPS{});
        CHECK(batch.pending() == (binPasses ? 2u : 0u));
        batch.draw(stLarge, b, v, {}, PassThroughVS{}, ColorPS{});  // another grid: the two run first
        CHECK(batch.pending() == (binPasses ? 1u : 0u));
        CHECK(small.load(5, 5).x == doctest::Approx(0.5f).epsilon(0.01));
        batch.draw(st, a, v, {}, PassThroughVS{}, ColorPS{});
        const DrawStats s = batch.run();
        CHECK(small.load(31, 31).x == doctest::Approx(0.75f).epsilon(0.01));
        CHECK(large.load(47, 0).x == doctest::Approx(0.25f).epsilon(0.01));
        CHECK(s.psInvocations == 3 * 32 * 32 + 48 * 32);
        CHECK(s.binnedDraws == (binPasses ? 4u : 0u));
        CHECK(s.binnedRuns == (binPasses ? 3u : 0u));  // {2 small}, {1 large}, {1 small}
    }
}

// The deferred light loop's shape: per "light", a stencil clear (the first of all tiles, then only
// where drawn), a depth-only draw that replaces the stencil over a small quad, and an additive draw
// over a larger quad that passes only where the stencil holds the replaced value. A tile left
// uncleared after a draw keeps the previous light's value there and shades it again.
struct LightLoop {
    Surface color, depth;
    DrawStats stats;
    std::vector<glm::vec4> outer;  // each light's outer quad in window pixels: x0, y0, x1, y1
};

LightLoop lightLoop(int mode, std::uint32_t threads, std::uint32_t tileSize) {  // mode 0: whole clears, draws on the device; 1: batch; 2: batch, binPasses off
    constexpr std::uint32_t w = 77, h = 53;
    LightLoop f{Surface({w, h, Format::R32_FLOAT, 1}), Surface({w, h, Format::D24_UNORM_S8_UINT, 1}), {}, {}};
    f.color.clearColor(glm::vec4(0.0f));
    f.depth.clearDepthStencil(true, 1.0f, true, 2);  // the marked value everywhere: the first clear must be whole
    DeviceConfig config{tileSize, threads};
    config.binPasses = mode != 2;
    Device dev(config);
    DrawBatch batch(dev);
    RenderTargets depthOnly, shade;
    depthOnly.depthStencil = &f.depth;
    shade.depthStencil = &f.depth;
    shade.colors[0] = &f.color;
    constexpr std::uint8_t kClear = 1, kMarked = 2;
    DrawState mark = countingState(f.color);
    mark.depthStencil.stencilEnable = true;
    mark.depthStencil.frontFace.passOp = mark.depthStencil.backFace.passOp = StencilOp::Replace;
    mark.stencilRef = kMarked;
    DrawState lit = countingState(f.color);
    lit.depthStencil.stencilEnable = true;
    lit.depthStencil.frontFace.func = lit.depthStencil.backFace.func = ComparisonFunc::Equal;
    lit.stencilRef = kMarked;
    std::vector<std::vector<ColorVertex>> quads;  // alive until the batch runs
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> pos(-10.0f, float(w) + 10.0f), size(2.0f, 14.0f);
    const auto quad = [&](float x0, float y0, float x1, float y1) {
        const glm::vec4 c(1.0f);
        quads.push_back({{windowToClip(x0, y0, w, h), c}, {windowToClip(x1, y0, w, h), c}, {windowToClip(x0, y1, w, h), c},
                         {windowToClip(x1, y0, w, h), c}, {windowToClip(x1, y1, w, h), c}, {windowToClip(x0, y1, w, h), c}});
        return std::span<const ColorVertex>(quads.back());
    };
    for (int light = 0; light < 24; ++light) {
        const float x = pos(rng), y = pos(rng), r = size(rng);
        const std::span<const ColorVertex> inner = quad(x - r, y - r, x + r, y + r);
        const std::span<const ColorVertex> outer = quad(x - 2.0f * r, y - 2.0f * r, x + 2.0f * r, y + 2.0f * r);
        f.outer.emplace_back(x - 2.0f * r, y - 2.0f * r, x + 2.0f * r, y + 2.0f * r);
        if (mode == 0) {
            f.depth.clearDepthStencil(false, 0.0f, true, kClear);
            f.stats += dev.draw(mark, depthOnly, inner, {}, PassThroughVS{}, NoPixelShader{});
            f.stats += dev.draw(lit, shade, outer, {}, PassThroughVS{}, ColorPS{});
        } else {
            batch.clearDepthStencil(f.depth, false, 0.0f, true, kClear, 0xFF, light > 0);
            batch.draw(mark, depthOnly, inner, {}, PassThroughVS{}, NoPixelShader{});
            batch.draw(lit, shade, outer, {}, PassThroughVS{}, ColorPS{});
        }
    }
    if (mode != 0) f.stats += batch.run();
    return f;
}

TEST_CASE("draw batch: recorded stencil clears keep their place between draws, and clearing only drawn tiles leaves the bytes of whole clears") {
    const LightLoop ref = lightLoop(0, 1, 16);
    // The loop exercises what it compares: lights overlap (a pixel shaded twice) and some are shaded.
    float maxCount = 0.0f;
    int shaded = 0;
    for (std::uint32_t y = 0; y < 53; ++y)
        for (std::uint32_t x = 0; x < 77; ++x) {
            maxCount = std::max(maxCount, ref.color.load(x, y).x);
            shaded += ref.color.load(x, y).x > 0.0f;
        }
    CHECK(maxCount >= 2.0f);
    CHECK(shaded > 300);
    for (const std::uint32_t tile : {8u, 16u, 64u}) {
        for (const std::uint32_t threads : {1u, 2u, 7u}) {
            for (const int mode : {1, 2}) {
                INFO("tile " << tile << ", threads " << threads << (mode == 1 ? ", binned" : ", binPasses off"));
                const LightLoop f = lightLoop(mode, threads, tile);
                CHECK(sameBytes(f.color, ref.color));
                CHECK(sameBytes(f.depth, ref.depth));
                CHECK(f.stats.psInvocations == ref.stats.psInvocations);
                CHECK(f.stats.samplesPassed == ref.stats.samplesPassed);
                // Clears are not draws: 48 draws binned in one run.
                CHECK(f.stats.binnedDraws == (mode == 1 ? 48u : 0u));
                CHECK(f.stats.binnedRuns == (mode == 1 ? 1u : 0u));
                // The clears' work is bounded by the volumes, not the target: light 0 clears every
                // tile, light k > 0 the tiles light k - 1's quads were binned into. The outer quad
                // holds the inner one, and its triangles' bounds hold at least the tiles of the
                // pixels whose centres it covers and at most those of its extent grown by a pixel.
                const auto tiles = [&](std::int32_t x0, std::int32_t y0, std::int32_t x1, std::int32_t y1) -> std::uint64_t {
                    x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, 76), y1 = std::min(y1, 52);  // inclusive pixels
                    if (x0 > x1 || y0 > y1) return 0;
                    return std::uint64_t(x1 / std::int32_t(tile) - x0 / std::int32_t(tile) + 1) *
                           std::uint64_t(y1 / std::int32_t(tile) - y0 / std::int32_t(tile) + 1);
                };
                const std::uint64_t all = tiles(0, 0, 76, 52);
                std::uint64_t low = all, high = all;
                for (std::size_t k = 0; k + 1 < f.outer.size(); ++k) {
                    const glm::vec4 q = f.outer[k];
                    low += tiles(std::int32_t(std::ceil(q.x - 0.5f)), std::int32_t(std::ceil(q.y - 0.5f)),
                                 std::int32_t(std::floor(q.z - 0.5f)), std::int32_t(std::floor(q.w - 0.5f)));
                    high += tiles(std::int32_t(std::floor(q.x)) - 1, std::int32_t(std::floor(q.y)) - 1, std::int32_t(std::ceil(q.z)),
                                  std::int32_t(std::ceil(q.w)));
                }
                CHECK(f.stats.batchClearedTiles >= low);
                CHECK(f.stats.batchClearedTiles <= high);
                if (tile == 8) CHECK(high < 24 * all);  // here a clear of every tile per light would fail the bound
            }
            // Both batch modes clear the same tiles (draw by draw, as their bounding rectangle).
            CHECK(lightLoop(1, threads, tile).stats.batchClearedTiles == lightLoop(2, threads, tile).stats.batchClearedTiles);
        }
    }
}

TEST_CASE("draw batch: invalid state throws at draw() and records nothing, and a batch destroyed unrun writes nothing") {
    Surface target({16, 16, Format::R8G8B8A8_UNORM, 1});
    target.clearColor(glm::vec4(0.0f));
    Device dev(DeviceConfig{8, 2});
    std::vector<ColorVertex> tri{{glm::vec4(-1, -1, 0.5f, 1), glm::vec4(1)},
                                 {glm::vec4(-1, 3, 0.5f, 1), glm::vec4(1)},
                                 {glm::vec4(3, -1, 0.5f, 1), glm::vec4(1)}};
    RenderTargets rt;
    rt.colors[0] = &target;
    const std::span<const ColorVertex> v(tri);
    {
        DrawBatch batch(dev);
        DrawState st = countingState(target);
        batch.draw(st, rt, v, {}, PassThroughVS{}, ColorPS{});
        st.viewport.width = 0.0f;
        CHECK_THROWS_WITH_AS(batch.draw(st, rt, v, {}, PassThroughVS{}, ColorPS{}), doctest::Contains("viewport size"),
                             std::invalid_argument);
        CHECK_THROWS_AS(batch.draw(countingState(target), rt, v.first(2), {}, PassThroughVS{}, ColorPS{}), std::invalid_argument);
        CHECK(batch.pending() == 1);
    }  // destroyed with one draw recorded: discarded
    CHECK(target.load(3, 3) == glm::vec4(0.0f));
    // The device is still usable, and its pooled scratch serves the next batch.
    DrawBatch again(dev);
    again.draw(countingState(target), rt, v, {}, PassThroughVS{}, ColorPS{});
    const DrawStats s = again.run();
    CHECK(s.psInvocations == 256);
    CHECK(target.load(3, 3).x == 1.0f);
}

} // namespace tessera_test::raster_draw_batch_test
