// D3D11.3 scalar data conversions (§3.1.5, §3.1.6, §3.2): normalized integers, float16,
// float11/float10, sRGB. Bit-exact by construction: integer bit manipulation, one exact double
// product per normalized conversion, and literal sRGB tables checked by conversion_test.cpp.
#include <tessera/buffers/conversion.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cstdint>

namespace tessera::convert {
namespace {

[[maybe_unused]] constexpr unsigned kMaxNormBits = 24; // x * (2^n - 1) exact in double for n <= 24
constexpr std::uint32_t kF32ExpMask = 0x7F800000u;  // float32 exponent field (also +INF)
constexpr std::uint32_t kF32FracMask = 0x007FFFFFu; // float32 fraction field, 23 bits
constexpr std::uint32_t kF32Hidden = 0x00800000u;   // implicit leading 1 of a normal float32
constexpr int kF32Bias = 127;
constexpr int kSmallBias = 15;     // float16 / float11 / float10 exponent bias (5-bit exponent)
constexpr std::uint32_t kSmallExpAllOnes = 31u; // e == 31: INF or NaN

std::uint32_t bitsOf(float x) { return std::bit_cast<std::uint32_t>(x); }
float floatOf(std::uint32_t u) { return std::bit_cast<float>(u); }

// Round half up of p in [0, 2^53): the integer part is exact (truncating conversion), and so is
// p - i (both share an exponent range: i >= p/2 whenever i >= 1), so the tie test is exact.
std::uint32_t roundHalfUp(double p) {
    const auto i = static_cast<std::uint64_t>(p);
    const double frac = p - static_cast<double>(i);
    return static_cast<std::uint32_t>(i + (frac >= 0.5 ? 1u : 0u));
}

// float32 magnitude bits `a` (sign cleared) -> a 5-bit-exponent float with `fracBits` fraction
// bits, rounding toward zero (§3.2.2). Returns the unsigned magnitude code.
std::uint32_t packMagnitudeRtz(std::uint32_t a, unsigned fracBits) {
    const std::uint32_t infCode = kSmallExpAllOnes << fracBits;
    const unsigned drop = 23u - fracBits; // float32 fraction bits that do not fit
    if (a > kF32ExpMask) {                // NaN: keep the top payload bits, stay a NaN
        std::uint32_t payload = (a & kF32FracMask) >> drop;
        if (payload == 0) payload = 1u << (fracBits - 1u);
        return infCode | payload;
    }
    if (a == kF32ExpMask) return infCode; // INF -> INF
    const int e = static_cast<int>(a >> 23) - kF32Bias;
    if (e > kSmallBias) return infCode - 1u; // finite overflow -> largest finite (RTZ)
    if (e >= 1 - kSmallBias) {              // normal in the target
        return (static_cast<std::uint32_t>(e + kSmallBias) << fracBits) | ((a & kF32FracMask) >> drop);
    }
    if ((a >> 23) == 0) return 0; // float32 zero or denormal (< 2^-126): truncates to 0
    // Target denormal: value = S * 2^(e-23) with S = 1.f as a 24-bit integer; the target unit
    // is 2^(1 - bias - fracBits) = 2^(-14 - fracBits), so the code is S >> (9 - fracBits - e).
    const auto shift = static_cast<unsigned>(9 - static_cast<int>(fracBits) - e);
    return shift >= 32u ? 0u : (kF32Hidden | (a & kF32FracMask)) >> shift;
}

// The inverse of packMagnitudeRtz: exact (every such value is a float32).
float unpackMagnitude(std::uint32_t code, unsigned fracBits) {
    const std::uint32_t e = code >> fracBits;
    const std::uint32_t f = code & ((1u << fracBits) - 1u);
    const unsigned lift = 23u - fracBits;
    if (e == kSmallExpAllOnes) return floatOf(kF32ExpMask | (f << lift)); // INF or NaN
    if (e == 0) {
        // Denormal f * 2^(-14 - fracBits): f < 2^fracBits is exact in float, the power of two
        // (>= 2^-24, a normal float32) scales exactly.
        const float unit = floatOf(static_cast<std::uint32_t>(kF32Bias + 1 - kSmallBias - static_cast<int>(fracBits)) << 23);
        return static_cast<float>(f) * unit;
    }
    return floatOf(((e - kSmallBias + kF32Bias) << 23) | (f << lift));
}

// FLOAT -> SRGB decision thresholds (§3.2.3.8): kSrgbThresholds[k-1] is the smallest float x
// whose ideal sRGB value reaches (k - 0.5)/255, i.e. the first x that encodes to code k.
// Generated with 60-digit arithmetic; regenerated and checked in long double by the unit test.
constexpr std::array<float, 255> kSrgbThresholds = {
    0x1.3e4568p-13f, 0x1.dd681cp-12f, 0x1.8dd6c2p-11f, 0x1.167cbcp-10f,
    0x1.660e16p-10f, 0x1.b59f7p-10f, 0x1.029866p-9f, 0x1.2a6112p-9f,
    0x1.5229bep-9f, 0x1.79f26cp-9f, 0x1.a1e5a2p-9f, 0x1.cbf736p-9f,
    0x1.f86806p-9f, 0x1.13a0cp-8f, 0x1.2c4666p-8f, 0x1.46297ap-8f,
    0x1.614e62p-8f, 0x1.7db96ep-8f, 0x1.9b6edap-8f, 0x1.ba72cep-8f,
    0x1.dac95ep-8f, 0x1.fc768cp-8f, 0x1.0fbf22p-7f, 0x1.21f236p-7f,
    0x1.34d664p-7f, 0x1.486d9p-7f, 0x1.5cb98ep-7f, 0x1.71bc34p-7f,
    0x1.877748p-7f, 0x1.9dec9p-7f, 0x1.b51dc8p-7f, 0x1.cd0ca8p-7f,
    0x1.e5bae2p-7f, 0x1.ff2a1ep-7f, 0x1.0cae04p-6f, 0x1.1a291ep-6f,
    0x1.28072cp-6f, 0x1.3648f8p-6f, 0x1.44ef4cp-6f, 0x1.53fafp-6f,
    0x1.636ca6p-6f, 0x1.73453p-6f, 0x1.838552p-6f, 0x1.942dc6p-6f,
    0x1.a53f48p-6f, 0x1.b6ba96p-6f, 0x1.c8a064p-6f, 0x1.daf16ap-6f,
    0x1.edae5cp-6f, 0x1.006bf8p-5f, 0x1.0a3768p-5f, 0x1.1439d8p-5f,
    0x1.1e73ap-5f, 0x1.28e514p-5f, 0x1.338e8ap-5f, 0x1.3e7058p-5f,
    0x1.498acep-5f, 0x1.54de44p-5f, 0x1.606b08p-5f, 0x1.6c316ep-5f,
    0x1.7831c8p-5f, 0x1.846c64p-5f, 0x1.90e194p-5f, 0x1.9d91a4p-5f,
    0x1.aa7ce6p-5f, 0x1.b7a3a6p-5f, 0x1.c5063p-5f, 0x1.d2a4d4p-5f,
    0x1.e07fdcp-5f, 0x1.ee9794p-5f, 0x1.fcec48p-5f, 0x1.05bf2p-4f,
    0x1.0d26e4p-4f, 0x1.14ad96p-4f, 0x1.1c5356p-4f, 0x1.24184ep-4f,
    0x1.2bfc9ep-4f, 0x1.34006ap-4f, 0x1.3c23d8p-4f, 0x1.446708p-4f,
    0x1.4cca2p-4f, 0x1.554d4p-4f, 0x1.5df08ep-4f, 0x1.66b42ap-4f,
    0x1.6f9836p-4f, 0x1.789cd6p-4f, 0x1.81c228p-4f, 0x1.8b0852p-4f,
    0x1.946f72p-4f, 0x1.9df7acp-4f, 0x1.a7a11ep-4f, 0x1.b16beap-4f,
    0x1.bb5832p-4f, 0x1.c56614p-4f, 0x1.cf95b2p-4f, 0x1.d9e72ap-4f,
    0x1.e45aap-4f, 0x1.eef02ep-4f, 0x1.f9a7f8p-4f, 0x1.02410ep-3f,
    0x1.07bf5cp-3f, 0x1.0d4ef6p-3f, 0x1.12efecp-3f, 0x1.18a24cp-3f,
    0x1.1e6628p-3f, 0x1.243b8ap-3f, 0x1.2a2286p-3f, 0x1.301b2ap-3f,
    0x1.362584p-3f, 0x1.3c41a2p-3f, 0x1.426f96p-3f, 0x1.48af6cp-3f,
    0x1.4f0132p-3f, 0x1.5564fap-3f, 0x1.5bdadp-3f, 0x1.6262c2p-3f,
    0x1.68fcep-3f, 0x1.6fa938p-3f, 0x1.7667d8p-3f, 0x1.7d38cep-3f,
    0x1.841c2ap-3f, 0x1.8b11f6p-3f, 0x1.921a44p-3f, 0x1.99352p-3f,
    0x1.a06298p-3f, 0x1.a7a2bap-3f, 0x1.aef594p-3f, 0x1.b65b34p-3f,
    0x1.bdd3a8p-3f, 0x1.c55efcp-3f, 0x1.ccfd3ep-3f, 0x1.d4ae7cp-3f,
    0x1.dc72c4p-3f, 0x1.e44a22p-3f, 0x1.ec34a4p-3f, 0x1.f43258p-3f,
    0x1.fc434ap-3f, 0x1.0233c4p-2f, 0x1.064f8ep-2f, 0x1.0a750cp-2f,
    0x1.0ea444p-2f, 0x1.12dd3ap-2f, 0x1.171ff8p-2f, 0x1.1b6c82p-2f,
    0x1.1fc2ep-2f, 0x1.242316p-2f, 0x1.288d2cp-2f, 0x1.2d012ap-2f,
    0x1.317f12p-2f, 0x1.3606eep-2f, 0x1.3a98c4p-2f, 0x1.3f3498p-2f,
    0x1.43da7p-2f, 0x1.488a56p-2f, 0x1.4d444cp-2f, 0x1.52085cp-2f,
    0x1.56d688p-2f, 0x1.5baedap-2f, 0x1.609154p-2f, 0x1.657ep-2f,
    0x1.6a74e2p-2f, 0x1.6f76p-2f, 0x1.748162p-2f, 0x1.79970ap-2f,
    0x1.7eb702p-2f, 0x1.83e14ep-2f, 0x1.8915f2p-2f, 0x1.8e54f8p-2f,
    0x1.939e64p-2f, 0x1.98f23cp-2f, 0x1.9e5084p-2f, 0x1.a3b944p-2f,
    0x1.a92c82p-2f, 0x1.aeaa42p-2f, 0x1.b4328cp-2f, 0x1.b9c564p-2f,
    0x1.bf62dp-2f, 0x1.c50ad4p-2f, 0x1.cabd7ap-2f, 0x1.d07ac6p-2f,
    0x1.d642bap-2f, 0x1.dc1562p-2f, 0x1.e1f2bep-2f, 0x1.e7dad6p-2f,
    0x1.edcdbp-2f, 0x1.f3cb5p-2f, 0x1.f9d3bcp-2f, 0x1.ffe6fcp-2f,
    0x1.03028ap-1f, 0x1.061704p-1f, 0x1.0930eep-1f, 0x1.0c504ep-1f,
    0x1.0f7524p-1f, 0x1.129f72p-1f, 0x1.15cf3ep-1f, 0x1.190488p-1f,
    0x1.1c3f54p-1f, 0x1.1f7fa4p-1f, 0x1.22c57cp-1f, 0x1.2610dcp-1f,
    0x1.2961c8p-1f, 0x1.2cb844p-1f, 0x1.301452p-1f, 0x1.3375f4p-1f,
    0x1.36dd2cp-1f, 0x1.3a49fep-1f, 0x1.3dbc6cp-1f, 0x1.413478p-1f,
    0x1.44b226p-1f, 0x1.483578p-1f, 0x1.4bbe7p-1f, 0x1.4f4d12p-1f,
    0x1.52e15ep-1f, 0x1.567b5ap-1f, 0x1.5a1b06p-1f, 0x1.5dc064p-1f,
    0x1.616b7ap-1f, 0x1.651c48p-1f, 0x1.68d2dp-1f, 0x1.6c8f16p-1f,
    0x1.70511ep-1f, 0x1.7418e6p-1f, 0x1.77e674p-1f, 0x1.7bb9cap-1f,
    0x1.7f92eap-1f, 0x1.8371d6p-1f, 0x1.87569p-1f, 0x1.8b411ep-1f,
    0x1.8f317ep-1f, 0x1.9327b6p-1f, 0x1.9723c6p-1f, 0x1.9b25bp-1f,
    0x1.9f2d7ap-1f, 0x1.a33b24p-1f, 0x1.a74ebp-1f, 0x1.ab6822p-1f,
    0x1.af877cp-1f, 0x1.b3acbep-1f, 0x1.b7d7eep-1f, 0x1.bc090cp-1f,
    0x1.c0401cp-1f, 0x1.c47d2p-1f, 0x1.c8c018p-1f, 0x1.cd090ap-1f,
    0x1.d157f6p-1f, 0x1.d5acep-1f, 0x1.da07cap-1f, 0x1.de68b4p-1f,
    0x1.e2cfa4p-1f, 0x1.e73c9ap-1f, 0x1.ebaf98p-1f, 0x1.f028a2p-1f,
    0x1.f4a7bap-1f, 0x1.f92ce2p-1f, 0x1.fdb81cp-1f,
};

// SRGB -> FLOAT (§3.2.3.7): kSrgbToLinear[k] is the float nearest the exact curve value at
// k/255 (the nearest lies >= 0.004 ULP from a rounding midpoint). Checked by the unit test.
constexpr std::array<float, 256> kSrgbToLinear = {
    0x0p+0f, 0x1.3e4568p-12f, 0x1.3e4568p-11f, 0x1.dd681cp-11f,
    0x1.3e4568p-10f, 0x1.8dd6c2p-10f, 0x1.dd681cp-10f, 0x1.167cbap-9f,
    0x1.3e4568p-9f, 0x1.660e14p-9f, 0x1.8dd6c2p-9f, 0x1.b6a31cp-9f,
    0x1.e1e31ep-9f, 0x1.07c38cp-8f, 0x1.1fcc2cp-8f, 0x1.390ffap-8f,
    0x1.53936cp-8f, 0x1.6f5adep-8f, 0x1.8c6a94p-8f, 0x1.aac6cp-8f,
    0x1.ca7382p-8f, 0x1.eb74e2p-8f, 0x1.06e76cp-7f, 0x1.18c2a6p-7f,
    0x1.2b4e0ap-7f, 0x1.3e8b7cp-7f, 0x1.527cd6p-7f, 0x1.6723eep-7f,
    0x1.7c8292p-7f, 0x1.929a88p-7f, 0x1.a96d92p-7f, 0x1.c0fd68p-7f,
    0x1.d94bbep-7f, 0x1.f25a44p-7f, 0x1.061552p-6f, 0x1.135f3ep-6f,
    0x1.210bb8p-6f, 0x1.2f1b8cp-6f, 0x1.3d8f84p-6f, 0x1.4c6866p-6f,
    0x1.5ba6fap-6f, 0x1.6b4c04p-6f, 0x1.7b5842p-6f, 0x1.8bcc74p-6f,
    0x1.9ca958p-6f, 0x1.adefaap-6f, 0x1.bfa02p-6f, 0x1.d1bb74p-6f,
    0x1.e4425ap-6f, 0x1.f73586p-6f, 0x1.054ad4p-5f, 0x1.0f31bap-5f,
    0x1.194fccp-5f, 0x1.23a55ep-5f, 0x1.2e32c8p-5f, 0x1.38f86p-5f,
    0x1.43f678p-5f, 0x1.4f2d64p-5f, 0x1.5a9d76p-5f, 0x1.664702p-5f,
    0x1.722a56p-5f, 0x1.7e47c8p-5f, 0x1.8a9fa4p-5f, 0x1.97323ap-5f,
    0x1.a3ffd8p-5f, 0x1.b108dp-5f, 0x1.be4d6cp-5f, 0x1.cbcdfap-5f,
    0x1.d98ac6p-5f, 0x1.e7841cp-5f, 0x1.f5ba48p-5f, 0x1.0216cap-4f,
    0x1.096f26p-4f, 0x1.10e65cp-4f, 0x1.187c9p-4f, 0x1.2031e8p-4f,
    0x1.280688p-4f, 0x1.2ffa92p-4f, 0x1.380e2ap-4f, 0x1.404174p-4f,
    0x1.489494p-4f, 0x1.5107acp-4f, 0x1.599adep-4f, 0x1.624e4ep-4f,
    0x1.6b221ep-4f, 0x1.74167p-4f, 0x1.7d2b66p-4f, 0x1.86612p-4f,
    0x1.8fb7cp-4f, 0x1.992f68p-4f, 0x1.a2c83ap-4f, 0x1.ac8256p-4f,
    0x1.b65ddcp-4f, 0x1.c05aecp-4f, 0x1.ca79a8p-4f, 0x1.d4ba3p-4f,
    0x1.df1ca2p-4f, 0x1.e9a12p-4f, 0x1.f447cap-4f, 0x1.ff10bcp-4f,
    0x1.04fe0cp-3f, 0x1.0a84fep-3f, 0x1.101d44p-3f, 0x1.15c6eep-3f,
    0x1.1b8208p-3f, 0x1.214ea6p-3f, 0x1.272cd4p-3f, 0x1.2d1ca2p-3f,
    0x1.331e1ep-3f, 0x1.393158p-3f, 0x1.3f566p-3f, 0x1.458d42p-3f,
    0x1.4bd60ep-3f, 0x1.5230d4p-3f, 0x1.589dap-3f, 0x1.5f1c84p-3f,
    0x1.65ad8ap-3f, 0x1.6c50c4p-3f, 0x1.73063ep-3f, 0x1.79ce06p-3f,
    0x1.80a82ep-3f, 0x1.8794cp-3f, 0x1.8e93ccp-3f, 0x1.95a55ep-3f,
    0x1.9cc986p-3f, 0x1.a40052p-3f, 0x1.ab49cep-3f, 0x1.b2a60ap-3f,
    0x1.ba1512p-3f, 0x1.c196f4p-3f, 0x1.c92bbep-3f, 0x1.d0d37cp-3f,
    0x1.d88e3ep-3f, 0x1.e05c0ep-3f, 0x1.e83cfcp-3f, 0x1.f03116p-3f,
    0x1.f83866p-3f, 0x1.00297ep-2f, 0x1.044072p-2f, 0x1.086116p-2f,
    0x1.0c8b7p-2f, 0x1.10bf86p-2f, 0x1.14fd6p-2f, 0x1.194502p-2f,
    0x1.1d9676p-2f, 0x1.21f1bep-2f, 0x1.2656e4p-2f, 0x1.2ac5ecp-2f,
    0x1.2f3edep-2f, 0x1.33c1cp-2f, 0x1.384e98p-2f, 0x1.3ce56cp-2f,
    0x1.418642p-2f, 0x1.46312p-2f, 0x1.4ae60ep-2f, 0x1.4fa51p-2f,
    0x1.546e2cp-2f, 0x1.59416cp-2f, 0x1.5e1edp-2f, 0x1.630664p-2f,
    0x1.67f82ap-2f, 0x1.6cf428p-2f, 0x1.71fa68p-2f, 0x1.770aecp-2f,
    0x1.7c25bcp-2f, 0x1.814adcp-2f, 0x1.867a54p-2f, 0x1.8bb428p-2f,
    0x1.90f86p-2f, 0x1.9647p-2f, 0x1.9ba01p-2f, 0x1.a10394p-2f,
    0x1.a67192p-2f, 0x1.abea1p-2f, 0x1.b16d14p-2f, 0x1.b6faa4p-2f,
    0x1.bc92c6p-2f, 0x1.c2357ep-2f, 0x1.c7e2d2p-2f, 0x1.cd9acap-2f,
    0x1.d35d6ap-2f, 0x1.d92ab6p-2f, 0x1.df02b8p-2f, 0x1.e4e57p-2f,
    0x1.ead2e8p-2f, 0x1.f0cb26p-2f, 0x1.f6ce2cp-2f, 0x1.fcdcp-2f,
    0x1.017a56p-1f, 0x1.048c18p-1f, 0x1.07a34ap-1f, 0x1.0abfeep-1f,
    0x1.0de208p-1f, 0x1.11099ap-1f, 0x1.1436a8p-1f, 0x1.176932p-1f,
    0x1.1aa13ep-1f, 0x1.1ddecap-1f, 0x1.2121dep-1f, 0x1.246a7ap-1f,
    0x1.27b8ap-1f, 0x1.2b0c54p-1f, 0x1.2e6598p-1f, 0x1.31c46ep-1f,
    0x1.3528dcp-1f, 0x1.3892ep-1f, 0x1.3c028p-1f, 0x1.3f77bcp-1f,
    0x1.42f29ap-1f, 0x1.467318p-1f, 0x1.49f93ep-1f, 0x1.4d850ap-1f,
    0x1.511682p-1f, 0x1.54ada4p-1f, 0x1.584a78p-1f, 0x1.5becfep-1f,
    0x1.5f9538p-1f, 0x1.634328p-1f, 0x1.66f6d4p-1f, 0x1.6ab03ap-1f,
    0x1.6e6f6p-1f, 0x1.723448p-1f, 0x1.75fef4p-1f, 0x1.79cf64p-1f,
    0x1.7da59ep-1f, 0x1.8181a4p-1f, 0x1.856378p-1f, 0x1.894b1cp-1f,
    0x1.8d3892p-1f, 0x1.912bdep-1f, 0x1.9525p-1f, 0x1.9923fep-1f,
    0x1.9d28d8p-1f, 0x1.a13392p-1f, 0x1.a5442cp-1f, 0x1.a95aacp-1f,
    0x1.ad771p-1f, 0x1.b1995ep-1f, 0x1.b5c198p-1f, 0x1.b9efbep-1f,
    0x1.be23d4p-1f, 0x1.c25ddep-1f, 0x1.c69ddcp-1f, 0x1.cae3d2p-1f,
    0x1.cf2fcp-1f, 0x1.d381aap-1f, 0x1.d7d994p-1f, 0x1.dc377ep-1f,
    0x1.e09b6ap-1f, 0x1.e5055cp-1f, 0x1.e97556p-1f, 0x1.edeb5cp-1f,
    0x1.f2676cp-1f, 0x1.f6e98cp-1f, 0x1.fb71bcp-1f, 0x1p+0f,
};

static_assert(std::is_sorted(kSrgbThresholds.begin(), kSrgbThresholds.end()));
static_assert(kSrgbToLinear.front() == 0.0f && kSrgbToLinear.back() == 1.0f); // §3.2.3.7 ends exact

} // namespace

std::uint32_t floatToUnorm(float x, unsigned bits) {
    assert(bits >= 1 && bits <= kMaxNormBits);
    const std::uint32_t maxCode = (1u << bits) - 1u;
    if (!(x > 0.0f)) return 0; // NaN, -INF, negatives, +-0
    if (x >= 1.0f) return maxCode;
    return roundHalfUp(static_cast<double>(x) * static_cast<double>(maxCode));
}

float unormToFloat(std::uint32_t c, unsigned bits) {
    assert(bits >= 1 && bits <= kMaxNormBits);
    const std::uint32_t maxCode = (1u << bits) - 1u;
    return static_cast<float>(c & maxCode) / static_cast<float>(maxCode);
}

std::uint32_t floatToSnorm(float x, unsigned bits) {
    assert(bits >= 2 && bits <= kMaxNormBits);
    const std::uint32_t maxCode = (1u << (bits - 1u)) - 1u;
    const std::uint32_t mask = (1u << bits) - 1u;
    if (x != x) return 0; // NaN
    const bool negative = x < 0.0f;
    const float mag = negative ? -x : x;
    const std::uint32_t r = mag >= 1.0f ? maxCode : roundHalfUp(static_cast<double>(mag) * static_cast<double>(maxCode));
    return (negative ? 0u - r : r) & mask; // two's complement in the low n bits
}

float snormToFloat(std::uint32_t c, unsigned bits) {
    assert(bits >= 2 && bits <= kMaxNormBits);
    const int maxCode = (1 << (bits - 1u)) - 1;
    const unsigned pad = 32u - bits;
    const auto v = static_cast<std::int32_t>(c << pad) >> pad; // sign-extend (C++20: arithmetic)
    if (v < -maxCode) return -1.0f;                              // most negative code
    return static_cast<float>(v) / static_cast<float>(maxCode);
}

std::uint16_t floatToHalf(float x) {
    const std::uint32_t u = bitsOf(x);
    const std::uint32_t sign = (u >> 16) & 0x8000u;
    return static_cast<std::uint16_t>(sign | packMagnitudeRtz(u & 0x7FFFFFFFu, 10));
}

float halfToFloat(std::uint16_t h) {
    const float mag = unpackMagnitude(h & 0x7FFFu, 10);
    return floatOf(bitsOf(mag) | (static_cast<std::uint32_t>(h & 0x8000u) << 16));
}

std::uint32_t floatToFloat11(float x) {
    const std::uint32_t u = bitsOf(x);
    const std::uint32_t a = u & 0x7FFFFFFFu;
    if (a <= kF32ExpMask && (u >> 31) != 0) return 0; // < 0, -0, -INF clamp to 0 (§3.1.6)
    return packMagnitudeRtz(a, 6);
}

std::uint32_t floatToFloat10(float x) {
    const std::uint32_t u = bitsOf(x);
    const std::uint32_t a = u & 0x7FFFFFFFu;
    if (a <= kF32ExpMask && (u >> 31) != 0) return 0;
    return packMagnitudeRtz(a, 5);
}

float float11ToFloat(std::uint32_t v) { return unpackMagnitude(v & 0x7FFu, 6); }
float float10ToFloat(std::uint32_t v) { return unpackMagnitude(v & 0x3FFu, 5); }

std::uint8_t linearToSrgb8(float linear) {
    if (!(linear > 0.0f)) return 0; // NaN, negatives, -INF, +-0
    // Number of thresholds <= linear; +INF and values >= 1 pass all 255.
    const auto it = std::upper_bound(kSrgbThresholds.begin(), kSrgbThresholds.end(), linear);
    return static_cast<std::uint8_t>(it - kSrgbThresholds.begin());
}

float srgb8ToLinear(std::uint8_t code) { return kSrgbToLinear[code]; }

} // namespace tessera::convert
