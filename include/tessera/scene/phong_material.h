// The 3dgep shading model's material (3dgep article §2.2.1; the demo's Engine/inc/Material.h, 160-byte
// constant buffer): Phong colours, opacity, specular power, eight texture slots, with the demo's
// defaults, and the one place where a glTF metallic-roughness material maps onto it.
#pragma once

#include <glm/glm.hpp>

#include <tessera/scene/material.h>

namespace tessera {

// Field names follow the HLSL struct (GlobalAmbient -> globalAmbient, ...). Defaults are the
// demo's MaterialProperties constructor (3dgep/ForwardPlus Engine/inc/Material.h).
struct PhongMaterial {
    glm::vec4 globalAmbient{0.1f, 0.1f, 0.15f, 1.0f};
    glm::vec4 ambientColor{0.0f, 0.0f, 0.0f, 1.0f};
    glm::vec4 emissiveColor{0.0f, 0.0f, 0.0f, 1.0f};
    glm::vec4 diffuseColor{1.0f, 1.0f, 1.0f, 1.0f};
    glm::vec4 specularColor{0.0f, 0.0f, 0.0f, 1.0f};
    glm::vec4 reflectance{0.0f, 0.0f, 0.0f, 0.0f};   // unused by the shaders
    float opacity = 1.0f;
    float specularPower = -1.0f;       // the shaders add specular only when specularPower > 1
    float indexOfRefraction = -1.0f;   // unused by the shaders
    float bumpIntensity = 5.0f;        // height scale of bump maps
    float specularScale = 128.0f;      // specular-power texture .r is multiplied by this
    float alphaThreshold = 0.1f;       // pixels with alpha * opacity < alphaThreshold are discarded (G-buffer PS)

    // Slots t0..t7 (Material::TextureType); present() <=> the HLSL Has*Texture flag.
    TextureRef ambientTexture, emissiveTexture, diffuseTexture, specularTexture, specularPowerTexture,
        normalTexture, bumpTexture, opacityTexture;

    // tessera additions (not in the demo's constant buffer):
    // The demo's Texture::IsTransparent() of the diffuse texture ("has an alpha channel").
    bool diffuseTextureHasAlpha = false;
    // glTF OPAQUE: a shader takes alpha = 1 instead of the diffuse colour's alpha (before
    // multiplying by opacity and testing alphaThreshold), as glTF 2.0 §3.9.4 requires.
    bool ignoreDiffuseAlpha = false;
    bool doubleSided = false;          // glTF doubleSided (the demo culls back faces of opaque geometry)
    // glTF 2.0 §3.9.5: back faces are shaded with N, T and B negated (reversesBackFaceNormals).
    bool reverseBackFaceNormals = false;

    // The demo's Material::IsTransparent(): opacity < 1, an opacity texture, a diffuse texture
    // with alpha, or alphaThreshold <= 0. Transparent materials are drawn in the blended pass.
    bool isTransparent() const {
        return opacity < 1.0f || opacityTexture.present() || (diffuseTexture.present() && diffuseTextureHasAlpha) ||
               alphaThreshold <= 0.0f;
    }
};

// 2^10.5 = 1448.1547: the largest specular power the deferred G-buffer's log2(p)/10.5 packing
// represents (3dgep article §3.1.1.4, the Killzone 2 method); phongFromGltf clamps to it.
inline constexpr float kPhongMaxSpecularPower = 1448.15466f;
// Specular colour of a dielectric (F0 = 0.04 = ((1.5 - 1) / (1.5 + 1))^2, IOR 1.5), as in the
// glTF 2.0 specification's Appendix B (metal-rough BRDF).
inline constexpr float kDielectricSpecular = 0.04f;

// Maps a glTF material onto the 3dgep material. Everything is binary32 arithmetic with +, -, *,
// / only (no libm), so the result is the same on every compiler.
//
//   PhongMaterial field        from the glTF material
//   -------------------------  -------------------------------------------------------------------
//   globalAmbient              demo default (0.1, 0.1, 0.15, 1)
//   ambientColor, Texture      (baseColorFactor.rgb, 1) and baseColorTexture: sponza.mtl's
//                              convention map_Ka = map_Kd (ambient = base colour x 0.1/0.1/0.15)
//   emissiveColor              (emissiveFactor, 1)
//   emissiveTexture            emissiveTexture, only when emissiveFactor != 0 (the demo's rule
//                              "any(colour) ? colour * texel : texel" would show the texel where
//                              glTF gives black)
//   diffuseColor               OPAQUE, BLEND: (baseColorFactor.rgb, 1); MASK: baseColorFactor (its
//                              alpha enters the cut-out through the demo's rule, which multiplies
//                              alpha too: alpha = factor.a x texel.a)
//   diffuseTexture             baseColorTexture, only when baseColorFactor.rgb != 0 (as above; a
//                              black factor gives black diffuse and loses the texture's alpha)
//   specularColor              (lerp(0.04, baseColorFactor.rgb, metallicFactor), 1)
//   specularPower              p = 2 / a^2 - 2 with a = roughnessFactor^2 (roughness clamped to
//                              [0, 1]), clamped to [0, 2^10.5]; the Beckmann/Blinn-Phong
//                              correspondence (Walter et al. 2007, "Microfacet Models for
//                              Refraction", eq. 33 solved for the exponent), used unchanged as
//                              the demo's Phong exponent. p <= 1 means "no specular" in the demo.
//                              roughness 1 -> 0, 0.5 -> 30, 0.25 -> 510, 0 -> 1448.15
//   opacity                    BLEND: baseColorFactor.a; OPAQUE, MASK: 1
//   alphaThreshold             OPAQUE: 0.1 (default, inert: ignoreDiffuseAlpha); MASK: alphaCutoff
//                              (a cutoff <= 0 cuts nothing: mapped as OPAQUE); BLEND: 0 (no
//                              cut-out; the demo's rule then classes the material transparent)
//   normalTexture              normalTexture (its scale kept in TextureRef::scale)
//   diffuseTextureHasAlpha     BLEND with a baseColorTexture (glTF reads its alpha)
//   ignoreDiffuseAlpha         OPAQUE (and MASK with alphaCutoff <= 0)
//   doubleSided                doubleSided
//   not mapped                 metallicRoughnessTexture, occlusionTexture (the demo has no slot;
//                              the factors alone are used), specular, specularPower, bump and
//                              opacity textures (none), reflectance, indexOfRefraction, bumpIntensity,
//                              specularScale (demo defaults)
//
// isTransparent() of the result: BLEND -> true; OPAQUE, MASK -> false.
PhongMaterial phongFromGltf(const Material& material);

} // namespace tessera
