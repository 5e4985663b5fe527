// Scalar data conversions of the D3D11.3 functional specification (§3.1.5, §3.1.6, §3.2
// "Data Conversion"), used by the texel codec (texel_codec.h) and the depth buffer (D24).
// Every function is exact and deterministic: the same input bits give the same output bits
// on every compiler and machine (no libm calls; sRGB goes through verified literal tables).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace tessera::convert {

// ---- Normalized integers (§3.2.3 "Integer Conversion") ------------------------------------
// `bits` is the field width n: 1..24 for UNORM, 2..24 for SNORM (24 = D24 depth). Up to 24 bits
// the float32 input times (2^n - 1) is exact in double (24 + 24 significand bits <= 53).

// §3.2.3.6 "FLOAT -> UNORM": NaN -> 0; c > 1 (incl. +INF) -> 1, c < 0 (incl. -INF) -> 0;
// c *= (2^n - 1); then "c = c + 0.5f, drop the decimal fraction" = round half UP. The spec
// permits 0.6 ULP on the integer side; tessera returns the exact result of that rule applied
// to the real-number product. Exact ties occur only at c = 0.5 (c * (2^n-1) = 2^(n-1) - 1/2,
// since 2^n - 1 is odd), where half-up and round-to-nearest-even agree for every n >= 2.
std::uint32_t floatToUnorm(float x, unsigned bits);
// §3.2.3.5 "UNORM -> FLOAT": float(c) / (2^n - 1); §3.2.3.2 requires 1/2 ULP, so this is the
// correctly rounded quotient (one IEEE division of two exactly representable operands).
float unormToFloat(std::uint32_t c, unsigned bits);
// §3.2.3.4 "FLOAT -> SNORM": NaN -> 0; clamp to [-1, 1] (incl. +-INF); c *= (2^(n-1) - 1);
// "if c >= 0, c = c + 0.5f, else c = c - 0.5f; drop the fraction" = round half AWAY from zero
// (0.6 ULP allowed; tessera is exact). The result is two's complement in the low n bits, so
// -1.0 gives -(2^(n-1) - 1) and the most negative code is never produced.
std::uint32_t floatToSnorm(float x, unsigned bits);
// §3.2.3.3 "SNORM -> FLOAT": the most negative code -2^(n-1) -> -1.0f; every other code c ->
// c / (2^(n-1) - 1), so -(2^(n-1) - 1) -> -1.0f too (two encodings of -1, §3.2.3.1). The spec
// writes c * (1.0f / (2^(n-1)-1)); §3.2.3.2 demands 1/2 ULP of the exact value, which tessera
// reads as the correctly rounded quotient (a single IEEE division), matching UNORM -> FLOAT.
float snormToFloat(std::uint32_t c, unsigned bits);

// ---- float16 (§3.1.5 "16-bit Floating Point", conversions §3.2.2) --------------------------
// §3.2.2 "Floating Point Conversion" (higher -> lower range): "Round-to-zero must be used
// during conversion to another float format"; finite values beyond the range become the
// largest finite value of the right sign (+-65504, "NOT including signed infinity"); +-INF ->
// +-INF; NaN -> NaN; values in the float16 denormal range become float16 denormals (truncated);
// float32 denormals (< 2^-126) truncate to a zero of the same sign. NaN keeps its sign and its
// top 10 payload bits; a payload that would truncate to 0 becomes the quiet NaN bit (0x200).
std::uint16_t floatToHalf(float x);
// Lower -> higher range (§3.2.2): exact. Denormals become normalized float32, +-INF and signed
// zero are kept, NaN keeps its sign and payload (shifted up 13 bits).
float halfToFloat(std::uint16_t h);

// ---- float11 / float10 (§3.1.6 "11-bit and 10-bit Floating Point", §19.3.3 R11G11B10) ------
// No sign bit; 5-bit exponent, bias 15; 6 (float11) or 5 (float10) fraction bits; e == 31 is
// +INF (f == 0) or NaN (f != 0); e == 0 is a denormal f * 2^(-14 - fractionBits).
// float32 -> float11/10 per §3.2.2 and §3.1.6: NaN (either sign) -> NaN (top payload bits kept,
// or the top fraction bit if they truncate to 0); anything less than zero, -0 and -INF clamp to
// 0 (§3.1.6 "Sign"); +INF -> +INF; finite overflow -> largest finite value (float11 65024 =
// 0x7BF, float10 64512 = 0x3DF), not INF; otherwise round toward zero, denormals kept.
// Results are the raw codes in the low 11 / 10 bits.
std::uint32_t floatToFloat11(float x);
std::uint32_t floatToFloat10(float x);
// Exact (every float11/10 value is a float32). Bits above the low 11 / 10 are ignored.
float float11ToFloat(std::uint32_t v);
float float10ToFloat(std::uint32_t v);

// ---- sRGB (§3.2.3.7 "SRGB -> FLOAT", §3.2.3.8 "FLOAT -> SRGB") ----------------------------
// §3.2.3.8: NaN -> 0; clamp to [0, 1] (incl. +-INF); c <= 0.0031308f ? 12.92*c :
// 1.055*c^(1/2.4) - 0.055; then *255, "+0.5, drop the fraction" (round half up; 0.6 ULP
// allowed). tessera returns the exact result of that rule on the real-valued curve (decimal
// constants): the code is the number of the 255 decision thresholds t_k <= linear, where t_k is
// the smallest float whose ideal sRGB value reaches (k - 0.5)/255. The literal threshold table
// is regenerated in long double by tests/buffers/conversion_test.cpp (closest float lies 2.2e-9
// code units from a decision boundary, far beyond the long double error).
std::uint8_t linearToSrgb8(float linear);
// §3.2.3.7: c = code/255; c <= 0.04045 ? c/12.92 : ((c + 0.055)/1.055)^2.4 (0.5 ULP tolerance
// on the sRGB side; 0 and 1 exact). tessera returns the float nearest the exact value, from a
// 256-entry literal table regenerated by the same test.
float srgb8ToLinear(std::uint8_t code);

// ---- Depth (D24_UNORM_S8_UINT) --------------------------------------------------------------
// D24 depth is a 24-bit UNORM (§3.2.3.5 / §3.2.3.6) in bits 0..23 of the texel.
// floatToUnorm(z, 24) spelled out so that the depth test inlines it: the same clamp, the
// product in double (exact: 24 + 24 bits), round half up on the exact fraction.
inline std::uint32_t depthToD24(float z) {
    if (!(z > 0.0f)) return 0;  // NaN, negatives, +-0
    if (z >= 1.0f) return 0xFFFFFFu;
    const double p = static_cast<double>(z) * 16777215.0;
    const auto i = static_cast<std::int32_t>(p);  // 0 <= p < 2^24
    return static_cast<std::uint32_t>(i) + (p - static_cast<double>(i) >= 0.5 ? 1u : 0u);
}
inline float d24ToDepth(std::uint32_t code) { return unormToFloat(code & 0xFFFFFFu, 24); }

// The UNORM conversion's clamp (D3D11.3 §3.2.3.6) without the rounding: NaN -> 0, then
// [0, 1]. What precision reference's float copy of an UNORM target holds.
inline glm::vec4 clampUnorm(const glm::vec4& v) {
    glm::vec4 out;
    for (int c = 0; c < 4; ++c) out[c] = v[c] > 0.0f ? (v[c] < 1.0f ? v[c] : 1.0f) : 0.0f;
    return out;
}

} // namespace tessera::convert
