// Deterministic transcendental functions (tessera's floating-point rule: results that reach an image
// must not depend on the libm or compiler). Built only from IEEE +, -, *, /, bit casts and fixed
// polynomials evaluated in double in a fixed order (the project compiles with -ffp-contract=off).
// Float versions are within 1 ulp of the correctly rounded result (tests/math/det_math_test.cpp).
#pragma once

#include <bit>
#include <cstdint>
#include <limits>

namespace tessera {

// Semantics (HLSL intrinsics; the D3D11.3 spec leaves the exact values to the hardware, tessera
// fixes these):
//   detLog2(x):  x < 0 or NaN -> NaN; +-0 -> -inf; +inf -> +inf; exact for powers of two.
//   detExp2(x):  NaN -> NaN; -inf -> 0; +inf -> +inf; overflow -> +inf; underflow -> 0 or a
//                subnormal (correctly scaled, no flush to zero); exact for integer x.
//   detPow(x,y): HLSL pow = exp2(y * log2(x)) evaluated in double, with the HLSL table's edge
//                cases first: x < 0 or x NaN -> NaN (HLSL: "x < 0: NaN"); then y == 0 -> 1 (also
//                for x == 0, which HLSL leaves GPU-dependent: tessera picks 1, as C's pow does);
//                y NaN -> NaN; x == 0: y > 0 -> 0, y < 0 -> +inf; x == +inf: y > 0 -> +inf,
//                y < 0 -> 0.
//   detCos, detSin, detTan (radians): Cody-Waite reduction by pi/2 with a three-part constant
//                (fdlibm's pio2_1/2/3, 33 bits each, + pio2_3t): k * pio2_i is exact for
//                |k| < 2^20, so the stated accuracy holds for |x| < 2^20 * pi/2 (about 1.6e6).
//                Beyond that the result stays deterministic but loses accuracy (GPUs only
//                promise sin/cos on [-pi, pi]). inf or NaN -> NaN.
// Double versions use the same kernels (accurate to a few double ulps; the tests bound it).

namespace detmath_detail {

constexpr double kLn2 = 0.69314718055994530942;     // ln(2), correctly rounded
constexpr double kLog2E = 1.4426950408889634074;    // 1 / ln(2)
constexpr double kSqrt2 = 1.4142135623730950488;
constexpr double kTwoTo64 = 18446744073709551616.0;

inline bool isNan(double x) { return x != x; }

// ln(m) for m in [sqrt(1/2), sqrt(2)): 2 atanh(s) = 2 (s + s^3/3 + ... + s^25/25),
// s = (m - 1) / (m + 1), |s| <= 0.1716, truncation < s^27 / 27 < 1e-21.
inline double lnMantissa(double m) {
    const double s = (m - 1.0) / (m + 1.0);
    const double s2 = s * s;
    double series = 1.0 / 25.0;
    series = series * s2 + 1.0 / 23.0;
    series = series * s2 + 1.0 / 21.0;
    series = series * s2 + 1.0 / 19.0;
    series = series * s2 + 1.0 / 17.0;
    series = series * s2 + 1.0 / 15.0;
    series = series * s2 + 1.0 / 13.0;
    series = series * s2 + 1.0 / 11.0;
    series = series * s2 + 1.0 / 9.0;
    series = series * s2 + 1.0 / 7.0;
    series = series * s2 + 1.0 / 5.0;
    series = series * s2 + 1.0 / 3.0;
    series = series * s2 + 1.0;
    return 2.0 * s * series;
}

// 2^g for g in [-0.5, 0.5]: e^(g ln2) by its Taylor series to degree 14 (|g ln2| <= 0.347,
// truncation < 0.347^15 / 15! < 1e-19).
inline double exp2Fraction(double g) {
    const double t = g * kLn2;
    double p = 1.0 / 87178291200.0;         // 1/14!
    p = p * t + 1.0 / 6227020800.0;         // 1/13!
    p = p * t + 1.0 / 479001600.0;          // 1/12!
    p = p * t + 1.0 / 39916800.0;           // 1/11!
    p = p * t + 1.0 / 3628800.0;            // 1/10!
    p = p * t + 1.0 / 362880.0;             // 1/9!
    p = p * t + 1.0 / 40320.0;              // 1/8!
    p = p * t + 1.0 / 5040.0;               // 1/7!
    p = p * t + 1.0 / 720.0;                // 1/6!
    p = p * t + 1.0 / 120.0;                // 1/5!
    p = p * t + 1.0 / 24.0;                 // 1/4!
    p = p * t + 1.0 / 6.0;                  // 1/3!
    p = p * t + 0.5;                        // 1/2!
    p = p * t + 1.0;
    return p * t + 1.0;
}

// 2^n as a double for n in [-1022, 1023].
inline double twoTo(int n) { return std::bit_cast<double>(std::uint64_t(n + 1023) << 52); }

// sin(r), cos(r) for |r| <= pi/4 (+ a little): Taylor to r^19 / r^20 (truncation < 1e-19).
inline double sinKernel(double r) {
    const double r2 = r * r;
    double p = -1.0 / 121645100408832000.0;  // -1/19!
    p = p * r2 + 1.0 / 355687428096000.0;    // 1/17!
    p = p * r2 - 1.0 / 1307674368000.0;      // -1/15!
    p = p * r2 + 1.0 / 6227020800.0;         // 1/13!
    p = p * r2 - 1.0 / 39916800.0;           // -1/11!
    p = p * r2 + 1.0 / 362880.0;             // 1/9!
    p = p * r2 - 1.0 / 5040.0;               // -1/7!
    p = p * r2 + 1.0 / 120.0;                // 1/5!
    p = p * r2 - 1.0 / 6.0;                  // -1/3!
    return r + (r * r2) * p;
}
inline double cosKernel(double r) {
    const double r2 = r * r;
    double p = 1.0 / 2432902008176640000.0;  // 1/20!
    p = p * r2 - 1.0 / 6402373705728000.0;   // -1/18!
    p = p * r2 + 1.0 / 20922789888000.0;     // 1/16!
    p = p * r2 - 1.0 / 87178291200.0;        // -1/14!
    p = p * r2 + 1.0 / 479001600.0;          // 1/12!
    p = p * r2 - 1.0 / 3628800.0;            // -1/10!
    p = p * r2 + 1.0 / 40320.0;              // 1/8!
    p = p * r2 - 1.0 / 720.0;                // -1/6!
    p = p * r2 + 1.0 / 24.0;                 // 1/4!
    return 1.0 + r2 * (-0.5 + r2 * p);
}

// x = k * pi/2 + r, |r| <= ~pi/4; returns k mod 4 (fdlibm e_rem_pio2.c constants).
inline int reducePiOver2(double x, double& r) {
    constexpr double kTwoOverPi = 6.36619772367581382433e-01;
    constexpr double kPio2_1 = 1.57079632673412561417e+00;   // first 33 bits of pi/2
    constexpr double kPio2_2 = 6.07710050630396597660e-11;   // next 33 bits
    constexpr double kPio2_3 = 2.02226624871116645580e-21;   // next 33 bits
    constexpr double kPio2_3t = 8.47842766036889956997e-32;  // pi/2 - (pio2_1 + pio2_2 + pio2_3)
    constexpr double kRoundMagic = 6755399441055744.0;       // 1.5 * 2^52: adding rounds to integer
    double k = x * kTwoOverPi;
    if (k < 4503599627370496.0 && k > -4503599627370496.0) k = (k + kRoundMagic) - kRoundMagic;  // round half even
    r = ((x - k * kPio2_1) - k * kPio2_2) - k * kPio2_3;
    r = r - k * kPio2_3t;
    // k mod 4: |k| >= 2^54 is a multiple of 4; below, k is an exact integer.
    const double magnitude = k < 0.0 ? -k : k;
    if (!(magnitude < 18014398509481984.0)) return 0;
    const int q = int(std::uint64_t(magnitude) & 3u);
    return k < 0.0 ? (4 - q) & 3 : q;
}

} // namespace detmath_detail

inline double detLog2(double x) {
    using namespace detmath_detail;
    if (isNan(x) || x < 0.0) return std::numeric_limits<double>::quiet_NaN();
    if (x == 0.0) return -std::numeric_limits<double>::infinity();
    if (x == std::numeric_limits<double>::infinity()) return x;
    std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
    int exponent = int((bits >> 52) & 0x7FFu);
    int extra = 0;
    if (exponent == 0) {  // subnormal: scale by 2^64 (exact) into the normal range
        bits = std::bit_cast<std::uint64_t>(x * kTwoTo64);
        exponent = int((bits >> 52) & 0x7FFu);
        extra = -64;
    }
    exponent = exponent - 1023 + extra;
    double m = std::bit_cast<double>((bits & 0x000FFFFFFFFFFFFFull) | 0x3FF0000000000000ull);  // [1, 2)
    if (m > kSqrt2) {
        m *= 0.5;
        ++exponent;
    }
    return double(exponent) + lnMantissa(m) * kLog2E;
}

inline double detExp2(double x) {
    using namespace detmath_detail;
    if (isNan(x)) return x;
    if (x >= 1024.0) return std::numeric_limits<double>::infinity();
    if (x < -1080.0) return 0.0;
    const double n = (x + 6755399441055744.0) - 6755399441055744.0;  // round to nearest integer
    const double g = x - n;                                          // exact, |g| <= 0.5
    const double p = exp2Fraction(g);                                // [0.707, 1.415]
    const int e = int(n);
    if (e > 1023) return (p * 2.0) * twoTo(1023);  // e = 1024 (x >= 1023.5): p < 1, may overflow to inf
    if (e >= -1022) return p * twoTo(e);
    // Subnormal result: scale in two steps so that only the last multiply rounds.
    return (p * twoTo(e + 64)) * twoTo(-64);
}

inline double detPow(double x, double y) {
    using namespace detmath_detail;
    constexpr double kInf = std::numeric_limits<double>::infinity();
    if (isNan(x) || x < 0.0) return std::numeric_limits<double>::quiet_NaN();
    if (y == 0.0) return 1.0;
    if (isNan(y)) return y;
    if (x == 0.0) return y > 0.0 ? 0.0 : kInf;
    if (x == kInf) return y > 0.0 ? kInf : 0.0;
    if (x == 1.0) return 1.0;
    return detExp2(y * detLog2(x));
}

inline double detSin(double x) {
    using namespace detmath_detail;
    if (isNan(x) || x == std::numeric_limits<double>::infinity() || x == -std::numeric_limits<double>::infinity())
        return std::numeric_limits<double>::quiet_NaN();
    double r = 0.0;
    switch (reducePiOver2(x, r)) {
    case 0: return sinKernel(r);
    case 1: return cosKernel(r);
    case 2: return -sinKernel(r);
    default: return -cosKernel(r);
    }
}

inline double detCos(double x) {
    using namespace detmath_detail;
    if (isNan(x) || x == std::numeric_limits<double>::infinity() || x == -std::numeric_limits<double>::infinity())
        return std::numeric_limits<double>::quiet_NaN();
    double r = 0.0;
    switch (reducePiOver2(x, r)) {
    case 0: return cosKernel(r);
    case 1: return -sinKernel(r);
    case 2: return -cosKernel(r);
    default: return sinKernel(r);
    }
}

inline double detTan(double x) {
    using namespace detmath_detail;
    if (isNan(x) || x == std::numeric_limits<double>::infinity() || x == -std::numeric_limits<double>::infinity())
        return std::numeric_limits<double>::quiet_NaN();
    double r = 0.0;
    const int quadrant = reducePiOver2(x, r);
    const double s = sinKernel(r), c = cosKernel(r);
    return (quadrant & 1) ? -c / s : s / c;
}

// Float versions: the double result rounded once to float (every float is exact in double).
inline float detLog2(float x) { return float(detLog2(double(x))); }
inline float detExp2(float x) { return float(detExp2(double(x))); }
inline float detPow(float x, float y) { return float(detPow(double(x), double(y))); }
inline float detSin(float x) { return float(detSin(double(x))); }
inline float detCos(float x) { return float(detCos(double(x))); }
inline float detTan(float x) { return float(detTan(double(x))); }

} // namespace tessera
