// Lights-per-tile debug colours of AMD's Forward+ samples (ForwardPlus11
// ForwardPlus11DebugDraw.hlsl): the "weather radar" ramp on a log scale and the grayscale
// view, count -> colour, as float4 (what the pixel shader returns) and as the RGBA8 UNORM texel a
// R8G8B8A8_UNORM target stores. Used by the forward-plus-amd heat-map buffers.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include <tessera/buffers/conversion.h>
#include <tessera/math/det_math.h>

namespace tessera {

// kRadarColors[14] of ForwardPlus11DebugDraw.hlsl, in order (cyan ... purple).
inline constexpr std::array<glm::vec4, 14> kAmdRadarColors{{
    {0.0f, 0.9255f, 0.9255f, 1.0f},      // cyan
    {0.0f, 0.62745f, 0.9647f, 1.0f},     // light blue
    {0.0f, 0.0f, 0.9647f, 1.0f},         // blue
    {0.0f, 1.0f, 0.0f, 1.0f},            // bright green
    {0.0f, 0.7843f, 0.0f, 1.0f},         // green
    {0.0f, 0.5647f, 0.0f, 1.0f},         // dark green
    {1.0f, 1.0f, 0.0f, 1.0f},            // yellow
    {0.90588f, 0.75294f, 0.0f, 1.0f},    // yellow-orange
    {1.0f, 0.5647f, 0.0f, 1.0f},         // orange
    {1.0f, 0.0f, 0.0f, 1.0f},            // bright red
    {0.8392f, 0.0f, 0.0f, 1.0f},         // red
    {0.75294f, 0.0f, 0.0f, 1.0f},        // dark red
    {1.0f, 0.0f, 1.0f, 1.0f},            // magenta
    {0.6f, 0.3333f, 0.7882f, 1.0f},      // purple
}};
inline constexpr glm::vec4 kAmdRadarAtMax{0.847f, 0.745f, 0.921f, 1.0f};  // "light purple for reaching the max"
inline constexpr glm::vec4 kAmdRadarOverMax{1.0f, 1.0f, 1.0f, 1.0f};      // "white for going over the max"
inline constexpr glm::vec4 kAmdRadarNone{0.0f, 0.0f, 0.0f, 1.0f};         // "black for no lights"

// The radar band of 1 <= count < maxPerTile (DebugDrawNumLightsPerTileRadarColorsPS):
//   fLogBase = exp2(0.07142857f * log2((float)max))      (the base b with log_b(max) = 14)
//   nColorIndex = floor(log2((float)count) / log2(fLogBase))
// log2 / exp2 are tessera's deterministic ones (math/det_math.h; HLSL leaves their precision to
// the hardware). 0.07142857f is a hair below 1/14, so b is a hair small and the index runs a hair
// high; it stays <= 13 for every count < max <= 65536 (tests/shading/tile_heat_colors_test.cpp).
// Returns 14 if it ever did not (the shader would index past the array).
inline std::uint32_t amdRadarColorIndex(std::uint32_t count, std::uint32_t maxPerTile) {
    const float logBase = detExp2(0.07142857f * detLog2(static_cast<float>(maxPerTile)));
    const float band = std::floor(detLog2(static_cast<float>(count)) / detLog2(logBase));
    return band < 14.0f ? static_cast<std::uint32_t>(band) : 14u;
}

// count -> colour, as the pixel shader returns it: 0 black; == max light purple; > max white;
// else kAmdRadarColors[amdRadarColorIndex] (index 14 clamps to the last colour).
inline glm::vec4 amdRadarColor(std::uint32_t count, std::uint32_t maxPerTile) {
    if (count == 0) return kAmdRadarNone;
    if (count == maxPerTile) return kAmdRadarAtMax;
    if (count > maxPerTile) return kAmdRadarOverMax;
    const std::uint32_t index = amdRadarColorIndex(count, maxPerTile);
    return kAmdRadarColors[index < 14u ? index : 13u];
}

// DebugDrawNumLightsPerTileGrayscalePS: fPercentOfMax = (float)count / (float)max, as grey.
inline glm::vec4 amdGrayscaleColor(std::uint32_t count, std::uint32_t maxPerTile) {
    const float percent = static_cast<float>(count) / static_cast<float>(maxPerTile);
    return {percent, percent, percent, 1.0f};
}

// The R8G8B8A8_UNORM texel of a float4 colour (D3D11.3 §3.2.3.6: clamp, x 255, round half up),
// packed 0xAABBGGRR (byte 0 = R in memory).
inline std::uint32_t rgba8FromColor(const glm::vec4& color) {
    return convert::floatToUnorm(color.x, 8) | (convert::floatToUnorm(color.y, 8) << 8) |
           (convert::floatToUnorm(color.z, 8) << 16) | (convert::floatToUnorm(color.w, 8) << 24);
}

inline std::uint32_t amdRadarColorRgba8(std::uint32_t count, std::uint32_t maxPerTile) {
    return rgba8FromColor(amdRadarColor(count, maxPerTile));
}

}  // namespace tessera
