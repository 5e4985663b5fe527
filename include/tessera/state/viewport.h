// D3D11_VIEWPORT and D3D11_RECT (scissor) as value types, with D3D11's bounds.
#pragma once

#include <cstdint>

namespace tessera {

// D3D11_VIEWPORT_BOUNDS_MIN/MAX: viewport corners must lie in [-32768, 32767] px.
inline constexpr float kViewportBoundsMin = -32768.0f;
inline constexpr float kViewportBoundsMax = 32767.0f;
// D3D11_REQ_TEXTURE2D_U_OR_V_DIMENSION: the largest surface side tessera accepts, in px.
inline constexpr std::uint32_t kMaxSurfaceDimension = 16384;

struct Viewport {
    float topLeftX = 0, topLeftY = 0;  // px, window space (origin top-left, y down)
    float width = 0, height = 0;       // px
    float minDepth = 0, maxDepth = 1;  // D3D11: both in [0,1]
};

// Scissor rectangle in integer pixels, [left, right) x [top, bottom).
struct ScissorRect {
    std::int32_t left = 0, top = 0, right = 0, bottom = 0;
};

} // namespace tessera
