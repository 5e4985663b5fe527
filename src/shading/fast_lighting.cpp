// fastLighting (shading/fast_lighting.h): the 3dgep light loop over lanes of lights. Per lane:
// L, distance, the range skip as a mask, 1 - smoothstep attenuation, the spot cone's smoothstep,
// Lambert, Phong's reflected vector and pow(R.V, p) as exp(p log x) (Highway's contrib math, a
// few ulp); masked lanes add 0. Compiled per SIMD target (foreach_target), chosen at run time.
#include <tessera/shading/fast_lighting.h>

#include <algorithm>
#include <cmath>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shading/fast_lighting.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

HWY_BEFORE_NAMESPACE();
namespace tessera::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// in: P (3), N (3), V (3), specularPower, withSpecular; out: diffuse rgb, specular rgb.
void FastLightLoop(const FastLightSet& L, const float* in, float* out) {
    const hn::ScalableTag<float> d;
    using V = hn::Vec<decltype(d)>;
    const V px = hn::Set(d, in[0]), py = hn::Set(d, in[1]), pz = hn::Set(d, in[2]);
    const V nx = hn::Set(d, in[3]), ny = hn::Set(d, in[4]), nz = hn::Set(d, in[5]);
    const V vx = hn::Set(d, in[6]), vy = hn::Set(d, in[7]), vz = hn::Set(d, in[8]);
    const V power = hn::Set(d, in[9]);
    const bool withSpecular = in[10] != 0.0f;
    const V zero = hn::Zero(d), one = hn::Set(d, 1.0f), two = hn::Set(d, 2.0f), three = hn::Set(d, 3.0f);
    const V half = hn::Set(d, 0.5f), threeHalves = hn::Set(d, 1.5f);
    const V tiny = hn::Set(d, 1e-30f);
    V dr = zero, dg = zero, db = zero, sr = zero, sg = zero, sb = zero;
    // smoothstep(a, b, x) with 1 / (b - a) precomputed per light (FastLightSet): t = clamp((x - a)
    // * invSpan), t * t * (3 - 2 t). No division in the loop.
    const auto smoothstep = [&](V a, V invSpan, V x) {
        const V t = hn::Min(hn::Max(hn::Mul(hn::Sub(x, a), invSpan), zero), one);
        return hn::Mul(hn::Mul(t, t), hn::NegMulAdd(two, t, three));
    };
    // 1 / sqrt(x): the hardware estimate (12 bits on SSE4 and AVX2, 14 on AVX-512) and one Newton
    // step, y (1.5 - 0.5 x y^2), about 22 correct bits; x >= tiny, so never infinite. The scalar
    // and emulated targets have no such estimate (Highway's stand-in is far coarser), so they
    // divide by the square root.
    const auto rsqrt = [&](V x) {
#if HWY_TARGET == HWY_SCALAR || HWY_TARGET == HWY_EMU128
        (void)half;
        (void)threeHalves;
        return hn::Div(one, hn::Sqrt(x));
#else
        const V y = hn::ApproximateReciprocalSqrt(x);
        return hn::Mul(y, hn::NegMulAdd(hn::Mul(half, x), hn::Mul(y, y), threeHalves));
#endif
    };
    const auto dot = [](V ax, V ay, V az, V bx, V by, V bz) { return hn::MulAdd(az, bz, hn::MulAdd(ay, by, hn::Mul(ax, bx))); };
    const std::size_t lanes = hn::Lanes(d);
    for (std::size_t i = 0; i < L.count; i += lanes) {
        const V kind = hn::LoadU(d, L.kind.data() + i);
        const auto isDirectional = hn::Eq(kind, two);
        const auto isSpot = hn::Eq(kind, one);
        const auto enabled = hn::Ge(kind, zero);
        const V ax = hn::LoadU(d, L.ax.data() + i), ay = hn::LoadU(d, L.ay.data() + i), az = hn::LoadU(d, L.az.data() + i);
        V lx = hn::Sub(hn::LoadU(d, L.px.data() + i), px);
        V ly = hn::Sub(hn::LoadU(d, L.py.data() + i), py);
        V lz = hn::Sub(hn::LoadU(d, L.pz.data() + i), pz);
        const V distance2 = hn::Max(dot(lx, ly, lz, lx, ly, lz), tiny);
        const V invDistance = rsqrt(distance2);
        const V distance = hn::Mul(distance2, invDistance);
        const V range = hn::LoadU(d, L.range.data() + i);
        lx = hn::IfThenElse(isDirectional, ax, hn::Mul(lx, invDistance));
        ly = hn::IfThenElse(isDirectional, ay, hn::Mul(ly, invDistance));
        lz = hn::IfThenElse(isDirectional, az, hn::Mul(lz, invDistance));
        // DoLighting skips a point or spot light with length > Range.
        const auto active = hn::And(enabled, hn::Or(isDirectional, hn::Le(distance, range)));
        V scale = hn::IfThenElse(isDirectional, one,
                                 hn::Sub(one, smoothstep(hn::LoadU(d, L.attenuationStart.data() + i),
                                                         hn::LoadU(d, L.invAttenuationSpan.data() + i), distance)));
        const V cosAngle = hn::Neg(dot(ax, ay, az, lx, ly, lz));
        const V cone = smoothstep(hn::LoadU(d, L.minCos.data() + i), hn::LoadU(d, L.invConeSpan.data() + i), cosAngle);
        scale = hn::IfThenElseZero(active, hn::IfThenElse(isSpot, hn::Mul(scale, cone), scale));
        const V nDotLRaw = dot(nx, ny, nz, lx, ly, lz);
        const V diffuse = hn::Mul(hn::Max(nDotLRaw, zero), scale);
        const V r = hn::LoadU(d, L.r.data() + i), g = hn::LoadU(d, L.g.data() + i), b = hn::LoadU(d, L.b.data() + i);
        dr = hn::MulAdd(r, diffuse, dr);
        dg = hn::MulAdd(g, diffuse, dg);
        db = hn::MulAdd(b, diffuse, db);
        if (withSpecular) {
            // R = normalize(reflect(-L, N)) = normalize(2 (N.L) N - L); pow(max(R.V, 0), p).
            const V twoNDotL = hn::Mul(two, nDotLRaw);
            const V rx = hn::MulSub(twoNDotL, nx, lx), ry = hn::MulSub(twoNDotL, ny, ly), rz = hn::MulSub(twoNDotL, nz, lz);
            const V invLength = rsqrt(hn::Max(dot(rx, ry, rz, rx, ry, rz), tiny));
            const V rDotV = hn::Mul(dot(rx, ry, rz, vx, vy, vz), invLength);
            const auto positive = hn::Gt(rDotV, tiny);
            const V specularPow = hn::IfThenElseZero(positive, hn::Exp(d, hn::Mul(power, hn::Log(d, hn::Max(rDotV, tiny)))));
            const V specular = hn::Mul(specularPow, scale);
            sr = hn::MulAdd(r, specular, sr);
            sg = hn::MulAdd(g, specular, sg);
            sb = hn::MulAdd(b, specular, sb);
        }
    }
    out[0] = hn::GetLane(hn::SumOfLanes(d, dr));
    out[1] = hn::GetLane(hn::SumOfLanes(d, dg));
    out[2] = hn::GetLane(hn::SumOfLanes(d, db));
    out[3] = hn::GetLane(hn::SumOfLanes(d, sr));
    out[4] = hn::GetLane(hn::SumOfLanes(d, sg));
    out[5] = hn::GetLane(hn::SumOfLanes(d, sb));
}

} // namespace tessera::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace tessera {

HWY_EXPORT(FastLightLoop);

FastLightSet FastLightSet::build(std::span<const ViewLight<float>> lights) {
    constexpr std::size_t kPad = 16;  // the widest lane count (AVX-512 floats)
    FastLightSet s;
    s.count = (lights.size() + kPad - 1) / kPad * kPad;
    for (auto* v : {&s.px, &s.py, &s.pz, &s.ax, &s.ay, &s.az, &s.r, &s.g, &s.b, &s.range, &s.attenuationStart,
                    &s.invAttenuationSpan, &s.minCos, &s.maxCos, &s.invConeSpan})
        v->assign(s.count, 0.0f);
    s.kind.assign(s.count, -1.0f);
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const ViewLight<float>& l = lights[i];
        s.px[i] = l.positionView.x;
        s.py[i] = l.positionView.y;
        s.pz[i] = l.positionView.z;
        glm::vec3 a(l.directionView);
        if (l.type == LightType::Directional) a = -a / std::sqrt(glm::dot(a, a));
        s.ax[i] = a.x;
        s.ay[i] = a.y;
        s.az[i] = a.z;
        s.r[i] = l.color.x * l.intensity;
        s.g[i] = l.color.y * l.intensity;
        s.b[i] = l.color.z * l.intensity;
        s.range[i] = l.range;
        s.attenuationStart[i] = l.range * 0.75f;  // DoAttenuation's smoothstep(0.75 Range, Range, d)
        s.invAttenuationSpan[i] = 1.0f / (l.range - s.attenuationStart[i]);
        const float minCos = l.spotMinCos == l.spotMinCos ? l.spotMinCos : std::cos(hlsl::radians(l.spotlightAngleDeg));
        s.minCos[i] = minCos;
        s.maxCos[i] = l.spotMaxCos == l.spotMaxCos ? l.spotMaxCos : hlsl::lerp(minCos, 1.0f, 0.5f);
        s.invConeSpan[i] = 1.0f / (s.maxCos[i] - minCos);
        s.kind[i] = !l.enabled ? -1.0f : l.type == LightType::Point ? 0.0f : l.type == LightType::Spot ? 1.0f : 2.0f;
    }
    return s;
}

LightingResult<float> fastLighting(const FastLightSet& lights, float specularPower, const glm::vec3& posView,
                                   const glm::vec3& normalView, bool withSpecular) {
    const glm::vec3 viewDir = -posView / std::sqrt(glm::dot(posView, posView));  // normalize(eye - P), eye = 0
    const float in[11] = {posView.x, posView.y, posView.z, normalView.x, normalView.y, normalView.z,
                          viewDir.x, viewDir.y, viewDir.z, specularPower, withSpecular ? 1.0f : 0.0f};
    float out[6];
    HWY_DYNAMIC_DISPATCH(FastLightLoop)(lights, in, out);
    LightingResult<float> r;
    r.diffuse = glm::vec4(out[0], out[1], out[2], 0.0f);
    r.specular = glm::vec4(out[3], out[4], out[5], 0.0f);
    return r;
}

} // namespace tessera
#endif  // HWY_ONCE
