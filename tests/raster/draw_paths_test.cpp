// DrawStats::paths: each draw names the pipeline path the rasterizer specialised for, so that
// `tessera render --stats` shows what a frame modelled: no depth work without a depth buffer,
// no blend without blending, the sample count, exact or fast raster.
#include <doctest/doctest.h>

#include <cstring>
#include <limits>
#include <vector>

#include <tessera/raster/device.h>

#include "support/test_draw.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::raster_draw_paths_test {

using namespace tessera;

namespace {
DrawStats drawOne(Format depthFormat, bool blend, std::uint32_t samples, Precision precision, bool stencil = false) {
    Surface color({16, 16, Format::R8G8B8A8_UNORM, samples});
    Surface depth({16, 16, depthFormat == Format::Unknown ? Format::D32_FLOAT : depthFormat, samples});
    const std::vector<test::ColorVertex> tri{{test::windowToClip(1, 1, 16, 16)}, {test::windowToClip(15, 1, 16, 16)},
                                             {test::windowToClip(1, 15, 16, 16)}};
    DrawState st;
    st.viewport = fullViewport(color);
    st.rasterizer.cullMode = CullMode::None;
    st.precision = precision;
    if (blend) st.blend.renderTarget[0] = kAlphaBlend;
    st.depthStencil.stencilEnable = stencil;
    RenderTargets rt;
    rt.colors[0] = &color;
    if (depthFormat != Format::Unknown) rt.depthStencil = &depth;
    Device device(DeviceConfig{16, 1});
    return device.draw(st, rt, std::span<const test::ColorVertex>(tri), {}, test::PassThroughVS{}, test::ColorPS{});
}
} // namespace

TEST_CASE("draw paths: each draw reports the path its state requires") {
    CHECK(drawOne(Format::Unknown, false, 1, Precision::Exact).paths == std::map<std::string, std::uint64_t>{{"ps depth:Off 1x raster:exact", 1}});
    CHECK(drawOne(Format::D32_FLOAT, false, 1, Precision::Exact).paths.count("ps depth:D32 1x raster:exact") == 1);
    CHECK(drawOne(Format::D24_UNORM_S8_UINT, true, 1, Precision::Exact).paths.count("ps depth:D24 1x blend raster:exact") == 1);
    CHECK(drawOne(Format::D24_UNORM_S8_UINT, false, 4, Precision::Fast, true).paths.count("ps depth:General 4x raster:fast") == 1);
    DrawStats sum = drawOne(Format::D32_FLOAT, false, 1, Precision::Exact);
    sum += drawOne(Format::D32_FLOAT, false, 1, Precision::Exact);
    sum += drawOne(Format::Unknown, false, 1, Precision::Exact);
    CHECK(sum.paths["ps depth:D32 1x raster:exact"] == 2);
    CHECK(sum.paths["ps depth:Off 1x raster:exact"] == 1);
}

TEST_CASE("SetupStats::touched holds every pixel a draw wrote, and is empty when nothing survived setup") {
    Surface color({40, 30, Format::R32G32B32A32_FLOAT, 1});
    color.clearColor(glm::vec4(0.0f));
    std::vector<test::ColorVertex> tris;
    for (const glm::vec2 p : {glm::vec2(5, 4), glm::vec2(22, 9)})
        for (const glm::vec2 d : {glm::vec2(0, 0), glm::vec2(6.3f, 0.2f), glm::vec2(1.1f, 5.7f)})
            tris.push_back({test::windowToClip(p.x + d.x, p.y + d.y, 40, 30), glm::vec4(1.0f)});
    DrawState st = test::countingState(color);
    RenderTargets rt;
    rt.colors[0] = &color;
    Device device(DeviceConfig{16, 2});
    const DrawStats s = device.draw(st, rt, std::span<const test::ColorVertex>(tris), {}, test::PassThroughVS{}, test::ColorPS{});
    const PixelRect r = s.setup.touched;
    REQUIRE_FALSE(r.empty());
    int written = 0;
    bool inside = true;
    for (std::uint32_t y = 0; y < 30; ++y)
        for (std::uint32_t x = 0; x < 40; ++x)
            if (color.load(x, y).x != 0.0f) {
                ++written;
                inside = inside && std::int32_t(x) >= r.minX && std::int32_t(x) < r.maxX && std::int32_t(y) >= r.minY &&
                         std::int32_t(y) < r.maxY;
            }
    CHECK(written > 20);
    CHECK(inside);
    CHECK(r.minX >= 4);   // bounded by the triangles, not the target: x from 5, y from 4
    CHECK(r.maxX <= 30);  // up to 22 + 6.3 (+ a pixel of reach)
    // A triangle entirely off the target is dropped in setup: nothing touched.
    const std::vector<test::ColorVertex> off{{test::windowToClip(-30, -30, 40, 30)}, {test::windowToClip(-20, -30, 40, 30)},
                                             {test::windowToClip(-30, -20, 40, 30)}};
    CHECK(device.draw(st, rt, std::span<const test::ColorVertex>(off), {}, test::PassThroughVS{}, test::ColorPS{}).setup.touched.empty());
}


namespace {
// Binds no colour target and writes nothing: the depth/stencil test runs with the vertex
// shader's varyings interpolated, as a draw with a pixel shader runs it.
struct NoTargetsPS {
    using Varyings = test::ColorVaryings;
    static constexpr int kTargetCount = 0;
    void operator()(const PixelInput<test::ColorVaryings>&, PixelOutput<0>&) const {}
};
} // namespace

// A draw without a pixel shader runs its vertex shader for the position alone (detail::PositionOnlyVS)
// and sets up no varyings. The depth and stencil it leaves, and its setup counters, must be those
// of the same draw with varyings: random triangles, some through the near plane (clipped, so new
// vertices are interpolated), some far outside the guard band, some with NaN colours, on D24S8
// with a depth test and stencil increments on pass and decrements on depth failure, at 1 and 4
// samples.
TEST_CASE("draw paths: a draw without a pixel shader sets up positions only, with the same depth, stencil and counters") {
    constexpr std::uint32_t kSize = 48;  // px
    std::uint32_t state = 7u;  // a fixed LCG: the same triangles every run
    auto uniform = [&](float lo, float hi) {
        state = state * 1664525u + 1013904223u;
        return lo + (hi - lo) * float(state >> 8) / float(1u << 24);
    };
    std::vector<test::ColorVertex> tris;
    for (int t = 0; t < 300; ++t)
        for (int k = 0; k < 3; ++k) {
            const float w = t % 5 == 0 ? uniform(-0.5f, 2.0f) : uniform(0.5f, 2.0f);  // every fifth may cross w = 0
            const float reach = t % 7 == 0 ? 4000.0f : 1.3f;  // every seventh reaches past the guard band
            test::ColorVertex v;
            v.posClip = glm::vec4(uniform(-reach, reach) * w, uniform(-reach, reach) * w, uniform(-0.2f, 1.1f) * w, w);
            v.color = t % 11 == 0 ? glm::vec4(std::numeric_limits<float>::quiet_NaN()) : glm::vec4(uniform(0.0f, 1.0f));
            tris.push_back(v);
        }
    for (const std::uint32_t samples : {1u, 4u}) {
        DrawState st;
        st.rasterizer.cullMode = CullMode::None;
        st.depthStencil.depthEnable = true;
        st.depthStencil.depthFunc = ComparisonFunc::Less;
        st.depthStencil.stencilEnable = true;
        const StencilFaceDesc face{StencilOp::Keep, StencilOp::Decr, StencilOp::Incr, ComparisonFunc::Always};
        st.depthStencil.frontFace = face;
        st.depthStencil.backFace = face;
        Surface withVaryings({kSize, kSize, Format::D24_UNORM_S8_UINT, samples});
        Surface positionsOnly({kSize, kSize, Format::D24_UNORM_S8_UINT, samples});
        st.viewport = fullViewport(withVaryings);
        DrawStats stats[2];
        for (int path = 0; path < 2; ++path) {
            Surface& depth = path == 0 ? withVaryings : positionsOnly;
            depth.clearDepthStencil(true, 1.0f, true, 128);
            RenderTargets rt;
            rt.depthStencil = &depth;
            Device device(DeviceConfig{16, 2});
            const std::span<const test::ColorVertex> vertices(tris);
            stats[path] = path == 0 ? device.draw(st, rt, vertices, {}, test::PassThroughVS{}, NoTargetsPS{})
                                    : device.draw(st, rt, vertices, {}, test::PassThroughVS{}, NoPixelShader{});
        }
        INFO(samples << " samples");
        CHECK(stats[0].setup.clipped > 0);
        CHECK(stats[0].setup.culledNonFinite + stats[0].setup.culledDegenerate < stats[0].setup.trianglesIn);
        CHECK(stats[0].samplesPassed > 0);
        CHECK(std::memcmp(withVaryings.bytes().data(), positionsOnly.bytes().data(), withVaryings.bytes().size()) == 0);
        CHECK(stats[1].setup.trianglesIn == stats[0].setup.trianglesIn);
        CHECK(stats[1].setup.trianglesOut == stats[0].setup.trianglesOut);
        CHECK(stats[1].setup.clipped == stats[0].setup.clipped);
        CHECK(stats[1].setup.culledNonFinite == stats[0].setup.culledNonFinite);
        CHECK(stats[1].setup.culledDegenerate == stats[0].setup.culledDegenerate);
        CHECK(stats[1].samplesPassed == stats[0].samplesPassed);
        CHECK(stats[1].quads == stats[0].quads);
        CHECK(stats[1].binnedTileTriangles == stats[0].binnedTileTriangles);
    }
}

} // namespace tessera_test::raster_draw_paths_test
