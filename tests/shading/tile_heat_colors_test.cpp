// AMD's lights-per-tile debug colours (shading/tile_heat_colors.h): the radar bands at their
// breakpoints for max = 256 (GPU Pro 4's LIGHT_CAPACITY), the special colours, RGBA8 texels, the
// index staying inside the 14-colour table, and the grayscale view.
#include <doctest/doctest.h>

#include <cstdint>
#include <utility>

#include <tessera/shading/tile_heat_colors.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::shading_tile_heat_colors_test {

using namespace tessera;

TEST_CASE("radar colours: band breakpoints for max = 256") {
    // max = 256: log2(max) = 8, b = 2^(8/14), band(n) = floor(log2(n) * 14/8) = floor(1.75 log2 n);
    // band k starts at n = 2^(4k/7): 1.49, 2.21, 3.28, 4.88, 7.24, 10.8, 16, ... 115.9, 172.3.
    // At n = 16 (k = 7) the real value is exactly 7; 0.07142857f is below 1/14, so log2(b) is below
    // 4/7 and the quotient 4 / log2(b) = 7.0000004 > 7: band 7.
    const std::pair<std::uint32_t, std::uint32_t> cases[] = {
        {1, 0},  {2, 1},  {3, 2},   {4, 3},    {5, 4},    {7, 4},    {8, 5},    {10, 5},
        {11, 6}, {15, 6}, {16, 7},  {115, 11}, {116, 12}, {172, 12}, {173, 13}, {255, 13}};
    for (const auto& entry : cases) {
        const std::uint32_t count = entry.first, band = entry.second;  // named copies: CAPTURE's lambda
        CAPTURE(count);
        CHECK(amdRadarColorIndex(count, 256) == band);
        CHECK(amdRadarColor(count, 256) == kAmdRadarColors[band]);
    }
}

TEST_CASE("radar colours: none, at max, over max, RGBA8 texels") {
    CHECK(amdRadarColor(0, 256) == glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    CHECK(amdRadarColor(256, 256) == kAmdRadarAtMax);
    CHECK(amdRadarColor(257, 256) == kAmdRadarOverMax);
    // UNORM8 = floor(c * 255 + 0.5): black 0xFF000000; white 0xFFFFFFFF.
    CHECK(amdRadarColorRgba8(0, 256) == 0xFF000000u);
    CHECK(amdRadarColorRgba8(1000, 256) == 0xFFFFFFFFu);
    // cyan (0, 0.9255, 0.9255): 0.9255 * 255 = 236.0 -> 236 = 0xEC.
    CHECK(amdRadarColorRgba8(1, 256) == 0xFFECEC00u);
    // at max (0.847, 0.745, 0.921): 215.985 -> 216 (0xD8), 189.975 -> 190 (0xBE), 234.855 -> 235 (0xEB).
    CHECK(amdRadarColorRgba8(256, 256) == 0xFFEBBED8u);
    // yellow-orange (0.90588, 0.75294, 0): 230.9994 -> 231 (0xE7), 191.9997 -> 192 (0xC0).
    CHECK(amdRadarColorRgba8(16, 256) == 0xFF00C0E7u);
}

TEST_CASE("radar colours: the index is monotone and never leaves the 14-entry table") {
    // Every count below max for max up to 4096, and the largest count (max - 1, where the index
    // is largest since it is monotone) for max up to 65536.
    for (std::uint32_t maxPerTile = 2; maxPerTile <= 4096; ++maxPerTile) {
        std::uint32_t previous = 0;
        for (std::uint32_t count = 1; count < maxPerTile; ++count) {
            const std::uint32_t index = amdRadarColorIndex(count, maxPerTile);
            if (index < previous || index > 13u) {
                CAPTURE(maxPerTile);
                CAPTURE(count);
                FAIL("radar index out of order or out of range: " << index);
            }
            previous = index;
        }
    }
    for (std::uint32_t maxPerTile = 4097; maxPerTile <= 65536; ++maxPerTile) {
        if (amdRadarColorIndex(maxPerTile - 1, maxPerTile) > 13u) {
            CAPTURE(maxPerTile);
            FAIL("radar index 14 at count max - 1");
        }
    }
    // The top band is reached: for max = 352 (ForwardPlus11 at 720p: 544 - 32 * 6) count 351 is 13.
    CHECK(amdRadarColorIndex(351, 352) == 13u);
}

TEST_CASE("grayscale view: count / max") {
    CHECK(amdGrayscaleColor(0, 256) == glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    CHECK(amdGrayscaleColor(64, 256) == glm::vec4(0.25f, 0.25f, 0.25f, 1.0f));
    CHECK(amdGrayscaleColor(256, 256) == glm::vec4(1.0f, 1.0f, 1.0f, 1.0f));
    // Over max the shader returns > 1; the UNORM store saturates it to 255.
    CHECK(amdGrayscaleColor(512, 256).x == 2.0f);
    CHECK(rgba8FromColor(amdGrayscaleColor(512, 256)) == 0xFFFFFFFFu);
}

} // namespace tessera_test::shading_tile_heat_colors_test
