// View-space position from a window position and a depth-buffer value, as the 3dgep deferred
// lighting pass reconstructs it (3dgep article §3.3.3 ClipToView / ScreenToView), plus the two pixel
// sample points: the demo's integer pixel corner (faithful) and the pixel centre (corrected).
// Binary32, fixed operation order; callers: the deferred lighting PS, Forward+ depth bounds.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace tessera {

// Where the deferred lighting PS evaluates a pixel's position (3dgep article §3.3.3, PS_DeferredLighting).
enum class PixelSamplePoint : std::uint8_t {
    Corner,  // faithful: `int2 texCoord = IN.position.xy` truncates SV_Position's +0.5 centre
    Centre,  // corrected: the pixel centre (x + 0.5, y + 0.5), where the G-buffer was sampled
};

// HLSL `mul(InverseProjection, clip)` then `view / view.w` (3dgep article §3.3.3 ClipToView). The product
// is evaluated row by row as dp4 in x, y, z, w order (glm column-major: m[col][row]).
glm::vec4 clipToView(const glm::vec4& posClip, const glm::mat4& inverseProjection);

// 3dgep article §3.3.3 ScreenToView: `texCoord = screen.xy / ScreenDimensions; clip =
// float4(float2(texCoord.x, 1 - texCoord.y) * 2 - 1, screen.z, screen.w)`, then ClipToView.
// posScreen: x, y in window px (origin top-left, y down), z the depth-buffer value, w = 1.
// screenDimensions: the viewport's width and height in px.
glm::vec4 screenToView(const glm::vec4& posScreen, const glm::vec2& screenDimensions,
                       const glm::mat4& inverseProjection);

// `int2 texCoord = IN.position.xy` (3dgep article §3.3.3, PS_DeferredLighting): HLSL float -> int
// truncates toward zero, so SV_Position (x + 0.5, y + 0.5) becomes the integer corner (x, y).
glm::ivec2 pixelFromSvPosition(const glm::vec2& posWindow);

// The window position (px) at which the lighting pass evaluates pixel (x, y): (x, y) for
// Corner, (x + 0.5, y + 0.5) for Centre.
glm::vec2 samplePointWindow(std::uint32_t pxX, std::uint32_t pxY, PixelSamplePoint samplePoint);

// The deferred lighting pass's P for pixel (x, y) holding depth-buffer value `depth`:
// screenToView(float4(samplePointWindow(x, y, samplePoint), depth, 1)).
// The faithful Corner point lies half a pixel up and left of the centre the G-buffer was
// rasterized at; at view distance d (= -z_view) P moves by -d / (W * P[0][0]) in view x and
// +d / (H * P[1][1]) in view y, z unchanged (P = the projection; tests/gbuffer/screen_to_view_test.cpp).
glm::vec4 reconstructPositionView(std::uint32_t pxX, std::uint32_t pxY, float depth,
                                  const glm::vec2& screenDimensions, const glm::mat4& inverseProjection,
                                  PixelSamplePoint samplePoint);

} // namespace tessera
