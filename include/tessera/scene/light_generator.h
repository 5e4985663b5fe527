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

enum class CallArgumentOrder : std::uint8_t;

// Which generator a "generate" entry of a scene file runs.
enum class LightGeneratorKind : std::uint8_t {
    Uniform,           // tessera's (below): PCG32, uniform in a box, the intervals of the spec
    AmdForwardPlus11,  // AMD ForwardPlus11's InitLights (generateLightsAmdForwardPlus11): the first
                       // `count` point and `spotCount` spot lights of the demo's 2048 + 2048; only
                       // count, spotCount, box and argumentOrder apply
};

struct LightGeneratorSpec {
    LightGeneratorKind kind = LightGeneratorKind::Uniform;
    std::uint32_t count = 0;                       // 0..1,000,000 (AmdForwardPlus11: point lights, 0..2048)
    std::uint32_t spotCount = 0;                   // AmdForwardPlus11 only: spot lights, 0..2048
    std::uint64_t seed = 0;
    float pointFraction = 1.0f;                    // probability of a point light (else spot), in [0, 1]
    std::optional<Bounds> box;                     // absent: the scene's bounds
    glm::vec2 range{1.0f, 2.0f};                   // [min, max], world units, > 0
    glm::vec2 spotHalfAngleDeg{35.0f, 60.0f};      // [min, max], in (0, 90)
    glm::vec2 intensity{1.0f, 1.0f};               // [min, max], >= 0
    glm::vec3 colorMin{0.0f}, colorMax{1.0f};      // per channel interval, linear RGB, >= 0
    CallArgumentOrder argumentOrder{};             // AmdForwardPlus11 only (default RightToLeft, as MSVC)
};

// Draw order per light (fixed, part of the format): type, position x, y, z, range, colour r, g, b,
// intensity, then for spots the angle and the direction. The direction is uniform on the sphere
// by rejection: p = (uniform(-1,1) x3) until 1e-6 < dot(p,p) <= 1, then p / sqrt(dot(p,p)).
// Only +, -, *, / and sqrt (all correctly rounded in IEEE 754), so no libm enters the result.
// Kind AmdForwardPlus11: lightsFromAmdForwardPlus11(generateLightsAmdForwardPlus11(box, 2048,
// argumentOrder), count, spotCount), box being the spec's or the scene's bounds (the demo's
// BBoxMin / BBoxMax); throws std::invalid_argument when count or spotCount exceeds 2048.
std::vector<Light> generateLights(const LightGeneratorSpec& spec, const Bounds& sceneBounds);

// ===== AMD ForwardPlus11's light generator (ForwardPlusUtil.cpp InitLights) ======================
// (docs/sources.md, ForwardPlus11). The demo fills MAX_NUM_LIGHTS = 2048 point lights, then 2048
// spot lights, from the MSVC C runtime's rand() after srand(1); the GUI then uses the first N of
// each. Every light gets the same radius, 0.075 * |half the scene AABB's diagonal|; spot lights
// fit the maximum-volume cone in that sphere (height 4/3 r, half angle atan(sqrt(2)/2) = 35.26 deg).
// Reproduced bit for bit, given the two things the source leaves to its compiler:
//  - the order in which the arguments of XMFLOAT4(GetRandFloat(..), GetRandFloat(..), ..) are
//    evaluated (C++ leaves it unspecified): CallArgumentOrder, default RightToLeft (what MSVC does
//    on x86 and x64 for such calls [tessera's inference, not guaranteed by MSVC]);
//  - AMD::ConvertF32ToF16 (amd_sdk HelperFunctions.cpp, not in our copy of the sources): taken as
//    the mantissa-truncating conversion, i.e. convert::floatToHalf (round toward zero) [ASSUMED].
// DirectXMath's XMVector3Length / XMVector3Normalize are evaluated as their SSE2 paths do it:
// sqrt((x*x + y*y) + z*z), then V / length.

// The MSVC CRT's rand(): holdrand = holdrand * 214013 + 2531011 (mod 2^32), returns
// (holdrand >> 16) & 0x7fff, RAND_MAX = 32767; srand(seed) sets holdrand = seed.
class MsvcRand {
public:
    explicit MsvcRand(std::uint32_t seed = 1) : mHoldRand(seed) {}
    std::uint32_t next();
    // GetRandFloat(min, max) = (float)rand() / (RAND_MAX + 1) * (max - min) + min, in binary32.
    float randFloat(float lo, float hi);
private:
    std::uint32_t mHoldRand;
};

enum class CallArgumentOrder : std::uint8_t { RightToLeft, LeftToRight };
static_assert(CallArgumentOrder{} == CallArgumentOrder::RightToLeft);

// One point light as the demo stores it: g_PointLightDataArrayCenterAndRadius[i] (world centre,
// radius) and g_PointLightDataArrayColor[i] (DWORD 0xAABBGGRR of R8G8B8A8_UNORM).
struct AmdPointLightData {
    glm::vec4 centerAndRadius{0.0f};
    std::uint32_t colorAbgr = 0;
};

// One spot light: bounding-sphere centre and radius, colour, and the R16G16B16A16_FLOAT spot
// parameters (dir.x, dir.y, cos(cone) with dir.z's sign in its sign bit, falloff radius) as half
// bits. directionWorld: the unit float direction before packing (for tessera's Light).
struct AmdSpotLightData {
    glm::vec4 centerAndRadius{0.0f};
    std::uint32_t colorAbgr = 0;
    std::uint16_t spotParams[4] = {0, 0, 0, 0};
    glm::vec3 directionWorld{0.0f, -1.0f, 0.0f};
};

struct AmdForwardPlus11Lights {
    std::vector<AmdPointLightData> points;
    std::vector<AmdSpotLightData> spots;
    float radius = 0.0f;             // fRadius = 0.075f * |0.5 (max - min)|, world units
    float spotFalloffRadius = 0.0f;  // 1.333333333333f * fRadius
};

inline constexpr std::uint32_t kAmdForwardPlus11MaxLights = 2048;            // ForwardPlus11::MAX_NUM_LIGHTS
inline constexpr float kAmdSpotCosCone = 0.816496580927726f;                 // cos(35.26438968 deg)
inline constexpr float kAmdSpotHalfAngleDeg = 35.26438968f;                  // atan(sqrt(2)/2)

// InitLights(BBoxMin, BBoxMax): `count` point lights, then `count` spot lights, from one MsvcRand(1)
// stream and one colour / direction counter each (the demo's function-static uCounter, shared by
// point and spot lights: colours alternate {R [0.9, 1], G, B [0, 1]} for odd calls and
// {R [0, 1], G [0.27, 1], B [0, 1]} for even calls; directions negate y on even calls).
// count = 2048 is the demo; a smaller count gives a prefix of the points, but different spots.
AmdForwardPlus11Lights generateLightsAmdForwardPlus11(const Bounds& sceneBounds,
                                                      std::uint32_t count = kAmdForwardPlus11MaxLights,
                                                      CallArgumentOrder order = CallArgumentOrder::RightToLeft);

// The first numPoint point and numSpot spot lights as tessera Lights (the demo's GUI picks the
// first N of each): colour = the UNORM codes / 255, intensity 1, point range = radius; spot
// position = centre - radius * direction (the apex, as the shader rebuilds it), range = the
// falloff radius, half angle kAmdSpotHalfAngleDeg. Throws std::invalid_argument if a count
// exceeds what `lights` holds.
std::vector<Light> lightsFromAmdForwardPlus11(const AmdForwardPlus11Lights& lights, std::uint32_t numPoint,
                                              std::uint32_t numSpot);

} // namespace tessera
