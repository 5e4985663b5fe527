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
    const V threeQuarters = hn::Set(d, 0.75f);
    const V tiny = hn::Set(d, 1e-30f);
    V dr = zero, dg = zero, db = zero, sr = zero, sg = zero, sb = zero;
    const auto smoothstep = [&](V a, V b, V x) {
        const V t = hn::Min(hn::Max(hn::Div(hn::Sub(x, a), hn::Sub(b, a)), zero), one);
        return hn::Mul(hn::Mul(t, t), hn::Sub(three, hn::Mul(two, t)));
    };
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
        const V distance = hn::Sqrt(hn::Add(hn::Add(hn::Mul(lx, lx), hn::Mul(ly, ly)), hn::Mul(lz, lz)));
        const V range = hn::LoadU(d, L.range.data() + i);
        const V invDistance = hn::Div(one, hn::Max(distance, tiny));
        lx = hn::IfThenElse(isDirectional, ax, hn::Mul(lx, invDistance));
        ly = hn::IfThenElse(isDirectional, ay, hn::Mul(ly, invDistance));
        lz = hn::IfThenElse(isDirectional, az, hn::Mul(lz, invDistance));
        // DoLighting skips a point or spot light with length > Range.
        const auto active = hn::And(enabled, hn::Or(isDirectional, hn::Le(distance, range)));
        V scale = hn::IfThenElse(isDirectional, one, hn::Sub(one, smoothstep(hn::Mul(range, threeQuarters), range, distance)));
        const V cosAngle = hn::Neg(hn::Add(hn::Add(hn::Mul(ax, lx), hn::Mul(ay, ly)), hn::Mul(az, lz)));
        const V cone = smoothstep(hn::LoadU(d, L.minCos.data() + i), hn::LoadU(d, L.maxCos.data() + i), cosAngle);
        scale = hn::IfThenElseZero(active, hn::IfThenElse(isSpot, hn::Mul(scale, cone), scale));
        const V nDotLRaw = hn::Add(hn::Add(hn::Mul(nx, lx), hn::Mul(ny, ly)), hn::Mul(nz, lz));
        const V diffuse = hn::Mul(hn::Max(nDotLRaw, zero), scale);
        const V r = hn::LoadU(d, L.r.data() + i), g = hn::LoadU(d, L.g.data() + i), b = hn::LoadU(d, L.b.data() + i);
        dr = hn::Add(dr, hn::Mul(r, diffuse));
        dg = hn::Add(dg, hn::Mul(g, diffuse));
        db = hn::Add(db, hn::Mul(b, diffuse));
        if (withSpecular) {
            // R = normalize(reflect(-L, N)) = normalize(2 (N.L) N - L); pow(max(R.V, 0), p).
            const V twoNDotL = hn::Mul(two, nDotLRaw);
            V rx = hn::Sub(hn::Mul(twoNDotL, nx), lx), ry = hn::Sub(hn::Mul(twoNDotL, ny), ly), rz = hn::Sub(hn::Mul(twoNDotL, nz), lz);
            const V invLength = hn::Div(one, hn::Sqrt(hn::Max(hn::Add(hn::Add(hn::Mul(rx, rx), hn::Mul(ry, ry)), hn::Mul(rz, rz)), tiny)));
            const V rDotV = hn::Mul(hn::Add(hn::Add(hn::Mul(rx, vx), hn::Mul(ry, vy)), hn::Mul(rz, vz)), invLength);
            const auto positive = hn::Gt(rDotV, tiny);
            const V specularPow = hn::IfThenElseZero(positive, hn::Exp(d, hn::Mul(power, hn::Log(d, hn::Max(rDotV, tiny)))));
            const V specular = hn::Mul(specularPow, scale);
            sr = hn::Add(sr, hn::Mul(r, specular));
            sg = hn::Add(sg, hn::Mul(g, specular));
            sb = hn::Add(sb, hn::Mul(b, specular));
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
    for (auto* v : {&s.px, &s.py, &s.pz, &s.ax, &s.ay, &s.az, &s.r, &s.g, &s.b, &s.range, &s.minCos, &s.maxCos})
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
        const float minCos = l.spotMinCos == l.spotMinCos ? l.spotMinCos : std::cos(hlsl::radians(l.spotlightAngleDeg));
        s.minCos[i] = minCos;
        s.maxCos[i] = l.spotMaxCos == l.spotMaxCos ? l.spotMaxCos : hlsl::lerp(minCos, 1.0f, 0.5f);
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
