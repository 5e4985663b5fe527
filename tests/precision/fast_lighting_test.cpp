// The `fast` SIMD light loop (shading/fast_lighting.h) against doLighting in double on random
// pixels and lights of every type (disabled ones and ones out of range included), with counts that
// are no multiple of any lane width: the same equations, so the error is float rounding plus
// Highway's exp/log (a few ulp each, amplified by the specular power) and the reciprocal square
// root estimate after its Newton step; on every SIMD target compiled in and supported here.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <hwy/targets.h>

#include <tessera/shading/fast_lighting.h>
#include <tessera/shading/phong_material_shader.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::precision_fast_lighting_test {

using namespace tessera;

namespace {
double largestError();
}

TEST_CASE("fastLighting equals doLighting<double> within 2e-5 relative on random lights of every type, on every SIMD target") {
    for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
        hwy::SetSupportedTargetsForTest(target);
        hwy::GetChosenTarget().Update(hwy::SupportedTargets());
        const double maxRelative = largestError();
        INFO("target " << std::string(hwy::TargetName(target)));
        MESSAGE("largest error relative to max(1, |value|) on " << std::string(hwy::TargetName(target)) << ": " << maxRelative);
        // Measured 4.2e-6 when this bound was set (AVX-512; 4.5e-6 with the rsqrt estimate + Newton
        // step): float rounding over up to 100 summed lights plus exp(p log x) for p up to 62 (an
        // ulp of log x becomes p ulps of the power); 2e-5 leaves a margin of about 4x and still
        // fails on a wrong term (a missing attenuation or cone is O(1)).
        CHECK(maxRelative <= 2e-5);
    }
    hwy::SetSupportedTargetsForTest(0);
    hwy::GetChosenTarget().Update(hwy::SupportedTargets());
    // Specular off: the sums leave it at 0, as doLighting does.
    const std::vector<ViewLight<float>> one = viewLights<float>(std::vector<Light>(1), glm::mat4(1.0f));
    CHECK(fastLighting(FastLightSet::build(one), 8.0f, glm::vec3(0, 0, -1), glm::vec3(0, 0, 1), false).specular == glm::vec4(0.0f));
}

namespace {
double largestError() {
    std::mt19937 rng(1202);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), unit(0.0f, 1.0f);
    double maxRelative = 0;
    for (const std::size_t count : {1u, 7u, 16u, 33u, 100u}) {
        std::vector<Light> world(count);
        for (std::size_t i = 0; i < count; ++i) {
            Light& l = world[i];
            l.type = i % 3 == 0 ? LightType::Point : i % 3 == 1 ? LightType::Spot : LightType::Directional;
            l.positionWorld = glm::vec3(u(rng), u(rng), u(rng)) * 10.0f;
            l.directionWorld = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
            l.color = glm::vec3(unit(rng), unit(rng), unit(rng));
            l.range = 2.0f + 12.0f * unit(rng);
            l.intensity = 0.5f + unit(rng);
            l.spotHalfAngleDeg = 10.0f + 60.0f * unit(rng);
            l.enabled = i % 5 != 4;
        }
        const std::vector<ViewLight<float>> lightsF = viewLights<float>(world, glm::mat4(1.0f));
        const std::vector<ViewLight<double>> lightsD = viewLights<double>(world, glm::mat4(1.0f));
        const FastLightSet fast = FastLightSet::build(lightsF);
        for (int p = 0; p < 200; ++p) {
            const glm::vec3 posView = glm::vec3(u(rng), u(rng), u(rng)) * 8.0f + glm::vec3(0.0f, 0.0f, -2.0f);
            const glm::vec3 normalView = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
            const float power = 2.0f + 60.0f * unit(rng);
            const LightingResult<float> f = fastLighting(fast, power, posView, normalView, true);
            const LightingResult<double> e = doLighting<double>(lightsD, double(power), Vec4<double>(glm::dvec3(posView), 1.0),
                                                                Vec4<double>(glm::dvec3(normalView), 0.0), true);
            for (int c = 0; c < 3; ++c) {
                const double scaleD = std::max(1.0, std::abs(e.diffuse[c])), scaleS = std::max(1.0, std::abs(e.specular[c]));
                maxRelative = std::max(maxRelative, std::abs(double(f.diffuse[c]) - e.diffuse[c]) / scaleD);
                maxRelative = std::max(maxRelative, std::abs(double(f.specular[c]) - e.specular[c]) / scaleS);
            }
        }
    }
    return maxRelative;
}
} // namespace

} // namespace tessera_test::precision_fast_lighting_test
