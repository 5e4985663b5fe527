// Surface formats tessera stores (a subset of DXGI_FORMAT) and their layout facts.
// Each texel is stored exactly as Direct3D 11 would lay it out in memory (little endian);
// encode/decode between shader values and stored bits lives in conversion.h and surface.h.
#pragma once

#include <cstdint>
#include <string_view>

namespace tessera {

enum class Format : std::uint8_t {
    Unknown = 0,
    R8G8B8A8_UNORM,
    R8G8B8A8_UNORM_SRGB,
    R10G10B10A2_UNORM,
    R11G11B10_FLOAT,
    R16G16_SNORM,
    R16G16B16A16_FLOAT,
    R32_FLOAT,
    R32G32_UINT,
    R32_UINT,
    R32G32B32A32_FLOAT,
    D24_UNORM_S8_UINT,   // uint32: depth in bits 0..23, stencil in bits 24..31
    D32_FLOAT,
    D32_FLOAT_S8X24_UINT, // 8 bytes: float depth, then stencil in byte 4, 24 unused bits
    R32G32B32A32_UINT     // HLSL uint4 / int4 (forward-plus-amd's 128-bit shadow mask per pixel)
};

enum class FormatKind : std::uint8_t { Unorm, Snorm, Float, Uint, DepthStencil };

struct FormatInfo {
    std::string_view name;   // DXGI spelling without the DXGI_FORMAT_ prefix
    std::uint32_t bytesPerTexel;
    std::uint32_t channels;  // colour channels (1..4); depth formats: 1
    FormatKind kind;
    bool srgb;
    bool hasDepth;
    bool hasStencil;
};

// Facts about a format; Unknown returns a zero-sized entry named "UNKNOWN".
const FormatInfo& formatInfo(Format format);
// Parses a DXGI name ("R8G8B8A8_UNORM", with or without "DXGI_FORMAT_"); Unknown if none.
Format parseFormat(std::string_view name);
inline bool isDepthFormat(Format f) { return formatInfo(f).hasDepth; }

} // namespace tessera
