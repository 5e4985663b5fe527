// The 3dgep lighting functions (tessera/shading/phong_lighting.h) against values derived by hand
// beside each check: attenuation, spot cone, Phong specular, the Range test's strictness, the
// Enabled skip, directional lights, and float (exact) against double (reference) templates.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <tessera/shading/phong_lighting.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::shading_phong_lighting_test {

using namespace tessera;

namespace {

template <class T>
ViewLight<T> pointLight(Vec4<T> position, T range) {
    ViewLight<T> l;
    l.type = LightType::Point;
    l.positionView = position;
    l.range = range;
    return l;
}

} // namespace

TEST_CASE("doAttenuation: 1 - smoothstep(0.75R, R, d)") {
    const ViewLight<float> light = pointLight<float>({0, 0, 0, 1}, 10.0f);
    // d = 0.8R = 8: t = (8 - 7.5) / (10 - 7.5) = 0.2; smoothstep = 0.2^2 (3 - 0.4) = 0.104; 1 - 0.104 = 0.896.
    CHECK(doAttenuation(light, 8.0f) == doctest::Approx(0.896f).epsilon(1e-6));
    CHECK(doAttenuation<double>(pointLight<double>({0, 0, 0, 1}, 10.0), 8.0) == doctest::Approx(0.896).epsilon(1e-14));
    // d <= 0.75R: t = 0 -> 1 exactly; d >= R: t = 1 -> 1 - 1 = 0 exactly.
    CHECK(doAttenuation(light, 0.0f) == 1.0f);
    CHECK(doAttenuation(light, 7.5f) == 1.0f);
    CHECK(doAttenuation(light, 10.0f) == 0.0f);
    CHECK(doAttenuation(light, 50.0f) == 0.0f);
    // Midpoint d = 8.75: t = 0.5 -> 0.25 * 2 = 0.5 -> 0.5 (all exact in binary).
    CHECK(doAttenuation(light, 8.75f) == 0.5f);
}

TEST_CASE("doSpotCone: smoothstep(cos(angle), lerp(cos(angle), 1, 0.5), dot(DirectionVS, -L))") {
    ViewLight<float> light;
    light.type = LightType::Spot;
    light.spotlightAngleDeg = 60.0f;              // minCos = cos(60 deg) = 0.5, maxCos = 0.5 + 0.5 * 0.5 = 0.75
    light.directionView = {0.0f, 0.0f, -1.0f, 0.0f};
    // L points from the surface to the light; -L is the light's ray. cosAngle = dot(dir, -L) = L.z.
    const auto cone = [&](float cosAngle) {
        const float sinAngle = std::sqrt(1.0f - cosAngle * cosAngle);
        return doSpotCone(light, Vec4<float>{sinAngle, 0.0f, cosAngle, 0.0f});
    };
    CHECK(cone(1.0f) == 1.0f);                        // on the axis
    CHECK(cone(0.75f) == 1.0f);                       // inner edge: t = 1
    CHECK(cone(0.4f) == 0.0f);                        // outside the cone
    // Edge: minCos = float(cos(1.0471976f)) is 0.5 to within an ulp, so at cosAngle 0.5 the
    // result is 0 or a few ulps above: t <= 2^-23 / 0.25, t^2 (3 - 2t) < 1e-12.
    CHECK(cone(0.5f) < 1e-12f);
    // Halfway, cosAngle 0.625: t = 0.5 -> 0.5 (up to the ulps of minCos).
    CHECK(cone(0.625f) == doctest::Approx(0.5f).epsilon(1e-5));
}

TEST_CASE("doSpecular: Phong R = normalize(reflect(-L, N)), pow(max(R.V, 0), power)") {
    ViewLight<float> light;
    light.color = {1.0f, 0.5f, 0.25f, 1.0f};
    const Vec4<float> n{0, 0, 1, 0};
    // L = N: reflect(-N, N) = -N - 2 dot(N, -N) N = N, so R = N; V = N gives R.V = 1, pow(1, p) = 1.
    CHECK(doSpecular(light, 32.0f, n, n, n) == light.color);
    // V at 60 degrees from R: R.V = 0.5; pow(0.5, 4) = 1/16 (exact through detPow).
    const Vec4<float> v{std::sqrt(3.0f) / 2.0f, 0.0f, 0.5f, 0.0f};
    const Vec4<float> s = doSpecular(light, 4.0f, v, n, n);
    CHECK(s.x == doctest::Approx(0.0625f).epsilon(1e-6));
    CHECK(s.y == doctest::Approx(0.03125f).epsilon(1e-6));
    // V behind: R.V < 0 -> max(., 0) = 0 -> pow(0, p) = 0.
    CHECK(doSpecular(light, 8.0f, Vec4<float>{0, 0, -1, 0}, n, n) == Vec4<float>(0.0f));
    // Phong, not Blinn-Phong: L at 45 degrees, V = N. Phong: R = (-sin45, 0, cos45), R.V = cos 45;
    // Blinn would use H = normalize(L + V) with N.H = cos 22.5.
    const float h = std::sqrt(0.5f);
    const Vec4<float> phong = doSpecular(light, 2.0f, n, Vec4<float>{h, 0, h, 0}, n);
    CHECK(phong.x == doctest::Approx(0.5f).epsilon(1e-6));  // cos^2(45) = 0.5 (Blinn: cos^2(22.5) = 0.854)
}

TEST_CASE("doDiffuse and doPointLight: Color * max(N.L, 0) * attenuation * Intensity") {
    // Surface at the origin facing +z, light 4 units above: L = (0,0,1), d = 4, R = 10 -> attenuation 1.
    ViewLight<float> light = pointLight<float>({0, 0, 4, 1}, 10.0f);
    light.color = {0.5f, 1.0f, 0.25f, 1.0f};
    light.intensity = 2.0f;
    const Vec4<float> p{0, 0, 0, 1}, n{0, 0, 1, 0}, v{0, 0, 1, 0};
    const LightingResult<float> r = doPointLight(light, 10.0f, v, p, n);
    CHECK(r.diffuse == Vec4<float>(1.0f, 2.0f, 0.5f, 2.0f));   // Color * 1 * 1 * 2 (w too: float4 math)
    CHECK(r.specular == Vec4<float>(1.0f, 2.0f, 0.5f, 2.0f));  // R = V: pow(1, 10) = 1
    // At d = 8 (0.8 R): x 0.896.
    light.positionView = {0, 0, 8, 1};
    CHECK(doPointLight(light, 10.0f, v, p, n).diffuse.y == doctest::Approx(2.0f * 0.896f).epsilon(1e-6));
    // Light below the surface: N.L = -1 -> 0.
    light.positionView = {0, 0, -4, 1};
    CHECK(doPointLight(light, 10.0f, v, p, n).diffuse == Vec4<float>(0.0f));
}

TEST_CASE("doDirectionalLight: L = normalize(-DirectionVS), x Intensity, no attenuation") {
    ViewLight<float> light;
    light.type = LightType::Directional;
    light.directionView = {0, 0, -2, 0};   // not unit: normalize(-(0,0,-2)) = (0,0,1)
    light.intensity = 0.5f;
    light.range = 0.001f;                  // ignored for directional lights
    const std::vector<ViewLight<float>> lights{light};
    const LightingResult<float> r =
        doLighting<float>(lights, 8.0f, Vec4<float>{0, 0, -100, 1}, Vec4<float>{0, 0, 1, 0});
    CHECK(r.diffuse == Vec4<float>(0.5f));
}

TEST_CASE("doLighting: the Range test is strict (length > Range skips) and disabled lights are skipped") {
    // P = (0,0,-5), light at (0,0,-2): distance exactly 3. A NaN intensity makes "shaded" visible:
    // a shaded light contributes NaN (0 attenuation x NaN), a skipped one nothing.
    const Vec4<float> p{0, 0, -5, 1}, n{0, 0, 1, 0};
    ViewLight<float> light = pointLight<float>({0, 0, -2, 1}, 3.0f);
    light.intensity = std::numeric_limits<float>::quiet_NaN();
    std::vector<ViewLight<float>> lights{light};
    CHECK(std::isnan(doLighting<float>(lights, 8.0f, p, n).diffuse.x));  // d == Range: shaded
    lights[0].range = std::nextafter(3.0f, 0.0f);
    CHECK(doLighting<float>(lights, 8.0f, p, n).diffuse == Vec4<float>(0.0f));  // d > Range: skipped
    lights[0].range = 3.0f;
    lights[0].enabled = false;
    CHECK(doLighting<float>(lights, 8.0f, p, n).diffuse == Vec4<float>(0.0f));  // disabled: skipped
}

TEST_CASE("doLighting: sums lights in span order, withSpecular = false leaves Specular 0") {
    const Vec4<float> p{0, 0, -5, 1}, n{0, 0, 1, 0};
    std::vector<ViewLight<float>> lights{pointLight<float>({0, 0, -1, 1}, 100.0f), pointLight<float>({0, 0, -3, 1}, 100.0f)};
    lights[1].color = {0.25f, 0.25f, 0.25f, 1.0f};
    const LightingResult<float> both = doLighting<float>(lights, 8.0f, p, n);
    CHECK(both.diffuse.x == 1.25f);
    CHECK(doLighting<float>(lights, 8.0f, p, n, false).specular == Vec4<float>(0.0f));
    CHECK(doLighting<float>(lights, 8.0f, p, n, false).diffuse == both.diffuse);
}

TEST_CASE("doLighting<float> agrees with doLighting<double> within 1e-5 on random scenes") {
    // Bound: each float operation contributes a relative error of 2^-24; the smoothstep edges
    // amplify (x - a) / (b - a) by R / (0.25 R) = 4 and pow by its exponent (<= 64 here); with
    // colours <= 1 and 8 lights the sum stays below 1e-5 (observed worst 6e-7 over 2000 scenes).
    std::uint64_t state = 12345;
    const auto uniform = [&](float lo, float hi) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return lo + (hi - lo) * float(state >> 40) / float(1ull << 24);
    };
    double worst = 0.0;
    for (int scene = 0; scene < 2000; ++scene) {
        std::vector<ViewLight<float>> lf;
        std::vector<ViewLight<double>> ld;
        for (int i = 0; i < 8; ++i) {
            ViewLight<float> l;
            l.type = i % 3 == 0 ? LightType::Spot : (i % 3 == 1 ? LightType::Point : LightType::Directional);
            l.positionView = {uniform(-5, 5), uniform(-5, 5), uniform(-10, 0), 1.0f};
            const Vec3<float> dir = hlsl::normalize(Vec3<float>{uniform(-1, 1), uniform(-1, 1), uniform(-1, 0.2f)});
            l.directionView = {dir.x, dir.y, dir.z, 0.0f};
            l.color = {uniform(0, 1), uniform(0, 1), uniform(0, 1), 1.0f};
            l.range = uniform(2, 12);
            l.spotlightAngleDeg = uniform(20, 60);
            l.intensity = uniform(0, 1) / 8.0f;
            lf.push_back(l);
            ld.push_back({Vec4<double>(l.positionView), Vec4<double>(l.directionView), Vec4<double>(l.color),
                          double(l.spotlightAngleDeg), double(l.range), double(l.intensity), l.enabled, l.type});
        }
        const Vec4<float> p{uniform(-3, 3), uniform(-3, 3), uniform(-8, -1), 1.0f};
        const Vec3<float> n3 = hlsl::normalize(Vec3<float>{uniform(-1, 1), uniform(-1, 1), uniform(0, 1)});
        const Vec4<float> n{n3.x, n3.y, n3.z, 0.0f};
        const float power = uniform(2, 64);
        const LightingResult<float> rf = doLighting<float>(lf, power, p, n);
        const LightingResult<double> rd = doLighting<double>(ld, double(power), Vec4<double>(p), Vec4<double>(n));
        for (int c = 0; c < 3; ++c) {
            worst = std::fmax(worst, std::fabs(double(rf.diffuse[c]) - rd.diffuse[c]));
            worst = std::fmax(worst, std::fabs(double(rf.specular[c]) - rd.specular[c]));
        }
    }
    MESSAGE("worst |float - double| = " << worst);
    CHECK(worst < 1e-5);
}

TEST_CASE("hlsl::normalize: where dot(v, v) over- or underflows, the power-of-two rescue gives the unit vector, elsewhere its bits are v / sqrt(dot(v, v))") {
    // Truth: the direction in double, rounded once to float; the rescued result is within 2 ulp of
    // it per component (the scaling is exact, then one dot, one sqrt and one division in float).
    const auto closeToTruth = [](const Vec4<float>& v) {
        const glm::dvec4 d(v);
        const glm::dvec4 truth = d / std::sqrt(glm::dot(d, d));
        const Vec4<float> got = hlsl::normalize(v);
        for (int i = 0; i < 4; ++i) {
            CAPTURE(i);
            CHECK(std::isfinite(got[i]));
            CHECK(std::fabs(double(got[i]) - truth[i]) <= 2.0 * double(std::numeric_limits<float>::epsilon()));
        }
    };
    closeToTruth({1e20f, 0.0f, 0.0f, 0.0f});                    // squared 1e40: overflows to inf
    closeToTruth({3e19f, -4e19f, 0.0f, 0.0f});                  // squared 2.5e39
    closeToTruth({3e-30f, 4e-30f, 0.0f, 0.0f});                 // squared 2.5e-59: underflows to 0
    closeToTruth({1e-40f, 0.0f, -1e-40f, 0.0f});                // subnormal components
    closeToTruth({std::numeric_limits<float>::max(), std::numeric_limits<float>::max(), 0.0f, 0.0f});
    CHECK(hlsl::normalize(Vec3<double>{1e200, 0.0, 0.0}) == Vec3<double>{1.0, 0.0, 0.0});  // double: 1e400 overflows
    // Zero stays 0 / 0 = NaN, as HLSL's normalize gives.
    CHECK(std::isnan(hlsl::normalize(Vec4<float>(0.0f)).x));
    // Ordinary vectors keep the plain formula's bits.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-100.0f, 100.0f);
    for (int i = 0; i < 1000; ++i) {
        const Vec4<float> v{u(rng), u(rng), u(rng), u(rng)};
        const Vec4<float> plain = v / std::sqrt(hlsl::dot(v, v));
        const Vec4<float> got = hlsl::normalize(v);
        CHECK(std::memcmp(&got, &plain, sizeof(got)) == 0);
    }
}

} // namespace tessera_test::shading_phong_lighting_test
