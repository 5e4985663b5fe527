// The SIMD, parallel masked fill behind every clear (buffers/fill.h) against its scalar oracle:
// every texel size 1..16, sizes that are no multiple of the 16-byte period or of a 64 KiB block,
// random keep masks and old contents; and Surface clears against texel-by-texel encodes.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <vector>

#include <tessera/buffers/fill.h>
#include <tessera/buffers/surface.h>
#include <tessera/buffers/texel_codec.h>
#include <tessera/state/depth_stencil_state.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::buffers_fill_test {

using namespace tessera;

TEST_CASE("maskedFill equals maskedFillScalar for every texel size, odd lengths and random masks") {
    std::mt19937 rng(20261202);
    std::uniform_int_distribution<int> byte(0, 255);
    // Texel counts: tiny, one below/above a 64 KiB block of 4-byte texels, a large odd count.
    const std::size_t counts[] = {1, 3, 17, 16383, 16385, 100003};
    for (std::uint32_t texel = 1; texel <= 16; ++texel)
        for (const std::size_t count : counts) {
            CAPTURE(texel);
            CAPTURE(count);
            std::vector<std::byte> a(texel * count), keep(texel), set(texel);
            for (auto& b : a) b = std::byte(byte(rng));
            for (std::uint32_t k = 0; k < texel; ++k) {
                keep[k] = std::byte(byte(rng) & 0xF0 ? 0xFF : 0x00) ^ std::byte(k % 3 == 0 ? byte(rng) : 0);
                set[k] = std::byte(byte(rng)) & ~keep[k];
            }
            std::vector<std::byte> b = a;
            maskedFill(a, keep.data(), set.data(), texel);
            maskedFillScalar(b, keep.data(), set.data(), texel);
            CHECK(a == b);
        }
    std::vector<std::byte> bad(10);
    const std::byte k[4]{}, s[4]{};
    CHECK_THROWS_AS(maskedFill(bad, k, s, 4), std::invalid_argument);
}

TEST_CASE("Surface clears equal the texel-by-texel encode for colour, uint and depth-stencil formats") {
    const glm::vec4 color(0.25f, -0.5f, 0.75f, 1.5f);
    for (const Format f : {Format::R8G8B8A8_UNORM, Format::R16G16B16A16_FLOAT, Format::R32G32B32A32_FLOAT, Format::R32_UINT,
                           Format::R32G32_UINT}) {
        CAPTURE(formatInfo(f).name);
        Surface s({37, 29, f, 1});
        std::byte texel[16];
        if (formatInfo(f).kind == FormatKind::Uint) {
            s.clearUint(glm::uvec4(7, 8, 9, 10));
            encodeTexelUint(f, glm::uvec4(7, 8, 9, 10), texel);
        } else {
            s.clearColor(color);
            encodeTexel(f, color, texel);
        }
        bool same = true;
        for (std::uint32_t y = 0; y < 29; ++y)
            for (std::uint32_t x = 0; x < 37; ++x) same = same && std::memcmp(s.texel(x, y), texel, formatInfo(f).bytesPerTexel) == 0;
        CHECK(same);
    }
    // Depth only, then stencil only: each keeps the other's bits.
    for (const Format f : {Format::D24_UNORM_S8_UINT, Format::D32_FLOAT_S8X24_UINT}) {
        Surface s({19, 7, f, 4});
        s.clearDepthStencil(true, 0.5f, true, 0x5A);
        s.clearDepthStencil(true, 0.25f, false, 0);
        s.clearDepthStencil(false, 0.0f, true, 0xC3);
        Surface expected({19, 7, f, 4});
        expected.clearDepthStencil(true, 0.25f, true, 0xC3);
        CHECK(std::memcmp(s.bytes().data(), expected.bytes().data(), s.bytes().size()) == 0);
        CHECK(s.loadStencil(18, 6, 3) == 0xC3);
        CHECK(s.loadDepth(18, 6, 3) == expected.loadDepth(0, 0, 0));
        CHECK(std::abs(s.loadDepth(0, 0, 0) - 0.25f) < 1e-6f);
    }
}

TEST_CASE("clearDepthStencilRect clears exactly the rectangle's texels, all samples, and clamps to the surface") {
    for (const Format f : {Format::D24_UNORM_S8_UINT, Format::D32_FLOAT_S8X24_UINT}) {
        Surface s({23, 11, f, 2}), expected({23, 11, f, 2});
        s.clearDepthStencil(true, 0.75f, true, 9);
        expected.clearDepthStencil(true, 0.75f, true, 9);
        s.clearDepthStencilRect(3, 2, 40, 7, false, 0.0f, true, 200);  // x1 past the width: clamped
        s.clearDepthStencilRect(5, 5, 5, 9, true, 0.0f, true, 1);      // empty: nothing
        bool inside = true, outside = true;
        for (std::uint32_t y = 0; y < 11; ++y)
            for (std::uint32_t x = 0; x < 23; ++x)
                for (std::uint32_t i = 0; i < 2; ++i) {
                    const bool in = x >= 3 && y >= 2 && y < 7;
                    if (in) inside = inside && s.loadStencil(x, y, i) == 200 && s.loadDepth(x, y, i) == expected.loadDepth(x, y, i);
                    else outside = outside && std::memcmp(s.texel(x, y, i), expected.texel(x, y, i), s.bytesPerTexel()) == 0;
                }
        CHECK(inside);
        CHECK(outside);
    }
}

TEST_CASE("a stencil clear with a write mask changes only the mask's bits, as a REPLACE draw with StencilWriteMask would") {
    // writeStencil (depth_stencil_state.h) is the draw's rule: (stored & ~mask) | (value & mask).
    for (const Format f : {Format::D24_UNORM_S8_UINT, Format::D32_FLOAT_S8X24_UINT}) {
        Surface s({9, 5, f, 4});
        s.clearDepthStencil(true, 0.25f, true, 0x00);
        // Every stencil value 0..255 somewhere, through full clears of single texels' rectangles.
        for (std::uint32_t k = 0; k < 9 * 5; ++k)
            s.clearDepthStencilRect(k % 9, k / 9, k % 9 + 1, k / 9 + 1, false, 0.0f, true, std::uint8_t(k * 37 + 11));
        const Surface before = s;
        s.clearDepthStencil(false, 0.0f, true, 0x01, 0x7F);  // deferred's per-light clear under MSAA
        s.clearDepthStencilRect(2, 1, 6, 4, false, 0.0f, true, 0xFF, 0x80);
        bool same = true;
        for (std::uint32_t y = 0; y < 5; ++y)
            for (std::uint32_t x = 0; x < 9; ++x)
                for (std::uint32_t i = 0; i < 4; ++i) {
                    std::uint8_t expected = writeStencil(before.loadStencil(x, y, i), 0x01, 0x7F);
                    if (x >= 2 && x < 6 && y >= 1 && y < 4) expected = writeStencil(expected, 0xFF, 0x80);
                    same = same && s.loadStencil(x, y, i) == expected && s.loadDepth(x, y, i) == before.loadDepth(x, y, i);
                }
        CHECK(same);
    }
}

} // namespace tessera_test::buffers_fill_test
