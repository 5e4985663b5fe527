// Pipeline behaviour at the pixel level: MSAA sample positions, perspective-correct
// interpolation, viewport depth mapping and depth clamp, early depth/stencil with discard,
// occlusion queries, scissor, SV_Depth output, facing, the guard band, bad input, and a device's
// reuse of draw storage.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include <tessera/raster/sample_pattern.h>

#include "support/surface_compare.h"
#include "support/test_draw.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::raster_pipeline_test {

using namespace tessera;
using namespace tessera::test;

namespace {

RenderTargets colorDepth(Surface* color, Surface* depth) {
    RenderTargets rt;
    rt.colors[0] = color;
    rt.depthStencil = depth;
    return rt;
}

std::vector<ColorVertex> quad(float x0, float y0, float x1, float y1, float w, float h, float z, glm::vec4 col = glm::vec4(1)) {
    const glm::vec4 a = windowToClip(x0, y0, w, h, z), b = windowToClip(x1, y0, w, h, z), c = windowToClip(x1, y1, w, h, z),
                    d = windowToClip(x0, y1, w, h, z);
    return {{a, col}, {b, col}, {c, col}, {a, col}, {c, col}, {d, col}};
}

template <class PS = NoPixelShader>
DrawStats drawList(Device& dev, const DrawState& st, const RenderTargets& rt, const std::vector<ColorVertex>& v,
                   const PS& ps = {}, OcclusionQuery* query = nullptr) {
    return dev.draw(st, rt, std::span<const ColorVertex>(v), {}, PassThroughVS{}, ps, query);
}

} // namespace

TEST_CASE("MSAA: coverage is tested at the D3D11 standard sample positions") {
    Device dev(DeviceConfig{16, 2});
    for (const std::uint32_t samples : {2u, 4u, 8u}) {
        Surface depth(SurfaceDesc{32, 8, Format::D32_FLOAT, samples});
        depth.clearDepthStencil(true, 1.0f, false, 0);
        DrawState st;
        st.viewport = fullViewport(depth);
        st.rasterizer.cullMode = CullMode::None;
        st.depthStencil.depthFunc = ComparisonFunc::Always;
        // For k = -7..7, a rectangle whose left edge lies k/16 px right of the centre of pixel
        // column c = 2(k+7)+1 and whose right edge is at c + 1: sample s of column c is
        // covered iff its x offset (1/16 px) >= k, since left edges are inclusive.
        std::vector<ColorVertex> v;
        for (int k = -7; k <= 7; ++k) {
            const float col = float(2 * (k + 7));
            const auto q = quad(col + 0.5f + float(k) / 16.0f + 1.0f, 0.0f, col + 2.0f, 8.0f, 32.0f, 8.0f, 0.25f);
            v.insert(v.end(), q.begin(), q.end());
        }
        drawList(dev, st, colorDepth(nullptr, &depth), v);
        const auto pattern = standardSamplePattern(samples);
        int wrong = 0;
        for (int k = -7; k <= 7; ++k) {
            const std::uint32_t x = std::uint32_t(2 * (k + 7) + 1);
            for (std::uint32_t s = 0; s < samples; ++s) {
                const bool want = pattern[s].x >= k;
                const bool got = depth.loadDepth(x, 3, s) == 0.25f;
                wrong += want != got;
            }
        }
        INFO(samples << " samples");
        CHECK(wrong == 0);
    }
}

struct UvVaryings {
    float u;
};
struct UvVertex {
    glm::vec4 posClip;
    float u;
};
struct UvVS {
    using Varyings = UvVaryings;
    VertexOutput<UvVaryings> operator()(const UvVertex& v) const { return {v.posClip, {v.u}}; }
};
struct UvPS {
    using Varyings = UvVaryings;
    static constexpr int kTargetCount = 1;
    void operator()(const PixelInput<UvVaryings>& in, PixelOutput<1>& out) const {
        out.target[0] = glm::vec4(in.varyings.u, in.posWindow.w, in.ddx.u, in.ddy.u);
    }
};

TEST_CASE("attributes are perspective-correct at pixel centres, SV_Position.w is clip w") {
    // A triangle with clip w = 1, 4, 2 at its vertices. u/w and 1/w are affine in window
    // space, so the exact u at a pixel centre is (sum l_i u_i / w_i) / (sum l_i / w_i) with
    // window-space barycentrics l_i; computed here in double from the window positions.
    constexpr float W = 64, H = 64;
    const glm::vec2 pWin[3] = {{4.0f, 4.0f}, {60.0f, 10.0f}, {12.0f, 58.0f}};
    const float w[3] = {1.0f, 4.0f, 2.0f}, u[3] = {0.0f, 1.0f, 0.5f};
    std::vector<UvVertex> v;
    for (int i = 0; i < 3; ++i) v.push_back({windowToClip(pWin[i].x, pWin[i].y, W, H, 0.5f, w[i]), u[i]});
    Surface target(SurfaceDesc{64, 64, Format::R32G32B32A32_FLOAT, 1});
    DrawState st;
    st.viewport = fullViewport(target);
    st.rasterizer.cullMode = CullMode::None;
    Device dev;
    RenderTargets rt;
    rt.colors[0] = &target;
    dev.draw(st, rt, std::span<const UvVertex>(v), {}, UvVS{}, UvPS{});
    double maxErrU = 0, maxErrW = 0;
    int covered = 0;
    const double area = (double(pWin[1].x) - pWin[0].x) * (double(pWin[2].y) - pWin[0].y) -
                        (double(pWin[1].y) - pWin[0].y) * (double(pWin[2].x) - pWin[0].x);
    for (std::uint32_t y = 0; y < 64; ++y)
        for (std::uint32_t x = 0; x < 64; ++x) {
            const double px = x + 0.5, py = y + 0.5;
            double l[3];
            for (int i = 0; i < 3; ++i) {
                const glm::vec2 a = pWin[(i + 1) % 3], b = pWin[(i + 2) % 3];
                l[i] = ((double(b.x) - a.x) * (py - a.y) - (double(b.y) - a.y) * (px - a.x)) / area;
            }
            if (l[0] <= 1e-9 || l[1] <= 1e-9 || l[2] <= 1e-9) continue;  // skip edge pixels
            ++covered;
            const double den = l[0] / w[0] + l[1] / w[1] + l[2] / w[2];
            const double uExact = (l[0] * u[0] / w[0] + l[1] * u[1] / w[1] + l[2] * u[2] / w[2]) / den;
            const glm::vec4 got = target.load(x, y);
            maxErrU = std::max(maxErrU, std::fabs(got.x - uExact));
            maxErrW = std::max(maxErrW, std::fabs(got.y - 1.0 / den) / (1.0 / den));
        }
    CHECK(covered > 1000);
    // Tolerance: float barycentrics and float interpolation, a few ulp of values <= 4.
    CHECK(maxErrU < 2e-6);
    CHECK(maxErrW < 2e-6);
    // Coarse derivatives: ddx(u) of the quad at (20,20)..(21,21) equals u(21,20) - u(20,20).
    const glm::vec4 q = target.load(20, 20), r = target.load(21, 20), b = target.load(20, 21);
    CHECK(q.z == r.x - q.x);
    CHECK(q.w == b.x - q.x);
}

TEST_CASE("viewport depth range maps NDC z, depth clip off clamps instead of clipping") {
    Device dev(DeviceConfig{16, 1});
    Surface depth(SurfaceDesc{16, 16, Format::D32_FLOAT, 1});
    DrawState st;
    st.viewport = Viewport{0, 0, 16, 16, 0.2f, 0.6f};
    st.depthStencil.depthFunc = ComparisonFunc::Always;
    st.rasterizer.cullMode = CullMode::None;
    auto run = [&](float zNdc, bool clip) {
        depth.clearDepthStencil(true, 1.0f, false, 0);
        st.rasterizer.depthClipEnable = clip;
        drawList(dev, st, colorDepth(nullptr, &depth), quad(0, 0, 16, 16, 16, 16, zNdc));
        return depth.loadDepth(8, 8);
    };
    // z = 0.2 + 0.5 * (0.6 - 0.2) = 0.4 (float: 0.2f + 0.5f * 0.4f).
    CHECK(run(0.5f, true) == 0.2f + 0.5f * (0.6f - 0.2f));
    CHECK(run(-0.5f, true) == 1.0f);          // clipped away: depth untouched
    CHECK(run(-0.5f, false) == 0.2f);         // clamped to MinDepth
    CHECK(run(1.5f, true) == 1.0f);           // clipped by the far plane
    CHECK(run(1.5f, false) == 0.6f);          // clamped to MaxDepth
}

struct DiscardAllPS {
    using Varyings = ColorVaryings;
    static constexpr int kTargetCount = 1;
    static constexpr bool kMayDiscard = true;
    void operator()(const PixelInput<ColorVaryings>&, PixelOutput<1>& out) const { out.discard(); }
};

TEST_CASE("early depth/stencil never changes results: discard suppresses stencil ops, shaders skip only where safe") {
    Device dev(DeviceConfig{16, 2});
    Surface color(SurfaceDesc{16, 16, Format::R8G8B8A8_UNORM, 1});
    Surface ds(SurfaceDesc{16, 16, Format::D24_UNORM_S8_UINT, 1});
    DrawState st;
    st.viewport = fullViewport(color);
    st.rasterizer.cullMode = CullMode::None;
    st.depthStencil.stencilEnable = true;
    st.depthStencil.frontFace = {StencilOp::Keep, StencilOp::IncrSat, StencilOp::Keep, ComparisonFunc::Always};
    st.depthStencil.backFace = st.depthStencil.frontFace;
    ds.clearDepthStencil(true, 0.0f, true, 0);  // everything fails LESS
    // Discarding shader: the depth-fail op must not run (a discarded pixel writes nothing).
    DrawStats s1 = drawList(dev, st, colorDepth(&color, &ds), quad(0, 0, 16, 16, 16, 16, 0.5f), DiscardAllPS{});
    CHECK(s1.psInvocations == 256);   // the shader had to run to know about the discard
    CHECK(ds.loadStencil(5, 5) == 0);
    CHECK(s1.samplesPassed == 0);
    // Non-discarding shader: skipped everywhere (every sample fails), depth-fail op applied.
    DrawStats s2 = drawList(dev, st, colorDepth(&color, &ds), quad(0, 0, 16, 16, 16, 16, 0.5f), ColorPS{});
    CHECK(s2.psInvocations == 0);
    CHECK(ds.loadStencil(5, 5) == 1);
}

TEST_CASE("occlusion query counts passing samples, scissor limits them") {
    Device dev(DeviceConfig{8, 2});
    Surface ds(SurfaceDesc{40, 30, Format::D32_FLOAT_S8X24_UINT, 4});
    ds.clearDepthStencil(true, 1.0f, true, 0);
    DrawState st;
    st.viewport = fullViewport(ds);
    st.rasterizer.cullMode = CullMode::None;
    OcclusionQuery q;
    q.begin();
    // Rectangle [4,24) x [2,12) on pixel edges: 20 * 10 px * 4 samples = 800 samples.
    drawList(dev, st, colorDepth(nullptr, &ds), quad(4, 2, 24, 12, 40, 30, 0.5f), NoPixelShader{}, &q);
    // Same rectangle again behind (z 0.7 > 0.5 fails LESS): 0 samples.
    drawList(dev, st, colorDepth(nullptr, &ds), quad(4, 2, 24, 12, 40, 30, 0.7f), NoPixelShader{}, &q);
    q.end();
    CHECK(q.samplesPassed() == 800u);
    st.rasterizer.scissorEnable = true;
    st.scissor = {10, 0, 15, 30};  // 5 columns of the rectangle's 10 rows: 50 px * 4 = 200
    q.begin();
    drawList(dev, st, colorDepth(nullptr, &ds), quad(4, 2, 24, 12, 40, 30, 0.25f), NoPixelShader{}, &q);
    q.end();
    CHECK(q.samplesPassed() == 200u);
}

struct DepthOutPS {
    using Varyings = ColorVaryings;
    static constexpr int kTargetCount = 0;
    static constexpr bool kWritesDepth = true;
    void operator()(const PixelInput<ColorVaryings>& in, PixelOutput<0>& out) const {
        out.depth = in.posWindow.x < 8.0f ? -3.0f : 0.125f;  // left half: below MinDepth, clamped
    }
};

TEST_CASE("SV_Depth replaces the interpolated depth and is clamped to the viewport range") {
    Device dev(DeviceConfig{16, 1});
    Surface depth(SurfaceDesc{16, 16, Format::D32_FLOAT, 1});
    depth.clearDepthStencil(true, 1.0f, false, 0);
    DrawState st;
    st.viewport = Viewport{0, 0, 16, 16, 0.1f, 1.0f};
    st.rasterizer.cullMode = CullMode::None;
    drawList(dev, st, colorDepth(nullptr, &depth), quad(0, 0, 16, 16, 16, 16, 0.9f), DepthOutPS{});
    CHECK(depth.loadDepth(2, 2) == 0.1f);
    CHECK(depth.loadDepth(12, 2) == 0.125f);
}

struct FacingPS {
    using Varyings = ColorVaryings;
    static constexpr int kTargetCount = 1;
    void operator()(const PixelInput<ColorVaryings>& in, PixelOutput<1>& out) const {
        out.target[0] = glm::vec4(in.isFrontFace ? 1.0f : 0.5f);
    }
};

TEST_CASE("facing: clockwise in window space is front unless FrontCounterClockwise, culling follows") {
    Device dev(DeviceConfig{16, 1});
    Surface color(SurfaceDesc{16, 16, Format::R32G32B32A32_FLOAT, 1});
    // Window (2,2) -> (14,2) -> (2,14): right then down-left, clockwise on screen (y down).
    const std::vector<ColorVertex> cw = {{windowToClip(2, 2, 16, 16)}, {windowToClip(14, 2, 16, 16)}, {windowToClip(2, 14, 16, 16)}};
    const std::vector<ColorVertex> ccw = {cw[0], cw[2], cw[1]};
    DrawState st;
    st.viewport = fullViewport(color);
    st.depthStencil.depthEnable = false;
    RenderTargets rt;
    rt.colors[0] = &color;
    auto run = [&](const std::vector<ColorVertex>& v, CullMode cull, bool fccw) {
        color.clearColor(glm::vec4(0));
        st.rasterizer.cullMode = cull;
        st.rasterizer.frontCounterClockwise = fccw;
        drawList(dev, st, rt, v, FacingPS{});
        return color.load(4, 4).x;
    };
    CHECK(run(cw, CullMode::None, false) == 1.0f);
    CHECK(run(ccw, CullMode::None, false) == 0.5f);
    CHECK(run(cw, CullMode::None, true) == 0.5f);
    CHECK(run(cw, CullMode::Back, false) == 1.0f);
    CHECK(run(ccw, CullMode::Back, false) == 0.0f);
    CHECK(run(cw, CullMode::Front, false) == 0.0f);
    CHECK(run(ccw, CullMode::Front, false) == 0.5f);
}

TEST_CASE("guard band: a screen-covering pair with vertices far outside covers every pixel once") {
    Device dev(DeviceConfig{32, 2});
    Surface target(SurfaceDesc{100, 70, Format::R32_FLOAT, 1});
    const DrawState st = countingState(target);
    RenderTargets rt;
    rt.colors[0] = &target;
    for (const float far : {3.0f, 5e3f, 1e7f, 1e30f}) {  // beyond 2^21 px the x/y clipper runs
        target.clearColor(glm::vec4(0));
        const std::vector<ColorVertex> v = {{{-far, far, 0.5f, 1}}, {{far, far, 0.5f, 1}}, {{far, -far, 0.5f, 1}},
                                            {{-far, far, 0.5f, 1}}, {{far, -far, 0.5f, 1}}, {{-far, -far, 0.5f, 1}}};
        drawList(dev, st, rt, v, ColorPS{});
        int wrong = 0;
        for (std::uint32_t y = 0; y < 70; ++y)
            for (std::uint32_t x = 0; x < 100; ++x) wrong += target.load(x, y).x != 1.0f;
        INFO("vertices at +-" << far);
        CHECK(wrong == 0);
    }
}

TEST_CASE("bad input: non-finite and degenerate triangles are dropped, invalid state is an error") {
    Device dev(DeviceConfig{16, 1});
    Surface color(SurfaceDesc{16, 16, Format::R8G8B8A8_UNORM, 1});
    DrawState st;
    st.viewport = fullViewport(color);
    st.rasterizer.cullMode = CullMode::None;
    RenderTargets rt;
    rt.colors[0] = &color;
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const std::vector<ColorVertex> bad = {
        {{nan, 0, 0.5f, 1}}, {{1, 1, 0.5f, 1}}, {{0, 1, 0.5f, 1}},     // NaN position
        {{-1, -1, 0.5f, 1}}, {{inf, 1, 0.5f, 1}}, {{0, 1, 0.5f, 1}},   // +Inf
        {{-1, -1, 0.5f, 1}}, {{0, 0, 0.5f, 1}}, {{1, 1, 0.5f, 1}},     // collinear: zero area
        {{0, 0, 0.5f, 0}}, {{1, 0, 0.5f, 0}}, {{0, 1, 0.5f, 0}},       // w = 0 everywhere
    };
    const DrawStats s = drawList(dev, st, rt, bad, ColorPS{});
    CHECK(s.setup.culledNonFinite == 2);
    CHECK(s.setup.culledDegenerate == 1);
    CHECK(s.setup.trianglesOut == 0);
    CHECK(s.psInvocations == 0);

    auto throwsMentioning = [&](auto&& f, const std::string& needle) {
        try {
            f();
        } catch (const std::invalid_argument& e) {
            INFO(e.what());
            return std::string(e.what()).find(needle) != std::string::npos;
        }
        return false;
    };
    const std::vector<ColorVertex> one = quad(0, 0, 4, 4, 16, 16, 0.5f);
    DrawState zeroVp = st;
    zeroVp.viewport.width = 0;
    CHECK(throwsMentioning([&] { drawList(dev, zeroVp, rt, one, ColorPS{}); }, "viewport size"));
    DrawState nanVp = st;
    nanVp.viewport.topLeftX = nan;
    CHECK(throwsMentioning([&] { drawList(dev, nanVp, rt, one, ColorPS{}); }, "non-finite"));
    DrawState hugeVp = st;
    hugeVp.viewport.width = 1e9f;
    CHECK(throwsMentioning([&] { drawList(dev, hugeVp, rt, one, ColorPS{}); }, "VIEWPORT_BOUNDS"));
    DrawState depthRange = st;
    depthRange.viewport.minDepth = 0.7f;
    depthRange.viewport.maxDepth = 0.3f;
    CHECK(throwsMentioning([&] { drawList(dev, depthRange, rt, one, ColorPS{}); }, "MinDepth"));
    DrawState dual = st;
    dual.blend.renderTarget[0] = {true, Blend::Src1Color, Blend::One, BlendOp::Add, Blend::One, Blend::One, BlendOp::Add, WriteAll};
    CHECK(throwsMentioning([&] { drawList(dev, dual, rt, one, ColorPS{}); }, "dual-source"));
    Surface other(SurfaceDesc{8, 16, Format::D32_FLOAT, 1});
    RenderTargets mismatched = rt;
    mismatched.depthStencil = &other;
    CHECK(throwsMentioning([&] { drawList(dev, st, mismatched, one, ColorPS{}); }, "depth-stencil target is 8x16"));
    CHECK(throwsMentioning([&] { drawList(dev, st, RenderTargets{}, one, ColorPS{}); }, "no render target"));
    CHECK(throwsMentioning([] { Surface invalidSurface(SurfaceDesc{0, 4, Format::R32_FLOAT, 1}); }, "width 0"));
    CHECK(throwsMentioning([] { Surface invalidSurface(SurfaceDesc{4, 1000000000u, Format::R32_FLOAT, 1}); }, "height 1000000000"));
    CHECK(throwsMentioning([] { Surface invalidSurface(SurfaceDesc{4, 4, Format::R32_FLOAT, 3}); }, "sample count 3"));
    CHECK(throwsMentioning([] { Device d(DeviceConfig{7, 1}); }, "tile size 7"));
}

TEST_CASE("x/y clipping beyond the guard band keeps edges where the unclipped triangle has them") {
    // Triangles whose vertices lie 10^7 px away (beyond the 2^21 px guard band) go through
    // the x/y clipper. Inside the viewport their edges must stay on the original lines:
    // every pixel centre farther than 1/64 px from an edge is classified as the exact
    // (double precision) triangle says. Clip vertices are at least 2^21 - 256 px away, so
    // snapping them moves an edge inside the viewport by far less than that margin.
    constexpr double kFar = 1e7;
    Device dev(DeviceConfig{32, 2});
    Surface target(SurfaceDesc{256, 256, Format::R32_FLOAT, 1});
    const DrawState st = countingState(target);
    RenderTargets rt;
    rt.colors[0] = &target;
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> yr(20.0, 236.0);
    int checked = 0, wrong = 0;
    for (int n = 0; n < 20; ++n) {
        target.clearColor(glm::vec4(0));
        // Vertex window positions: far left and far right on a random line, and far below.
        const double ya = yr(rng), yb = yr(rng);
        const glm::dvec2 pWin[3] = {{-kFar, ya}, {kFar, yb}, {0.0, kFar}};
        std::vector<ColorVertex> v;
        glm::dvec2 used[3];
        for (int i = 0; i < 3; ++i) {
            const glm::vec4 c(float(pWin[i].x / 128.0 - 1.0), float(1.0 - pWin[i].y / 128.0), 0.5f, 1.0f);
            v.push_back({c});
            used[i] = {(double(c.x) + 1.0) * 128.0, (1.0 - double(c.y)) * 128.0};  // what the floats really say
        }
        drawList(dev, st, rt, v, ColorPS{});
        for (std::uint32_t y = 0; y < 256; ++y)
            for (std::uint32_t x = 0; x < 256; ++x) {
                const glm::dvec2 p(x + 0.5, y + 0.5);
                bool inside = true, nearEdge = false;
                for (int i = 0; i < 3; ++i) {
                    const glm::dvec2 a = used[(i + 1) % 3], b = used[(i + 2) % 3];
                    const glm::dvec2 d = b - a;
                    const double dist = (d.x * (p.y - a.y) - d.y * (p.x - a.x)) / glm::length(d);  // > 0 inside (clockwise)
                    nearEdge |= std::fabs(dist) < 1.0 / 64.0;
                    inside &= dist > 0.0;
                }
                if (nearEdge) continue;
                ++checked;
                wrong += (target.load(x, y).x == 1.0f) != inside;
            }
    }
    CHECK(checked > 1000000);
    CHECK(wrong == 0);
}

TEST_CASE("a device reuses a draw's storage: each draw gives the bytes and counters it gives on a fresh device") {
    // The device keeps the set-up chunks, tile counters and vertex outputs of its largest draw
    // (detail::DrawScratch). A large indexed draw (30,000 triangles: 15 set-up chunks of 2048)
    // followed by small indexed and non-indexed ones must leave nothing of itself in them: a
    // stale chunk binned again would add its triangles to the additive count below.
    constexpr std::uint32_t kSize = 64;  // px
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> pos(-8.0f, float(kSize) + 8.0f);
    auto soup = [&](std::size_t vertexCount, std::size_t triangleCount, std::vector<ColorVertex>& v, std::vector<std::uint32_t>& idx) {
        v.clear();
        idx.clear();
        for (std::size_t i = 0; i < vertexCount; ++i)
            v.push_back({windowToClip(pos(rng), pos(rng), float(kSize), float(kSize)), glm::vec4(1.0f)});
        std::uniform_int_distribution<std::uint32_t> pick(0, std::uint32_t(vertexCount - 1));
        for (std::size_t i = 0; i < triangleCount * 3; ++i) idx.push_back(pick(rng));
    };
    std::vector<ColorVertex> bigV, smallV, listV;
    std::vector<std::uint32_t> bigI, smallI, none;
    soup(20000, 30000, bigV, bigI);
    soup(40, 100, smallV, smallI);
    std::vector<std::uint32_t> unusedI;
    soup(90, 0, listV, unusedI);  // 30 triangles, three vertices each

    auto draw = [&](Device& dev, const std::vector<ColorVertex>& v, const std::vector<std::uint32_t>& idx, Surface& target) {
        target.clearColor(glm::vec4(0.0f));
        RenderTargets rt;
        rt.colors[0] = &target;
        return dev.draw(countingState(target), rt, std::span<const ColorVertex>(v), std::span<const std::uint32_t>(idx),
                        PassThroughVS{}, ColorPS{});
    };
    const SurfaceDesc desc{kSize, kSize, Format::R32_FLOAT};
    Surface big(desc), smallReused(desc), listReused(desc), smallFresh(desc), listFresh(desc);
    Device reused(DeviceConfig{16, 2});
    const DrawStats bigStats = draw(reused, bigV, bigI, big);
    REQUIRE(bigStats.setup.trianglesIn == 30000);
    const DrawStats smallAfter = draw(reused, smallV, smallI, smallReused);
    const DrawStats listAfter = draw(reused, listV, none, listReused);
    Device freshA(DeviceConfig{16, 2}), freshB(DeviceConfig{16, 2});
    const DrawStats smallAlone = draw(freshA, smallV, smallI, smallFresh);
    const DrawStats listAlone = draw(freshB, listV, none, listFresh);
    CHECK(smallAlone.setup.trianglesOut > 0);
    CHECK(listAlone.setup.trianglesOut > 0);
    CHECK(sameBytes(smallReused, smallFresh));
    CHECK(sameBytes(listReused, listFresh));
    for (const auto& [after, alone] : {std::pair{smallAfter, smallAlone}, std::pair{listAfter, listAlone}}) {
        CHECK(after.setup.trianglesIn == alone.setup.trianglesIn);
        CHECK(after.setup.trianglesOut == alone.setup.trianglesOut);
        CHECK(after.binnedTileTriangles == alone.binnedTileTriangles);
        CHECK(after.quads == alone.quads);
        CHECK(after.psInvocations == alone.psInvocations);
        CHECK(after.samplesPassed == alone.samplesPassed);
    }
}

} // namespace tessera_test::raster_pipeline_test
