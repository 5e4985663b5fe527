// AMD's Forward+ lighting (shading/amd_lighting.h): the falloff at its end points in binary32 and
// in double (with the derivations of the rounded values), its monotonicity and the sliver where
// the binary32 value is negative (x = 1 only), hand-derived point and spot cases, the dark NaN spot, the
// compose step, and float against double.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include <tessera/scene/light_generator.h>
#include <tessera/shading/amd_lighting.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::shading_amd_lighting_test {

using namespace tessera;

TEST_CASE("AMD falloff: end points in binary32 and double") {
    // x = 0: -0.05f + 1.05f / 1. 1.05f = 1.0499999523, 0.05f = 0.0500000007; the exact difference
    // 0.9999999516 lies between 1 - 2^-24 (0.99999994) and 1, nearer the former: 1 - 2^-24.
    CHECK(amdFalloff(0.0f) == 1.0f - 0x1p-24f);
    // In double: 1.05 - 0.05 = 1.0000000000000000416 rounds to 1.
    CHECK(amdFalloff(0.0) == 1.0);
    // x = 1: real value -0.05 + 1.05/21 = 0. Binary32: 1.05f / 21 = 0.0499999977 rounds to
    // 0.05f - 2^-28 (0.0499999970, the float below 0.05f, spacing 2^-28 in [2^-5, 2^-4)), so
    // -0.05f + (0.05f - 2^-28) = -2^-28 exactly.
    CHECK(amdFalloff(1.0f) == -0x1p-28f);
    CHECK(std::abs(amdFalloff(1.0)) < 1e-16);
    // x = 0.5: 1 + 20 * 0.25 = 6 exactly; -0.05 + 1.05/6 = 0.125.
    CHECK(amdFalloff(0.5) == doctest::Approx(0.125).epsilon(1e-15));
    CHECK(amdFalloff(0.5f) == doctest::Approx(0.125f).epsilon(1e-6));
}

TEST_CASE("AMD falloff: non-increasing on [0, 1], binary32 is negative only at x = 1, which d < rad never reaches") {
    float previous = amdFalloff(0.0f);
    double previousD = amdFalloff(0.0);
    for (int i = 1; i <= 100000; ++i) {
        const float x = static_cast<float>(i) / 100000.0f;
        const float f = amdFalloff(x);
        REQUIRE(f <= previous);
        previous = f;
        const double fd = amdFalloff(static_cast<double>(i) / 100000.0);
        REQUIRE(fd <= previousD);
        previousD = fd;
    }
    // Where binary32 goes negative: x = 1 only (-2^-28 above). The float below 1, 1 - 2^-24, gives
    // 1 + 20 x^2 = 21 - 20 * 2^-23 (rounded to 20.999998), and 1.05f / 20.999998 >= 0.05f.
    CHECK(amdFalloff(std::nextafter(1.0f, 0.0f)) >= 0.0f);
    // The shader only runs the falloff for d < rad, where x = d / rad <= 1 - 2^-24: the exact
    // quotient of the largest d below rad is 1 - ulp(rad)/rad, at least 2^-24 below 1, so it never
    // rounds up to 1. Checked for radii across binades: the negative value is never reached.
    for (float rad : {0.001f, 0.75f, 1.0f, 1.5f, 3.0f, 7.3f, 100.0f, 12345.678f}) {
        const float dBelow = std::nextafter(rad, 0.0f);
        CHECK(dBelow / rad < 1.0f);
        CHECK(amdFalloff(dBelow / rad) >= 0.0f);
    }
}

TEST_CASE("AMD point light: hand-derived cases") {
    AmdPointLight<float> light;
    light.centerWorld = {0.0f, 0.0f, 2.0f};
    light.radius = 4.0f;
    light.color = {1.0f, 0.5f, 0.25f};
    const Vec3<float> normal(0.0f, 0.0f, 1.0f);
    const Vec3<float> viewDir = amdViewDir(Vec3<float>(0.0f, 0.0f, 10.0f), Vec3<float>(0.0f));
    CHECK(viewDir == Vec3<float>(0.0f, 0.0f, 1.0f));
    // Head-on: L = N = V = H = +z, d = 2, x = 0.5: diffuse = specular = color * 1 * f(0.5), and
    // multiplying by 1, 0.5 and 0.25 is exact.
    AmdLightingResult<float> r = amdPointLight(light, Vec3<float>(0.0f), normal, viewDir);
    const float f = amdFalloff(0.5f);
    CHECK(r.diffuse == light.color * f);
    CHECK(r.specular == light.color * f);
    // 45 degrees: light at (2, 0, 2): L = (1, 0, 1)/sqrt2, N.L = 0.70711; H = normalize(V + L) is
    // 22.5 degrees off N: N.H = cos(22.5) = 0.92388, ^8 = 0.53033; d = 2 sqrt2, x^2 = 0.5:
    // f = -0.05 + 1.05/11 = 0.0454545.
    light.centerWorld = {2.0f, 0.0f, 2.0f};
    r = amdPointLight(light, Vec3<float>(0.0f), normal, viewDir);
    const double f45 = -0.05 + 1.05 / 11.0;
    const double cos225 = std::cos(3.14159265358979323846 / 8.0);
    CHECK(r.diffuse.x == doctest::Approx(std::sqrt(0.5) * f45).epsilon(1e-6));
    CHECK(r.specular.x == doctest::Approx(std::pow(cos225, 8.0) * f45).epsilon(1e-6));
    CHECK(r.diffuse.y == doctest::Approx(0.5 * std::sqrt(0.5) * f45).epsilon(1e-6));
    // Facing away: N.L saturates to 0 and so does the diffuse; specular stays (H = normalize(V + L)
    // with L = -z and V = +z is 0/0: NaN, saturate(NaN) = 0 in D3D, so the specular is 0 too).
    light.centerWorld = {0.0f, 0.0f, -2.0f};
    r = amdPointLight(light, Vec3<float>(0.0f), normal, viewDir);
    CHECK(r.diffuse == Vec3<float>(0.0f));
    CHECK(r.specular == Vec3<float>(0.0f));
    // At and beyond the radius (strict d < rad): nothing.
    light.centerWorld = {0.0f, 0.0f, 4.0f};
    r = amdPointLight(light, Vec3<float>(0.0f), normal, viewDir);
    CHECK(r.diffuse == Vec3<float>(0.0f));
    CHECK(r.specular == Vec3<float>(0.0f));
}

TEST_CASE("AMD spot light: on axis, off axis, outside the cone, and the dark NaN spot") {
    // Apex at (0, 0, 4) pointing down -z; bounding radius 1 puts the sphere centre 1 along dir:
    // (0, 0, 3). Packed params: dir.x = dir.y = 0, z = -cos(cone) (dir.z < 0), falloff radius 8.
    const float cosCone = 0.816496580927726f;  // ForwardPlus11's cone (35.26 deg)
    AmdSpotLight<float> spot;
    spot.boundingCenterWorld = {0.0f, 0.0f, 3.0f};
    spot.boundingRadius = 1.0f;
    spot.color = {1.0f, 1.0f, 1.0f};
    spot.spotParams = {0.0f, 0.0f, -cosCone, 8.0f};
    CHECK(amdSpotDirection(spot.spotParams) == Vec3<float>(0.0f, 0.0f, -1.0f));
    CHECK(amdSpotPosition(spot, Vec3<float>(0.0f, 0.0f, -1.0f)) == Vec3<float>(0.0f, 0.0f, 4.0f));
    const Vec3<float> normal(0.0f, 0.0f, 1.0f);
    const Vec3<float> viewDir(0.0f, 0.0f, 1.0f);
    // On axis at the origin: d = 4, x = 0.5, cosCur = 1: radial = ((1 - c)/(1 - c))^2 = 1.
    AmdLightingResult<float> r = amdSpotLight(spot, Vec3<float>(0.0f), normal, viewDir);
    CHECK(r.diffuse.x == amdFalloff(0.5f));
    CHECK(r.specular.x == amdFalloff(0.5f));
    // Off axis at (1, 0, 0): to light (-1, 0, 4), d = sqrt17, cosCur = 4/sqrt17 = 0.970143;
    // radial = ((0.970143 - c)/(1 - c))^2; N.L = 0.970143; x = sqrt17 / 8.
    r = amdSpotLight(spot, Vec3<float>(1.0f, 0.0f, 0.0f), normal, viewDir);
    const double d = std::sqrt(17.0), cosCur = 4.0 / d, c = 0.816496580927726;
    const double radial = ((cosCur - c) / (1.0 - c)) * ((cosCur - c) / (1.0 - c));
    const double x = d / 8.0;
    CHECK(r.diffuse.x == doctest::Approx(cosCur * (-0.05 + 1.05 / (1.0 + 20.0 * x * x)) * radial).epsilon(1e-5));
    // Outside the cone at (4, 0, 0): cosCur = 4/sqrt32 = 0.7071 < 0.8165.
    r = amdSpotLight(spot, Vec3<float>(4.0f, 0.0f, 0.0f), normal, viewDir);
    CHECK(r.diffuse == Vec3<float>(0.0f));
    // Packed x = y = 0.75: 1 - 0.5625 - 0.5625 < 0, z = sqrt(negative) = NaN; the position and the
    // distance are NaN, `d < rad` is false: the light adds exactly 0, not NaN.
    spot.spotParams = {0.75f, 0.75f, cosCone, 8.0f};
    CHECK(std::isnan(amdSpotDirection(spot.spotParams).z));
    r = amdSpotLight(spot, Vec3<float>(0.0f), normal, viewDir);
    CHECK(r.diffuse == Vec3<float>(0.0f));
    CHECK(r.specular == Vec3<float>(0.0f));
}

TEST_CASE("AMD compose: pump x2 / x8, up/down ambient, texture modulation") {
    AmdLightingResult<float> accum;
    accum.diffuse = {0.125f, 0.25f, 0.5f};
    accum.specular = {0.0625f, 0.0f, 0.125f};
    // N = +y: blend = 1, ambient = up * 1 + down * 0 = up (exact).
    Vec3<float> out = amdComposePixel(accum, Vec3<float>(0.0f, 1.0f, 0.0f), Vec3<float>(1.0f), 0.5f,
                                      Vec3<float>(kAmdAmbientUp), Vec3<float>(kAmdAmbientDown));
    // r = 1 * ((0.25 + 0.013) + 0.5 * 0.5) = 0.513; g = 0.5 + 0.015; b = (1 + 0.05) + 1 * 0.5.
    CHECK(out.x == doctest::Approx(0.513f).epsilon(1e-6));
    CHECK(out.y == doctest::Approx(0.515f).epsilon(1e-6));
    CHECK(out.z == doctest::Approx(1.55f).epsilon(1e-6));
    // N = -y: blend = 0: ambient = down exactly; texture 0.5 halves everything (exact).
    out = amdComposePixel(AmdLightingResult<float>{}, Vec3<float>(0.0f, -1.0f, 0.0f), Vec3<float>(0.5f), 1.0f,
                          Vec3<float>(kAmdAmbientUp), Vec3<float>(kAmdAmbientDown));
    CHECK(out == Vec3<float>(kAmdAmbientDown) * 0.5f);
}

TEST_CASE("AMD light buffers decode: RGBA8 colour and half spot parameters") {
    // 0xAABBGGRR = 0xFF0080FF: r = 255 -> 1, g = 128 -> 128/255, b = 0.
    const glm::vec3 c = amdColorFromRgba8(0xFF0080FFu);
    CHECK(c.x == 1.0f);
    CHECK(c.y == 128.0f / 255.0f);
    CHECK(c.z == 0.0f);
    // Half 0x3C00 = 1, 0xBC00 = -1, 0x3800 = 0.5, 0x4800 = 8.
    const std::uint16_t halfs[4] = {0x3C00u, 0xBC00u, 0x3800u, 0x4800u};
    CHECK(amdSpotParamsFromHalf(halfs) == glm::vec4(1.0f, -1.0f, 0.5f, 8.0f));
}

TEST_CASE("AMD lighting: binary32 against the double reference over random configurations") {
    Pcg32 rng(11);
    double worst = 0.0;
    for (int i = 0; i < 5000; ++i) {
        AmdPointLight<float> lf;
        lf.centerWorld = {rng.uniform(-3.0f, 3.0f), rng.uniform(-3.0f, 3.0f), rng.uniform(0.1f, 3.0f)};
        lf.radius = rng.uniform(0.5f, 6.0f);
        lf.color = {rng.uniform01(), rng.uniform01(), rng.uniform01()};
        AmdPointLight<double> ld{Vec3<double>(lf.centerWorld), double(lf.radius), Vec3<double>(lf.color)};
        const Vec3<float> pos(rng.uniform(-1.0f, 1.0f), rng.uniform(-1.0f, 1.0f), 0.0f);
        const Vec3<float> normal(0.0f, 0.0f, 1.0f);
        const Vec3<float> view = amdViewDir(Vec3<float>(0.0f, 0.0f, 5.0f), pos);
        const Vec3<double> viewD = amdViewDir(Vec3<double>(0.0, 0.0, 5.0), Vec3<double>(pos));
        const auto rf = amdPointLight(lf, pos, normal, view);
        const auto rd = amdPointLight(ld, Vec3<double>(pos), Vec3<double>(normal), viewD);
        for (int k = 0; k < 3; ++k) {
            worst = std::max(worst, std::abs(double(rf.diffuse[k]) - rd.diffuse[k]));
            worst = std::max(worst, std::abs(double(rf.specular[k]) - rd.specular[k]));
        }
    }
    MESSAGE("AMD point light: max |binary32 - double| over 5000 cases = " << worst);
    CHECK(worst < 1e-5);
}

} // namespace tessera_test::shading_amd_lighting_test
