// AMD ForwardPlus11's light generator (scene/light_generator.h): the MSVC rand() stream, the first
// point light derived by hand from it, argument order, colour alternation and ranges, spot
// parameters and directions, determinism, counts, and the conversion to tessera Lights.
#include <tessera/scene/light_generator.h>

#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include <tessera/buffers/conversion.h>
#include <tessera/shading/amd_lighting.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::scene_amd_light_generator_test {

using namespace tessera;

namespace {
Bounds box(glm::vec3 lo, glm::vec3 hi) {
    Bounds b;
    b.minWorld = lo;
    b.maxWorld = hi;
    return b;
}
}  // namespace

TEST_CASE("MsvcRand: the MSVC CRT sequence after srand(1)") {
    // holdrand = 1 * 214013 + 2531011 = 2745024 -> >> 16 = 41; the well-known MSVC sequence.
    MsvcRand rng(1);
    const std::uint32_t expected[] = {41, 18467, 6334, 26500, 19169, 15724, 11478, 29358, 26962, 24464};
    for (std::uint32_t value : expected) CHECK(rng.next() == value);
    // GetRandFloat(lo, hi) = rand() / 32768 * (hi - lo) + lo: with [0, 32768) it returns rand() exactly.
    MsvcRand a(1);
    CHECK(a.randFloat(0.0f, 32768.0f) == 41.0f);
    CHECK(a.randFloat(-1.0f, 1.0f) == 18467.0f / 32768.0f * 2.0f - 1.0f);
}

TEST_CASE("AMD generator: the first point light, derived from the rand() stream") {
    // Box [0, 32768)^3: each centre coordinate is the rand() value itself. Right-to-left argument
    // evaluation draws z, y, x: z = 41, y = 18467, x = 6334.
    const AmdForwardPlus11Lights lights = generateLightsAmdForwardPlus11(box(glm::vec3(0.0f), glm::vec3(32768.0f)), 4);
    CHECK(lights.points[0].centerAndRadius == glm::vec4(6334.0f, 18467.0f, 41.0f, lights.radius));
    // radius = 0.075f * sqrt(3 * 16384^2) = 0.075 * 16384 * sqrt3 = 2128.34
    CHECK(lights.radius == doctest::Approx(0.075 * 16384.0 * std::sqrt(3.0)).epsilon(1e-6));
    CHECK(lights.spotFalloffRadius == 1.333333333333f * lights.radius);
    // Colour: first GetRandColor call, counter 1 (odd): (R [0.9, 1], G [0, 1], B [0, 1]), drawn
    // b, g, r: b = 26500/32768 = 0.80872 -> 0.80872 * 255 + 0.5 = 206.7 -> 206;
    // g = 19169/32768 = 0.58499 -> 149.67 -> 149; r = 0.9 + 15724/32768 * 0.1 = 0.94799 -> 242.24 -> 242.
    CHECK(lights.points[0].colorAbgr == 0xFFCE95F2u);  // A 255, B 206, G 149, R 242
    // Light 1 continues the stream: centre z, y, x = 11478, 29358, 26962.
    CHECK(glm::vec3(lights.points[1].centerAndRadius) == glm::vec3(26962.0f, 29358.0f, 11478.0f));
    // Left-to-right evaluation draws x first instead.
    const AmdForwardPlus11Lights ltr =
        generateLightsAmdForwardPlus11(box(glm::vec3(0.0f), glm::vec3(32768.0f)), 4, CallArgumentOrder::LeftToRight);
    CHECK(glm::vec3(ltr.points[0].centerAndRadius) == glm::vec3(41.0f, 18467.0f, 6334.0f));
}

TEST_CASE("AMD generator: 2048 + 2048 lights, deterministic, inside the box, colours alternate") {
    const Bounds b = box({-20.0f, 0.0f, -10.0f}, {20.0f, 15.0f, 10.0f});
    const AmdForwardPlus11Lights lights = generateLightsAmdForwardPlus11(b);
    REQUIRE(lights.points.size() == kAmdForwardPlus11MaxLights);
    REQUIRE(lights.spots.size() == kAmdForwardPlus11MaxLights);
    const AmdForwardPlus11Lights again = generateLightsAmdForwardPlus11(b);
    for (std::size_t i = 0; i < lights.points.size(); ++i) {
        CHECK(lights.points[i].centerAndRadius == again.points[i].centerAndRadius);
        CHECK(lights.points[i].colorAbgr == again.points[i].colorAbgr);
        CHECK(std::bit_cast<std::uint64_t>(lights.spots[i].spotParams) == std::bit_cast<std::uint64_t>(again.spots[i].spotParams));
    }
    // Radius: 0.075 * |(20, 7.5, 10)| = 0.075 * sqrt(556.25) = 1.76886.
    CHECK(lights.radius == doctest::Approx(0.075 * std::sqrt(556.25)).epsilon(1e-6));
    std::uint32_t nanDirections = 0;
    for (std::uint32_t i = 0; i < 2 * kAmdForwardPlus11MaxLights; ++i) {
        const bool spot = i >= kAmdForwardPlus11MaxLights;
        const std::uint32_t j = spot ? i - kAmdForwardPlus11MaxLights : i;
        const glm::vec4 c = spot ? lights.spots[j].centerAndRadius : lights.points[j].centerAndRadius;
        for (glm::length_t a = 0; a < 3; ++a) {
            CHECK(c[a] >= b.minWorld[a]);
            CHECK(c[a] <= b.maxWorld[a]);
        }
        // Colour counter = i + 1 across points then spots: odd counts (i even) have R in [0.9, 1]
        // -> code >= (DWORD)(0.9f * 255 + 0.5) = 230; even counts have G in [0.27, 1] -> >= 69.
        const std::uint32_t abgr = spot ? lights.spots[j].colorAbgr : lights.points[j].colorAbgr;
        CHECK((abgr >> 24) == 255u);
        if (i % 2 == 0) CHECK((abgr & 0xFFu) >= 230u);
        else CHECK(((abgr >> 8) & 0xFFu) >= 69u);
        if (spot) {
            const AmdSpotLightData& s = lights.spots[j];
            const glm::vec3 d = s.directionWorld;
            CHECK(std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z) == doctest::Approx(1.0).epsilon(1e-6));
            // Direction counter j + 1: even counts (j odd) point down.
            CHECK((j % 2 == 1 ? d.y < 0.0f : d.y > 0.0f));
            // Sign bit of the cone cosine = sign of dir.z; magnitude = half(0.8164966) truncated.
            CHECK(((s.spotParams[2] & 0x8000u) != 0) == (d.z < 0.0f));
            CHECK((s.spotParams[2] & 0x7FFFu) == convert::floatToHalf(kAmdSpotCosCone));
            CHECK(s.spotParams[3] == convert::floatToHalf(lights.spotFalloffRadius));
            // The shader's rebuilt direction.
            const glm::vec3 rebuilt = amdSpotDirection(Vec4<float>(amdSpotParamsFromHalf(s.spotParams)));
            if (std::isnan(rebuilt.z)) ++nanDirections;
            else CHECK(glm::dot(rebuilt, d) > 0.999f);
        }
    }
    MESSAGE("AMD generator: " << nanDirections << " of 2048 spot lights rebuild a NaN direction (x^2 + y^2 > 1 after half packing)");
}

TEST_CASE("AMD generator: as tessera Lights") {
    const Bounds b = box({0.0f, 0.0f, 0.0f}, {10.0f, 10.0f, 10.0f});
    const AmdForwardPlus11Lights amd = generateLightsAmdForwardPlus11(b, 16);
    const std::vector<Light> lights = lightsFromAmdForwardPlus11(amd, 3, 2);
    REQUIRE(lights.size() == 5);
    CHECK(lights[0].type == LightType::Point);
    CHECK(lights[0].positionWorld == glm::vec3(amd.points[0].centerAndRadius));
    CHECK(lights[0].range == amd.radius);
    CHECK(lights[0].color.x == convert::unormToFloat(amd.points[0].colorAbgr & 0xFFu, 8));
    CHECK(lights[3].type == LightType::Spot);
    const glm::vec3 dir = amd.spots[0].directionWorld;
    const glm::vec3 apex = glm::vec3(amd.spots[0].centerAndRadius) - amd.radius * dir;
    CHECK(lights[3].positionWorld.x == doctest::Approx(apex.x));
    CHECK(lights[3].positionWorld.z == doctest::Approx(apex.z));
    CHECK(lights[3].directionWorld == dir);
    CHECK(lights[3].range == amd.spotFalloffRadius);
    CHECK(lights[3].spotHalfAngleDeg == kAmdSpotHalfAngleDeg);
    CHECK_THROWS_AS(lightsFromAmdForwardPlus11(amd, 17, 0), std::invalid_argument);
}

} // namespace tessera_test::scene_amd_light_generator_test
