// Unit tests for tessera::convert (D3D11.3 §3.1.5, §3.1.6, §3.2): hand-derived tables for
// NaN, +-INF, denormals, clamping and exact rounding ties; exhaustive round trips; and the
// sRGB literal tables regenerated here in long double (std::pow is fine in a test).
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <tessera/buffers/conversion.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::buffers_conversion_test {

using namespace tessera::convert;

namespace {

float fromBits(std::uint32_t u) { return std::bit_cast<float>(u); }
std::uint32_t toBits(float x) { return std::bit_cast<std::uint32_t>(x); }
float nextDown(float x) { return std::nextafter(x, -std::numeric_limits<float>::infinity()); }
float nextUp(float x) { return std::nextafter(x, std::numeric_limits<float>::infinity()); }

constexpr float kInf = std::numeric_limits<float>::infinity();
const float kNaN = fromBits(0x7FC00000u);      // quiet NaN
const float kNegNaN = fromBits(0xFFC00000u);   // quiet NaN, sign set
const float kMinDenorm = fromBits(0x00000001u); // 2^-149, float32 denormal
const float kMaxDenorm = fromBits(0x007FFFFFu); // 2^-126 - 2^-149

struct NormCase {
    float x;
    unsigned bits;
    std::uint32_t expected;
    const char* why;
};

} // namespace

TEST_CASE("floatToUnorm: NaN, infinities, clamping, denormals and exact ties (§3.2.3.6)") {
    const std::vector<NormCase> cases = {
        {kNaN, 8, 0, "NaN -> 0"},
        {kNegNaN, 8, 0, "negative NaN -> 0"},
        {-kInf, 8, 0, "-INF clamps to 0"},
        {-1.0f, 8, 0, "negative clamps to 0"},
        {-0.0f, 8, 0, "-0 -> 0"},
        {kInf, 8, 255, "+INF clamps to 1 -> 2^8-1"},
        {2.0f, 8, 255, "> 1 clamps to 1"},
        {1.0f, 8, 255, "1 * 255 = 255"},
        {kMinDenorm, 8, 0, "2^-149 * 255 ~ 3.6e-43 -> 0"},
        {kMaxDenorm, 24, 0, "(2^-126) * (2^24-1) ~ 2.0e-31 -> 0"},
        // 0.5 * 255 = 127.5 exactly: a true tie. §3.2.3.6 adds 0.5 and truncates -> 128
        // (round-to-nearest-even agrees: 128 is even).
        {0.5f, 8, 128, "tie 127.5 -> 128"},
        // nextDown(0.5) = 0.5 - 2^-25: 127.5 - 255*2^-25 = 127.4999924 -> 127.
        {nextDown(0.5f), 8, 127, "just below the tie"},
        {nextUp(0.5f), 8, 128, "just above the tie: 127.5000152 -> 128"},
        // 1/255 as a float is 0x1.010102p-8 (1/255 = 2^-8 (1 + 2^-8 + 2^-16 + 2^-24 + ...)
        // rounds up in the 23rd fraction bit); * 255 = 1.0000000298 -> 1.
        {fromBits(0x3B808081u), 8, 1, "float(1/255) -> 1"},
        {0.5f, 10, 512, "tie 1023/2 = 511.5 -> 512"},
        {nextDown(0.5f), 10, 511, "511.4999695 -> 511"},
        {0.5f, 16, 32768, "tie 65535/2 = 32767.5 -> 32768"},
        {0.5f, 24, 8388608, "tie (2^24-1)/2 = 8388607.5 -> 8388608"},
        {1.0f, 24, 16777215, "1 -> 2^24-1"},
        // nextDown(1) = 1 - 2^-24: (1 - 2^-24)(2^24 - 1) = 2^24 - 2 + 2^-24 -> 16777214.
        {nextDown(1.0f), 24, 16777214, "needs the exact 48-bit product"},
        // x = (2^23 + 1) 2^-24: x (2^24 - 1) = 2^23 + 1 - (2^23 + 1) 2^-24 = 8388608.49999994 -> 8388608.
        {fromBits(0x3F000001u), 24, 8388608, "0.5 + 2^-24 just below the 8388608.5 boundary"},
        // 1-bit UNORM: 0.5 * 1 = 0.5, a tie. §3.2.3.6 "+0.5 then drop the fraction" -> 1, where
        // round-to-nearest-even would give 0: this row pins the spec's half-up rule.
        {0.5f, 1, 1, "UNORM1 tie rounds up, not to even"},
        {nextDown(0.5f), 1, 0, "UNORM1 below the tie"},
        // 2-bit: 1/3 as a float is 0x3EAAAAAB = 1/3 + 2^-25/3, * 3 = 1 + 2^-25 -> 1.
        {1.0f / 3.0f, 2, 1, "float(1/3) * 3 -> 1"},
    };
    for (const NormCase& c : cases) {
        CAPTURE(c.why);
        CAPTURE(c.bits);
        CHECK(floatToUnorm(c.x, c.bits) == c.expected);
    }
}

TEST_CASE("floatToSnorm: NaN, infinities, clamping and ties away from zero (§3.2.3.4)") {
    const std::vector<NormCase> cases = {
        {kNaN, 16, 0, "NaN -> 0"},
        {kInf, 16, 0x7FFF, "+INF clamps to 1 -> 32767"},
        {-kInf, 16, 0x8001, "-INF clamps to -1 -> -32767 (0x8001), never 0x8000"},
        {-2.0f, 16, 0x8001, "< -1 clamps to -1"},
        {1.0f, 16, 0x7FFF, "1 -> 32767"},
        {-1.0f, 16, 0x8001, "-1 -> -32767"},
        {0.0f, 16, 0, "+0 -> 0"},
        {-0.0f, 16, 0, "-0 -> 0"},
        {-kMinDenorm, 16, 0, "-2^-149 * 32767 = -4.6e-41 rounds to 0"},
        // 0.5 * 32767 = 16383.5, a tie: "c = c + 0.5f, drop the fraction" -> 16384 (even as well).
        {0.5f, 16, 16384, "tie 16383.5 -> 16384"},
        {-0.5f, 16, 0xC000, "tie -16383.5 -> -16384 = 0xC000"},
        {nextDown(0.5f), 16, 16383, "16383.4995 -> 16383"},
        // 2-bit SNORM: scale 2^1 - 1 = 1; 0.5 is a tie -> away from zero = 1 (RNE would give 0).
        {0.5f, 2, 1, "SNORM2 tie rounds away from zero"},
        {-0.5f, 2, 3, "SNORM2 -0.5 -> -1 = 0b11"},
        {0.25f, 2, 0, "0.25 -> 0"},
        // 8-bit: 0.5 * 127 = 63.5 -> 64; -0.25 * 127 = -31.75 -> -32 = 0xE0.
        {0.5f, 8, 64, "63.5 -> 64"},
        {-0.25f, 8, 0xE0, "-31.75 -> -32"},
    };
    for (const NormCase& c : cases) {
        CAPTURE(c.why);
        CAPTURE(c.bits);
        CHECK(floatToSnorm(c.x, c.bits) == c.expected);
    }
}

TEST_CASE("unormToFloat / snormToFloat: values (§3.2.3.5, §3.2.3.3)") {
    CHECK(unormToFloat(0, 8) == 0.0f);
    CHECK(unormToFloat(255, 8) == 1.0f);
    CHECK(toBits(unormToFloat(1, 8)) == 0x3B808081u); // 0x1.010102p-8, nearest float to 1/255
    CHECK(unormToFloat(0xFFFFFF, 24) == 1.0f);
    CHECK(d24ToDepth(0xFFFFFFu) == 1.0f);
    CHECK(d24ToDepth(0xFF000000u) == 0.0f); // stencil bits are ignored
    CHECK(depthToD24(0.5f) == 0x800000u);   // tie 8388607.5 -> 8388608
    CHECK(depthToD24(kNaN) == 0u);
    CHECK(depthToD24(-0.0f) == 0u);
    // The inlined depthToD24 equals floatToUnorm(z, 24) on every float in [0, 1] with the low
    // 6 mantissa bits varied (2^24 samples spanning every exponent), and on the edges.
    bool sameAsUnorm = depthToD24(1.0f) == floatToUnorm(1.0f, 24) && depthToD24(2.0f) == 0xFFFFFFu;
    for (std::uint32_t bits = 0; bits <= 0x3F800000u && sameAsUnorm; bits += 61)
        sameAsUnorm = depthToD24(std::bit_cast<float>(bits)) == floatToUnorm(std::bit_cast<float>(bits), 24);
    CHECK(sameAsUnorm);

    // §3.2.3.3's 5-bit examples: 10000 -> -1, 10001 -> -1 (-15/15), 01111 -> 1.
    CHECK(snormToFloat(0b10000, 5) == -1.0f);
    CHECK(snormToFloat(0b10001, 5) == -1.0f);
    CHECK(snormToFloat(0b01111, 5) == 1.0f);
    CHECK(snormToFloat(0x8000, 16) == -1.0f);
    CHECK(snormToFloat(0x8001, 16) == -1.0f);
    CHECK(snormToFloat(0x7FFF, 16) == 1.0f);
    CHECK(snormToFloat(0, 16) == 0.0f);
    CHECK(snormToFloat(0xFFFF, 16) == -1.0f / 32767.0f);
    CHECK(snormToFloat(0xFFFF0001u, 16) == 1.0f / 32767.0f); // bits above n ignored
}

TEST_CASE("UNORM / SNORM correctly rounded decode: every code of every width 1..16 and 24") {
    // §3.2.3.2: 1/2 ULP of the exact quotient. Check against the quotient in double rounded to
    // float (double rounding is harmless: c/(2^n-1) is never within 2^-53 of a float midpoint
    // unless it is exactly one, and a quotient with odd denominator 2^n-1 > 1 never is).
    for (unsigned n : {1u, 2u, 5u, 8u, 10u, 16u, 24u}) {
        CAPTURE(n);
        const std::uint32_t maxCode = (1u << n) - 1u;
        bool ok = true;
        for (std::uint32_t c = 0; c <= maxCode && ok; ++c) {
            ok = unormToFloat(c, n) == static_cast<float>(static_cast<double>(c) / maxCode);
        }
        CHECK(ok);
    }
    for (unsigned n : {2u, 5u, 8u, 16u}) {
        CAPTURE(n);
        const int maxCode = (1 << (n - 1)) - 1;
        bool ok = true;
        for (int v = -maxCode; v <= maxCode && ok; ++v) {
            ok = snormToFloat(static_cast<std::uint32_t>(v), n) == static_cast<float>(static_cast<double>(v) / maxCode);
        }
        CHECK(ok);
    }
}

TEST_CASE("UNORM / SNORM round trips code -> float -> code are the identity (§19.1.2)") {
    for (unsigned n = 1; n <= 24; ++n) {
        CAPTURE(n);
        const std::uint32_t maxCode = (1u << n) - 1u;
        std::uint32_t firstBad = 0xFFFFFFFFu;
        for (std::uint32_t c = 0; c <= maxCode; ++c) {
            if (floatToUnorm(unormToFloat(c, n), n) != c) {
                firstBad = c;
                break;
            }
        }
        CHECK(firstBad == 0xFFFFFFFFu);
    }
    for (unsigned n : {2u, 8u, 10u, 16u}) {
        CAPTURE(n);
        const std::uint32_t mask = (1u << n) - 1u;
        const std::uint32_t mostNegative = 1u << (n - 1);
        std::uint32_t firstBad = 0xFFFFFFFFu;
        for (std::uint32_t c = 0; c <= mask; ++c) {
            // §19.1.2.1: the extra -1 encoding (most negative code) comes back as -(2^(n-1)-1).
            const std::uint32_t expect = c == mostNegative ? mostNegative + 1u : c;
            if (floatToSnorm(snormToFloat(c, n), n) != expect) {
                firstBad = c;
                break;
            }
        }
        CHECK(firstBad == 0xFFFFFFFFu);
    }
}

TEST_CASE("floatToHalf: special values, denormals, overflow and round-toward-zero (§3.2.2)") {
    struct HalfCase {
        float x;
        std::uint16_t expected;
        const char* why;
    };
    const std::vector<HalfCase> cases = {
        {0.0f, 0x0000, "+0"},
        {-0.0f, 0x8000, "-0 keeps its sign"},
        {1.0f, 0x3C00, "1 = 2^0: e = 15"},
        {-2.0f, 0xC000, "-2: sign, e = 16"},
        {0.5f, 0x3800, "0.5: e = 14"},
        // 0.1f = 0x3DCCCCCD = 1.6000000238 * 2^-4: e = 11 (0x2C00); fraction 0x4CCCCD >> 13 = 0x266.
        {0.1f, 0x2E66, "0.1f"},
        {65504.0f, 0x7BFF, "largest finite half"},
        // 65520 is the RNE overflow boundary; §3.2.2 round-to-zero keeps the largest finite value.
        {65520.0f, 0x7BFF, "RTZ: 65520 -> 65504, not INF"},
        {1.0e10f, 0x7BFF, "finite overflow -> max finite, NOT infinity (§3.2.2)"},
        {-1.0e10f, 0xFBFF, "negative finite overflow -> -65504"},
        {std::numeric_limits<float>::max(), 0x7BFF, "FLT_MAX -> 65504"},
        {kInf, 0x7C00, "+INF -> +INF"},
        {-kInf, 0xFC00, "-INF -> -INF"},
        {kNaN, 0x7E00, "quiet NaN: payload 0x400000 >> 13 = 0x200"},
        {kNegNaN, 0xFE00, "NaN keeps its sign"},
        {fromBits(0x7F800001u), 0x7E00, "payload truncating to 0 becomes the quiet bit, stays NaN"},
        {fromBits(0x7FBFE000u), 0x7DFF, "signalling NaN keeps its top 10 payload bits 0x1FF"},
        // 1 + 2^-11 lies halfway between 1 and 1 + 2^-10: RTZ -> 1.
        {1.0f + 0x1p-11f, 0x3C00, "tie truncates"},
        // 1 + 3*2^-11 lies halfway between 1 + 2^-10 (0x3C01) and 1 + 2^-9 (0x3C02): RTZ -> 0x3C01
        // (round-to-nearest-even would pick 0x3C02).
        {1.0f + 0x3p-11f, 0x3C01, "RTZ, not RNE"},
        {-(1.0f + 0x3p-11f), 0xBC01, "RTZ is toward zero for negatives too"},
        {nextDown(2.0f), 0x3FFF, "2 - 2^-23 truncates to 2 - 2^-10"},
        {0x1p-14f, 0x0400, "smallest normal half"},
        {nextDown(0x1p-14f), 0x03FF, "just below 2^-14: denormal 1023 * 2^-24 (truncated)"},
        {0x1p-24f, 0x0001, "smallest half denormal"},
        {0x1.8p-24f, 0x0001, "1.5 * 2^-24 truncates to 2^-24"},
        {0x1p-25f, 0x0000, "half the smallest denormal truncates to 0"},
        {0x1.8p-25f, 0x0000, "0.75 * 2^-24 -> 0 (RNE would give 0x0001)"},
        {-0x1p-24f, 0x8001, "negative denormal"},
        {-0x1p-30f, 0x8000, "negative underflow -> -0"},
        {kMinDenorm, 0x0000, "float32 denormal 2^-149 -> +0"},
        {-kMinDenorm, 0x8000, "float32 denormal -2^-149 -> -0"},
        {kMaxDenorm, 0x0000, "largest float32 denormal -> +0"},
    };
    for (const HalfCase& c : cases) {
        CAPTURE(c.why);
        CHECK(floatToHalf(c.x) == c.expected);
    }
}

TEST_CASE("halfToFloat: values") {
    CHECK(halfToFloat(0x3C00) == 1.0f);
    CHECK(halfToFloat(0x7BFF) == 65504.0f);
    CHECK(halfToFloat(0x0001) == 0x1p-24f);      // denormal -> normalized float32 (§3.2.2)
    CHECK(halfToFloat(0x03FF) == 0x1.ff8p-15f);  // 1023 * 2^-24
    CHECK(halfToFloat(0x0400) == 0x1p-14f);
    CHECK(toBits(halfToFloat(0x8000)) == 0x80000000u);
    CHECK(halfToFloat(0x7C00) == kInf);
    CHECK(halfToFloat(0xFC00) == -kInf);
    CHECK(toBits(halfToFloat(0x7E00)) == 0x7FC00000u);
    CHECK(toBits(halfToFloat(0xFD01)) == 0xFFA02000u); // NaN: sign and payload 0x101 << 13 kept
}

TEST_CASE("half: all 65536 patterns round trip half -> float -> half bit for bit") {
    int bad = 0;
    std::uint32_t firstBad = 0;
    for (std::uint32_t h = 0; h <= 0xFFFF; ++h) {
        const float f = halfToFloat(static_cast<std::uint16_t>(h));
        // Independent decode for finite values: (-1)^s 2^(e-15) (1 + m/1024), or m 2^-24.
        const std::uint32_t e = (h >> 10) & 0x1F, m = h & 0x3FF;
        const double mag = e == 0 ? std::ldexp(static_cast<double>(m), -24)
                                  : std::ldexp(1.0 + m / 1024.0, static_cast<int>(e) - 15);
        const bool valueOk = e == 31 ? (m == 0 ? std::isinf(f) : std::isnan(f))
                                     : static_cast<double>(f) == ((h & 0x8000) ? -mag : mag) &&
                                           std::signbit(f) == ((h & 0x8000) != 0);
        if (!valueOk || floatToHalf(f) != h) {
            if (bad++ == 0) firstBad = h;
        }
    }
    CAPTURE(firstBad);
    CHECK(bad == 0);
}

TEST_CASE("floatToHalf is round-toward-zero on a sweep of 2^32/251 float patterns") {
    // Property of RTZ: |decode(h)| <= |x| < |decode(h + 1)| for finite |x| <= 65504 (bigger
    // finite values give 0x7BFF), and the sign bit follows x.
    int bad = 0;
    std::uint64_t firstBad = 0;
    for (std::uint64_t u = 0; u <= 0xFFFFFFFFu; u += 251) {
        const float x = fromBits(static_cast<std::uint32_t>(u));
        if (std::isnan(x) || std::isinf(x)) continue;
        const std::uint16_t h = floatToHalf(x);
        const float ax = std::fabs(x);
        bool ok = ((h & 0x8000) != 0) == std::signbit(x);
        const std::uint16_t mag = h & 0x7FFF;
        if (ax > 65504.0f) {
            ok = ok && mag == 0x7BFF;
        } else {
            ok = ok && halfToFloat(mag) <= ax && ax < halfToFloat(static_cast<std::uint16_t>(mag + 1));
        }
        if (!ok && bad++ == 0) firstBad = u;
    }
    CAPTURE(firstBad);
    CHECK(bad == 0);
}

TEST_CASE("floatToFloat11 / floatToFloat10: specials, negatives, denormals, overflow (§3.1.6, §3.2.2)") {
    struct SmallCase {
        float x;
        std::uint32_t f11, f10;
        const char* why;
    };
    const std::vector<SmallCase> cases = {
        {0.0f, 0x000, 0x000, "+0"},
        {-0.0f, 0x000, 0x000, "-0 -> 0 (no sign bit)"},
        {1.0f, 15u << 6, 15u << 5, "1 = 2^0: e = 15"},
        {2.0f, 16u << 6, 16u << 5, "2: e = 16"},
        {0.5f, 14u << 6, 14u << 5, "0.5: e = 14"},
        {-1.0f, 0x000, 0x000, "negatives clamp to 0"},
        {-1.0e30f, 0x000, 0x000, "large negative -> 0"},
        {-kInf, 0x000, 0x000, "-INF -> 0 (less than zero; no sign to keep)"},
        {-kMinDenorm, 0x000, 0x000, "negative float32 denormal -> 0"},
        {kInf, 0x7C0, 0x3E0, "+INF -> +INF (e = 31, f = 0)"},
        // Largest finite: float11 2^15 (1 + 63/64) = 65024, float10 2^15 (1 + 31/32) = 64512.
        {65024.0f, 0x7BF, 0x3DF, "float11 max; float10 truncates 65024 -> 64512"},
        {64512.0f, 0x7BE, 0x3DF, "float10 max; float11 2^15 (1 + 62/64)"},
        {65535.0f, 0x7BF, 0x3DF, "RTZ keeps the largest finite value"},
        {1.0e10f, 0x7BF, 0x3DF, "finite overflow -> max finite, not INF (§3.2.2)"},
        {std::numeric_limits<float>::max(), 0x7BF, 0x3DF, "FLT_MAX -> max finite"},
        // 1 + 2^-7 is halfway between float11 1 and 1 + 2^-6: RTZ -> 1. For float10 the step is
        // 2^-5, so it is a quarter step: -> 1.
        {1.0f + 0x1p-7f, 0x3C0, 0x1E0, "tie truncates"},
        // 1 + 3*2^-7: float11 halfway between 1 + 2^-6 and 1 + 2^-5 -> 0x3C1 (RNE: 0x3C2);
        // float10: 1 + 0.75 * 2^-5 -> 0x1E0.
        {1.0f + 0x3p-7f, 0x3C1, 0x1E0, "RTZ, not RNE"},
        {0x1p-14f, 0x040, 0x020, "smallest normal: e = 1"},
        // Largest denormals: float11 63 * 2^-20, float10 31 * 2^-19.
        {nextDown(0x1p-14f), 0x03F, 0x01F, "just below 2^-14 -> largest denormal"},
        {0x1p-20f, 0x001, 0x000, "float11 smallest denormal 2^-20; float10 unit is 2^-19"},
        {0x1p-19f, 0x002, 0x001, "float10 smallest denormal"},
        {0x1.8p-20f, 0x001, 0x000, "1.5 * 2^-20 truncates"},
        {0x1p-21f, 0x000, 0x000, "below every denormal -> 0"},
        {kMinDenorm, 0x000, 0x000, "float32 denormal -> 0"},
    };
    for (const SmallCase& c : cases) {
        CAPTURE(c.why);
        CHECK(floatToFloat11(c.x) == c.f11);
        CHECK(floatToFloat10(c.x) == c.f10);
    }
    // NaN of either sign -> a NaN code (e = 31, f != 0); no sign bit, so the sign is dropped.
    for (float nan : {kNaN, kNegNaN, fromBits(0x7F800001u), fromBits(0xFF800001u)}) {
        const std::uint32_t c11 = floatToFloat11(nan), c10 = floatToFloat10(nan);
        CHECK((c11 >> 6) == 31u);
        CHECK((c11 & 0x3Fu) != 0u);
        CHECK((c10 >> 5) == 31u);
        CHECK((c10 & 0x1Fu) != 0u);
    }
    CHECK(floatToFloat11(kNaN) == 0x7E0u); // quiet bit 0x400000 >> 17 = 0x20
    CHECK(floatToFloat10(kNaN) == 0x3F0u); // 0x400000 >> 18 = 0x10
}

TEST_CASE("float11 / float10 decode values and exhaustive round trips") {
    CHECK(float11ToFloat(0x3C0) == 1.0f);
    CHECK(float11ToFloat(0x7BF) == 65024.0f);
    CHECK(float10ToFloat(0x3DF) == 64512.0f);
    CHECK(float11ToFloat(0x001) == 0x1p-20f);
    CHECK(float10ToFloat(0x001) == 0x1p-19f);
    CHECK(float11ToFloat(0x7C0) == kInf);
    CHECK(std::isnan(float11ToFloat(0x7C1)));
    CHECK(float10ToFloat(0x3E0) == kInf);
    CHECK(std::isnan(float10ToFloat(0x3FF)));
    CHECK(float11ToFloat(0xFFFFF800u | 0x3C0u) == 1.0f); // bits above 11 ignored

    for (unsigned fracBits : {6u, 5u}) {
        CAPTURE(fracBits);
        const std::uint32_t count = 1u << (5 + fracBits);
        int bad = 0;
        for (std::uint32_t v = 0; v < count; ++v) {
            const float f = fracBits == 6 ? float11ToFloat(v) : float10ToFloat(v);
            const std::uint32_t e = v >> fracBits, m = v & ((1u << fracBits) - 1u);
            const double expect = e == 0 ? std::ldexp(static_cast<double>(m), -14 - static_cast<int>(fracBits))
                                         : std::ldexp(1.0 + std::ldexp(static_cast<double>(m), -static_cast<int>(fracBits)),
                                                      static_cast<int>(e) - 15);
            const bool valueOk = e == 31 ? (m == 0 ? f == kInf : std::isnan(f)) : static_cast<double>(f) == expect;
            const std::uint32_t back = fracBits == 6 ? floatToFloat11(f) : floatToFloat10(f);
            if (!valueOk || back != v) ++bad;
        }
        CHECK(bad == 0);
    }
}

TEST_CASE("floatToFloat11 / 10 are round-toward-zero on a sweep of positive floats") {
    int bad = 0;
    for (std::uint32_t u = 0; u < 0x7F800000u; u += 127) {
        const float x = fromBits(u);
        const std::uint32_t c11 = floatToFloat11(x), c10 = floatToFloat10(x);
        const bool ok11 = x > 65024.0f ? c11 == 0x7BFu : (float11ToFloat(c11) <= x && x < float11ToFloat(c11 + 1));
        const bool ok10 = x > 64512.0f ? c10 == 0x3DFu : (float10ToFloat(c10) <= x && x < float10ToFloat(c10 + 1));
        if (!ok11 || !ok10) ++bad;
    }
    CHECK(bad == 0);
}

namespace {

// §3.2.3.8's ideal curve before scaling (decimal constants), evaluated in long double.
long double srgbIdeal(float x) {
    if (x <= 0.0031308f) return 12.92L * x;
    return 1.055L * std::pow(static_cast<long double>(x), 1.0L / 2.4L) - 0.055L;
}

// §3.2.3.7's ideal curve at code/255, in long double.
long double linearIdeal(unsigned code) {
    const long double c = code / 255.0L;
    if (c <= 0.04045L) return c / 12.92L;
    return std::pow((c + 0.055L) / 1.055L, 2.4L);
}

} // namespace

TEST_CASE("linearToSrgb8: the 255 decision thresholds, regenerated in long double (§3.2.3.8)") {
    long double minMargin = 1.0L;
    for (unsigned k = 1; k <= 255; ++k) {
        CAPTURE(k);
        // Code k starts where the ideal value reaches (k - 0.5)/255 ("+0.5, drop the fraction").
        const long double target = (k - 0.5L) / 255.0L;
        const long double guess = target <= 12.92L * 0.0031308L ? target / 12.92L
                                                               : std::pow((target + 0.055L) / 1.055L, 2.4L);
        float t = static_cast<float>(guess);
        while (srgbIdeal(t) >= target) t = nextDown(t);
        while (srgbIdeal(t) < target) t = nextUp(t);
        // The long double evaluation (error ~1e-18) must be far from deciding the comparison.
        const long double margin = std::min(srgbIdeal(t) - target, target - srgbIdeal(nextDown(t))) * 255.0L;
        minMargin = std::min(minMargin, margin);
        CHECK(margin > 1.0e-12L);
        CHECK(linearToSrgb8(t) == k);
        CHECK(linearToSrgb8(nextDown(t)) == k - 1);
    }
    MESSAGE("closest float to an sRGB decision boundary: " << static_cast<double>(minMargin) << " code units");
}

TEST_CASE("linearToSrgb8: special values and hand-derived codes (§3.2.3.8)") {
    CHECK(linearToSrgb8(kNaN) == 0);
    CHECK(linearToSrgb8(kNegNaN) == 0);
    CHECK(linearToSrgb8(-kInf) == 0);
    CHECK(linearToSrgb8(-0.5f) == 0);
    CHECK(linearToSrgb8(-0.0f) == 0);
    CHECK(linearToSrgb8(0.0f) == 0);
    CHECK(linearToSrgb8(kMinDenorm) == 0);
    CHECK(linearToSrgb8(1.0f) == 255);
    CHECK(linearToSrgb8(2.0f) == 255);
    CHECK(linearToSrgb8(kInf) == 255);
    // 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357 * 1.055 - 0.055 = 0.7353569 -> * 255 = 187.516 -> 188.
    CHECK(linearToSrgb8(0.5f) == 188);
    // 0.2: 1.055 * 0.2^(1/2.4) - 0.055 = 0.484529 -> * 255 = 123.555 -> 124.
    CHECK(linearToSrgb8(0.2f) == 124);
    // Linear segment: 0.001 * 12.92 * 255 = 3.2946 -> 3.
    CHECK(linearToSrgb8(0.001f) == 3);
}

TEST_CASE("linearToSrgb8 matches the long double curve on a sweep of [0, 1]") {
    int bad = 0;
    std::uint8_t previous = 0;
    for (std::uint32_t u = 0; u <= 0x3F800000u; u += 4099) {
        const float x = fromBits(u);
        const auto expected = static_cast<unsigned>(std::floor(srgbIdeal(x) * 255.0L + 0.5L));
        const std::uint8_t got = linearToSrgb8(x);
        if (got != expected || got < previous) ++bad;
        previous = got;
    }
    CHECK(bad == 0);
}

TEST_CASE("srgb8ToLinear: the 256-entry table, regenerated in long double (§3.2.3.7)") {
    for (unsigned k = 0; k <= 255; ++k) {
        CAPTURE(k);
        const long double exact = linearIdeal(k);
        const float got = srgb8ToLinear(static_cast<std::uint8_t>(k));
        CHECK(got == static_cast<float>(exact));
        if (k > 0 && k < 255) {
            // Correct rounding needs the exact value clear of both float midpoints around `got`.
            // (1e-6 ULP of clearance dwarfs the ~2^-40 ULP error of the long double evaluation.)
            const long double g = got, lo = nextDown(got), hi = nextUp(got);
            CHECK(exact - (g + lo) / 2.0L > 1.0e-6L * (g - lo));
            CHECK((g + hi) / 2.0L - exact > 1.0e-6L * (hi - g));
        }
    }
    CHECK(srgb8ToLinear(0) == 0.0f); // §3.2.3.7: the ends are exact
    CHECK(srgb8ToLinear(255) == 1.0f);
    CHECK(toBits(srgb8ToLinear(128)) == toBits(0x1.ba1512p-3f)); // ((128/255 + 0.055)/1.055)^2.4 = 0.2158605
}

TEST_CASE("sRGB: all 256 codes round trip code -> linear -> code") {
    for (unsigned k = 0; k <= 255; ++k) {
        CAPTURE(k);
        CHECK(linearToSrgb8(srgb8ToLinear(static_cast<std::uint8_t>(k))) == k);
    }
}

} // namespace tessera_test::buffers_conversion_test
