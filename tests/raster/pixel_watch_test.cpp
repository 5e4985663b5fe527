// Device::setPixelWatch (raster/pixel_watch.h): the watched pixel's events name the draw and
// primitive, the coverage, the depth outcome, the shader output and the texels before and after,
// in order; the last event's texels are the final buffers'; SIMD blocks on or off change nothing.
#include <doctest/doctest.h>

#include <cstring>

#include "support/test_draw.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::raster_pixel_watch_test {

using namespace tessera;
using namespace tessera::test;

namespace {

constexpr std::uint32_t kSize = 32;  // px; one 64 px tile, the watched pixel inside 8x8 blocks

// Two full-screen triangles per draw (a quad) at window depth z, colour c.
std::vector<ColorVertex> quadAt(float z, glm::vec4 c) {
    const glm::vec4 p00 = windowToClip(0, 0, kSize, kSize, z), p10 = windowToClip(kSize, 0, kSize, kSize, z);
    const glm::vec4 p01 = windowToClip(0, kSize, kSize, kSize, z), p11 = windowToClip(kSize, kSize, kSize, kSize, z);
    return {{p00, c}, {p10, c}, {p01, c}, {p10, c}, {p11, c}, {p01, c}};
}

SurfaceDesc desc(Format format) {
    SurfaceDesc d;
    d.width = kSize;
    d.height = kSize;
    d.format = format;
    d.sampleCount = 1;
    return d;
}

struct Result {
    Surface color = Surface(desc(Format::R8G8B8A8_UNORM));
    Surface depth = Surface(desc(Format::D24_UNORM_S8_UINT));
    PixelWatch watch;
};

void render(bool simd, Result& r, bool stencilDraw = false) {
    r.watch.x = 13;
    r.watch.y = 21;  // below the diagonal: primitive 1 of each quad
    r.color.clearColor(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    r.depth.clearDepthStencil(true, 1.0f, true, 0);
    DeviceConfig config{64, 2};
    config.simdBlocks = simd;
    Device device(config);
    device.setPixelWatch(&r.watch);
    RenderTargets rt;
    rt.colors[0] = &r.color;
    rt.depthStencil = &r.depth;
    DrawState st;
    st.viewport = fullViewport(r.color);
    st.rasterizer.cullMode = CullMode::None;
    const auto near = quadAt(0.5f, {1.0f, 0.0f, 0.0f, 1.0f}), far = quadAt(0.75f, {0.0f, 1.0f, 0.0f, 1.0f});
    device.draw(st, rt, std::span<const ColorVertex>(near), {}, PassThroughVS{}, ColorPS{});  // draw 0: written
    device.draw(st, rt, std::span<const ColorVertex>(far), {}, PassThroughVS{}, ColorPS{});   // draw 1: fails LESS
    st.blend.renderTarget[0] = kAlphaBlend;
    st.depthStencil.depthWriteEnable = false;
    const auto blended = quadAt(0.25f, {0.0f, 0.0f, 1.0f, 0.5f});
    device.draw(st, rt, std::span<const ColorVertex>(blended), {}, PassThroughVS{}, ColorPS{});  // draw 2: blends
    if (!stencilDraw) return;
    // draw 3: z 0.9 fails LESS against 0.5 with the stencil test passing: DEPTH_FAIL's REPLACE writes ref 7.
    st.blend.renderTarget[0] = {};
    st.depthStencil.stencilEnable = true;
    st.depthStencil.frontFace = {StencilOp::Keep, StencilOp::Replace, StencilOp::IncrSat, ComparisonFunc::Always};
    st.depthStencil.backFace = st.depthStencil.frontFace;
    st.stencilRef = 7;
    const auto behind = quadAt(0.9f, {1.0f, 1.0f, 1.0f, 1.0f});
    device.draw(st, rt, std::span<const ColorVertex>(behind), {}, PassThroughVS{}, ColorPS{});
}

std::uint32_t d24(const std::array<std::byte, 8>& texel) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, texel.data(), 4);
    return bits & 0xFFFFFFu;
}

} // namespace

TEST_CASE("pixel watch: draws, primitives, depth outcome, shader output and texels before/after at one pixel") {
    Result r;
    render(true, r);
    const auto& e = r.watch.events;
    REQUIRE(e.size() == 3);
    for (std::size_t i = 0; i < 3; ++i) {
        CAPTURE(i);
        CHECK(e[i].draw == i);
        CHECK(e[i].primitive == 1);
        CHECK(e[i].coverage == 1u);
        CHECK(e[i].shaded == (i != 1));  // draw 1 fails the early depth test: its shader never runs
        CHECK(e[i].colorFormat == Format::R8G8B8A8_UNORM);
        CHECK(e[i].depthFormat == Format::D24_UNORM_S8_UINT);
    }
    // The shader's inputs: SV_Position at the pixel centre, the interpolated colour varyings.
    CHECK(e[0].posWindow.x == 13.5f);
    CHECK(e[0].posWindow.y == 21.5f);
    CHECK(e[0].posWindow.z == 0.5f);
    REQUIRE(e[0].inputCount == 4);
    CHECK(e[0].inputs[0] == 1.0f);
    CHECK(e[0].inputs[1] == 0.0f);
    CHECK(e[0].inputs[3] == 1.0f);
    CHECK(e[2].inputs[2] == 1.0f);  // draw 2's blue
    // The test outcomes; no stencil test ran.
    CHECK(e[0].outcome == PixelDrawEvent::Outcome::Pass);
    CHECK(e[1].outcome == PixelDrawEvent::Outcome::DepthFail);
    CHECK(e[2].outcome == PixelDrawEvent::Outcome::Pass);
    CHECK(!e[0].stencilTested);
    // Draw 0: the cleared depth (code 2^24 - 1) becomes 0.5 (code 8388608 = round(0.5 * (2^24 - 1))); red written.
    CHECK(e[0].passed == 1u);
    CHECK(d24(e[0].depthBefore) == 0xFFFFFFu);
    CHECK(d24(e[0].depthAfter) == 8388608u);
    CHECK(std::to_integer<int>(e[0].colorAfter[0]) == 255);
    CHECK(e[0].output == glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    // Draw 1: z 0.75 fails LESS against 0.5: nothing changes.
    CHECK(e[1].z == 0.75f);
    CHECK(e[1].passed == 0u);
    CHECK(e[1].depthAfter == e[1].depthBefore);
    CHECK(e[1].colorAfter == e[1].colorBefore);
    // Draw 2: blue at alpha 0.5 over red: 0.5 * 255 = 127.5 -> 128 blue, red 1 * 0.5 -> 128; depth kept.
    CHECK(e[2].passed == 1u);
    CHECK(e[2].colorBefore == e[1].colorAfter);
    CHECK(std::to_integer<int>(e[2].colorAfter[0]) == 128);
    CHECK(std::to_integer<int>(e[2].colorAfter[2]) == 128);
    CHECK(e[2].depthAfter == e[2].depthBefore);
    // The last event's texels are the final buffers'.
    CHECK(std::memcmp(e[2].colorAfter.data(), r.color.texel(13, 21), 4) == 0);
    CHECK(std::memcmp(e[2].depthAfter.data(), r.depth.texel(13, 21), 4) == 0);
    // SIMD blocks on or off: the same events and bytes (the watched pixel takes the per-quad path).
    Result scalar;
    render(false, scalar);
    REQUIRE(scalar.watch.events.size() == 3);
    for (std::size_t i = 0; i < 3; ++i) {
        CHECK(scalar.watch.events[i].colorAfter == e[i].colorAfter);
        CHECK(scalar.watch.events[i].depthAfter == e[i].depthAfter);
    }
    CHECK(std::memcmp(scalar.color.bytes().data(), r.color.bytes().data(), r.color.bytes().size()) == 0);
}

TEST_CASE("pixel watch: the stencil outcome names the op the state chose and its reference, and the stencil byte follows it") {
    Result r;
    render(true, r, true);
    const auto& e = r.watch.events;
    REQUIRE(e.size() == 4);
    CHECK(e[3].outcome == PixelDrawEvent::Outcome::DepthFail);  // 0.9 against the stored 0.5 with LESS
    CHECK(e[3].stencilTested);
    CHECK(e[3].stencilOp == StencilOp::Replace);  // the front face's depthFailOp
    CHECK(e[3].stencilRef == 7);
    CHECK(std::to_integer<int>(e[3].depthBefore[3]) == 0);  // D24S8: the stencil byte is the texel's fourth
    CHECK(std::to_integer<int>(e[3].depthAfter[3]) == 7);
    CHECK(e[3].colorAfter == e[3].colorBefore);
}

} // namespace tessera_test::raster_pixel_watch_test
