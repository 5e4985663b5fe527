// The lighting of Practical Rendering and Computation with Direct3D 11 (Zink, Pettineo, Hoxley 2011),
// ch. 11: classic deferred's CalcLighting (Listing 11.3: linear range falloff max(0, 1 - d/range),
// the spot's saturate((rho - cos outer) / (cos inner - cos outer)), Lambert, Blinn-Phong specular
// times N.L), the light pre-pass light buffer (Listing 11.5: diffuse RGB, monochrome specular in A)
// and its final geometry pass (Listing 11.6). World space, generic over the scalar. `normalizeV`
// false is the listings' unnormalized V (H = normalize(L + V) with |V| the eye distance, the
// chapter's Eq. 11.1 intends a unit V); tests/gbuffer/prc_gbuffer_test.cpp ("prc lighting: ...") checks the worked values.
#pragma once

#include <tessera/scene/light.h>
#include <tessera/shading/phong_lighting.h>

namespace tessera {

// LightParams of Listing 11.3 (one light per draw).
template <class T>
struct PrcLight {
    LightType type = LightType::Point;
    Vec3<T> position{T(0)};
    Vec3<T> color{T(1)};
    Vec3<T> direction{T(0), T(0), T(1)};  // the direction the light travels (spot, directional)
    T cosInner = T(1), cosOuter = T(0);   // SpotlightAngles.x, .y (cosines)
    T range = T(1);                       // LightRange.x
};

// L and the attenuation of Listing 11.3's preprocessor branches.
template <class T>
struct PrcIncidence {
    Vec3<T> toLight{T(0)};
    T attenuation = T(1);
};

template <class T>
PrcIncidence<T> prcIncidence(const PrcLight<T>& light, const Vec3<T>& position) {
    PrcIncidence<T> r;
    if (light.type == LightType::Directional) {
        r.toLight = -light.direction;
        return r;
    }
    r.toLight = light.position - position;
    const T dist = std::sqrt(hlsl::dot(r.toLight, r.toLight));
    r.attenuation = std::max(T(0), T(1) - (dist / light.range));
    r.toLight = r.toLight / dist;
    if (light.type == LightType::Spot) {
        const T rho = hlsl::dot(-r.toLight, light.direction);
        r.attenuation *= hlsl::saturate((rho - light.cosOuter) / (light.cosInner - light.cosOuter));
    }
    return r;
}

// Listing 11.3 CalcLighting: (diffuse + specular) * attenuation with diffuse = N.L * LightColor *
// diffuseAlbedo and specular = pow(saturate(N.H), power) * LightColor * specularAlbedo * N.L.
template <class T>
Vec3<T> prcClassicLighting(const PrcLight<T>& light, const Vec3<T>& normal, const Vec3<T>& position,
                           const Vec3<T>& diffuseAlbedo, const Vec3<T>& specularAlbedo, T specularPower,
                           const Vec3<T>& cameraPos, bool normalizeV = false) {
    const PrcIncidence<T> in = prcIncidence(light, position);
    const T nDotL = hlsl::saturate(hlsl::dot(normal, in.toLight));
    const Vec3<T> diffuse = nDotL * light.color * diffuseAlbedo;
    Vec3<T> v = cameraPos - position;
    if (normalizeV) v = hlsl::normalize(v);
    const Vec3<T> h = hlsl::normalize(in.toLight + v);
    const Vec3<T> specular = detPow(hlsl::saturate(hlsl::dot(normal, h)), specularPower) * light.color * specularAlbedo * nDotL;
    return (diffuse + specular) * in.attenuation;
}

// Listing 11.5: the light buffer's float4(N.L * LightColor * attenuation, pow(N.H, power) *
// attenuation * N.L): diffuse light in RGB, monochrome specular (no light colour) in A.
template <class T>
Vec4<T> prcLightBufferTexel(const PrcLight<T>& light, const Vec3<T>& normal, T specularPower, const Vec3<T>& position,
                            const Vec3<T>& cameraPos, bool normalizeV = false) {
    const PrcIncidence<T> in = prcIncidence(light, position);
    const T nDotL = hlsl::saturate(hlsl::dot(normal, in.toLight));
    const Vec3<T> diffuse = nDotL * light.color * in.attenuation;
    Vec3<T> v = cameraPos - position;
    if (normalizeV) v = hlsl::normalize(v);
    const Vec3<T> h = hlsl::normalize(in.toLight + v);
    const T specular = detPow(hlsl::saturate(hlsl::dot(normal, h)), specularPower) * in.attenuation * nDotL;
    return {diffuse, specular};
}

// Listing 11.6: lighting.xyz * diffuse texel + lighting.w * SpecularAlbedo.
template <class T>
Vec3<T> prcLightPrePassFinal(const Vec4<T>& lighting, const Vec3<T>& diffuseTexel, const Vec3<T>& specularAlbedo) {
    return Vec3<T>(lighting) * diffuseTexel + lighting.w * specularAlbedo;
}

} // namespace tessera
