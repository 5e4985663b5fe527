// Window-space fixed point: D3D11 snaps post-viewport vertex positions to 16.8 fixed point
// (D3D11.3 §3.2.4 "Fixed Point Integers" and §15.? "Rasterization Rules"; 8 sub-pixel bits,
// D3D11_SUBPIXEL_FRACTIONAL_BIT_COUNT = 8), and tessera's guard band limits.
#pragma once

#include <cmath>
#include <cstdint>

namespace tessera::fixed {

inline constexpr int kSubpixelBits = 8;                        // D3D11_SUBPIXEL_FRACTIONAL_BIT_COUNT
inline constexpr std::int64_t kOne = 1 << kSubpixelBits;       // 256 units per pixel
inline constexpr std::int64_t kHalf = kOne / 2;                // the pixel centre offset, 128 units

// Guard band: triangles whose window coordinates stay within +-2^21 px are rasterized
// without x/y clipping; larger ones are clipped in homogeneous space to that box. Overflow
// argument for the int64 edge functions E = A*(X - Xa) + B*(Y - Ya) (units of 1/256 px):
//   |X|, |Y| <= 2^21 px * 2^8 = 2^29 units for vertices and for every sample point (the
//   largest surface, 16384 px = 2^22 units, lies inside); differences <= 2^30; each product
//   <= 2^60; the sum of two <= 2^61 < 2^63. Twice the triangle area obeys the same bound.
inline constexpr double kGuardBandPx = 2097152.0;  // 2^21 px

// Snaps a window coordinate (px) to 16.8 fixed point, rounding to nearest even as the
// D3D11.3 float -> fixed conversion does (§3.2.4.1). Caller guarantees |px| <= kGuardBandPx.
inline std::int32_t snap(float px) {
    return static_cast<std::int32_t>(std::nearbyint(static_cast<double>(px) * double(kOne)));
}

} // namespace tessera::fixed
