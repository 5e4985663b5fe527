// The HLSL Development Cookbook's G-buffer math (gbuffer/cookbook_gbuffer.h) against the chapter's
// formulas worked by hand and against geometric truth: specular power packing through the 8-bit
// target, the printed double decode (ERRATA.md), the normal through R11G11B10_FLOAT, linear depth
// and world position reconstruction of projected points.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include <tessera/buffers/conversion.h>
#include <tessera/buffers/surface.h>
#include <tessera/gbuffer/cookbook_gbuffer.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::gbuffer_cookbook_gbuffer_test {

using namespace tessera;

namespace {
float roundTrip(float power) { return unpackCookbookSpecPower(convert::unormToFloat(cookbookSpecPowerCode(power), 8)); }
} // namespace

TEST_CASE("cookbook gbuffer: specular power packs linearly over [0.1, 250.1] through the 8-bit target") {
    // (p - 0.1) / 250 -> code round(255 x) -> 0.1 + 250 * code / 255:
    //   0.1 -> 0 -> 0.1;  16 -> 0.0636 -> 16 -> 15.7863;  64 -> 0.2556 -> 65 -> 63.8255;
    //   128 -> 0.5116 -> 130 -> 127.551;  250.1 -> 1 -> 255 -> 250.1;  300 -> clamp -> 255 -> 250.1.
    CHECK(cookbookSpecPowerCode(0.1f) == 0);
    CHECK(roundTrip(0.1f) == doctest::Approx(0.1f));
    CHECK(cookbookSpecPowerCode(16.0f) == 16);
    CHECK(roundTrip(16.0f) == doctest::Approx(15.7863f).epsilon(1e-5));
    CHECK(cookbookSpecPowerCode(64.0f) == 65);
    CHECK(roundTrip(64.0f) == doctest::Approx(63.8255f).epsilon(1e-5));
    CHECK(cookbookSpecPowerCode(128.0f) == 130);
    CHECK(roundTrip(128.0f) == doctest::Approx(127.551f).epsilon(1e-5));
    CHECK(cookbookSpecPowerCode(250.1f) == 255);
    CHECK(roundTrip(300.0f) == doctest::Approx(250.1f));
    CHECK(cookbookSpecPowerCode(0.0f) == 0);  // below the range: stored 0 decodes to the minimum
    CHECK(cookbookSpecPowerCode(-5.0f) == 0);
    // Round-trip bound inside the range: half a code step, 250 / 255 / 2 = 0.4902 (the book:
    // "a step of about 0.98").
    for (float p = 0.1f; p <= 250.1f; p += 0.37f) CHECK(std::abs(roundTrip(p) - p) <= 250.0f / 510.0f + 1e-4f);
}

TEST_CASE("cookbook gbuffer: the chapter's printed unpack decodes twice and multiplies by 251 (ERRATA)") {
    // UnpackGBuffer as printed: norm + norm * 250 = 251 norm; each light PS then applies 0.1 + 250 x.
    CHECK(unpackCookbookSpecPowerAsPrinted(1.0f) == doctest::Approx(0.1f + 250.0f * 251.0f));  // 62750.1
    CHECK(unpackCookbookSpecPowerAsPrinted(0.0f) == doctest::Approx(0.1f));
    // 16 packs to code 16 and should come back near 16; the printed path gives ~ 3938.
    const float norm = convert::unormToFloat(cookbookSpecPowerCode(16.0f), 8);
    CHECK(unpackCookbookSpecPowerAsPrinted(norm) > 3900.0f);
    CHECK(unpackCookbookSpecPower(norm) == doctest::Approx(15.7863f).epsilon(1e-5));
}

TEST_CASE("cookbook gbuffer: the normal through R11G11B10_FLOAT") {
    // n = (0.6, 0.8, 0) -> n * 0.5 + 0.5 = (0.8, 0.9, 0.5) -> 11/11/10-bit floats (6/6/5-bit
    // mantissas, round to nearest): (0.796875, 0.8984375, 0.5) -> normalize(x * 2 - 1) =
    // (0.597481, 0.801883, 0).
    Surface s({1, 1, Format::R11G11B10_FLOAT, 1});
    s.store(0, 0, 0, glm::vec4(packCookbookNormal({0.6f, 0.8f, 0.0f}), 0.0f));
    const glm::vec3 stored(s.load(0, 0));
    CHECK(stored.x == 0.796875f);
    CHECK(stored.y == 0.8984375f);
    CHECK(stored.z == 0.5f);
    const glm::vec3 n = unpackCookbookNormal(stored);
    CHECK(n.x == doctest::Approx(0.597481f).epsilon(1e-5));
    CHECK(n.y == doctest::Approx(0.801883f).epsilon(1e-5));
    CHECK(n.z == 0.0f);
    // Unit normals in every direction come back within the format's precision. tessera's float
    // -> float11/10 rounds toward zero (D3D11.3 §3.2.2 allows it): on [0, 1) a stored x or y is
    // off by < 2^-7 (6-bit mantissa), z by < 2^-6 (5-bit); decoded (x 2 - 1) by < 2^-6, 2^-6,
    // 2^-5: a vector error below 2^-5 sqrt(1.5) = 0.0383, so an angle below 0.0383 rad (2.2 deg).
    std::mt19937 rng(3);
    std::normal_distribution<float> g;
    for (int i = 0; i < 500; ++i) {
        const glm::vec3 dir = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
        s.store(0, 0, 0, glm::vec4(packCookbookNormal(dir), 0.0f));
        const glm::vec3 back = unpackCookbookNormal(glm::vec3(s.load(0, 0)));
        CHECK(glm::dot(back, dir) >= std::cos(0.0383f));
    }
}

TEST_CASE("cookbook gbuffer: linear depth and world position reconstruct projected points") {
    // Zn = 1, Zf = 100: Q = 100/99, PV.z = -Q, PV.w = -Q; depth 0 -> 1, 0.5 -> 1.98020,
    // 0.9 -> 9.17431, 0.99 -> 50.2514, 1 -> 100 (float: 100.00048).
    const glm::mat4 projectionLh = glm::perspectiveLH_ZO(glm::radians(60.0f), 16.0f / 9.0f, 1.0f, 100.0f);
    const CookbookPerspectiveValues pv = cookbookPerspectiveValues(projectionLh);
    CHECK(pv.z == doctest::Approx(-100.0 / 99.0));
    CHECK(pv.w == doctest::Approx(-100.0 / 99.0));
    CHECK(cookbookLinearDepth(0.0f, pv) == doctest::Approx(1.0f));
    CHECK(cookbookLinearDepth(0.5f, pv) == doctest::Approx(1.98020f).epsilon(1e-5));
    CHECK(cookbookLinearDepth(0.9f, pv) == doctest::Approx(9.17431f).epsilon(1e-5));
    CHECK(cookbookLinearDepth(0.99f, pv) == doctest::Approx(50.2514f).epsilon(1e-5));
    CHECK(cookbookLinearDepth(1.0f, pv) == doctest::Approx(100.0f).epsilon(1e-5));
    // CalcWorldPos with PV.xy = (1, 1) and ViewInv = I: cs (0.5, -0.5), z 1.980198 ->
    // (0.990099, -0.990099, 1.980198).
    const CookbookPerspectiveValues unit{1.0f, 1.0f, pv.z, pv.w};
    const glm::vec3 p = cookbookWorldPosition(glm::vec2(0.5f, -0.5f), 1.980198f, unit, glm::mat4(1.0f));
    CHECK(p.x == doctest::Approx(0.990099f).epsilon(1e-5));
    CHECK(p.y == doctest::Approx(-0.990099f).epsilon(1e-5));
    CHECK(p.z == doctest::Approx(1.980198f).epsilon(1e-5));
    // Geometric truth: random world points seen by a rotated camera, projected, recovered.
    const glm::mat4 viewLh = glm::lookAtLH(glm::vec3(3.0f, 2.0f, -7.0f), glm::vec3(0.5f, 0.0f, 1.0f), glm::vec3(0, 1, 0));
    const glm::mat4 worldFromViewLh = glm::inverse(viewLh);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-6.0f, 6.0f);
    int checked = 0;
    for (int i = 0; i < 400; ++i) {
        const glm::vec3 world(u(rng), u(rng), u(rng));
        const glm::vec4 view = viewLh * glm::vec4(world, 1.0f);
        if (view.z < 1.5f) continue;  // in front of the near plane
        const glm::vec4 clip = projectionLh * view;
        const float depth = clip.z / clip.w;
        const float linear = cookbookLinearDepth(depth, pv);
        // Float depth near 1 loses the view z: its relative error grows like Zf/Zn x 2^-24 / (1 - depth).
        CHECK(linear == doctest::Approx(view.z).epsilon(1e-4));
        const glm::vec3 back = cookbookWorldPosition(glm::vec2(clip) / clip.w, linear, pv, worldFromViewLh);
        CHECK(glm::length(back - world) <= 1e-4f * glm::length(glm::vec3(view)) + 1e-5f);
        ++checked;
    }
    CHECK(checked > 100);
}

} // namespace tessera_test::gbuffer_cookbook_gbuffer_test
