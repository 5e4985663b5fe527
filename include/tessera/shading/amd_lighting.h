// AMD's Forward+ lighting model, as ForwardPlus11's RenderScenePS evaluates it (ForwardPlus11
// Shaders/ForwardPlus11.hlsl): the "fake inverse squared" falloff -0.05 + 1.05/(1 + 20x^2),
// Lambert diffuse and Blinn-Phong specular (power 8), squared-linear spot cone, the x2 / x8 "pump",
// the up/down ambient and the final texture modulation. Generic over the scalar like
// phong_lighting.h (T = float: `exact`; T = double: `reference`), in the shader's operation order.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include <tessera/buffers/conversion.h>
#include <tessera/shading/light_term.h>
#include <tessera/shading/phong_lighting.h>

namespace tessera {

// ===== Light data as the shader reads it =========================================================
// The demo keeps geometry (culling) and properties (shading) in separate buffers (as GPU Pro 4 §5.3.1 advises):
//   g_PointLightBufferCenterAndRadius  R32G32B32A32_FLOAT  (centre xyz world, radius)
//   g_PointLightBufferColor            R8G8B8A8_UNORM      (rgb; a = 1)
//   g_SpotLightBufferCenterAndRadius   R32G32B32A32_FLOAT  (bounding-sphere centre, bounding radius)
//   g_SpotLightBufferColor             R8G8B8A8_UNORM
//   g_SpotLightBufferSpotParams        R16G16B16A16_FLOAT  (dir.x, dir.y, +-cos(cone) with the sign
//                                                          of dir.z, falloff radius)
// These structs hold the values after the SRV's format conversion (UNORM / half -> float).
template <class T>
struct AmdPointLight {
    Vec3<T> centerWorld{T(0)};
    T radius = T(1);          // world units; culling sphere and falloff distance are the same
    Vec3<T> color{T(1)};      // rgb of the UNORM colour
};

template <class T>
struct AmdSpotLight {
    Vec3<T> boundingCenterWorld{T(0)};  // centre of the sphere that bounds the cone (culling)
    T boundingRadius = T(1);            // its radius: the apex sits this far back along -dir
    Vec3<T> color{T(1)};
    Vec4<T> spotParams{T(0), T(0), T(1), T(1)};  // (dir.x, dir.y, cosCone * sign(dir.z), falloff radius)
};

// The UNORM colour buffer: DWORD 0xAABBGGRR (DXGI_FORMAT_R8G8B8A8_UNORM, little-endian), each
// channel code / 255 (D3D11.3 §3.2.3.5, correctly rounded).
inline glm::vec3 amdColorFromRgba8(std::uint32_t abgr) {
    return {convert::unormToFloat(abgr & 0xFFu, 8), convert::unormToFloat((abgr >> 8) & 0xFFu, 8),
            convert::unormToFloat((abgr >> 16) & 0xFFu, 8)};
}

// The R16G16B16A16_FLOAT spot parameters as the shader sees them (half -> float is exact).
inline glm::vec4 amdSpotParamsFromHalf(const std::uint16_t (&halfs)[4]) {
    return {convert::halfToFloat(halfs[0]), convert::halfToFloat(halfs[1]), convert::halfToFloat(halfs[2]),
            convert::halfToFloat(halfs[3])};
}

template <class T>
struct AmdLightingResult {
    Vec3<T> diffuse{T(0)};   // AccumDiffuse before the x2 pump
    Vec3<T> specular{T(0)};  // AccumSpecular before the x8 pump
};

// ===== The pieces ================================================================================
// fFalloff = -0.05 + 1.05/(1+20*x*x) with x = distance / radius, the "fake inverse squared
// falloff -(1/k)(1 - (k+1)/(1 + k x^2)), k = 20" (ForwardPlus11.hlsl comment). 1 at x = 0; exactly
// 0 at x = 1 in real arithmetic. In binary32 the literals round (0.05f = 0.0500000007,
// 1.05f = 1.04999995): the value at x = 0 is 1 - 2^-24 and at x = 1 it is -2^-28. x = 1 is the
// only float in [0, 1] where it is negative, and the shader never evaluates it there: it runs
// only for distance < radius, and then distance / radius <= 1 - 2^-24 (tests/shading/amd_lighting_test.cpp).
template <class T>
T amdFalloff(T x) {
    return T(-0.05) + T(1.05) / (T(1) + T(20) * x * x);
}

// HLSL pow(s, 8) with the literal exponent. HLSL leaves pow's precision to the hardware; tessera
// evaluates it as three squarings (((s^2)^2)^2), the expansion compilers use for small literal
// integer exponents, so no libm or exp2/log2 approximation enters the result.
template <class T>
T amdPow8(T s) {
    const T s2 = s * s;
    const T s4 = s2 * s2;
    return s4 * s4;
}

// vViewDir = normalize(g_vCameraPos - vPositionWS).
template <class T>
Vec3<T> amdViewDir(const Vec3<T>& cameraPosWorld, const Vec3<T>& posWorld) {
    return hlsl::normalize(cameraPosWorld - posWorld);
}

// The spot's unit direction rebuilt from the packed x, y (ForwardPlus11.hlsl):
//   z = sqrt(1 - x*x - y*y); z = (SpotParams.z > 0) ? z : -z
// With half-rounded x, y the radicand can be negative for a direction nearly perpendicular to z:
// z is then NaN, and so are the light position and distance; `fLightDistance < fRad` is false and
// the light contributes nothing (test "a spot whose packed direction has x^2 + y^2 > 1 is dark").
template <class T>
Vec3<T> amdSpotDirection(const Vec4<T>& spotParams) {
    Vec3<T> dir(spotParams.x, spotParams.y, T(0));
    dir.z = std::sqrt((T(1) - dir.x * dir.x) - dir.y * dir.y);
    dir.z = spotParams.z > T(0) ? dir.z : -dir.z;
    return dir;
}

// LightPosition = BoundingSphereCenterAndRadius.xyz - BoundingSphereCenterAndRadius.w * SpotLightDir
// (the apex is the bounding radius back from the sphere's centre).
template <class T>
Vec3<T> amdSpotPosition(const AmdSpotLight<T>& light, const Vec3<T>& dir) {
    return light.boundingCenterWorld - light.boundingRadius * dir;
}

// One point light (the loop body of RenderScenePS):
//   vToLight = c - P; L = normalize(vToLight); d = length(vToLight)
//   if (d < rad): x = d / rad; f = falloff(x)
//     diffuse  = color * saturate(dot(L, N)) * f
//     H = normalize(V + L); specular = color * pow(saturate(dot(H, N)), 8) * f
template <class T>
AmdLightingResult<T> amdPointLight(const AmdPointLight<T>& light, const Vec3<T>& posWorld, const Vec3<T>& normalWorld,
                                   const Vec3<T>& viewDirWorld) {
    const Vec3<T> toLight = light.centerWorld - posWorld;
    const Vec3<T> lightDir = hlsl::normalize(toLight);
    const T distance = std::sqrt(hlsl::dot(toLight, toLight));
    AmdLightingResult<T> result;
    if (distance < light.radius) {
        const T x = distance / light.radius;
        const T falloff = amdFalloff(x);
        result.diffuse = light.color * hlsl::saturate(hlsl::dot(lightDir, normalWorld)) * falloff;
        const Vec3<T> halfAngle = hlsl::normalize(viewDirWorld + lightDir);
        result.specular = light.color * amdPow8(hlsl::saturate(hlsl::dot(halfAngle, normalWorld))) * falloff;
    }
    return result;
}

// One spot light:
//   dir = amdSpotDirection; pos = amdSpotPosition; vToLight = pos - P; L = normalize(vToLight)
//   d = length(vToLight); cosCur = dot(-L, dir); rad = SpotParams.w; cosCone = |SpotParams.z|
//   if (d < rad && cosCur > cosCone):
//     radial = (cosCur - cosCone) / (1.0 - cosCone); radial *= radial; f = falloff(d / rad)
//     diffuse = color * saturate(dot(L, N)) * f * radial; specular likewise with pow(N.H, 8)
template <class T>
AmdLightingResult<T> amdSpotLight(const AmdSpotLight<T>& light, const Vec3<T>& posWorld, const Vec3<T>& normalWorld,
                                  const Vec3<T>& viewDirWorld) {
    const Vec3<T> spotDir = amdSpotDirection(light.spotParams);
    const Vec3<T> lightPos = amdSpotPosition(light, spotDir);
    const Vec3<T> toLight = lightPos - posWorld;
    const Vec3<T> toLightNormalized = hlsl::normalize(toLight);
    const T distance = std::sqrt(hlsl::dot(toLight, toLight));
    const Vec3<T> negL(-toLightNormalized.x, -toLightNormalized.y, -toLightNormalized.z);
    const T cosCurrent = hlsl::dot(negL, spotDir);
    const T radius = light.spotParams.w;
    const T cosCone = light.spotParams.z > T(0) ? light.spotParams.z : -light.spotParams.z;
    AmdLightingResult<T> result;
    if (distance < radius && cosCurrent > cosCone) {
        T radial = (cosCurrent - cosCone) / (T(1) - cosCone);
        radial = radial * radial;
        const T falloff = amdFalloff(distance / radius);
        result.diffuse = light.color * hlsl::saturate(hlsl::dot(toLightNormalized, normalWorld)) * falloff * radial;
        const Vec3<T> halfAngle = hlsl::normalize(viewDirWorld + toLightNormalized);
        result.specular =
            light.color * amdPow8(hlsl::saturate(hlsl::dot(halfAngle, normalWorld))) * falloff * radial;
    }
    return result;
}

// What a point / spot light added at a surface, for a pixel watch (raster/pixel_watch.h): the
// factors recomputed with the operations above (so the same values) and the result it added.
template <class T>
LightTerm amdDescribePoint(std::uint32_t index, const AmdPointLight<T>& light, const Vec3<T>& posWorld,
                           const Vec3<T>& normalWorld, const AmdLightingResult<T>& added) {
    const Vec3<T> toLight = light.centerWorld - posWorld;
    const T distance = std::sqrt(hlsl::dot(toLight, toLight));
    LightTerm term;
    term.light = index;
    term.distance = float(distance);
    term.range = float(light.radius);
    term.nDotL = float(hlsl::dot(hlsl::normalize(toLight), normalWorld));
    if (distance < light.radius) term.falloff = float(amdFalloff(distance / light.radius));
    else term.skip = LightTerm::Skip::OutOfRange;
    term.diffuse = glm::vec4(glm::vec3(added.diffuse), 0.0f);
    term.specular = glm::vec4(glm::vec3(added.specular), 0.0f);
    return term;
}
template <class T>
LightTerm amdDescribeSpot(std::uint32_t index, const AmdSpotLight<T>& light, const Vec3<T>& posWorld,
                          const Vec3<T>& normalWorld, const AmdLightingResult<T>& added) {
    const Vec3<T> spotDir = amdSpotDirection(light.spotParams);
    const Vec3<T> toLight = amdSpotPosition(light, spotDir) - posWorld;
    const Vec3<T> toLightNormalized = hlsl::normalize(toLight);
    const T distance = std::sqrt(hlsl::dot(toLight, toLight));
    const T cosCurrent = hlsl::dot(Vec3<T>(-toLightNormalized.x, -toLightNormalized.y, -toLightNormalized.z), spotDir);
    const T radius = light.spotParams.w;
    const T cosCone = light.spotParams.z > T(0) ? light.spotParams.z : -light.spotParams.z;
    LightTerm term;
    term.light = index;
    term.distance = float(distance);
    term.range = float(radius);
    term.nDotL = float(hlsl::dot(toLightNormalized, normalWorld));
    if (!(distance < radius)) {
        term.skip = LightTerm::Skip::OutOfRange;
    } else if (!(cosCurrent > cosCone)) {
        term.skip = LightTerm::Skip::OutsideCone;
        term.cone = 0.0f;
    } else {
        const T radial = (cosCurrent - cosCone) / (T(1) - cosCone);
        term.cone = float(radial * radial);
        term.falloff = float(amdFalloff(distance / radius));
    }
    term.diffuse = glm::vec4(glm::vec3(added.diffuse), 0.0f);
    term.specular = glm::vec4(glm::vec3(added.specular), 0.0f);
    return term;
}

// The two loops of RenderScenePS over a tile's lists (point list, then spot list, each in list
// order), summing AccumDiffuse / AccumSpecular. Indices address `points` / `spots`.
template <class T>
AmdLightingResult<T> amdAccumulateLights(std::span<const AmdPointLight<T>> points, std::span<const std::uint32_t> pointList,
                                         std::span<const AmdSpotLight<T>> spots, std::span<const std::uint32_t> spotList,
                                         const Vec3<T>& posWorld, const Vec3<T>& normalWorld, const Vec3<T>& viewDirWorld) {
    AmdLightingResult<T> accum;
    for (std::uint32_t index : pointList) {
        const AmdLightingResult<T> r = amdPointLight(points[index], posWorld, normalWorld, viewDirWorld);
        accum.diffuse += r.diffuse;
        accum.specular += r.specular;
    }
    for (std::uint32_t index : spotList) {
        const AmdLightingResult<T> r = amdSpotLight(spots[index], posWorld, normalWorld, viewDirWorld);
        accum.diffuse += r.diffuse;
        accum.specular += r.specular;
    }
    return accum;
}

// The demo's per-object ambient colours (ForwardPlus11.cpp,
// g_MaterialAmbientColorUp / Down).
inline constexpr glm::vec3 kAmdAmbientUp{0.013f, 0.015f, 0.050f};
inline constexpr glm::vec3 kAmdAmbientDown{0.0013f, 0.0015f, 0.0050f};

// The tail of RenderScenePS:
//   AccumDiffuse *= 2; AccumSpecular *= 8                      ("pump up the lights")
//   fAmbientBlend = 0.5f * N.y + 0.5; Ambient = up * blend + down * (1 - blend)
//   return float4(DiffuseTex.xyz * ((AccumDiffuse + Ambient) + AccumSpecular * fSpecMask), 1)
// fSpecMask is the diffuse texture's alpha (0 with USE_ALPHA_TEST). Returns the rgb; alpha is 1.
template <class T>
Vec3<T> amdComposePixel(const AmdLightingResult<T>& accum, const Vec3<T>& normalWorld, const Vec3<T>& diffuseTex,
                        T specMask, const Vec3<T>& ambientUp, const Vec3<T>& ambientDown) {
    const Vec3<T> accumDiffuse = accum.diffuse * T(2);
    const Vec3<T> accumSpecular = accum.specular * T(8);
    const T ambientBlend = T(0.5) * normalWorld.y + T(0.5);
    const Vec3<T> ambient = ambientUp * ambientBlend + ambientDown * (T(1) - ambientBlend);
    const Vec3<T> diffuseAndAmbient = accumDiffuse + ambient;
    return diffuseTex * (diffuseAndAmbient + accumSpecular * specMask);
}

}  // namespace tessera
