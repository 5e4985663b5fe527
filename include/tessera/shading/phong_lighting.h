// The 3dgep lighting model (3dgep article §2.3.2; the demo's CommonInclude.hlsl), written once and
// generic over the scalar: T = float is the `exact` precision mode, T = double `reference`.
// Everything works on 4-component vectors as the HLSL does (dot products include w), with the
// article's order of operations, since multiplication order decides the bits.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/math/det_math.h>
#include <tessera/shading/light_term.h>
#include <tessera/scene/light.h>

namespace tessera {

template <class T>
using Vec4 = glm::vec<4, T, glm::defaultp>;
template <class T>
using Vec3 = glm::vec<3, T, glm::defaultp>;

// HLSL intrinsics with the evaluation order tessera fixes (HLSL itself leaves the order of a
// dp4's additions and the precision of rsqrt to the hardware):
namespace hlsl {

// D3D11.3 §3.1 min/max: a NaN operand yields the other operand.
template <class T>
constexpr T max(T a, T b) {
    if (a != a) return b;
    if (b != b) return a;
    return b > a ? b : a;
}
// saturate: clamp to [0, 1]; NaN -> 0 (D3D11.3 §3.1 "saturate ... NaN -> 0").
template <class T>
constexpr T saturate(T x) {
    return x > T(0) ? (x < T(1) ? x : T(1)) : T(0);
}
// dp4 summed left to right: ((x*x' + y*y') + z*z') + w*w'.
template <class T>
constexpr T dot(const Vec4<T>& a, const Vec4<T>& b) {
    return ((a.x * b.x + a.y * b.y) + a.z * b.z) + a.w * b.w;
}
template <class T>
constexpr T dot(const Vec3<T>& a, const Vec3<T>& b) {
    return (a.x * b.x + a.y * b.y) + a.z * b.z;
}
// Unary minus as a sign flip (glm's operator- computes 0 - v, which turns -0 into +0).
template <class T>
constexpr Vec4<T> neg(const Vec4<T>& v) {
    return {-v.x, -v.y, -v.z, -v.w};
}
// length = sqrt(dot(v, v)) (IEEE sqrt, correctly rounded).
template <class T>
T length(const Vec4<T>& v) {
    return std::sqrt(dot(v, v));
}
// normalize: v / sqrt(dot(v, v)). HLSL compiles normalize to v * rsq(dot(v, v)), whose rsq is
// an approximation (D3D11.3 §22.10.29: 2^-21.6 relative); tessera chooses the correctly
// rounded form so the result does not depend on an rsq implementation. One rescue, as
// cullmath::unitCross's: where dot(v, v) leaves T's normal range (a view normal of a world
// scaled by 1e20 has length 1e20 and its square overflows, so v / inf = 0 and the G-buffer
// codecs that normalize again store NaN), v is first scaled by a power of two that puts its
// largest component in [0.5, 1). The scaling is exact, so the result is the direction the real
// numbers give; where the plain dot(v, v) is a normal number the bits are its own. Zero stays
// 0 / 0 = NaN, as in HLSL.
// The common case is inlined and the rescue kept out of line: a Vec4 returned from a call that
// is not inlined crosses in two register halves that the caller reassembles through the stack (a
// store-forwarding stall; normalize was 5% of a Forward+ frame).
namespace detail {
template <class V>
[[gnu::noinline]] V powerOfTwoNormalizeRescue(const V& v, typename V::value_type lengthSquared) {
    using T = typename V::value_type;
    T largest = T(0);
    for (int i = 0; i < V::length(); ++i) largest = std::max(largest, std::fabs(v[i]));
    if (!(largest > T(0)) || !(largest <= std::numeric_limits<T>::max())) return v / std::sqrt(lengthSquared);
    int exponent = 0;
    (void)std::frexp(largest, &exponent);
    V scaled = v;
    for (int i = 0; i < V::length(); ++i) scaled[i] = std::ldexp(v[i], -exponent);
    return scaled / std::sqrt(dot(scaled, scaled));
}
template <class V>
[[gnu::always_inline]] inline V powerOfTwoNormalize(const V& v) {
    using T = typename V::value_type;
    const T lengthSquared = dot(v, v);
    if (lengthSquared >= std::numeric_limits<T>::min() && lengthSquared <= std::numeric_limits<T>::max()) [[likely]]
        return v / std::sqrt(lengthSquared);
    return powerOfTwoNormalizeRescue(v, lengthSquared);
}
} // namespace detail
template <class T>
Vec4<T> normalize(const Vec4<T>& v) {
    return detail::powerOfTwoNormalize(v);
}
template <class T>
Vec3<T> normalize(const Vec3<T>& v) {
    return detail::powerOfTwoNormalize(v);
}
// reflect(i, n) = i - 2 * dot(n, i) * n (doubling is exact, so 2*d*n == (2*n)*d bit for bit).
template <class T>
Vec4<T> reflect(const Vec4<T>& i, const Vec4<T>& n) {
    return i - (T(2) * dot(n, i)) * n;
}
// lerp(a, b, s) = a + s * (b - a).
template <class T>
constexpr T lerp(T a, T b, T s) {
    return a + s * (b - a);
}
// smoothstep(a, b, x): t = saturate((x - a) / (b - a)); t * t * (3 - 2 * t).
template <class T>
constexpr T smoothstep(T a, T b, T x) {
    const T t = saturate((x - a) / (b - a));
    return t * t * (T(3) - T(2) * t);
}
// radians(x) = x * (pi / 180), the constant rounded to T.
template <class T>
constexpr T radians(T degrees) {
    return degrees * T(0.017453292519943295769);
}

} // namespace hlsl

// The `fast` precision mode's approximations of the intrinsics above (precision.h): float
// throughout, the C library's powf/cosf instead of the deterministic detPow/detCos, normalize as
// one reciprocal square root and a multiply. Their error against `reference` is measured by
// tests/precision, never assumed; kFast = false selects the exact forms everywhere below.
// (kFast is only ever set with T = float.)
namespace fastmath {
template <class T>
Vec4<T> normalize(const Vec4<T>& v) {
    const T inv = T(1) / std::sqrt(hlsl::dot(v, v));
    return v * inv;
}
} // namespace fastmath

// normalize, pow and cos as the mode asks: HLSL's pow(x, y) for the x >= 0 the lighting passes
// (powf(0, y > 0) = 0, as HLSL's table says).
template <class T, bool kFast>
Vec4<T> lightingNormalize(const Vec4<T>& v) {
    if constexpr (kFast) return fastmath::normalize(v);
    else return hlsl::normalize(v);
}
template <class T, bool kFast>
T lightingPow(T x, T y) {
    if constexpr (kFast) return std::pow(x, y);
    else return detPow(x, y);
}
template <class T, bool kFast>
T lightingCos(T x) {
    if constexpr (kFast) return std::cos(x);
    else return detCos(x);
}

// The article's Light struct in view space (3dgep article §2.2.3; 112 bytes there, a plain value here).
// positionView = View * (positionWorld, 1); directionView = normalize(View * (directionWorld, 0)).
template <class T>
struct ViewLight {
    Vec4<T> positionView{T(0), T(0), T(0), T(1)};
    Vec4<T> directionView{T(0), T(0), T(-1), T(0)};
    Vec4<T> color{T(1)};              // one colour for diffuse and specular (w as given: 1)
    T spotlightAngleDeg = T(45);      // half angle of the cone, degrees
    T range = T(100);                 // view-space units (the view matrix is rigid)
    T intensity = T(1);
    bool enabled = true;
    LightType type = LightType::Point;
    // DoSpotCone's per-light constants, minCos = cos(radians(SpotlightAngle)) and maxCos =
    // lerp(minCos, 1, 0.5), computed once per frame by cacheSpotCone with the same functions
    // doSpotCone would call per pixel (so the same bits). NaN: not cached, computed per pixel.
    T spotMinCos = std::numeric_limits<T>::quiet_NaN();
    T spotMaxCos = std::numeric_limits<T>::quiet_NaN();
};

// Fills light's spotMinCos / spotMaxCos exactly as doSpotCone<T, false> computes them per pixel.
template <class T>
void cacheSpotCone(ViewLight<T>& light) {
    light.spotMinCos = detCos(hlsl::radians(light.spotlightAngleDeg));
    light.spotMaxCos = hlsl::lerp(light.spotMinCos, T(1), T(0.5));
}

template <class T>
struct LightingResult {
    Vec4<T> diffuse{T(0)};
    Vec4<T> specular{T(0)};
};

// DoDiffuse: light.Color * max(dot(N, L), 0).
template <class T>
Vec4<T> doDiffuse(const ViewLight<T>& light, const Vec4<T>& lightDirView, const Vec4<T>& normalView) {
    const T nDotL = hlsl::max(hlsl::dot(normalView, lightDirView), T(0));
    return light.color * nDotL;
}

// DoSpecular (Phong, not Blinn-Phong): R = normalize(reflect(-L, N)); Color * pow(max(R.V, 0), p).
template <class T, bool kFast = false>
Vec4<T> doSpecular(const ViewLight<T>& light, T specularPower, const Vec4<T>& viewDirView, const Vec4<T>& lightDirView,
                   const Vec4<T>& normalView) {
    const Vec4<T> reflected = lightingNormalize<T, kFast>(hlsl::reflect(hlsl::neg(lightDirView), normalView));
    const T rDotV = hlsl::max(hlsl::dot(reflected, viewDirView), T(0));
    return light.color * lightingPow<T, kFast>(rDotV, specularPower);
}

// DoAttenuation: 1 - smoothstep(0.75 Range, Range, d): 1 below 0.75 Range, 0 from Range on.
template <class T>
T doAttenuation(const ViewLight<T>& light, T distance) {
    return T(1) - hlsl::smoothstep(light.range * T(0.75), light.range, distance);
}

// DoSpotCone: minCos = cos(radians(angle)); maxCos = lerp(minCos, 1, 0.5);
// smoothstep(minCos, maxCos, dot(DirectionVS, -L)).
template <class T, bool kFast = false>
T doSpotCone(const ViewLight<T>& light, const Vec4<T>& lightDirView) {
    T minCos = light.spotMinCos, maxCos = light.spotMaxCos;
    if (minCos != minCos) {  // not cached (cacheSpotCone)
        minCos = lightingCos<T, kFast>(hlsl::radians(light.spotlightAngleDeg));
        maxCos = hlsl::lerp(minCos, T(1), T(0.5));
    }
    const T cosAngle = hlsl::dot(light.directionView, hlsl::neg(lightDirView));
    return hlsl::smoothstep(minCos, maxCos, cosAngle);
}

// DoPointLight: L = PositionVS - P; d = length(L); L /= d; x attenuation x Intensity.
template <class T, bool kFast = false>
LightingResult<T> doPointLight(const ViewLight<T>& light, T specularPower, const Vec4<T>& viewDirView,
                               const Vec4<T>& posView, const Vec4<T>& normalView, bool withSpecular = true) {
    Vec4<T> lightDir = light.positionView - posView;
    const T distance = hlsl::length(lightDir);
    lightDir = lightDir / distance;
    const T attenuation = doAttenuation(light, distance);
    LightingResult<T> result;
    result.diffuse = doDiffuse(light, lightDir, normalView) * attenuation * light.intensity;
    if (withSpecular)
        result.specular = doSpecular<T, kFast>(light, specularPower, viewDirView, lightDir, normalView) * attenuation * light.intensity;
    return result;
}

// DoSpotLight: as the point light, x spotIntensity between attenuation and Intensity.
template <class T, bool kFast = false>
LightingResult<T> doSpotLight(const ViewLight<T>& light, T specularPower, const Vec4<T>& viewDirView,
                              const Vec4<T>& posView, const Vec4<T>& normalView, bool withSpecular = true) {
    Vec4<T> lightDir = light.positionView - posView;
    const T distance = hlsl::length(lightDir);
    lightDir = lightDir / distance;
    const T attenuation = doAttenuation(light, distance);
    const T spotIntensity = doSpotCone<T, kFast>(light, lightDir);
    LightingResult<T> result;
    result.diffuse = doDiffuse(light, lightDir, normalView) * attenuation * spotIntensity * light.intensity;
    if (withSpecular)
        result.specular =
            doSpecular<T, kFast>(light, specularPower, viewDirView, lightDir, normalView) * attenuation * spotIntensity * light.intensity;
    return result;
}

// DoDirectionalLight: L = normalize(-DirectionVS); x Intensity.
template <class T, bool kFast = false>
LightingResult<T> doDirectionalLight(const ViewLight<T>& light, T specularPower, const Vec4<T>& viewDirView,
                                     const Vec4<T>& normalView, bool withSpecular = true) {
    const Vec4<T> lightDir = lightingNormalize<T, kFast>(hlsl::neg(light.directionView));
    LightingResult<T> result;
    result.diffuse = doDiffuse(light, lightDir, normalView) * light.intensity;
    if (withSpecular) result.specular = doSpecular<T, kFast>(light, specularPower, viewDirView, lightDir, normalView) * light.intensity;
    return result;
}

// What `light` (scene index `index`) added at a surface, for a pixel watch (raster/pixel_watch.h):
// the factors recomputed with the functions the shading used (so the same values), and the sums
// it added. `skip` says why the loop did not evaluate it.
template <class T, bool kFast = false>
LightTerm describeLight(std::uint32_t index, const ViewLight<T>& light, const Vec4<T>& posView, const Vec4<T>& normalView,
                        const LightingResult<T>& added, LightTerm::Skip skip = LightTerm::Skip::None) {
    LightTerm term;
    term.light = index;
    term.skip = skip;
    Vec4<T> lightDir;
    if (light.type == LightType::Directional) {
        lightDir = lightingNormalize<T, kFast>(hlsl::neg(light.directionView));
        term.distance = 0.0f;
    } else {
        lightDir = light.positionView - posView;
        const T distance = hlsl::length(lightDir);
        lightDir = lightDir / distance;
        term.distance = float(distance);
        term.range = float(light.range);
        term.falloff = float(doAttenuation(light, distance));
        if (light.type == LightType::Spot) term.cone = float(doSpotCone<T, kFast>(light, lightDir));
    }
    term.nDotL = float(hlsl::dot(normalView, lightDir));
    term.diffuse = glm::vec4(added.diffuse);
    term.specular = glm::vec4(added.specular);
    return term;
}

// One light of DoLighting's loop: skips a disabled light and a non-directional light with
// length(PositionVS - P) > Range (strict: a pixel exactly at Range is shaded, and gets
// attenuation 0), otherwise adds its Diffuse and Specular to `total`. `trace` (a pixel watch's
// terms; null almost always) receives what light `index` added or why it was skipped.
template <class T, bool kFast = false>
void accumulateLight(LightingResult<T>& total, const ViewLight<T>& light, T specularPower, const Vec4<T>& viewDirView,
                     const Vec4<T>& posView, const Vec4<T>& normalView, bool withSpecular, std::uint32_t index = 0,
                     std::vector<LightTerm>* trace = nullptr) {
    if (!light.enabled) {
        if (trace) [[unlikely]]
            trace->push_back(describeLight<T, kFast>(index, light, posView, normalView, {}, LightTerm::Skip::Disabled));
        return;
    }
    if (light.type != LightType::Directional && hlsl::length(light.positionView - posView) > light.range) {
        if (trace) [[unlikely]]
            trace->push_back(describeLight<T, kFast>(index, light, posView, normalView, {}, LightTerm::Skip::OutOfRange));
        return;
    }
    LightingResult<T> result;
    switch (light.type) {
    case LightType::Directional: result = doDirectionalLight<T, kFast>(light, specularPower, viewDirView, normalView, withSpecular); break;
    case LightType::Point: result = doPointLight<T, kFast>(light, specularPower, viewDirView, posView, normalView, withSpecular); break;
    case LightType::Spot: result = doSpotLight<T, kFast>(light, specularPower, viewDirView, posView, normalView, withSpecular); break;
    case LightType::Capsule: break;  // not a 3dgep light: viewLights disables capsules, so never reached
    }
    total.diffuse += result.diffuse;
    total.specular += result.specular;
    if (trace) [[unlikely]] trace->push_back(describeLight<T, kFast>(index, light, posView, normalView, result));
}

// DoLighting: V = normalize(eye - P) with eye = (0,0,0,1); lights in span order through
// accumulateLight (the skips above). Sums Diffuse and Specular in light order.
// withSpecular = false leaves Specular at 0 without evaluating it: the pixel shaders pass
// SpecularPower > 1, since they ignore lit.Specular otherwise (the image is the same bits).
template <class T, bool kFast = false>
LightingResult<T> doLighting(std::span<const ViewLight<T>> lights, T specularPower, const Vec4<T>& posView,
                             const Vec4<T>& normalView, bool withSpecular = true) {
    const Vec4<T> eyeView{T(0), T(0), T(0), T(1)};
    const Vec4<T> viewDirView = hlsl::normalize(eyeView - posView);
    LightingResult<T> total;
    std::vector<LightTerm>* const trace = watchedLightTerms();
    for (std::size_t i = 0; i < lights.size(); ++i)
        accumulateLight<T, kFast>(total, lights[i], specularPower, viewDirView, posView, normalView, withSpecular, std::uint32_t(i), trace);
    return total;
}

// The Forward+ PS loop (the demo's ForwardPlusRendering.hlsl PS_main; 3dgep article §4.6 "Final
// Shading"): `for (i = 0; i < lightCount; i++) light = Lights[LightIndexList[startOffset
// + i]]` with DoLighting's skips and sums. lightIndexAt(i) is LightIndexList[startOffset + i]
// as the PS loads it; an index past the light list reads a zeroed Light (D3D11 out-of-bounds
// StructuredBuffer load: 0), whose Enabled is false, so it is skipped. If the list is in
// ascending light index and every light it omits is skipped by doLighting or adds exactly +-0
// there (x + 0 == x, and the sums start at +0 so never hold -0), the result equals doLighting's
// bit for bit (the Forward+ == forward invariant, tests/golden/forward_plus_scenes_test.cpp).
template <class T, bool kFast = false, class IndexFn>
LightingResult<T> doLightingListed(std::span<const ViewLight<T>> lights, std::uint32_t lightCount, IndexFn&& lightIndexAt,
                                   T specularPower, const Vec4<T>& posView, const Vec4<T>& normalView, bool withSpecular = true) {
    const Vec4<T> eyeView{T(0), T(0), T(0), T(1)};
    const Vec4<T> viewDirView = hlsl::normalize(eyeView - posView);
    LightingResult<T> total;
    std::vector<LightTerm>* const trace = watchedLightTerms();
    for (std::uint32_t i = 0; i < lightCount; ++i) {
        const std::uint32_t index = lightIndexAt(i);
        if (index >= lights.size()) continue;
        accumulateLight<T, kFast>(total, lights[index], specularPower, viewDirView, posView, normalView, withSpecular, index, trace);
    }
    return total;
}

} // namespace tessera
