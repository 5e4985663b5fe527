// Per-format texel codec: shader values <-> the bytes one texel occupies in a surface, laid out
// as D3D11.3 stores them (§19.1.3.1, little endian). Colour formats only; the surface code
// handles depth/stencil formats itself. Conversions are those of conversion.h.
#pragma once

#include <cstddef>

#include <glm/glm.hpp>

#include <tessera/buffers/format.h>

namespace tessera {

// Encodes a shader float4 into formatInfo(f).bytesPerTexel bytes at dst. Channels the format
// lacks are ignored. UNORM/SNORM/SRGB/FLOAT per conversion.h (_SRGB converts R, G, B; A stays
// linear UNORM, §19.1.3.2). Packed layouts (LSb first): R10G10B10A2 R 0..9, G 10..19, B 20..29,
// A 30..31; R11G11B10 R 0..10, G 11..21, B 22..31. Throws std::invalid_argument naming the
// format for UINT formats (use encodeTexelUint), depth formats and Unknown.
void encodeTexel(Format f, const glm::vec4& value, std::byte* dst);
// Decodes one texel to float4; missing channels read as (0, 0, 0, 1) (§19.1.3.3 "Defaults for
// Missing Components"). Throws std::invalid_argument like encodeTexel.
glm::vec4 decodeTexel(Format f, const std::byte* src);

// UINT formats (R32_UINT, R32G32_UINT): raw 32-bit channels, no conversion. Missing channels
// decode as (0, 0, 0, 1) (§19.1.3.3: integer formats default A to 0x1). Any other format throws
// std::invalid_argument naming it.
void encodeTexelUint(Format f, const glm::uvec4& value, std::byte* dst);
glm::uvec4 decodeTexelUint(Format f, const std::byte* src);

} // namespace tessera
