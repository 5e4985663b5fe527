// PCG32 and the seeded light generators of scene files: the PRNG, the draw order and the
// arithmetic are part of the file format (binary32, +,-,*,/ and sqrt only, no libm), so a
// scene file gives the same lights bit for bit on every machine and compiler.
#include <tessera/scene/light_generator.h>

#include <cmath>

namespace tessera {

namespace {
// The LCG multiplier of pcg32 (O'Neill 2014, pcg_basic.c: PCG_DEFAULT_MULTIPLIER_64).
constexpr std::uint64_t kPcgMultiplier = 6364136223846793005ull;
// 2^-24: scales a 24-bit integer into [0, 1) exactly.
constexpr float kTwoToMinus24 = 1.0f / 16777216.0f;
}

// Seeding as pcg32_srandom_r in pcg_basic.c: state = 0, inc = (stream << 1) | 1, step,
// state += seed, step.
Pcg32::Pcg32(std::uint64_t seed, std::uint64_t stream) : mState(0), mIncrement((stream << 1u) | 1u) {
    next();
    mState += seed;
    next();
}

// pcg32_random_r: XSH-RR output of the old state, then the LCG step.
std::uint32_t Pcg32::next() {
    const std::uint64_t oldState = mState;
    mState = oldState * kPcgMultiplier + mIncrement;
    const auto xorShifted = static_cast<std::uint32_t>(((oldState >> 18u) ^ oldState) >> 27u);
    const auto rotation = static_cast<std::uint32_t>(oldState >> 59u);
    return (xorShifted >> rotation) | (xorShifted << ((32u - rotation) & 31u));
}

float Pcg32::uniform01() { return static_cast<float>(next() >> 8u) * kTwoToMinus24; }

float Pcg32::uniform(float lo, float hi) {
    // Two separately rounded binary32 operations (the build uses -ffp-contract=off: no FMA).
    const float span = hi - lo;
    const float scaled = span * uniform01();
    return lo + scaled;
}

std::vector<Light> generateLights(const LightGeneratorSpec& spec, const Bounds& sceneBounds) {
    const Bounds& box = spec.box ? *spec.box : sceneBounds;
    Pcg32 rng(spec.seed);
    std::vector<Light> lights;
    lights.reserve(spec.count);
    for (std::uint32_t i = 0; i < spec.count; ++i) {
        Light light;
        // Draw order (part of the format): type, position x y z, range, colour r g b, intensity,
        // then for spots the angle and the direction.
        light.type = rng.uniform01() < spec.pointFraction ? LightType::Point : LightType::Spot;
        light.positionWorld.x = rng.uniform(box.minWorld.x, box.maxWorld.x);
        light.positionWorld.y = rng.uniform(box.minWorld.y, box.maxWorld.y);
        light.positionWorld.z = rng.uniform(box.minWorld.z, box.maxWorld.z);
        light.range = rng.uniform(spec.range.x, spec.range.y);
        light.color.x = rng.uniform(spec.colorMin.x, spec.colorMax.x);
        light.color.y = rng.uniform(spec.colorMin.y, spec.colorMax.y);
        light.color.z = rng.uniform(spec.colorMin.z, spec.colorMax.z);
        light.intensity = rng.uniform(spec.intensity.x, spec.intensity.y);
        if (light.type == LightType::Spot) {
            light.spotHalfAngleDeg = rng.uniform(spec.spotHalfAngleDeg.x, spec.spotHalfAngleDeg.y);
            // Uniform on the unit sphere by rejection from the cube [-1, 1)^3 (the ball's volume
            // is pi/6 of the cube's, so about 1.9 tries per direction).
            glm::vec3 p{0.0f};
            float lengthSquared = 0.0f;
            do {
                p.x = rng.uniform(-1.0f, 1.0f);
                p.y = rng.uniform(-1.0f, 1.0f);
                p.z = rng.uniform(-1.0f, 1.0f);
                const float xx = p.x * p.x, yy = p.y * p.y, zz = p.z * p.z;
                lengthSquared = (xx + yy) + zz;
            } while (!(lengthSquared > 1e-6f && lengthSquared <= 1.0f));
            const float length = std::sqrt(lengthSquared);  // IEEE 754: correctly rounded
            light.directionWorld = glm::vec3(p.x / length, p.y / length, p.z / length);
        }
        lights.push_back(light);
    }
    return lights;
}

} // namespace tessera
