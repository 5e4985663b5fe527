// PCG32 and the seeded light generators of scene files: the PRNG, the draw order and the
// arithmetic are part of the file format (binary32, +,-,*,/ and sqrt only, no libm), so a
// scene file gives the same lights bit for bit on every machine and compiler.
#include <tessera/scene/light_generator.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include <tessera/buffers/conversion.h>

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
    if (spec.kind == LightGeneratorKind::AmdForwardPlus11) {
        if (spec.count > kAmdForwardPlus11MaxLights || spec.spotCount > kAmdForwardPlus11MaxLights)
            throw std::invalid_argument("generateLights: AMD ForwardPlus11 has at most 2048 point and 2048 spot lights");
        return lightsFromAmdForwardPlus11(generateLightsAmdForwardPlus11(box, kAmdForwardPlus11MaxLights, spec.argumentOrder),
                                          spec.count, spec.spotCount);
    }
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

// ===== AMD ForwardPlus11 ========================================================================

namespace {
constexpr std::uint32_t kMsvcRandMultiplier = 214013u;  // MSVC CRT rand.c
constexpr std::uint32_t kMsvcRandIncrement = 2531011u;
constexpr float kMsvcRandMaxPlusOne = 32768.0f;         // RAND_MAX + 1

// (DWORD)(c * 255.0f + 0.5f): truncation of the binary32 sum.
std::uint32_t unormByteAmd(float c) { return static_cast<std::uint32_t>(c * 255.0f + 0.5f); }

// XMFLOAT4(f(a), f(b), f(c), w): the three calls in the chosen argument order.
template <class F>
glm::vec3 threeCalls(CallArgumentOrder order, F&& f) {
    glm::vec3 v{0.0f};
    if (order == CallArgumentOrder::RightToLeft) {
        v.z = f(2);
        v.y = f(1);
        v.x = f(0);
    } else {
        v.x = f(0);
        v.y = f(1);
        v.z = f(2);
    }
    return v;
}

// DirectXMath SSE2 XMVector3Length: sqrt((x*x + y*y) + z*z).
float lengthXm(const glm::vec3& v) {
    const float xx = v.x * v.x, yy = v.y * v.y, zz = v.z * v.z;
    return std::sqrt((xx + yy) + zz);
}

// GetRandColor: counter++ first; even -> (R [0,1], G [0.27,1], B [0,1]); odd -> (R [0.9,1], G, B [0,1]).
std::uint32_t randColorAmd(MsvcRand& rng, std::uint32_t& counter, CallArgumentOrder order) {
    ++counter;
    const bool even = counter % 2u == 0u;
    const glm::vec3 c = threeCalls(order, [&](int channel) {
        if (channel == 0) return even ? rng.randFloat(0.0f, 1.0f) : rng.randFloat(0.9f, 1.0f);
        if (channel == 1) return even ? rng.randFloat(0.27f, 1.0f) : rng.randFloat(0.0f, 1.0f);
        return rng.randFloat(0.0f, 1.0f);
    });
    const std::uint32_t r = unormByteAmd(c.x), g = unormByteAmd(c.y), b = unormByteAmd(c.z);
    const std::uint32_t a = unormByteAmd(1.0f);
    return (a << 24) | (b << 16) | (g << 8) | r;  // ABGR = DXGI_FORMAT_R8G8B8A8_UNORM
}

// GetRandLightDirection: counter++; x [-1,1), y [0.1,1), z [-1,1) as three statements; y negated
// on even counts; XMVector3Normalize.
glm::vec3 randDirectionAmd(MsvcRand& rng, std::uint32_t& counter) {
    ++counter;
    glm::vec3 v;
    v.x = rng.randFloat(-1.0f, 1.0f);
    v.y = rng.randFloat(0.1f, 1.0f);
    v.z = rng.randFloat(-1.0f, 1.0f);
    if (counter % 2u == 0u) v.y = -v.y;
    const float length = lengthXm(v);
    return {v.x / length, v.y / length, v.z / length};
}
}  // namespace

std::uint32_t MsvcRand::next() {
    mHoldRand = mHoldRand * kMsvcRandMultiplier + kMsvcRandIncrement;
    return (mHoldRand >> 16u) & 0x7FFFu;
}

float MsvcRand::randFloat(float lo, float hi) {
    const float unit = static_cast<float>(next()) / kMsvcRandMaxPlusOne;  // exact: 15 bits / 2^15
    const float scaled = unit * (hi - lo);
    return scaled + lo;
}

AmdForwardPlus11Lights generateLightsAmdForwardPlus11(const Bounds& sceneBounds, std::uint32_t count, CallArgumentOrder order) {
    AmdForwardPlus11Lights out;
    MsvcRand rng(1);  // srand(1)
    std::uint32_t colorCounter = 0, directionCounter = 0;
    const glm::vec3 boxMin = sceneBounds.minWorld, boxMax = sceneBounds.maxWorld;
    const glm::vec3 extents = 0.5f * (boxMax - boxMin);
    out.radius = 0.075f * lengthXm(extents);
    out.spotFalloffRadius = 1.333333333333f * out.radius;
    const auto randCenter = [&] {
        return threeCalls(order, [&](int axis) {
            const auto a = static_cast<glm::length_t>(axis);
            return rng.randFloat(boxMin[a], boxMax[a]);
        });
    };
    out.points.reserve(count);
    for (std::uint32_t i = 0; i < count; ++i) {
        AmdPointLightData light;
        light.centerAndRadius = glm::vec4(randCenter(), out.radius);
        light.colorAbgr = randColorAmd(rng, colorCounter, order);
        out.points.push_back(light);
    }
    out.spots.reserve(count);
    for (std::uint32_t i = 0; i < count; ++i) {
        AmdSpotLightData light;
        light.centerAndRadius = glm::vec4(randCenter(), out.radius);
        light.colorAbgr = randColorAmd(rng, colorCounter, order);
        light.directionWorld = randDirectionAmd(rng, directionCounter);
        // PackSpotParams: halves of dir.x, dir.y, cos(cone), falloff radius; dir.z's sign goes
        // into the cone's sign bit (|= 0x8000 if z < 0, else &= 0x7fff).
        light.spotParams[0] = convert::floatToHalf(light.directionWorld.x);
        light.spotParams[1] = convert::floatToHalf(light.directionWorld.y);
        light.spotParams[2] = convert::floatToHalf(kAmdSpotCosCone);
        light.spotParams[3] = convert::floatToHalf(out.spotFalloffRadius);
        if (light.directionWorld.z < 0.0f) light.spotParams[2] = static_cast<std::uint16_t>(light.spotParams[2] | 0x8000u);
        else light.spotParams[2] = static_cast<std::uint16_t>(light.spotParams[2] & 0x7FFFu);
        out.spots.push_back(light);
    }
    return out;
}

std::vector<Light> lightsFromAmdForwardPlus11(const AmdForwardPlus11Lights& lights, std::uint32_t numPoint,
                                              std::uint32_t numSpot) {
    if (numPoint > lights.points.size() || numSpot > lights.spots.size())
        throw std::invalid_argument("lightsFromAmdForwardPlus11: asked for " + std::to_string(numPoint) + " point and " +
                                    std::to_string(numSpot) + " spot lights, the set holds " +
                                    std::to_string(lights.points.size()) + " and " + std::to_string(lights.spots.size()));
    const auto colour = [](std::uint32_t abgr) {
        return glm::vec3(convert::unormToFloat(abgr & 0xFFu, 8), convert::unormToFloat((abgr >> 8) & 0xFFu, 8),
                         convert::unormToFloat((abgr >> 16) & 0xFFu, 8));
    };
    std::vector<Light> out;
    out.reserve(std::size_t{numPoint} + numSpot);
    for (std::uint32_t i = 0; i < numPoint; ++i) {
        Light light;
        light.type = LightType::Point;
        light.positionWorld = glm::vec3(lights.points[i].centerAndRadius);
        light.range = lights.points[i].centerAndRadius.w;
        light.color = colour(lights.points[i].colorAbgr);
        light.name = "amd-point-" + std::to_string(i);
        out.push_back(light);
    }
    for (std::uint32_t i = 0; i < numSpot; ++i) {
        const AmdSpotLightData& spot = lights.spots[i];
        Light light;
        light.type = LightType::Spot;
        const glm::vec3 dir = spot.directionWorld;
        const float r = spot.centerAndRadius.w;
        light.positionWorld = glm::vec3(spot.centerAndRadius.x - r * dir.x, spot.centerAndRadius.y - r * dir.y,
                                        spot.centerAndRadius.z - r * dir.z);
        light.directionWorld = dir;
        light.range = lights.spotFalloffRadius;
        light.spotHalfAngleDeg = kAmdSpotHalfAngleDeg;
        light.color = colour(spot.colorAbgr);
        light.name = "amd-spot-" + std::to_string(i);
        out.push_back(light);
    }
    return out;
}

} // namespace tessera
