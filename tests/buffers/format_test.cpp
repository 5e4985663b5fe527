// Unit tests for the Format table (format.h), DXGI name parsing, and the per-format texel codec
// (texel_codec.h): hand-derived byte layouts (D3D11.3 §19.1.3.1), missing-channel defaults
// (§19.1.3.3), error paths, and byte -> value -> byte invertibility (§19.1.2).
#include <doctest/doctest.h>

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <tessera/buffers/conversion.h>
#include <tessera/buffers/format.h>
#include <tessera/buffers/texel_codec.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::buffers_format_test {

using tessera::Format;
using tessera::FormatKind;

namespace {

constexpr Format kLastFormat = Format::R32G32B32A32_UINT;

std::vector<Format> allFormats() {
    std::vector<Format> out;
    for (unsigned i = 0; i <= static_cast<unsigned>(kLastFormat); ++i) out.push_back(static_cast<Format>(i));
    return out;
}

using Bytes = std::array<std::uint8_t, 16>;

Bytes encode(Format f, const glm::vec4& v) {
    Bytes b{};
    tessera::encodeTexel(f, v, reinterpret_cast<std::byte*>(b.data()));
    return b;
}
glm::vec4 decode(Format f, const Bytes& b) { return tessera::decodeTexel(f, reinterpret_cast<const std::byte*>(b.data())); }
std::uint32_t word(const Bytes& b, std::size_t index = 0) {
    std::uint32_t w;
    std::memcpy(&w, b.data() + 4 * index, 4);
    return w;
}
std::uint32_t bitsOf(float x) { return std::bit_cast<std::uint32_t>(x); }

std::string exceptionMessage(auto&& fn) {
    try {
        fn();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "<no std::invalid_argument thrown>";
}

} // namespace

TEST_CASE("formatInfo: one hand-checked row per format") {
    struct Row {
        Format f;
        const char* name;
        std::uint32_t bytes, channels;
        FormatKind kind;
        bool srgb, depth, stencil;
    };
    // bytes = sum of component bits / 8 (e.g. R11G11B10: 32 bits = 4; D32_FLOAT_S8X24: 64 = 8).
    const std::vector<Row> rows = {
        {Format::Unknown, "UNKNOWN", 0, 0, FormatKind::Unorm, false, false, false},
        {Format::R8G8B8A8_UNORM, "R8G8B8A8_UNORM", 4, 4, FormatKind::Unorm, false, false, false},
        {Format::R8G8B8A8_UNORM_SRGB, "R8G8B8A8_UNORM_SRGB", 4, 4, FormatKind::Unorm, true, false, false},
        {Format::R10G10B10A2_UNORM, "R10G10B10A2_UNORM", 4, 4, FormatKind::Unorm, false, false, false},
        {Format::R11G11B10_FLOAT, "R11G11B10_FLOAT", 4, 3, FormatKind::Float, false, false, false},
        {Format::R16G16_SNORM, "R16G16_SNORM", 4, 2, FormatKind::Snorm, false, false, false},
        {Format::R16G16B16A16_FLOAT, "R16G16B16A16_FLOAT", 8, 4, FormatKind::Float, false, false, false},
        {Format::R32_FLOAT, "R32_FLOAT", 4, 1, FormatKind::Float, false, false, false},
        {Format::R32G32_UINT, "R32G32_UINT", 8, 2, FormatKind::Uint, false, false, false},
        {Format::R32_UINT, "R32_UINT", 4, 1, FormatKind::Uint, false, false, false},
        {Format::R32G32B32A32_FLOAT, "R32G32B32A32_FLOAT", 16, 4, FormatKind::Float, false, false, false},
        {Format::D24_UNORM_S8_UINT, "D24_UNORM_S8_UINT", 4, 1, FormatKind::DepthStencil, false, true, true},
        {Format::D32_FLOAT, "D32_FLOAT", 4, 1, FormatKind::DepthStencil, false, true, false},
        {Format::D32_FLOAT_S8X24_UINT, "D32_FLOAT_S8X24_UINT", 8, 1, FormatKind::DepthStencil, false, true, true},
        {Format::R32G32B32A32_UINT, "R32G32B32A32_UINT", 16, 4, FormatKind::Uint, false, false, false},
    };
    REQUIRE(rows.size() == allFormats().size());
    for (const Row& r : rows) {
        CAPTURE(r.name);
        const tessera::FormatInfo& info = tessera::formatInfo(r.f);
        CHECK(info.name == r.name);
        CHECK(info.bytesPerTexel == r.bytes);
        CHECK(info.channels == r.channels);
        CHECK(info.kind == r.kind);
        CHECK(info.srgb == r.srgb);
        CHECK(info.hasDepth == r.depth);
        CHECK(info.hasStencil == r.stencil);
        CHECK(tessera::isDepthFormat(r.f) == r.depth);
    }
    // An out-of-range enum value reads as UNKNOWN rather than past the table.
    CHECK(tessera::formatInfo(static_cast<Format>(200)).name == "UNKNOWN");
}

TEST_CASE("parseFormat: every name round trips, with or without DXGI_FORMAT_, any case") {
    for (Format f : allFormats()) {
        const std::string name(tessera::formatInfo(f).name);
        CAPTURE(name);
        CHECK(tessera::parseFormat(name) == f);
        CHECK(tessera::parseFormat("DXGI_FORMAT_" + name) == f);
        std::string lower = name;
        for (char& c : lower) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
        CHECK(tessera::parseFormat("dxgi_format_" + lower) == f);
    }
    for (const char* bad : {"", "DXGI_FORMAT_", "R8G8B8A8", "R8G8B8A8_UNORM_SRGBX", " R32_FLOAT", "B8G8R8A8_UNORM",
                            "DXGI_FORMAT_DXGI_FORMAT_R32_FLOAT"}) {
        CAPTURE(bad);
        CHECK(tessera::parseFormat(bad) == Format::Unknown);
    }
}

TEST_CASE("encodeTexel: hand-derived byte layouts") {
    SUBCASE("R8G8B8A8_UNORM") {
        // 0 -> 0, 0.5 -> 127.5 rounds up -> 128 (§3.2.3.6), 1 -> 255, 2 clamps -> 255.
        const Bytes b = encode(Format::R8G8B8A8_UNORM, {0.0f, 0.5f, 1.0f, 2.0f});
        CHECK(word(b) == 0xFFFF8000u);
        CHECK(b[4] == 0); // nothing written past the 4-byte texel
    }
    SUBCASE("R8G8B8A8_UNORM_SRGB: RGB through the sRGB curve, A linear (§19.1.3.2)") {
        // linear 0.5 -> sRGB 0.73536 * 255 = 187.516 -> 188 = 0xBC; alpha 0.5 -> 128 = 0x80.
        const Bytes b = encode(Format::R8G8B8A8_UNORM_SRGB, {0.5f, 0.0f, 1.0f, 0.5f});
        CHECK(word(b) == 0x80FF00BCu);
    }
    SUBCASE("R10G10B10A2_UNORM: R bits 0..9, G 10..19, B 20..29, A 30..31") {
        // R 1 -> 1023; G 0 -> 0; B 0.5 -> 511.5 -> 512; A float(1/3) * 3 = 1 + 2^-25 -> 1.
        // 1023 | 0 << 10 | 512 << 20 | 1 << 30 = 0x3FF | 0x20000000 | 0x40000000 = 0x600003FF.
        const Bytes b = encode(Format::R10G10B10A2_UNORM, {1.0f, 0.0f, 0.5f, 1.0f / 3.0f});
        CHECK(word(b) == 0x600003FFu);
        CHECK(b[0] == 0xFF);
        CHECK(b[3] == 0x60); // little endian
    }
    SUBCASE("R11G11B10_FLOAT: R bits 0..10, G 11..21, B 22..31") {
        // R 1 -> e 15 -> 0x3C0; G 2 -> e 16 -> 0x400; B 0.5 -> float10 e 14 -> 14 << 5 = 0x1C0.
        // 0x3C0 | 0x400 << 11 | 0x1C0 << 22 = 0x3C0 | 0x200000 | 0x70000000 = 0x702003C0.
        const Bytes b = encode(Format::R11G11B10_FLOAT, {1.0f, 2.0f, 0.5f, 123.0f});
        CHECK(word(b) == 0x702003C0u);
        // Negatives clamp to 0 (§3.1.6); +INF -> 0x7C0 (float11) / 0x3E0 (float10).
        const Bytes c = encode(Format::R11G11B10_FLOAT, {-1.0f, std::numeric_limits<float>::infinity(),
                                                         std::numeric_limits<float>::infinity(), 0.0f});
        CHECK(word(c) == ((0x7C0u << 11) | (0x3E0u << 22)));
    }
    SUBCASE("R16G16_SNORM") {
        // 1 -> 0x7FFF; -1 -> -32767 = 0x8001 (never 0x8000, §3.2.3.4).
        const Bytes b = encode(Format::R16G16_SNORM, {1.0f, -1.0f, 0.25f, 0.25f});
        CHECK(word(b) == 0x80017FFFu);
    }
    SUBCASE("R16G16B16A16_FLOAT") {
        // 1 -> 0x3C00, -2 -> 0xC000, 65504 -> 0x7BFF, 1e9 -> max finite 0x7BFF (§3.2.2, RTZ).
        const Bytes b = encode(Format::R16G16B16A16_FLOAT, {1.0f, -2.0f, 65504.0f, 1.0e9f});
        CHECK(word(b, 0) == 0xC0003C00u);
        CHECK(word(b, 1) == 0x7BFF7BFFu);
    }
    SUBCASE("R32_FLOAT and R32G32B32A32_FLOAT store the float32 bits unchanged") {
        const float nanWithPayload = std::bit_cast<float>(0x7FC12345u);
        CHECK(word(encode(Format::R32_FLOAT, {nanWithPayload, 1.0f, 2.0f, 3.0f})) == 0x7FC12345u);
        const Bytes b = encode(Format::R32G32B32A32_FLOAT, {-0.0f, 1.0e-40f, 1.0f, -3.5f});
        CHECK(word(b, 0) == 0x80000000u);
        CHECK(word(b, 1) == bitsOf(1.0e-40f)); // a float32 denormal passes through a plain store
        CHECK(word(b, 2) == 0x3F800000u);
        CHECK(word(b, 3) == 0xC0600000u);
    }
}

TEST_CASE("decodeTexel: values and missing channels (0, 0, 0, 1) (§19.1.3.3)") {
    auto fromWord = [](std::uint32_t w0, std::uint32_t w1 = 0) {
        Bytes b{};
        std::memcpy(b.data(), &w0, 4);
        std::memcpy(b.data() + 4, &w1, 4);
        return b;
    };
    CHECK(decode(Format::R8G8B8A8_UNORM, fromWord(0xFF00FF00u)) == glm::vec4(0.0f, 1.0f, 0.0f, 1.0f));
    CHECK(decode(Format::R8G8B8A8_UNORM_SRGB, fromWord(0x8000FF00u)) ==
          glm::vec4(0.0f, 1.0f, 0.0f, tessera::convert::unormToFloat(0x80, 8)));
    CHECK(decode(Format::R10G10B10A2_UNORM, fromWord(0xC00003FFu)) == glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    CHECK(decode(Format::R11G11B10_FLOAT, fromWord(0x702003C0u)) == glm::vec4(1.0f, 2.0f, 0.5f, 1.0f));
    CHECK(decode(Format::R16G16_SNORM, fromWord(0x80007FFFu)) == glm::vec4(1.0f, -1.0f, 0.0f, 1.0f));
    CHECK(decode(Format::R16G16B16A16_FLOAT, fromWord(0xC0003C00u, 0x00017BFFu)) ==
          glm::vec4(1.0f, -2.0f, 65504.0f, 0x1p-24f));
    CHECK(decode(Format::R32_FLOAT, fromWord(0x40490FDBu)) == glm::vec4(std::bit_cast<float>(0x40490FDBu), 0.0f, 0.0f, 1.0f));

    Bytes u{};
    tessera::encodeTexelUint(Format::R32G32_UINT, {0xDEADBEEFu, 7u, 9u, 9u}, reinterpret_cast<std::byte*>(u.data()));
    CHECK(word(u, 0) == 0xDEADBEEFu);
    CHECK(word(u, 1) == 7u);
    CHECK(word(u, 2) == 0u);
    CHECK(tessera::decodeTexelUint(Format::R32G32_UINT, reinterpret_cast<const std::byte*>(u.data())) ==
          glm::uvec4(0xDEADBEEFu, 7u, 0u, 1u));
    // R32G32B32A32_UINT (the int4 shadow mask): all four words, raw.
    tessera::encodeTexelUint(Format::R32G32B32A32_UINT, {0xFFFFFFFFu, 0x80000000u, 5u, 0u}, reinterpret_cast<std::byte*>(u.data()));
    CHECK(word(u, 0) == 0xFFFFFFFFu);
    CHECK(word(u, 1) == 0x80000000u);
    CHECK(word(u, 2) == 5u);
    CHECK(word(u, 3) == 0u);
    CHECK(tessera::decodeTexelUint(Format::R32G32B32A32_UINT, reinterpret_cast<const std::byte*>(u.data())) ==
          glm::uvec4(0xFFFFFFFFu, 0x80000000u, 5u, 0u));
    tessera::encodeTexelUint(Format::R32_UINT, {42u, 1u, 1u, 1u}, reinterpret_cast<std::byte*>(u.data()));
    CHECK(tessera::decodeTexelUint(Format::R32_UINT, reinterpret_cast<const std::byte*>(u.data())) ==
          glm::uvec4(42u, 0u, 0u, 1u));
}

TEST_CASE("texel codec rejects depth, UINT-on-float-path, float-on-UINT-path and Unknown, naming the format") {
    Bytes b{};
    auto* p = reinterpret_cast<std::byte*>(b.data());
    for (Format f : {Format::D24_UNORM_S8_UINT, Format::D32_FLOAT, Format::D32_FLOAT_S8X24_UINT}) {
        const std::string name(tessera::formatInfo(f).name);
        CAPTURE(name);
        CHECK(exceptionMessage([&] { tessera::encodeTexel(f, glm::vec4(0.5f), p); }).find(name) != std::string::npos);
        CHECK(exceptionMessage([&] { (void)tessera::decodeTexel(f, p); }).find(name) != std::string::npos);
        CHECK(exceptionMessage([&] { tessera::encodeTexelUint(f, glm::uvec4(1u), p); }).find(name) != std::string::npos);
        CHECK(exceptionMessage([&] { (void)tessera::decodeTexelUint(f, p); }).find(name) != std::string::npos);
        CHECK(exceptionMessage([&] { tessera::encodeTexel(f, glm::vec4(0.5f), p); }).find("depth") != std::string::npos);
    }
    CHECK(exceptionMessage([&] { tessera::encodeTexel(Format::R32_UINT, glm::vec4(1.0f), p); }).find("R32_UINT") !=
          std::string::npos);
    CHECK(exceptionMessage([&] { (void)tessera::decodeTexel(Format::R32G32_UINT, p); }).find("R32G32_UINT") !=
          std::string::npos);
    CHECK(exceptionMessage([&] { tessera::encodeTexelUint(Format::R8G8B8A8_UNORM, glm::uvec4(1u), p); })
              .find("R8G8B8A8_UNORM") != std::string::npos);
    CHECK(exceptionMessage([&] { (void)tessera::decodeTexel(Format::Unknown, p); }).find("UNKNOWN") !=
          std::string::npos);
}

TEST_CASE("texel codec: stored bytes -> value -> bytes is the identity (§19.1.2 Data Invertability)") {
    // Fixed-seed LCG (Numerical Recipes constants) so the patterns are the same on every run.
    std::uint32_t state = 12345u;
    auto next = [&state] { return state = state * 1664525u + 1013904223u; };
    for (Format f : allFormats()) {
        const tessera::FormatInfo& info = tessera::formatInfo(f);
        if (info.bytesPerTexel == 0 || info.hasDepth) continue;
        CAPTURE(info.name);
        int bad = 0;
        for (int i = 0; i < 20000; ++i) {
            Bytes in{};
            for (std::uint32_t w = 0; w < info.bytesPerTexel / 4; ++w) {
                const std::uint32_t r = next();
                std::memcpy(in.data() + 4 * w, &r, 4);
            }
            Bytes expect = in;
            if (f == Format::R16G16_SNORM) {
                // §19.1.2.1: the extra -1 encoding 0x8000 comes back as 0x8001.
                for (int c = 0; c < 2; ++c) {
                    if (expect[2 * c + 1] == 0x80 && expect[2 * c] == 0x00) expect[2 * c] = 0x01;
                }
            }
            Bytes out{};
            if (info.kind == FormatKind::Uint) {
                const glm::uvec4 v = tessera::decodeTexelUint(f, reinterpret_cast<const std::byte*>(in.data()));
                tessera::encodeTexelUint(f, v, reinterpret_cast<std::byte*>(out.data()));
            } else {
                out = encode(f, decode(f, in));
            }
            if (out != expect) ++bad;
        }
        CHECK(bad == 0);
    }
}

} // namespace tessera_test::buffers_format_test
