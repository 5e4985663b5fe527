// Specular power in the 3dgep G-buffer (3dgep article §3.1.1.4, "Killzone 2 method"): the specular
// target's alpha stores log2(p)/10.5, the R8G8B8A8_UNORM target quantizes it to 8 bits, and the
// lighting pass unpacks exp2(a * 10.5). Called by the deferred G-buffer and lighting shaders;
// tests/gbuffer/specular_power_packing_test.cpp checks the round trip's error bound.
#pragma once

#include <cstdint>

namespace tessera {

// log2 range stored in a in [0, 1]: p in [2^0, 2^10.5] = [1, 1448.15] (3dgep article §3.1.1.4).
inline constexpr float kSpecularPowerLog2Range = 10.5f;
// 2^10.5 = 1448.1547 (float nearest): the largest power the packing represents; larger
// powers saturate to it (UNORM clamps a > 1 to code 255).
inline constexpr float kMaxPackedSpecularPower = 1448.15466f;

// G-buffer PS: `log2(specularPower) / 10.5f` (3dgep article §3.1.2). Unclamped: the target's
// float -> UNORM conversion saturates it. p = 1 gives 0; p in (0, 1) a negative value, p = 0
// -inf, p < 0 and NaN give NaN: all store code 0 (D3D11.3 §3.2.3.6: NaN -> 0, c < 0 -> 0).
float packSpecularPower(float specularPower);

// Lighting PS: `exp2(specular.a * 10.5f)` (3dgep article §3.3.3). a = 0 gives exactly 1.
float unpackSpecularPower(float packed);

// The 8-bit code the R8G8B8A8_UNORM specular target stores for a power (float -> UNORM,
// round half up, D3D11.3 §3.2.3.6, through tessera::convert::floatToUnorm).
std::uint8_t specularPowerCode(float specularPower);

// The power the lighting pass sees after the G-buffer round trip:
// unpack(unormToFloat(specularPowerCode(p), 8)).
// Error bound (derived in the test): code k = round(255 * log2(p) / 10.5), so for p in
// [1, 1448.15] |log2 p' - log2 p| <= (1/2) * 10.5/255 and p'/p lies in
// [2^(-10.5/510), 2^(10.5/510)]: relative error <= 2^(10.5/510) - 1 = 1.4374 % (one code step
// is a factor 2^(10.5/255) = 1.0290). Outside that range:
//   p <= 1 (incl. 0, negative, NaN) -> 1. The 3dgep shaders gate specular with
//     `SpecularPower > 1.0f`; the G-buffer PS writes specular colour 0 for such materials
//     (demo PS_Geometry), so the unpacked 1 contributes nothing. Note that p in (1, 2^(10.5/510))
//     = (1, 1.01437) passes the gate at G-buffer time but still stores code 0 and unpacks to 1.
//   p > 1448.15 (incl. +inf) -> 1448.15 (saturated).
float roundTripSpecularPower(float specularPower);

} // namespace tessera
