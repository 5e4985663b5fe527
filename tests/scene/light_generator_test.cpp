// Tests of PCG32 against the reference pcg32-demo output and of the seeded light generators:
// a first light computed by hand from the PCG outputs, bit-exact determinism, lights inside
// the box and their intervals, unit directions, and the point fraction over 10,000 lights.
#include <tessera/scene/light_generator.h>

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::scene_light_generator_test {

using tessera::Bounds;
using tessera::Light;
using tessera::LightGeneratorSpec;
using tessera::LightType;
using tessera::Pcg32;

namespace {
Bounds box(glm::vec3 lo, glm::vec3 hi) {
    Bounds b;
    b.minWorld = lo;
    b.maxWorld = hi;
    return b;
}
// 2^-k as a float, exact.
float twoToMinus(int k) { return std::ldexp(1.0f, -k); }
} // namespace

TEST_CASE("Pcg32 reproduces the reference pcg32-demo output for seed 42, stream 54") {
    // pcg32-demo (pcg-c-basic) prints these for pcg32_srandom_r(&rng, 42u, 54u).
    Pcg32 rng(42u, 54u);
    const std::uint32_t expected[] = {0xa15c02b7u, 0x7b47f409u, 0xba1d3330u, 0x83d2f293u, 0xbfa4784bu, 0xcbed606eu};
    for (std::uint32_t value : expected) CHECK(rng.next() == value);
}

TEST_CASE("Pcg32 uniform01 uses the top 24 bits and stays below 1") {
    Pcg32 a(7), b(7);
    for (int i = 0; i < 1000; ++i) {
        const std::uint32_t raw = a.next();
        const float u = b.uniform01();
        CHECK(u == static_cast<float>(raw >> 8) * twoToMinus(24));
        CHECK(u >= 0.0f);
        CHECK(u < 1.0f);
    }
    Pcg32 c(7), d(7);
    CHECK(c.uniform(3.0f, 3.0f) == 3.0f);
    d.next();
    CHECK(c.uniform(-1.0f, 1.0f) == -1.0f + 2.0f * (static_cast<float>(d.next() >> 8) * twoToMinus(24)));
}

TEST_CASE("generateLights: the first light for seed 7, computed by hand from the PCG outputs") {
    // Pcg32(7) (default stream) outputs 1..16:
    // 50a0129b dcee7ac9 826f933c b5028a7d bccab907 6680ccd5 e433c762 2baac197
    // fcea3385 cce1be65 d50ffe56 c1747759 09afd6f5 c4bf340e 3d86f989 c92f3a1d
    Pcg32 check(7);
    const std::uint32_t outputs[] = {0x50a0129bu, 0xdcee7ac9u, 0x826f933cu, 0xb5028a7du, 0xbccab907u, 0x6680ccd5u,
                                     0xe433c762u, 0x2baac197u, 0xfcea3385u, 0xcce1be65u, 0xd50ffe56u, 0xc1747759u,
                                     0x09afd6f5u, 0xc4bf340eu, 0x3d86f989u, 0xc92f3a1du};
    for (std::uint32_t value : outputs) REQUIRE(check.next() == value);

    // Intervals [0, 2^k] make every draw exact: uniform(0, 2^k) = (output >> 8) * 2^(k - 24).
    LightGeneratorSpec spec;
    spec.count = 1;
    spec.seed = 7;
    spec.pointFraction = 0.25f;  // u1 = 0x50a012 / 2^24 = 0.3149 >= 0.25: a spot
    spec.box = box(glm::vec3(0.0f), glm::vec3(256.0f));
    spec.range = {0.0f, 8.0f};
    spec.colorMin = glm::vec3(0.0f);
    spec.colorMax = glm::vec3(1.0f);
    spec.intensity = {0.0f, 4.0f};
    spec.spotHalfAngleDeg = {0.0f, 64.0f};
    const std::vector<Light> lights = tessera::generateLights(spec, Bounds{});
    REQUIRE(lights.size() == 1);
    const Light& l = lights[0];
    auto bits = [](std::uint32_t output) { return static_cast<float>(output >> 8); };
    CHECK(l.type == LightType::Spot);
    CHECK(l.positionWorld.x == bits(0xdcee7ac9u) * twoToMinus(16));  // 220.931549
    CHECK(l.positionWorld.y == bits(0x826f933cu) * twoToMinus(16));  // 130.435837
    CHECK(l.positionWorld.z == bits(0xb5028a7du) * twoToMinus(16));  // 181.009918
    CHECK(l.range == bits(0xbccab907u) * twoToMinus(21));            // 5.89974642
    CHECK(l.color.x == bits(0x6680ccd5u) * twoToMinus(24));          // 0.400402784
    CHECK(l.color.y == bits(0xe433c762u) * twoToMinus(24));          // 0.89141506
    CHECK(l.color.z == bits(0x2baac197u) * twoToMinus(24));          // 0.170574248
    CHECK(l.intensity == bits(0xfcea3385u) * twoToMinus(22));        // 3.95179439
    CHECK(l.spotHalfAngleDeg == bits(0xcce1be65u) * twoToMinus(18)); // 51.2204514
    // Direction: outputs 11..13 give p = (0.664, 0.511, -0.924), |p|^2 = 1.56 > 1: rejected;
    // outputs 14..16 give p = (0.537, -0.519, 0.572), |p|^2 = 0.885: accepted, normalized.
    auto coordinate = [&](std::uint32_t output) { return -1.0 + double(output >> 8) * std::ldexp(1.0, -23); };
    const double p[3] = {coordinate(0xc4bf340eu), coordinate(0x3d86f989u), coordinate(0xc92f3a1du)};
    const double length = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    CHECK(l.directionWorld.x == doctest::Approx(p[0] / length).epsilon(1e-6));  // 0.57089746
    CHECK(l.directionWorld.y == doctest::Approx(p[1] / length).epsilon(1e-6));  // -0.552012384
    CHECK(l.directionWorld.z == doctest::Approx(p[2] / length).epsilon(1e-6));  // 0.607748747
    CHECK(l.directionWorld.x == 0.57089746f);
    CHECK(l.directionWorld.y == -0.552012384f);
    CHECK(l.directionWorld.z == 0.607748747f);
}

TEST_CASE("generateLights is deterministic bit for bit and respects box and intervals") {
    LightGeneratorSpec spec;
    spec.count = 2000;
    spec.seed = 0x123456789abcdefull;
    spec.pointFraction = 0.5f;
    spec.box = box({-15.0f, 0.1f, -15.0f}, {15.0f, 15.0f, 15.0f});
    spec.range = {1.0f, 2.0f};
    spec.spotHalfAngleDeg = {35.0f, 60.0f};
    spec.intensity = {0.5f, 1.5f};
    spec.colorMin = {0.1f, 0.2f, 0.3f};
    spec.colorMax = {0.4f, 0.5f, 0.6f};
    const std::vector<Light> a = tessera::generateLights(spec, Bounds{});
    const std::vector<Light> b = tessera::generateLights(spec, Bounds{});
    REQUIRE(a.size() == 2000);
    REQUIRE(b.size() == 2000);
    int spots = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const Light& l = a[i];
        CHECK(l.type == b[i].type);
        CHECK(std::memcmp(&l.positionWorld, &b[i].positionWorld, sizeof(glm::vec3)) == 0);
        CHECK(std::memcmp(&l.directionWorld, &b[i].directionWorld, sizeof(glm::vec3)) == 0);
        CHECK(std::memcmp(&l.color, &b[i].color, sizeof(glm::vec3)) == 0);
        CHECK(l.range == b[i].range);
        CHECK(l.intensity == b[i].intensity);
        CHECK(l.spotHalfAngleDeg == b[i].spotHalfAngleDeg);
        for (glm::length_t axis = 0; axis < 3; ++axis) {
            CHECK(l.positionWorld[axis] >= spec.box->minWorld[axis]);
            CHECK(l.positionWorld[axis] <= spec.box->maxWorld[axis]);
            CHECK(l.color[axis] >= spec.colorMin[axis]);
            CHECK(l.color[axis] <= spec.colorMax[axis]);
        }
        CHECK(l.range >= 1.0f);
        CHECK(l.range <= 2.0f);
        CHECK(l.intensity >= 0.5f);
        CHECK(l.intensity <= 1.5f);
        CHECK(l.enabled);
        if (l.type == LightType::Spot) {
            ++spots;
            CHECK(l.spotHalfAngleDeg >= 35.0f);
            CHECK(l.spotHalfAngleDeg <= 60.0f);
            // Unit length within a few binary32 rounding errors (eps = 2^-24): the float sum of
            // squares carries <= 3 eps relative (half of it in the length), sqrt 1/2 eps, each
            // division 1 eps, so |length - 1| <= 3 eps and |length^2 - 1| <= 6 eps.
            const double d = glm::dot(glm::dvec3(l.directionWorld), glm::dvec3(l.directionWorld));
            CHECK(std::abs(d - 1.0) <= 6.0 * std::ldexp(1.0, -24));
        } else {
            CHECK(l.type == LightType::Point);
        }
    }
    CHECK(spots > 0);

    // Another seed gives other lights.
    spec.seed += 1;
    const std::vector<Light> c = tessera::generateLights(spec, Bounds{});
    CHECK(std::memcmp(&c[0].positionWorld, &a[0].positionWorld, sizeof(glm::vec3)) != 0);
}

TEST_CASE("generateLights uses the scene bounds when the spec has no box") {
    LightGeneratorSpec spec;
    spec.count = 500;
    spec.seed = 3;
    const Bounds scene = box({-2.0f, 1.0f, 5.0f}, {-1.0f, 4.0f, 5.0f});  // flat in z
    const std::vector<Light> lights = tessera::generateLights(spec, scene);
    REQUIRE(lights.size() == 500);
    for (const Light& l : lights) {
        CHECK(l.type == LightType::Point);  // pointFraction defaults to 1
        CHECK(l.positionWorld.x >= -2.0f);
        CHECK(l.positionWorld.x <= -1.0f);
        CHECK(l.positionWorld.y >= 1.0f);
        CHECK(l.positionWorld.y <= 4.0f);
        CHECK(l.positionWorld.z == 5.0f);
    }
    spec.count = 0;
    CHECK(tessera::generateLights(spec, scene).empty());
}

TEST_CASE("generateLights respects pointFraction over 10,000 lights") {
    // The number of point lights is Binomial(n = 10000, p): standard deviation
    // sqrt(n p (1 - p)) <= 50. The check allows 5 standard deviations (a fair generator fails
    // with probability < 6e-7; the seeds are fixed, so the outcome is deterministic anyway).
    const float fractions[] = {0.0f, 0.1f, 0.5f, 0.9f, 1.0f};
    for (float p : fractions) {
        LightGeneratorSpec spec;
        spec.count = 10000;
        spec.seed = 99;
        spec.pointFraction = p;
        spec.box = box(glm::vec3(0.0f), glm::vec3(1.0f));
        int points = 0;
        for (const Light& l : tessera::generateLights(spec, Bounds{})) points += l.type == LightType::Point ? 1 : 0;
        const double n = 10000.0, mean = n * p, sigma = std::sqrt(n * p * (1.0 - p));
        CAPTURE(p);
        CHECK(std::abs(points - mean) <= 5.0 * sigma);
        if (p == 0.0f) CHECK(points == 0);
        if (p == 1.0f) CHECK(points == 10000);
    }
}

} // namespace tessera_test::scene_light_generator_test
