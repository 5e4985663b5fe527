// The HLSL Development Cookbook's light functions (Feinstein 2013): ch. 2's deferred recipes call
// ch. 1's CalcAmbient / CalcDirectional / CalcPoint / CalcSpot / CalcCapsule, which the chapter
// does not print. tessera follows the book's companion code for ch. 1 and 2 (see docs/sources.md):
// hemispheric ambient, Lambert diffuse with Blinn specular, squared linear range falloff
// (1 - saturate(d / range))^2, squared cone falloff, and the capsule's nearest point on its
// segment. World space, generic over the scalar (float: exact, double: reference) and kFast
// (std::pow and an approximate normalize, the `fast` mode), in the shaders' operation order.
#pragma once

#include <cstdint>

#include <tessera/shading/phong_lighting.h>

namespace tessera {

// SURFACE_DATA after MaterialFromGBuffer: unit world normal, base colour, Blinn exponent, intensity.
template <class T>
struct CookbookMaterial {
    Vec3<T> normal{T(0)};
    Vec3<T> diffuseColor{T(0)};
    T specPow = T(1);
    T specIntensity = T(0);
};

namespace cookbook_detail {
template <class T>
T saturate(T x) {
    return hlsl::saturate(x);
}
template <class T, bool kFast>
Vec3<T> normalize3(const Vec3<T>& v) {
    if constexpr (kFast) return v * (T(1) / std::sqrt(hlsl::dot(v, v)));
    else return hlsl::normalize(v);
}
// Blinn: NDotH = saturate(dot(normalize(ToEye + ToLight), N)); pow(NDotH, SpecPow) * SpecIntensity.
template <class T, bool kFast>
T blinn(const Vec3<T>& toEye, const Vec3<T>& toLight, const CookbookMaterial<T>& m) {
    const Vec3<T> halfWay = normalize3<T, kFast>(toEye + toLight);
    const T nDotH = saturate(hlsl::dot(halfWay, m.normal));
    return lightingPow<T, kFast>(nDotH, m.specPow) * m.specIntensity;
}
} // namespace cookbook_detail

// The point light's terms at a surface, for the light loops and a pixel watch's LightTerm.
template <class T>
struct CookbookTerms {
    Vec3<T> color{T(0)};
    T distance = T(0), nDotL = T(0), attenuation = T(1), cone = T(1);
};

namespace cookbook_detail {
// The part CalcPoint and CalcSpot share: ToLight = LightPos - P, d = length, L = ToLight / d;
// diffuseColor * saturate(N.L) + Blinn; and the falloff (1 - saturate(d * RangeRcp))^2. Returns
// the unlit-by-colour sum; `t` gets distance, N.L, attenuation and L.
template <class T, bool kFast>
Vec3<T> litByPoint(const Vec3<T>& posWorld, const Vec3<T>& eyeWorld, const CookbookMaterial<T>& m, const Vec3<T>& lightPos,
                   T rangeRcp, CookbookTerms<T>& t, Vec3<T>& toLight) {
    toLight = lightPos - posWorld;
    t.distance = std::sqrt(hlsl::dot(toLight, toLight));
    toLight = toLight / t.distance;
    t.nDotL = hlsl::dot(toLight, m.normal);
    Vec3<T> finalColor = m.diffuseColor * saturate(t.nDotL);
    const Vec3<T> toEye = normalize3<T, kFast>(eyeWorld - posWorld);
    finalColor += Vec3<T>(blinn<T, kFast>(toEye, toLight, m));
    const T distToLightNorm = T(1) - saturate(t.distance * rangeRcp);
    t.attenuation = distToLightNorm * distToLightNorm;
    return finalColor;
}
} // namespace cookbook_detail

// CalcAmbient: (AmbientDown + (N.y * 0.5 + 0.5) * AmbientRange) * color, AmbientRange = up - down.
template <class T>
Vec3<T> cookbookAmbient(const Vec3<T>& normal, const Vec3<T>& color, const Vec3<T>& ambientDown, const Vec3<T>& ambientRange) {
    const T up = normal.y * T(0.5) + T(0.5);
    return (ambientDown + ambientRange * up) * color;
}

// CalcDirectional: (DirLightColor * saturate(N.L) + DirLightColor * Blinn) * diffuseColor.
template <class T, bool kFast = false>
Vec3<T> cookbookDirectional(const Vec3<T>& posWorld, const Vec3<T>& eyeWorld, const CookbookMaterial<T>& m,
                            const Vec3<T>& dirToLight, const Vec3<T>& color) {
    using namespace cookbook_detail;
    const T nDotL = hlsl::dot(dirToLight, m.normal);
    Vec3<T> finalColor = color * saturate(nDotL);
    const Vec3<T> toEye = normalize3<T, kFast>(eyeWorld - posWorld);
    finalColor += color * blinn<T, kFast>(toEye, dirToLight, m);
    return finalColor * m.diffuseColor;
}

// CalcPoint: ToLight = LightPos - P; d = length; Phong (Lambert) diffuse diffuseColor * saturate(N.L)
// plus Blinn (not multiplied by the diffuse colour), all x LightColor x (1 - saturate(d / range))^2.
template <class T, bool kFast = false>
CookbookTerms<T> cookbookPoint(const Vec3<T>& posWorld, const Vec3<T>& eyeWorld, const CookbookMaterial<T>& m,
                               const Vec3<T>& lightPos, T rangeRcp, const Vec3<T>& color) {
    CookbookTerms<T> t;
    Vec3<T> toLight;
    const Vec3<T> finalColor = cookbook_detail::litByPoint<T, kFast>(posWorld, eyeWorld, m, lightPos, rangeRcp, t, toLight);
    t.color = finalColor * (color * t.attenuation);  // finalColor *= PointColor.rgb * Attn
    return t;
}

// CalcSpot: CalcPoint's terms x the cone: conAtt = saturate((dot(-dir, L) - cosOuter) /
// (cosInner - cosOuter))^2 (SpotCosConeAttRange = cosInner - cosOuter; 0 makes a hard edge).
template <class T, bool kFast = false>
CookbookTerms<T> cookbookSpot(const Vec3<T>& posWorld, const Vec3<T>& eyeWorld, const CookbookMaterial<T>& m,
                              const Vec3<T>& lightPos, T rangeRcp, const Vec3<T>& color, const Vec3<T>& dirToLight, T cosOuter,
                              T cosConeAttRange) {
    using namespace cookbook_detail;
    CookbookTerms<T> t;
    Vec3<T> toLight;
    const Vec3<T> finalColor = litByPoint<T, kFast>(posWorld, eyeWorld, m, lightPos, rangeRcp, t, toLight);
    const T cosAng = hlsl::dot(dirToLight, toLight);
    T conAtt = cosConeAttRange > T(0) ? saturate((cosAng - cosOuter) / cosConeAttRange) : (cosAng >= cosOuter ? T(1) : T(0));
    conAtt *= conAtt;
    t.cone = conAtt;
    t.color = finalColor * ((color * t.attenuation) * conAtt);  // finalColor *= SpotColor.rgb * Attn * conAtt
    return t;
}

// CalcCapsule: the light comes from the segment's nearest point to P (start + dir *
// saturate(dot(P - start, dir) / len) * len), then as CalcPoint.
template <class T, bool kFast = false>
CookbookTerms<T> cookbookCapsule(const Vec3<T>& posWorld, const Vec3<T>& eyeWorld, const CookbookMaterial<T>& m,
                                 const Vec3<T>& start, const Vec3<T>& dir, T length, T rangeRcp, const Vec3<T>& color) {
    using namespace cookbook_detail;
    const Vec3<T> toCapsuleStart = posWorld - start;
    T distOnLine = hlsl::dot(toCapsuleStart, dir) / length;
    distOnLine = saturate(distOnLine) * length;
    const Vec3<T> pointOnLine = start + dir * distOnLine;
    return cookbookPoint<T, kFast>(posWorld, eyeWorld, m, pointOnLine, rangeRcp, color);
}

} // namespace tessera
