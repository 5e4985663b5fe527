// Texture sampling with the rules of the D3D11.3 functional specification §7.18 "Texture
// Sampling": LOD from derivatives, bias and clamps, mip selection, texel addressing, address
// modes, bilinear and trilinear filtering. Called per pixel by pixel shaders (through
// Texture2D::sample and friends); no allocation, no virtual calls.
//
// One sample, step by step (for each of U and V independently where it says "per axis"):
//  1. LOD (§7.18.11), `sample` only: derivatives scaled by the level-0 size in texels,
//       LOD = log2(max(|ddx * size|, |ddy * size|)).
//     §7.18.11 gives an isotropic formula (this one) and allows approximations of an ideal
//     orthogonalised-Jacobian transform [Heckbert 89]. tessera uses the isotropic formula
//     exactly as written, without the transform: it is the spec's literal pseudocode for
//     non-anisotropic samplers (the only kind SamplerState has), the transform is optional, and
//     the plain formula is cheap and exact where it matters (powers of two give integer LODs).
//     It is evaluated as 0.5 * log2(max(|dX|^2, |dY|^2)) in double from the float derivatives,
//     with a libm-independent log2, then rounded once to float.
//  2. biased = LOD + MipLODBias (+ the sampleBias operand); clamped = max(MinLOD, min(MaxLOD,
//     biased)), with D3D min/max (§3.1: a NaN operand yields the other one), so MinLOD wins when
//     MinLOD > MaxLOD and a NaN LOD becomes MaxLOD.
//  3. Magnification when clamped <= 0 (§7.18.11 "Magnifying = (LOD <= 0)"): magFilter, else
//     minFilter. The spec leaves open whether the decision comes before or after MinLOD/MaxLOD;
//     tessera decides on the clamped LOD, as the spec's own worked examples do (§5.8.6 "since
//     the post-clamped LOD is > 0, the minfilter is used").
//  4. Mip selection (§7.18.10) on clamped LOD limited to [0, levels - 1]: mipFilter Point takes
//     the nearest level (fraction >= 0.5 rounds up); Linear takes floor and floor + 1 with
//     weight wCeil = fraction and blends the two filtered results.
//  5. Range reduction per axis (§7.18.6): Wrap frac(u); Mirror 2 * signedFrac(u / 2);
//     Clamp/Border/MirrorOnce clamp to [-10, 10]. This keeps texel indices small for any input
//     (huge or infinite u cannot overflow); NaN becomes texel coordinate 0 (§3.2.4.1).
//  6. Texel addressing per axis: Point (§7.18.7) t = floor(u * size); Linear (§7.18.8)
//     s = u * size - 0.5, tFloor = floor(s), tCeil = tFloor + 1, wCeil = s - floor(s).
//  7. Address mode per texel index (§7.18.9, see addressTexel below); Border in either axis
//     returns the border colour for that tap (§7.18.9.1), clamped to [0, 1] for the UNORM
//     formats (NaN -> 0) and used as given for R32G32B32A32_FLOAT.
//  8. Texels are decoded before filtering (sRGB to linear, §3.2.3.7 and §22.4.15 "Return Type
//     Control"), then blended: a + (b - a) * w along U, then along V, then between mips.
//
// Precision: §7.18.16.1 requires at least 8 fractional bits of subtexel precision and 8
// fractional LOD bits; hardware quantizes weights to 1/256. tessera keeps exact float weights
// (wCeil = s - floor(s) is exact in float; the mip weight is the exact LOD fraction) and does
// not quantize them: the result is the ideal bilinear/trilinear value in float32, which
// satisfies the spec's minimum precision and is identical on every machine. The lerp form
// returns a constant texture's colour exactly and is monotonic in each weight (§7.18.16.3).
// Taps whose weight is 0 are not fetched, so NaN/INF in them does not propagate (§7.18.16.2).
#pragma once

#include <glm/glm.hpp>

#include <tessera/texture/sampler_state.h>
#include <tessera/texture/texture2d.h>

namespace tessera {

// HLSL Texture2D.Sample(sampler, uv) (`sample`, §22.4.15) with the shader's coarse derivatives
// of uv: pass in.ddx.uv and in.ddy.uv of PixelInput. LOD per pixel from these derivatives.
glm::vec4 sample(const Texture2D& texture, const SamplerState& sampler, glm::vec2 uv, glm::vec2 ddxUv,
                 glm::vec2 ddyUv);

// HLSL Texture2D.SampleBias (`sample_b`, §22.4.16): `lodBias` (levels, -16..15.99) is added to
// the computed LOD together with MipLODBias, before the MinLOD/MaxLOD clamp.
glm::vec4 sampleBias(const Texture2D& texture, const SamplerState& sampler, glm::vec2 uv, glm::vec2 ddxUv,
                     glm::vec2 ddyUv, float lodBias);

// HLSL Texture2D.SampleGrad (`sample_d`, §22.4.17): derivatives given by the caller. Since
// `sample` already takes its derivatives explicitly (and tessera computes its LOD per pixel,
// which §22.4.15 allows), the two are the same function.
inline glm::vec4 sampleGrad(const Texture2D& texture, const SamplerState& sampler, glm::vec2 uv,
                            glm::vec2 ddxUv, glm::vec2 ddyUv) {
    return sample(texture, sampler, uv, ddxUv, ddyUv);
}

// HLSL Texture2D.SampleLevel (`sample_l`, §22.4.18): `lod` given directly (levels, isotropic);
// MipLODBias, MinLOD and MaxLOD still apply; LOD <= 0 after them magnifies level 0.
glm::vec4 sampleLevel(const Texture2D& texture, const SamplerState& sampler, glm::vec2 uv, float lod);

// HLSL CalculateLevelOfDetailUnclamped (`lod` instruction .y, §22.5.6): step 1 above, no bias,
// no clamp; -INF for zero derivatives, NaN for NaN ones. 0 for an empty texture.
float calculateLodUnclamped(const Texture2D& texture, glm::vec2 ddxUv, glm::vec2 ddyUv);

// HLSL CalculateLevelOfDetail (`lod` instruction .x): the LOD `sample` would use for mip
// selection: steps 1, 2 and the limit to [0, levels - 1] (fractional; NaN -> 0).
float calculateLod(const Texture2D& texture, const SamplerState& sampler, glm::vec2 ddxUv, glm::vec2 ddyUv);

// The address mode of §7.18.9 applied to one integer texel index `texel` of an axis `size`
// texels long: the index to fetch, or -1 for Border when the index is off the texture.
//   Wrap       texel mod size (into [0, size))
//   Mirror     t = texel < 0 ? -texel - 1 : texel; odd tiles (t / size odd) run backwards
//   Clamp      clamp to [0, size - 1]
//   MirrorOnce t = texel < 0 ? -texel - 1 : texel; clamp to [0, size - 1]
//   Border     -1 when texel < 0 or texel >= size
// E.g. size 4: texel -1 -> Wrap 3, Mirror 0, Clamp 0, MirrorOnce 0, Border -1;
//              texel  5 -> Wrap 1, Mirror 2, Clamp 3, MirrorOnce 3, Border -1.
inline int addressTexel(int texel, int size, AddressMode mode) {
    if (texel >= 0 && texel < size) return texel;
    switch (mode) {
    case AddressMode::Wrap: {
        int t = texel % size;
        return t < 0 ? t + size : t;
    }
    case AddressMode::Mirror: {
        int t = texel < 0 ? -texel - 1 : texel;
        const bool flip = ((t / size) & 1) != 0;  // odd tile
        t %= size;
        return flip ? size - t - 1 : t;
    }
    case AddressMode::Clamp: return texel < 0 ? 0 : size - 1;
    case AddressMode::MirrorOnce: {
        const int t = texel < 0 ? -texel - 1 : texel;
        return t < size ? t : size - 1;
    }
    case AddressMode::Border: return -1;
    }
    return 0;  // §7.18.9 "default: scaledU = 0"
}

} // namespace tessera
