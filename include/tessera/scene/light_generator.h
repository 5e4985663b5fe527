// Seeded light generators: N point and/or spot lights placed uniformly in a box (the scene's
// bounds or a given one) with range, spot-angle, intensity and colour drawn from intervals.
// The PRNG is specified bit for bit (see Pcg32 below), so the same file gives the same lights
// on every machine and compiler.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/scene/light.h>
#include <tessera/scene/scene.h>

namespace tessera {

// PCG32 (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient Statistically Good
// Algorithms for Random Number Generation", pcg32 = XSH-RR 64/32, LCG multiplier
// 6364136223846793005). uniform01() = (next() >> 8) * 2^-24: 24 random bits, exact in binary32,
// in [0, 1). uniform(a, b) = a + (b - a) * uniform01(), evaluated in binary32 without FMA.
class Pcg32 {
public:
    explicit Pcg32(std::uint64_t seed, std::uint64_t stream = 0x14057B7EF767814Full);
    std::uint32_t next();
    float uniform01();
    float uniform(float lo, float hi);
private:
    std::uint64_t mState = 0, mIncrement = 0;
};

struct LightGeneratorSpec {
    std::uint32_t count = 0;                       // 0..1,000,000
    std::uint64_t seed = 0;
    float pointFraction = 1.0f;                    // probability of a point light (else spot), in [0, 1]
    std::optional<Bounds> box;                     // absent: the scene's bounds
    glm::vec2 range{1.0f, 2.0f};                   // [min, max], world units, > 0
    glm::vec2 spotHalfAngleDeg{35.0f, 60.0f};      // [min, max], in (0, 90)
    glm::vec2 intensity{1.0f, 1.0f};               // [min, max], >= 0
    glm::vec3 colorMin{0.0f}, colorMax{1.0f};      // per channel interval, linear RGB, >= 0
};

// Draw order per light (fixed, part of the format): type, position x, y, z, range, colour r, g, b,
// intensity, then for spots the angle and the direction. The direction is uniform on the sphere
// by rejection: p = (uniform(-1,1) x3) until 1e-6 < dot(p,p) <= 1, then p / sqrt(dot(p,p)).
// Only +, -, *, / and sqrt (all correctly rounded in IEEE 754), so no libm enters the result.
std::vector<Light> generateLights(const LightGeneratorSpec& spec, const Bounds& sceneBounds);

} // namespace tessera
