// The HLSL Development Cookbook's G-buffer math (Feinstein 2013, ch. 2 "Deferred Shading", recipes
// "GBuffer generation" and "GBuffer unpacking"): specular power packed linearly over
// g_SpecPowerRange = {0.1, 250}, the normal stored as n * 0.5 + 0.5, linear depth from
// PerspectiveValues and the world position from it. Left-handed view space (+z forward) and
// row-vector matrices as the book; tests/gbuffer/cookbook_gbuffer_test.cpp checks each against
// geometric truth and the book's worked values.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace tessera {

// g_SpecPowerRange: x = the minimum power, y = "the affective range (maximum - minimum)"
// (Cookbook ch. 2, GBuffer generation): powers 0.1 .. 250.1.
inline constexpr float kCookbookSpecPowerMin = 0.1f;
inline constexpr float kCookbookSpecPowerRange = 250.0f;

// PackGBuffer: SpecPowerNorm = (SpecPower - g_SpecPowerRange.x) / g_SpecPowerRange.y. Unclamped
// (the R8G8B8A8_UNORM target saturates it: powers below 0.1 store 0, above 250.1 store 255).
float packCookbookSpecPower(float specPower);

// The intended decode, applied once: 0.1 + 250 * norm ("the inverse operation with the same
// values"). Stored 0 decodes to the minimum 0.1; code 255 to 250.1.
float unpackCookbookSpecPower(float norm);

// The decode as the chapter prints it (ERRATA.md): UnpackGBuffer's
// `SpecPowerNorm.x + SpecPowerNorm * g_SpecPowerRange.y` (= 251 * norm) and then every light
// pixel shader's `g_SpecPowerRange.x + g_SpecPowerRange.y * gbd.SpecPow` on that result:
// 0.1 + 250 * (251 * norm). Code 255 gives 62750.1; code 0 still 0.1.
float unpackCookbookSpecPowerAsPrinted(float norm);

// The 8-bit code the R8G8B8A8_UNORM target stores for a power (float -> UNORM, D3D11.3 §3.2.3.6).
std::uint8_t cookbookSpecPowerCode(float specPower);

// PackGBuffer's normal: Normal.xyz * 0.5 + 0.5 (stored in R11G11B10_FLOAT, W ignored).
glm::vec3 packCookbookNormal(const glm::vec3& normal);
// UnpackGBuffer's normal: normalize(stored * 2.0 - 1.0).
glm::vec3 unpackCookbookNormal(const glm::vec3& stored);

// cbGBufferUnpack.PerspectiveValues (Cookbook ch. 2, GBuffer unpacking): x = 1 / Pm[0][0],
// y = 1 / Pm[1][1], z = Pm[3][2], w = -Pm[2][2] of the row-vector left-handed projection
// [w 0 0 0; 0 h 0 0; 0 0 Q 1; 0 0 -Q Zn 0] with Q = Zf / (Zf - Zn).
struct CookbookPerspectiveValues {
    float x = 1.0f, y = 1.0f, z = 0.0f, w = 0.0f;
};
// From a column-vector left-handed projection (tessera's projectionLh: clip = P * posViewLh),
// whose element P[col][row] is the row-vector matrix's Pm[col][row] transposed: Pm[3][2] = P[3][2]
// in glm's [column][row] indexing, Pm[2][2] = P[2][2].
CookbookPerspectiveValues cookbookPerspectiveValues(const glm::mat4& projectionLh);

// ConvertDepthToLinear: PerspectiveValues.z / (depth + PerspectiveValues.w), the view-space z
// (the book's "linear depth") of a depth-buffer value: depth 0 -> Zn, 1 -> Zf. T = float is the
// shader's arithmetic; T = double the reference mode's.
template <class T>
T cookbookLinearDepth(T depth, const CookbookPerspectiveValues& pv) {
    return T(pv.z) / (depth + T(pv.w));
}

// CalcWorldPos: position = (csPos * PerspectiveValues.xy * linearDepth, linearDepth, 1) in view
// space, then mul(position, ViewInv): the world position under the pixel whose clip-space x, y
// is csPos. worldFromViewLh is the column-vector inverse view (ViewInv transposed).
template <class T>
glm::vec<3, T> cookbookWorldPosition(const glm::vec<2, T>& csPos, T linearDepth, const CookbookPerspectiveValues& pv,
                                     const glm::mat<4, 4, T>& worldFromViewLh) {
    const glm::vec<4, T> posViewLh(csPos.x * T(pv.x) * linearDepth, csPos.y * T(pv.y) * linearDepth, linearDepth, T(1));
    return glm::vec<3, T>(worldFromViewLh * posViewLh);
}

} // namespace tessera
