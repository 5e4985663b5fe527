// The SIMD block pipeline (raster/quad_block.h) against the scalar path it replaces: each kernel
// on every SIMD target compiled into this build and supported here (AVX-512, AVX2, SSE4, ...,
// EMU128) against the scalar operations lane by lane, bit for bit; then whole draws with
// DeviceConfig::simdBlocks on and off over random states, which must give identical buffers.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <hwy/targets.h>

#include <tessera/buffers/conversion.h>
#include <tessera/raster/output_merger.h>
#include <tessera/raster/quad_block.h>

#include "support/surface_compare.h"
#include "support/test_draw.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::raster_quad_block_test {

using namespace tessera;
using namespace tessera::test;

namespace {

struct SevenVaryings {
    float v[7];
};

bool sameBits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }

// Runs `body` once per SIMD target that is both compiled and supported by this CPU, with the
// kernels' dispatch pinned to it; checks that the dispatch really switched.
template <class F>
void forEachTarget(F&& body) {
    const std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
    REQUIRE(!targets.empty());
    for (const std::int64_t target : targets) {
        hwy::SetSupportedTargetsForTest(target);
        hwy::GetChosenTarget().Update(hwy::SupportedTargets());
        const std::string name = hwy::TargetName(target);
        INFO("target " << name);
        CHECK(std::string(quadBlockTarget()) == name);
        body();
    }
    hwy::SetSupportedTargetsForTest(0);
    hwy::GetChosenTarget().Update(hwy::SupportedTargets());
}

// Random triangles through the real setup, in a 512x512 target; clip w varies so that the
// varyings are perspective-divided.
struct RandomTriangles {
    std::vector<SetupTriangle> tris;
    std::vector<float> varyings;  // 7 floats per vertex
    explicit RandomTriangles(std::uint32_t seed, int count) {
        DrawState st;
        st.rasterizer.cullMode = CullMode::None;
        st.viewport = Viewport{0, 0, 512, 512, 0, 1};
        const SetupContext ctx{&st, PixelRect{0, 0, 512, 512}, 7};
        std::mt19937 rng(seed);
        std::uniform_real_distribution<float> pos(-1.5f, 1.5f), z(-0.2f, 1.2f), w(0.3f, 4.0f), val(-3.0f, 3.0f);
        SetupStats stats;
        for (int k = 0; k < count; ++k) {
            glm::vec4 posClip[3];
            float vary[3][7];
            const float* varPtr[3];
            for (int v = 0; v < 3; ++v) {
                const float cw = w(rng);
                posClip[v] = glm::vec4(pos(rng) * cw, pos(rng) * cw, z(rng) * cw, cw);
                for (float& f : vary[v]) f = val(rng);
                varPtr[v] = vary[v];
            }
            setupTriangle(ctx, posClip, varPtr, tris, varyings, stats);
        }
    }
};

// E_i at the centre of pixel (x, y), as rasterizeTile evaluates it.
std::int64_t edgeAt(const SetupTriangle& t, int i, std::int32_t x, std::int32_t y) {
    const std::int64_t X = std::int64_t(x) * fixed::kOne + fixed::kHalf, Y = std::int64_t(y) * fixed::kOne + fixed::kHalf;
    return std::int64_t(t.a[i]) * (X - t.edgeX[i]) + std::int64_t(t.b[i]) * (Y - t.edgeY[i]);
}

void checkCoverageAndCentres() {
    const RandomTriangles rt(77, 400);
    REQUIRE(rt.tris.size() > 300);
    std::mt19937 rng(5);
    int blocks = 0, coveredLanes = 0, mismatches = 0;
    for (const SetupTriangle& t : rt.tris) {
        // Two blocks per triangle: one at the bounds' corner, one random inside the bounds.
        for (int pick = 0; pick < 2; ++pick) {
            std::int32_t bx = t.bounds.minX & ~1, by = t.bounds.minY & ~1;
            if (pick == 1) {
                bx = (t.bounds.minX + std::int32_t(rng() % std::uint32_t(std::max(1, t.bounds.maxX - t.bounds.minX)))) & ~1;
                by = (t.bounds.minY + std::int32_t(rng() % std::uint32_t(std::max(1, t.bounds.maxY - t.bounds.minY)))) & ~1;
            }
            QuadBlock::Edges e;
            for (int i = 0; i < 3; ++i) {
                e.origin[i] = edgeAt(t, i, bx, by);
                e.stepX[i] = std::int64_t(t.a[i]) * fixed::kOne;
                e.stepY[i] = std::int64_t(t.b[i]) * fixed::kOne;
            }
            const auto columns = std::uint8_t(pick == 0 ? 0xFF : rng() & 0xFF), rows = std::uint8_t(pick == 0 ? 0xFF : rng() & 0xFF);
            const std::uint64_t covered = quadBlockCoverage(t, e, columns, rows);
            const bool fast = (blocks & 2) != 0;
            QuadBlock block;
            quadBlockCentres(t, e, rt.varyings.data() + t.varyingOffset, 7, true, fast, block);
            ++blocks;
            for (std::int32_t qy = 0; qy < 8; qy += 2)
                for (std::int32_t qx = 0; qx < 8; qx += 2) {
                    std::int64_t ePix[4][3];
                    for (int p = 0; p < 4; ++p)
                        for (int i = 0; i < 3; ++i) ePix[p][i] = edgeAt(t, i, bx + qx + (p & 1), by + qy + (p >> 1));
                    detail::QuadCentres<SevenVaryings> qc;
                    detail::quadCentres<SevenVaryings, true>(t, rt.varyings.data(), ePix, qc, fast);
                    for (int p = 0; p < 4; ++p) {
                        const int x = qx + (p & 1), y = qy + (p >> 1), lane = y * 8 + x;
                        bool in = ((columns >> x) & 1u) && ((rows >> y) & 1u);
                        for (int i = 0; i < 3; ++i) in = in && ePix[p][i] >= t.bias[i];
                        coveredLanes += in;
                        bool same = ((covered >> lane) & 1u) == (in ? 1u : 0u);
                        for (int i = 0; i < 3; ++i) same = same && sameBits(block.l[i][lane], qc.l[i][p]);
                        same = same && sameBits(block.z[lane], qc.z[p]) && sameBits(block.posW[lane], qc.posW[p]);
                        for (int k = 0; k < 7; ++k) same = same && sameBits(block.varyings[k * 64 + lane], qc.varyings[std::size_t(p)].v[k]);
                        mismatches += !same;
                    }
                }
        }
    }
    CHECK(mismatches == 0);
    CHECK(coveredLanes > 2000);  // the blocks really hold covered pixels (5313 with these seeds)
    CHECK(blocks > 600);
}

void checkEncode() {
    // Specials, values within float rounding of the half-codes (k + 0.5) / 255, and random ones.
    std::vector<float> values = {0.0f, -0.0f, 1.0f, -1.0f, 2.0f, 0.5f, std::numeric_limits<float>::quiet_NaN(),
                                 std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                                 std::numeric_limits<float>::denorm_min(), std::nextafter(1.0f, 0.0f)};
    for (int k = 0; k < 255; ++k) {
        const float half = (float(k) + 0.5f) / 255.0f;
        for (float x = std::nextafter(std::nextafter(half, 0.0f), 0.0f); x <= std::nextafter(std::nextafter(half, 1.0f), 1.0f);
             x = std::nextafter(x, 1.0f))
            values.push_back(x);
    }
    // The exact encode works on the significand and exponent: every power of two in
    // [2^-12, 1] and its neighbours (the exponent's boundaries; below 2^-9 the code is 0).
    for (int e = -12; e <= 0; ++e) {
        const float power = std::ldexp(1.0f, e);
        for (const float x : {std::nextafter(power, 0.0f), power, std::nextafter(power, 2.0f)}) values.push_back(x);
    }
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-0.1f, 1.1f);
    while (values.size() % 256 != 0 || values.size() < 4096) values.push_back(u(rng));
    int mismatches = 0;
    for (const bool fast : {false, true}) {
        for (std::size_t base = 0; base < values.size(); base += 256) {
            alignas(64) float rgba[4 * 64];
            for (int lane = 0; lane < 64; ++lane)
                for (int c = 0; c < 4; ++c) rgba[c * 64 + lane] = values[base + std::size_t(lane) * 4 + std::size_t(c)];
            alignas(64) std::uint32_t codes[64];
            quadBlockEncodeRgba8(rgba, fast, codes);
            for (int lane = 0; lane < 64; ++lane) {
                const glm::vec4 src(rgba[lane], rgba[64 + lane], rgba[128 + lane], rgba[192 + lane]);
                std::byte expect[4];
                if (fast) writeColorRgba8UnormFast(expect, src);
                else writeColorRgba8Unorm(expect, src);
                mismatches += std::memcmp(expect, &codes[lane], 4) != 0;
            }
        }
    }
    CHECK(mismatches == 0);
}

void checkBlend() {
    // Random sources (outside [0, 1] and NaN too) over random destination codes, for every factor
    // pair, op and write mask against writeColorSample on an R8G8B8A8_UNORM texel.
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u(-0.2f, 1.2f);
    const Blend factors[] = {Blend::Zero, Blend::One, Blend::SrcColor, Blend::InvSrcColor, Blend::SrcAlpha,
                             Blend::InvSrcAlpha, Blend::DestAlpha, Blend::InvDestAlpha, Blend::DestColor,
                             Blend::InvDestColor, Blend::SrcAlphaSat, Blend::BlendFactor, Blend::InvBlendFactor};
    const glm::vec4 blendFactor(0.3f, 1.7f, std::numeric_limits<float>::quiet_NaN(), 0.6f);
    int mismatches = 0, cases = 0;
    for (int op = 1; op <= 5; ++op)
        for (const Blend src : factors)
            for (const Blend dst : factors) {
                const std::uint8_t mask = std::uint8_t(1 + (cases % 15));
                const RenderTargetBlendDesc desc{true, src, dst, BlendOp(op), dst, src, BlendOp(1 + (op % 5)), mask};
                ++cases;
                alignas(64) float rgba[4 * 64];
                alignas(64) std::uint32_t dstCodes[64];
                for (int lane = 0; lane < 64; ++lane) {
                    dstCodes[lane] = std::uint32_t(rng());
                    for (int c = 0; c < 4; ++c)
                        rgba[c * 64 + lane] = lane == 5 && c == 1 ? std::numeric_limits<float>::quiet_NaN() : u(rng);
                }
                float blended[4 * 64];
                std::memcpy(blended, rgba, sizeof(rgba));
                quadBlockBlendRgba8(blended, dstCodes, desc, blendFactor);
                alignas(64) std::uint32_t codes[64];
                quadBlockEncodeRgba8(blended, false, codes);
                for (int lane = 0; lane < 64; ++lane) {
                    std::uint32_t expect = dstCodes[lane];
                    writeColorSample(Format::R8G8B8A8_UNORM, reinterpret_cast<std::byte*>(&expect),
                                     glm::vec4(rgba[lane], rgba[64 + lane], rgba[128 + lane], rgba[192 + lane]), desc,
                                     blendFactor);
                    mismatches += expect != codes[lane];
                }
            }
    CHECK(cases == 5 * 13 * 13);
    CHECK(mismatches == 0);
}

void checkDepthTest() {
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> u(-0.2f, 1.2f);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    int mismatches = 0, passes = 0;
    for (int round = 0; round < 64; ++round) {
        alignas(64) float z[64];
        alignas(64) std::uint32_t storedD32[64], storedD24[64];
        for (int lane = 0; lane < 64; ++lane) {
            // Every few lanes an exact tie with the stored value, a D24 half-step, NaN or an
            // infinity; the rest random.
            z[lane] = lane % 9 == 0 ? nan : lane % 11 == 0 ? std::numeric_limits<float>::infinity() : u(rng);
            if (lane % 7 == 0) z[lane] = (float(rng() % 16777215u) + 0.5f) / 16777215.0f;
            const float stored = lane % 5 == 0 ? z[lane] : (lane % 13 == 0 ? nan : u(rng));
            storedD32[lane] = std::bit_cast<std::uint32_t>(stored);
            storedD24[lane] = (std::uint32_t(rng()) & 0xFF000000u) |
                              (lane % 5 == 0 ? convert::depthToD24(std::clamp(z[lane], 0.0f, 1.0f)) : std::uint32_t(rng() & 0xFFFFFFu));
        }
        const std::uint64_t lanes = (std::uint64_t(rng()) << 32) | rng();
        const float minDepth = round % 4 == 0 ? 0.25f : 0.0f, maxDepth = round % 4 == 1 ? 0.75f : 1.0f;
        for (int f = 1; f <= 8; ++f)
            for (const bool d24 : {false, true}) {
                const auto func = ComparisonFunc(f);
                alignas(64) float zClamped[64];
                alignas(64) std::uint32_t incoming[64];
                const std::uint64_t pass = quadBlockDepthTest(z, d24 ? storedD24 : storedD32, lanes, d24, func, minDepth, maxDepth,
                                                              zClamped, incoming);
                for (int lane = 0; lane < 64; ++lane) {
                    if (!((lanes >> lane) & 1u)) {
                        mismatches += int((pass >> lane) & 1u);  // never outside `lanes`
                        continue;
                    }
                    const float zc = detail::clampDepth(z[lane], minDepth, maxDepth);
                    bool expect;
                    std::uint32_t value;
                    if (d24) {
                        value = convert::depthToD24(zc);
                        expect = compare(func, value, storedD24[lane] & 0xFFFFFFu);
                    } else {
                        value = std::bit_cast<std::uint32_t>(zc);
                        expect = compare(func, zc, std::bit_cast<float>(storedD32[lane]));
                    }
                    const bool got = (pass >> lane) & 1u;
                    passes += got;
                    mismatches += got != expect || !sameBits(zClamped[lane], zc) || incoming[lane] != value;
                }
            }
    }
    CHECK(mismatches == 0);
    CHECK(passes > 1000);
}

// ---- whole draws: simdBlocks on == off ----

struct DepthOutPS {  // writes SV_Depth: the per-quad path handles it inside the block
    using Varyings = ColorVaryings;
    static constexpr int kTargetCount = 1;
    static constexpr bool kWritesDepth = true;
    void operator()(const PixelInput<ColorVaryings>& in, PixelOutput<1>& out) const {
        out.target[0] = in.varyings.color;
        out.depth = in.varyings.color.z;
    }
};

struct DiscardPS {  // may discard, and writes derivatives and SV_Position into a float target
    using Varyings = ColorVaryings;
    static constexpr int kTargetCount = 2;
    static constexpr bool kMayDiscard = true;
    void operator()(const PixelInput<ColorVaryings>& in, PixelOutput<2>& out) const {
        if (in.varyings.color.w > 0.8f) out.discard();
        out.target[0] = in.varyings.color;
        out.target[1] = glm::vec4(in.posWindow.z, in.posWindow.w, in.ddx.color.x * 64.0f, in.ddy.color.y * 64.0f);
    }
};

struct Targets {
    Surface color, extra, depth;
};

struct DrawCounts {
    std::uint64_t simdBlocks = 0, leanBlocks = 0;
};

Targets renderRandomDraws(bool simd, Format colorFormat, Format depthFormat, std::uint32_t samples, std::uint32_t seed,
                          DrawCounts& counts) {
    constexpr std::uint32_t kW = 141, kH = 99;  // odd: partial blocks and quads at the edges
    Targets f{Surface({kW, kH, colorFormat, samples}), Surface({kW, kH, Format::R32G32B32A32_FLOAT, samples}),
              Surface({kW, kH, depthFormat, samples})};
    f.color.clearColor(glm::vec4(0.1f, 0.2f, 0.3f, 0.5f));
    f.extra.clearColor(glm::vec4(0.0f));
    f.depth.clearDepthStencil(true, 0.6f, true, 3);
    DeviceConfig config{16, 2};
    config.simdBlocks = simd;
    Device dev(config);
    RenderTargets rt;
    rt.colors[0] = &f.color;
    rt.colors[1] = &f.extra;
    rt.depthStencil = &f.depth;
    std::mt19937 rng(seed);
    for (int draw = 0; draw < 24; ++draw) {
        const std::vector<ColorVertex> verts = randomLargeTriangles(rng, 8);
        DrawState st = cyclingDepthState(draw, f.color);
        st.depthStencil.frontFace = {StencilOp::IncrSat, StencilOp::Invert, StencilOp::Incr, ComparisonFunc::GreaterEqual};
        st.stencilRef = std::uint8_t(draw * 17);
        st.blend.independentBlendEnable = true;
        // Every blend factor and op appears (alpha blending, additive, and two states that use the
        // rest), beside overwrites; partial write masks on blended and unblended draws.
        const RenderTargetBlendDesc blends[] = {
            RenderTargetBlendDesc{}, kAlphaBlend, kAdditiveBlend,
            {true, Blend::SrcColor, Blend::InvDestColor, BlendOp::Subtract, Blend::DestAlpha, Blend::InvSrcAlpha,
             BlendOp::RevSubtract, WriteAll},
            {true, Blend::SrcAlphaSat, Blend::BlendFactor, BlendOp::Min, Blend::InvBlendFactor, Blend::InvDestAlpha,
             BlendOp::Max, WriteAll},
            {true, Blend::DestColor, Blend::InvSrcColor, BlendOp::Max, Blend::Zero, Blend::SrcAlphaSat, BlendOp::Min,
             WriteAll}};
        st.blend.renderTarget[0] = blends[draw % 3 == 0 ? 0 : 1 + (draw / 3) % 5];
        st.blend.renderTarget[0].renderTargetWriteMask = std::uint8_t(draw % 9 == 8 ? 0x5 : (draw % 11 == 7 ? 0x0 : 0xF));
        st.blendFactor = {0.25f, 1.5f, -0.5f, 0.75f};  // clamped to [0, 1] for UNORM targets
        st.rasterizer.scissorEnable = draw == 10;
        st.scissor = {13, 7, 120, 90};
        const std::span<const ColorVertex> vs(verts);
        DrawStats stats;
        switch (draw % 4) {
        case 0: stats = dev.draw(st, rt, vs, {}, PassThroughVS{}, DiscardPS{}); break;
        case 1: stats = dev.draw(st, rt, vs, {}, PassThroughVS{}, DepthOutPS{}); break;
        case 2: stats = dev.draw(st, rt, vs, {}, PassThroughVS{}, NoPixelShader{}); break;
        default: stats = dev.draw(st, rt, vs, {}, PassThroughVS{}, ColorPS{}); break;
        }
        counts.simdBlocks += stats.simdBlocks;
        counts.leanBlocks += stats.leanBlocks;
    }
    return f;
}

} // namespace

TEST_CASE("SIMD block coverage, barycentrics, depth, w and varyings equal the scalar quad path on every target") {
    forEachTarget(checkCoverageAndCentres);
}

TEST_CASE("SIMD block RGBA8 encode equals writeColorRgba8Unorm (exact) and writeColorRgba8UnormFast on every target") {
    forEachTarget(checkEncode);
}

TEST_CASE("SIMD block RGBA8 blend equals writeColorSample for every factor, op and write mask on every target") {
    forEachTarget(checkBlend);
}

TEST_CASE("SIMD block depth test equals clampDepth + depthToD24 + compare for every function on every target") {
    forEachTarget(checkDepthTest);
}

TEST_CASE("draws with SIMD blocks give the same bytes as the scalar path: formats, depth, stencil, blend, discard, SV_Depth, MSAA") {
    struct Case {
        Format color, depth;
        std::uint32_t samples;
    };
    const Case cases[] = {{Format::R8G8B8A8_UNORM, Format::D32_FLOAT, 1},
                          {Format::R8G8B8A8_UNORM, Format::D24_UNORM_S8_UINT, 1},
                          {Format::R8G8B8A8_UNORM_SRGB, Format::D32_FLOAT_S8X24_UINT, 1},
                          {Format::R16G16B16A16_FLOAT, Format::D24_UNORM_S8_UINT, 1},
                          {Format::R8G8B8A8_UNORM, Format::D24_UNORM_S8_UINT, 4}};
    for (const Case& k : cases) {
        for (const std::uint32_t seed : {1u, 2u}) {
            INFO("colour " << formatInfo(k.color).name << ", depth " << formatInfo(k.depth).name << ", " << k.samples
                           << "x, seed " << seed);
            DrawCounts simd, scalar;
            const Targets a = renderRandomDraws(true, k.color, k.depth, k.samples, seed, simd);
            const Targets b = renderRandomDraws(false, k.color, k.depth, k.samples, seed, scalar);
            CHECK(sameBytes(a.color, b.color));
            CHECK(sameBytes(a.extra, b.extra));
            CHECK(sameBytes(a.depth, b.depth));
            CHECK(scalar.simdBlocks == 0);
            if (k.samples == 1) {
                CHECK(simd.simdBlocks > 100);  // the comparison really covers the SIMD path
                CHECK(simd.leanBlocks > 50);
                CHECK(simd.leanBlocks < simd.simdBlocks);  // and the per-quad stage behind it
            } else {
                CHECK(simd.simdBlocks == 0);  // multisampled draws stay on the per-quad path
            }
        }
    }
}

TEST_CASE("small triangles stay on the per-quad path at every pixel and quad alignment, and large ones take SIMD blocks") {
    // A right triangle with legs of `legPx` px placed at every offset of 0..1.75 px in x and y (so
    // its rectangle starts on even and odd columns and rows). A 3 px triangle's pixel rectangle is
    // at most 6x6 = 36 px (set-up bounds reach 7/16 px past the centres it can cover), below
    // kSimdBlockMinPixels (40): no SIMD block may be taken. A 16 px triangle's rectangle holds the
    // whole 8x8 block [24, 32)^2, whose corner pixel (24, 24) it covers: a SIMD block each time.
    constexpr std::uint32_t kW = 64, kH = 64;
    for (const float legPx : {3.0f, 16.0f}) {
        std::uint64_t simdBlocks = 0;
        for (int oy = 0; oy < 8; ++oy)
            for (int ox = 0; ox < 8; ++ox) {
                Surface color({kW, kH, Format::R8G8B8A8_UNORM, 1});
                DeviceConfig config{16, 1};
                Device dev(config);
                RenderTargets rt;
                rt.colors[0] = &color;
                DrawState st;
                st.viewport = fullViewport(color);
                st.rasterizer.cullMode = CullMode::None;
                const auto at = [&](float xPx, float yPx) {  // window px -> clip space, w = 1
                    return glm::vec4(2.0f * xPx / float(kW) - 1.0f, 1.0f - 2.0f * yPx / float(kH), 0.5f, 1.0f);
                };
                const float x0 = 20.0f + 0.25f * float(ox), y0 = 20.0f + 0.25f * float(oy);
                const std::vector<ColorVertex> verts = {{at(x0, y0), glm::vec4(1.0f)},
                                                        {at(x0 + legPx, y0), glm::vec4(1.0f)},
                                                        {at(x0, y0 + legPx), glm::vec4(1.0f)}};
                const DrawStats stats = dev.draw(st, rt, std::span<const ColorVertex>(verts), {}, PassThroughVS{}, ColorPS{});
                simdBlocks += stats.simdBlocks;
            }
        INFO("legs " << legPx << " px");
        if (legPx < 4.0f) CHECK(simdBlocks == 0);
        else CHECK(simdBlocks >= 64);
    }
}

} // namespace tessera_test::raster_quad_block_test
