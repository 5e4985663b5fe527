// The viewable companions of dumped buffers (inspect/buffer_view.h): each rule checked on
// hand-made surfaces whose pictures are known pixel by pixel.
#include <doctest/doctest.h>

#include <cstring>

#include <tessera/buffers/texel_codec.h>
#include <tessera/inspect/buffer_view.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::inspect_buffer_view_test {

using namespace tessera;

namespace {
std::uint32_t rgbAt(const Surface& image, std::uint32_t x, std::uint32_t y) {
    std::uint32_t rgba = 0;
    std::memcpy(&rgba, image.texel(x, y), 4);
    CHECK((rgba >> 24) == 0xFFu);  // opaque
    return rgba & 0xFFFFFFu;
}
} // namespace

TEST_CASE("buffer view: depth is stretched over the covered range, near white, far dark grey, cleared black") {
    Surface depth({4, 1, Format::D24_UNORM_S8_UINT, 1});
    depth.clearDepthStencil(true, 1.0f, true, 0);
    const float values[4] = {1.0f, 0.5f, 0.75f, 0.625f};
    for (std::uint32_t x = 1; x < 4; ++x) depth.clearDepthStencilRect(x, 0, x + 1, 1, true, values[x], false, 0);
    const auto view = viewBuffer("depth", depth);
    REQUIRE(view);
    CHECK(view->image.width() == 4);
    CHECK(view->image.height() == 1);
    CHECK(rgbAt(view->image, 0, 0) == 0x000000u);  // cleared
    CHECK(rgbAt(view->image, 1, 0) == 0xFFFFFFu);  // nearest: 1.0
    CHECK(rgbAt(view->image, 2, 0) == 0x333333u);  // farthest: 0.2 * 255 = 51 = 0x33
    // 0.625 is halfway (D24 codes are exact at these values): 1 - 0.8 * 0.5 = 0.6 -> 153 = 0x99
    CHECK(rgbAt(view->image, 3, 0) == 0x999999u);
    CHECK(view->rule.find("[0.500000, 0.750000]") != std::string::npos);
}

TEST_CASE("buffer view: stencil values through a 12-colour palette, 0 black, a legend bar below") {
    Surface ds({4, 1, Format::D24_UNORM_S8_UINT, 1});
    ds.clearDepthStencil(true, 1.0f, true, 0);
    const std::uint8_t values[4] = {0, 1, 2, 13};
    for (std::uint32_t x = 1; x < 4; ++x) ds.clearDepthStencilRect(x, 0, x + 1, 1, false, 0.0f, true, values[x]);
    const auto view = viewBuffer("depth", ds, ViewChannel::Stencil);
    REQUIRE(view);
    CHECK(view->image.height() == 1 + 8);
    CHECK(rgbAt(view->image, 0, 0) == 0u);
    CHECK(rgbAt(view->image, 1, 0) != 0u);
    CHECK(rgbAt(view->image, 1, 0) != rgbAt(view->image, 2, 0));
    CHECK(rgbAt(view->image, 1, 0) == rgbAt(view->image, 3, 0));  // 13 = 1 + 12
    CHECK(rgbAt(view->image, 0, 1) == 0u);                         // legend starts at 0
    CHECK(view->rule.find("1..13") != std::string::npos);
    CHECK_FALSE(viewBuffer("d", Surface({1, 1, Format::D32_FLOAT, 1}), ViewChannel::Stencil));
}

TEST_CASE("buffer view: light grids show the count on a heat ramp from black to white with a colour bar") {
    Surface grid({3, 1, Format::R32G32_UINT, 1});
    const std::uint32_t counts[3] = {0, 5, 10};
    for (std::uint32_t x = 0; x < 3; ++x) encodeTexelUint(Format::R32G32_UINT, glm::uvec4(999, counts[x], 0, 1), grid.texel(x, 0));
    const auto view = viewBuffer("lightgrid.opaque", grid);
    REQUIRE(view);
    CHECK(rgbAt(view->image, 0, 0) == 0u);
    CHECK(rgbAt(view->image, 1, 0) == heatColor(0.5f));
    CHECK(rgbAt(view->image, 2, 0) == 0xFFFFFFu);
    CHECK(rgbAt(view->image, 2, 1) == 0xFFFFFFu);  // the bar's right end is the max
    CHECK(view->rule.find("0..10") != std::string::npos);
    // Not a light grid: channel 0 (the offsets, all 999 here: every pixel at the max).
    const auto raw = viewBuffer("lightindex.opaque", grid);
    REQUIRE(raw);
    CHECK(rgbAt(raw->image, 0, 0) == 0xFFFFFFu);
}

TEST_CASE("buffer view: normals as n * 0.5 + 0.5, colours scaled by the exposure, RGBA8 needs no view") {
    Surface normals({1, 1, Format::R32G32B32A32_FLOAT, 1});
    normals.clearColor(glm::vec4(0.0f, -1.0f, 1.0f, 0.0f));
    const auto n = viewBuffer("gbuffer.normal", normals);
    REQUIRE(n);
    CHECK(rgbAt(n->image, 0, 0) == (128u | (0u << 8) | (255u << 16)));
    Surface hdr({1, 1, Format::R32G32B32A32_FLOAT, 1});
    hdr.clearColor(glm::vec4(4.0f, 1.0f, 0.25f, 1.0f));
    const auto c = viewBuffer("accumulation", hdr, ViewChannel::Depth, 0.5f);
    REQUIRE(c);
    CHECK(rgbAt(c->image, 0, 0) == (255u | (128u << 8) | (32u << 16)));  // 2 -> 1, 0.5 -> 128, 0.125 -> 32
    CHECK_FALSE(viewBuffer("backbuffer", Surface({1, 1, Format::R8G8B8A8_UNORM, 1})));
    CHECK(heatColor(0.0f) == 0u);
    CHECK(heatColor(1.0f) == 0xFFFFFFu);
}

TEST_CASE("buffer view: a G-buffer's alpha alone, and tile light counts averaged over the image") {
    Surface spec({2, 1, Format::R32G32B32A32_FLOAT, 1});
    spec.clearColor(glm::vec4(0.0f, 0.0f, 0.0f, 250.0f));  // an unpacked specular power
    encodeTexel(Format::R32G32B32A32_FLOAT, glm::vec4(0.0f, 0.0f, 0.0f, 125.0f), spec.texel(0, 0));
    const auto alpha = viewBuffer("gbuffer.specular", spec, ViewChannel::Alpha);
    REQUIRE(alpha);
    CHECK(rgbAt(alpha->image, 1, 0) == 0xFFFFFFu);  // the max
    CHECK(rgbAt(alpha->image, 0, 0) == 0x808080u);  // 125 / 250 = 0.5 -> 128
    CHECK_FALSE(viewBuffer("depth", Surface({1, 1, Format::D32_FLOAT, 1}), ViewChannel::Alpha));
    // The rgb alone, opaque: an RGBA8 target whose alpha is data (specular intensity 0.04).
    Surface color({1, 1, Format::R8G8B8A8_UNORM, 1});
    color.clearColor(glm::vec4(1.0f, 0.5f, 0.0f, 0.04f));
    const auto rgb = viewBuffer("gbuffer.color", color, ViewChannel::Rgb);
    REQUIRE(rgb);
    CHECK(rgbAt(rgb->image, 0, 0) == (255u | (128u << 8)));  // 0.5 -> code 128 -> 128
    CHECK_FALSE(viewBuffer("depth", Surface({1, 1, Format::D32_FLOAT, 1}), ViewChannel::Rgb));
    // An encoded normal (R11G11B10_FLOAT holds n * 0.5 + 0.5) is shown as stored, not remapped again.
    Surface encoded({1, 1, Format::R11G11B10_FLOAT, 1});
    encoded.clearColor(glm::vec4(0.5f, 1.0f, 0.0f, 0.0f));
    const auto n = viewBuffer("gbuffer.normal", encoded);
    REQUIRE(n);
    CHECK(rgbAt(n->image, 0, 0) == (128u | (255u << 8)));

    // A 2x1 grid of 4 px tiles over an 8x4 black image: counts 0 and 6.
    Surface grid({2, 1, Format::R32G32_UINT, 1});
    encodeTexelUint(Format::R32G32_UINT, glm::uvec4(0, 0, 0, 1), grid.texel(0, 0));
    encodeTexelUint(Format::R32G32_UINT, glm::uvec4(0, 6, 0, 1), grid.texel(1, 0));
    Surface image({8, 4, Format::R8G8B8A8_UNORM, 1});
    image.clearColor(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    const auto overlay = overlayTileCounts(grid, 4, image);
    REQUIRE(overlay);
    CHECK(overlay->image.height() == 4 + 8);
    CHECK(rgbAt(overlay->image, 1, 1) == 0u);         // count 0 over black
    CHECK(rgbAt(overlay->image, 6, 2) == 0x808080u);  // white heat averaged with black: (0 + 255 + 1) / 2 = 128
    CHECK_FALSE(overlayTileCounts(grid, 8, image));   // 8 px tiles would make a 1x1 grid
}

} // namespace tessera_test::inspect_buffer_view_test

namespace tessera_test::inspect_buffer_view_test {

TEST_CASE("buffer view: colour bars carry ticks at each quarter, named in the rule") {
    Surface grid({5, 1, Format::R32G32_UINT, 1});
    for (std::uint32_t x = 0; x < 5; ++x) encodeTexelUint(Format::R32G32_UINT, glm::uvec4(0, x * 5 / 2, 0, 1), grid.texel(x, 0));
    const auto view = viewBuffer("lightgrid.opaque", grid);  // counts 0, 2, 5, 7, 10
    REQUIRE(view);
    REQUIRE(view->image.height() == 1 + 8);
    // Ticks at x = 0, 1, 2, 3, 4 (width 5: every column is a quarter) in the bar's bottom 3 rows:
    // white over the dark start of the ramp, black over its white end; the rows above keep the ramp.
    CHECK(rgbAt(view->image, 0, 1 + 7) == 0xFFFFFFu);
    CHECK(rgbAt(view->image, 4, 1 + 7) == 0x000000u);
    CHECK(rgbAt(view->image, 4, 1 + 0) == 0xFFFFFFu);
    CHECK(view->rule.find("ticks at 0, 2.5, 5, 7.5, 10") != std::string::npos);
}

TEST_CASE("buffer view: a light index list is wrapped 256 entries per row, 2 px each") {
    Surface list({600, 1, Format::R32_UINT, 1});  // one long row, as lightindex.* is stored
    for (std::uint32_t x = 0; x < 600; ++x) encodeTexelUint(Format::R32_UINT, glm::uvec4(x % 7, 0, 0, 1), list.texel(x, 0));
    const auto view = viewBuffer("lightindex.opaque", list);
    REQUIRE(view);
    // 600 entries: 3 rows of 256 (the last part-filled), 2 px each, then the 8-row bar.
    CHECK(view->image.width() == 512);
    CHECK(view->image.height() == 3 * 2 + 8);
    // Entry 257 (value 257 mod 7 = 5 of max 6) sits at column 1 of row 1: pixels (2..3, 2..3).
    CHECK(rgbAt(view->image, 2, 2) == heatColor(5.0f / 6.0f));
    CHECK(rgbAt(view->image, 3, 3) == heatColor(5.0f / 6.0f));
    // Entry 6 (value 6, the max) at column 6 of row 0; past entry 599: black.
    CHECK(rgbAt(view->image, 12, 0) == 0xFFFFFFu);
    CHECK(rgbAt(view->image, 511, 5) == 0u);
    CHECK(view->rule.find("256 entries per row") != std::string::npos);
}

TEST_CASE("buffer view: tile frustums as four triangles per tile coloured by the planes' normals, and counters have no picture") {
    Surface frustums({4, 1, Format::R32G32B32A32_FLOAT, 1});  // one tile: left, right, top, bottom
    const float planes[4][4] = {{1, 0, 0, 0}, {-1, 0, 0, 0}, {0, -1, 0, 0}, {0, 1, 0, 0}};
    for (std::uint32_t i = 0; i < 4; ++i) std::memcpy(frustums.texel(i, 0), planes[i], sizeof planes[i]);
    const auto view = viewBuffer("frustums", frustums);
    REQUIRE(view);
    CHECK(view->image.width() == 16);
    CHECK(view->image.height() == 16);
    // n * 0.5 + 0.5 in 8-bit codes: 1 -> 255, 0 -> 128 (0.5 * 255 = 127.5 rounds up), -1 -> 0.
    CHECK(rgbAt(view->image, 0, 8) == (255u | 128u << 8 | 128u << 16));   // left edge: the left plane, +x
    CHECK(rgbAt(view->image, 15, 8) == (0u | 128u << 8 | 128u << 16));    // right edge: -x
    CHECK(rgbAt(view->image, 8, 0) == (128u | 0u << 8 | 128u << 16));     // top edge: -y
    CHECK(rgbAt(view->image, 8, 15) == (128u | 255u << 8 | 128u << 16));  // bottom edge: +y
    CHECK_FALSE(viewBuffer("lightlist.counters", Surface({8, 2, Format::R32_UINT, 1})));
}

} // namespace tessera_test::inspect_buffer_view_test
