// The 3dgep pixel shaders' material gathering (3dgep article §2.3.1; the demo's ForwardRendering.hlsl
// PS_main and DeferredRendering.hlsl PS_Geometry share it): diffuse, alpha and the optional
// cut-out, ambient, emissive, specular power and colour, the view-space normal with normal or
// bump mapping, in the shaders' order of operations. Forward, Forward+ and the G-buffer run it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>

#include <tessera/shading/light_term.h>
#include <tessera/shading/phong_material_shader.h>

namespace tessera {

namespace phong_detail {

template <class T>
Vec3<T> cross3(const Vec3<T>& a, const Vec3<T>& b) {  // HLSL cross: a.yzx * b.zxy - a.zxy * b.yzx
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
Vec3<T> neg3(const Vec3<T>& v) {
    return {-v.x, -v.y, -v.z};
}
// mul(v, float3x3(T, B, N)) with the rows T, B, N: v.x * T + v.y * B + v.z * N, left to right.
template <class T>
Vec3<T> mulRowTbn(const Vec3<T>& v, const Vec3<T>& t, const Vec3<T>& b, const Vec3<T>& n) {
    return (t * v.x + b * v.y) + n * v.z;
}
// The colour/texture rule: c = any(c.rgb) ? c * texel : texel (alpha included).
template <class T>
[[gnu::always_inline]] inline Vec4<T> textureRule(const Vec4<T>& color, const Vec4<T>& texel) {  // inlined: see hlsl::normalize
    const bool any = color.x != T(0) || color.y != T(0) || color.z != T(0);
    return any ? color * texel : texel;
}

} // namespace phong_detail

// The compile-time specializations of the Phong shaders (forward's PS and the G-buffer PS): bit b
// of a variant index selects kPhongVariantAxes[b]; the other features are tested at run time.
inline constexpr std::array<std::uint32_t, 5> kPhongVariantAxes{kPhongAmbientTexture, kPhongEmissiveTexture,
                                                                kPhongDiffuseTexture, kPhongNormalMap, kPhongAlphaTest};
static_assert((kPhongVariantAxes[0] | kPhongVariantAxes[1] | kPhongVariantAxes[2] | kPhongVariantAxes[3] |
               kPhongVariantAxes[4]) == kPhongSpecializedAxes);
inline constexpr std::size_t kPhongVariantCount = std::size_t(1) << kPhongVariantAxes.size();

// The feature mask (kPhong*) of variant `index`, and the variant index of a feature mask.
constexpr std::uint32_t phongVariantMask(std::size_t index) {
    std::uint32_t mask = 0;
    for (std::size_t b = 0; b < kPhongVariantAxes.size(); ++b)
        if ((index >> b) & 1u) mask |= kPhongVariantAxes[b];
    return mask;
}
constexpr std::size_t phongVariantIndex(std::uint32_t mask) {
    std::size_t index = 0;
    for (std::size_t b = 0; b < kPhongVariantAxes.size(); ++b)
        if ((mask & kPhongVariantAxes[b]) != 0) index |= std::size_t(1) << b;
    return index;
}

// One pixel's material inputs to the lighting, as the shaders hold them before lighting.
template <class T>
struct PhongSurface {
    Vec4<T> diffuse;       // DiffuseColor with the texture rule (not yet lit)
    T alpha;               // diffuse.a, or the opacity texture's .r
    Vec4<T> ambient;       // AmbientColor (texture rule) * GlobalAmbient
    Vec4<T> emissive;      // EmissiveColor (texture rule)
    T specularPower;       // SpecularPower, or the texture's .r * SpecularScale
    Vec4<T> specular;      // SpecularColor (texture rule) when specularPower > 1, else 0
    Vec4<T> normalView;    // view-space N, w = 0 (bump mapped: not normalized)
};

// Gathers the surface of pixel `in` for material `d` with compile-time features F (kPhong*).
// Returns false when the alpha test (kPhongAlphaTest) discards the pixel; then only diffuse
// and alpha are set.
template <class T, std::uint32_t F>
bool gatherPhongSurface(const PhongShaderData<T>& d, const PixelInput<PhongVaryings>& in, PhongSurface<T>& s) {
    using namespace phong_detail;
    const auto texel = [&](const BoundTexture& slot) { return Vec4<T>(slot.sample(in)); };
    // The tangent frame this face is lit with (glTF 2.0 §3.9.5: reversed on double-sided back faces).
    const PhongVaryings v = facingVaryings(in.varyings, in.isFrontFace, d.reverseBackFaceNormals);

    // Diffuse, alpha (and the optional cut-out) first: a discarded pixel needs nothing else.
    Vec4<T> diffuse = d.diffuseColor;
    if constexpr ((F & kPhongDiffuseTexture) != 0)
        if (d.diffuseTexture.bound()) diffuse = textureRule(diffuse, texel(d.diffuseTexture));
    T alpha = d.ignoreDiffuseAlpha ? T(1) : diffuse.w;
    if constexpr ((F & kPhongOpacityTexture) != 0)
        if (d.opacityTexture.bound()) alpha = texel(d.opacityTexture).x;  // .r: 1-channel textures return a = 1
    if constexpr ((F & kPhongAlphaTest) != 0)
        if (alpha * d.opacity < d.alphaThreshold) {  // PS_Geometry: discard
            s.diffuse = diffuse;
            s.alpha = alpha;
            return false;
        }

    Vec4<T> ambient = d.ambientColor;
    if constexpr ((F & kPhongAmbientTexture) != 0)
        if (d.ambientTexture.bound()) ambient = textureRule(ambient, texel(d.ambientTexture));
    ambient *= d.globalAmbient;

    Vec4<T> emissive = d.emissiveColor;
    if constexpr ((F & kPhongEmissiveTexture) != 0)
        if (d.emissiveTexture.bound()) emissive = textureRule(emissive, texel(d.emissiveTexture));

    T specularPower = d.specularPower;
    if constexpr ((F & kPhongSpecularPowerTexture) != 0)
        if (d.specularPowerTexture.bound()) specularPower = texel(d.specularPowerTexture).x * d.specularScale;

    Vec4<T> normalView;
    bool mapped = false;
    if constexpr ((F & kPhongNormalMap) != 0) {
        if (d.normalTexture.bound()) {  // DoNormalMapping: normalize(mul(tex * 2 - 1, TBN))
            const Vec3<T> t = hlsl::normalize(Vec3<T>(v.tangentView));
            const Vec3<T> b = hlsl::normalize(Vec3<T>(v.binormalView));
            const Vec3<T> n = hlsl::normalize(Vec3<T>(v.normalView));
            const Vec3<T> expanded = Vec3<T>(texel(d.normalTexture)) * T(2) - T(1);
            normalView = hlsl::normalize(Vec4<T>(mulRowTbn(expanded, t, b, n), T(0)));
            mapped = true;
        }
    }
    if constexpr ((F & kPhongBumpMap) != 0) {
        if (!mapped && d.bumpTexture.bound()) {  // DoBumpMapping with the negated binormal; NOT normalized
            const Vec3<T> t = hlsl::normalize(Vec3<T>(v.tangentView));
            const Vec3<T> b = hlsl::normalize(neg3(Vec3<T>(v.binormalView)));
            const Vec3<T> n = hlsl::normalize(Vec3<T>(v.normalView));
            const T height = T(d.bumpTexture.sample(in).x) * d.bumpIntensity;
            const T heightU = T(d.bumpTexture.sample(in, glm::ivec2(1, 0)).x) * d.bumpIntensity;
            const T heightV = T(d.bumpTexture.sample(in, glm::ivec2(0, 1)).x) * d.bumpIntensity;
            const Vec3<T> p{T(0), T(0), height}, pU{T(1), T(0), heightU}, pV{T(0), T(1), heightV};
            const Vec3<T> normal = cross3(hlsl::normalize(pU - p), hlsl::normalize(pV - p));
            normalView = Vec4<T>(mulRowTbn(normal, t, b, n), T(0));
            mapped = true;
        }
    }
    if (!mapped) normalView = hlsl::normalize(Vec4<T>(Vec3<T>(v.normalView), T(0)));

    Vec4<T> specular(T(0));
    if (specularPower > T(1)) {  // "If specular power is too low, don't use it."
        specular = d.specularColor;
        if constexpr ((F & kPhongSpecularTexture) != 0)
            if (d.specularTexture.bound()) specular = textureRule(specular, texel(d.specularTexture));
    }
    s.diffuse = diffuse;
    s.alpha = alpha;
    s.ambient = ambient;
    s.emissive = emissive;
    s.specularPower = specularPower;
    s.specular = specular;
    s.normalView = normalView;
    if (WatchedSurface* watched = watchedSurface()) [[unlikely]] {  // `tessera probe`'s pixel
        const auto d4 = [](const Vec4<T>& c) { return glm::dvec4(double(c.x), double(c.y), double(c.z), double(c.w)); };
        *watched = {true, d4(diffuse), d4(ambient), d4(emissive), d4(specular), double(alpha), double(specularPower)};
    }
    return true;
}

// The float gather for a material's feature mask (phongFeatures): a compile-time specialisation
// when the mask uses only kPhongSpecializedAxes, otherwise the generic all-features shader (with
// or without the alpha test). `name` is "<prefix>:<features>" or "<prefix>:generic(<features>)",
// the shader-variant counter's key (--stats).
using PhongGatherFn = bool (*)(const PhongShaderData<float>&, const PixelInput<PhongVaryings>&, PhongSurface<float>&);
struct PhongGatherVariant {
    PhongGatherFn fn = nullptr;
    bool mayDiscard = false;
    std::string name;
};

namespace phong_detail {
template <std::size_t... I>
constexpr std::array<PhongGatherFn, sizeof...(I)> makeGatherTable(std::index_sequence<I...>) {
    return {&gatherPhongSurface<float, phongVariantMask(I)>...};
}
inline constexpr auto kGatherTable = makeGatherTable(std::make_index_sequence<kPhongVariantCount>{});
} // namespace phong_detail

inline PhongGatherVariant selectPhongGather(std::uint32_t features, std::string_view prefix) {
    PhongGatherVariant v;
    v.mayDiscard = (features & kPhongAlphaTest) != 0;
    v.name = prefix;
    if ((features & ~kPhongSpecializedAxes) == 0) {
        v.fn = phong_detail::kGatherTable[phongVariantIndex(features)];
        v.name += ':';
        v.name += phongFeatureNames(features);
    } else {
        v.fn = v.mayDiscard ? &gatherPhongSurface<float, kPhongAllFeatures>
                            : &gatherPhongSurface<float, kPhongAllFeatures & ~kPhongAlphaTest>;
        v.name += ":generic(";
        v.name += phongFeatureNames(features);
        v.name += ')';
    }
    return v;
}

} // namespace tessera
