// Texel encode/decode for tessera's colour formats: packs shader float4 / uint4 values into the
// D3D11.3 memory layout of each Format and back, through the exact conversions of
// conversion.cpp. Called per texel by the surface code (render-target writes, texture reads).
#include <tessera/buffers/texel_codec.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include <tessera/buffers/conversion.h>

namespace tessera {
namespace {

static_assert(std::endian::native == std::endian::little,
              "texel layouts are written as host-endian words; tessera targets little endian");

// Field widths of the packed formats, in bits.
constexpr unsigned kUnorm8 = 8;
constexpr unsigned kUnorm10 = 10;
constexpr unsigned kUnorm2 = 2;
constexpr unsigned kSnorm16 = 16;

template <class T> void store(std::byte* dst, std::size_t index, T v) {
    std::memcpy(dst + index * sizeof(T), &v, sizeof(T));
}
template <class T> T load(const std::byte* src, std::size_t index) {
    T v;
    std::memcpy(&v, src + index * sizeof(T), sizeof(T));
    return v;
}

[[noreturn]] void unsupported(const char* what, Format f, const char* why) {
    throw std::invalid_argument(std::string(what) + ": format " + std::string(formatInfo(f).name) + " " + why);
}

[[noreturn]] void rejectFloatPath(const char* what, Format f) {
    const FormatInfo& info = formatInfo(f);
    if (info.hasDepth) unsupported(what, f, "is a depth format (handled by the depth surface, not the texel codec)");
    if (info.kind == FormatKind::Uint) unsupported(what, f, "is an integer format (use the *TexelUint functions)");
    unsupported(what, f, "has no texel codec");
}

} // namespace

void encodeTexel(Format f, const glm::vec4& value, std::byte* dst) {
    using namespace convert;
    switch (f) {
    case Format::R8G8B8A8_UNORM:
        for (int i = 0; i < 4; ++i) store(dst, i, static_cast<std::uint8_t>(floatToUnorm(value[i], kUnorm8)));
        return;
    case Format::R8G8B8A8_UNORM_SRGB:
        for (int i = 0; i < 3; ++i) store(dst, i, linearToSrgb8(value[i]));
        store(dst, 3, static_cast<std::uint8_t>(floatToUnorm(value.w, kUnorm8))); // alpha stays linear
        return;
    case Format::R10G10B10A2_UNORM:
        store(dst, 0, floatToUnorm(value.x, kUnorm10) | (floatToUnorm(value.y, kUnorm10) << 10) |
                          (floatToUnorm(value.z, kUnorm10) << 20) | (floatToUnorm(value.w, kUnorm2) << 30));
        return;
    case Format::R11G11B10_FLOAT:
        store(dst, 0, floatToFloat11(value.x) | (floatToFloat11(value.y) << 11) | (floatToFloat10(value.z) << 22));
        return;
    case Format::R16G16_SNORM:
        for (int i = 0; i < 2; ++i) store(dst, i, static_cast<std::uint16_t>(floatToSnorm(value[i], kSnorm16)));
        return;
    case Format::R16G16B16A16_FLOAT:
        for (int i = 0; i < 4; ++i) store(dst, i, floatToHalf(value[i]));
        return;
    case Format::R32_FLOAT: store(dst, 0, value.x); return;
    case Format::R32G32B32A32_FLOAT:
        for (int i = 0; i < 4; ++i) store(dst, i, value[i]);
        return;
    default: rejectFloatPath("encodeTexel", f);
    }
}

glm::vec4 decodeTexel(Format f, const std::byte* src) {
    using namespace convert;
    switch (f) {
    case Format::R8G8B8A8_UNORM: {
        glm::vec4 v;
        for (int i = 0; i < 4; ++i) v[i] = unormToFloat(load<std::uint8_t>(src, i), kUnorm8);
        return v;
    }
    case Format::R8G8B8A8_UNORM_SRGB: {
        glm::vec4 v;
        for (int i = 0; i < 3; ++i) v[i] = srgb8ToLinear(load<std::uint8_t>(src, i));
        v.w = unormToFloat(load<std::uint8_t>(src, 3), kUnorm8);
        return v;
    }
    case Format::R10G10B10A2_UNORM: {
        const auto w = load<std::uint32_t>(src, 0);
        return {unormToFloat(w & 0x3FFu, kUnorm10), unormToFloat((w >> 10) & 0x3FFu, kUnorm10),
                unormToFloat((w >> 20) & 0x3FFu, kUnorm10), unormToFloat(w >> 30, kUnorm2)};
    }
    case Format::R11G11B10_FLOAT: {
        const auto w = load<std::uint32_t>(src, 0);
        return {float11ToFloat(w & 0x7FFu), float11ToFloat((w >> 11) & 0x7FFu), float10ToFloat(w >> 22), 1.0f};
    }
    case Format::R16G16_SNORM:
        return {snormToFloat(load<std::uint16_t>(src, 0), kSnorm16), snormToFloat(load<std::uint16_t>(src, 1), kSnorm16),
                0.0f, 1.0f};
    case Format::R16G16B16A16_FLOAT: {
        glm::vec4 v;
        for (int i = 0; i < 4; ++i) v[i] = halfToFloat(load<std::uint16_t>(src, i));
        return v;
    }
    case Format::R32_FLOAT: return {load<float>(src, 0), 0.0f, 0.0f, 1.0f};
    case Format::R32G32B32A32_FLOAT: {
        glm::vec4 v;
        for (int i = 0; i < 4; ++i) v[i] = load<float>(src, i);
        return v;
    }
    default: rejectFloatPath("decodeTexel", f);
    }
}

void encodeTexelUint(Format f, const glm::uvec4& value, std::byte* dst) {
    switch (f) {
    case Format::R32_UINT: store(dst, 0, static_cast<std::uint32_t>(value.x)); return;
    case Format::R32G32_UINT:
        store(dst, 0, static_cast<std::uint32_t>(value.x));
        store(dst, 1, static_cast<std::uint32_t>(value.y));
        return;
    case Format::R32G32B32A32_UINT:
        for (int i = 0; i < 4; ++i) store(dst, i, static_cast<std::uint32_t>(value[i]));
        return;
    default: unsupported("encodeTexelUint", f, "is not a UINT colour format");
    }
}

glm::uvec4 decodeTexelUint(Format f, const std::byte* src) {
    switch (f) {
    case Format::R32_UINT: return {load<std::uint32_t>(src, 0), 0u, 0u, 1u};
    case Format::R32G32_UINT: return {load<std::uint32_t>(src, 0), load<std::uint32_t>(src, 1), 0u, 1u};
    case Format::R32G32B32A32_UINT:
        return {load<std::uint32_t>(src, 0), load<std::uint32_t>(src, 1), load<std::uint32_t>(src, 2), load<std::uint32_t>(src, 3)};
    default: unsupported("decodeTexelUint", f, "is not a UINT colour format");
    }
}

} // namespace tessera
