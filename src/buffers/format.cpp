// The FormatInfo table (one row per tessera::Format, DXGI spelling and layout facts) and the
// DXGI-name parser used by scene files and the CLI. Sizes follow the DXGI_FORMAT bit layouts
// (D3D11.3 §19.1.3.1): bytesPerTexel = sum of the component bit counts / 8.
#include <tessera/buffers/format.h>

#include <array>
#include <cstddef>

namespace tessera {
namespace {

using enum FormatKind;

// Indexed by the Format enum value; the static_assert below keeps it in step with the enum.
//                 name                    bytes ch  kind          srgb   depth  stencil
constexpr std::array<FormatInfo, 15> kFormats = {{
    {"UNKNOWN",                0,  0, Unorm,        false, false, false},
    {"R8G8B8A8_UNORM",         4,  4, Unorm,        false, false, false},
    {"R8G8B8A8_UNORM_SRGB",    4,  4, Unorm,        true,  false, false},
    {"R10G10B10A2_UNORM",      4,  4, Unorm,        false, false, false},
    {"R11G11B10_FLOAT",        4,  3, Float,        false, false, false},
    {"R16G16_SNORM",           4,  2, Snorm,        false, false, false},
    {"R16G16B16A16_FLOAT",     8,  4, Float,        false, false, false},
    {"R32_FLOAT",              4,  1, Float,        false, false, false},
    {"R32G32_UINT",            8,  2, Uint,         false, false, false},
    {"R32_UINT",               4,  1, Uint,         false, false, false},
    {"R32G32B32A32_FLOAT",     16, 4, Float,        false, false, false},
    {"D24_UNORM_S8_UINT",      4,  1, DepthStencil, false, true,  true},
    {"D32_FLOAT",              4,  1, DepthStencil, false, true,  false},
    {"D32_FLOAT_S8X24_UINT",   8,  1, DepthStencil, false, true,  true},
    {"R32G32B32A32_UINT",      16, 4, Uint,         false, false, false},
}};
static_assert(kFormats.size() == static_cast<std::size_t>(Format::R32G32B32A32_UINT) + 1,
              "kFormats must have one row per Format enumerator, in enum order");

constexpr std::string_view kDxgiPrefix = "DXGI_FORMAT_";

constexpr char toUpperAscii(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c; }

constexpr bool equalsIgnoreCase(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (toUpperAscii(a[i]) != toUpperAscii(b[i])) return false;
    }
    return true;
}

} // namespace

const FormatInfo& formatInfo(Format format) {
    const auto index = static_cast<std::size_t>(format);
    return index < kFormats.size() ? kFormats[index] : kFormats[0];
}

Format parseFormat(std::string_view name) {
    if (name.size() > kDxgiPrefix.size() && equalsIgnoreCase(name.substr(0, kDxgiPrefix.size()), kDxgiPrefix)) {
        name.remove_prefix(kDxgiPrefix.size());
    }
    for (std::size_t i = 1; i < kFormats.size(); ++i) {
        if (equalsIgnoreCase(name, kFormats[i].name)) return static_cast<Format>(i);
    }
    return Format::Unknown;
}

} // namespace tessera
