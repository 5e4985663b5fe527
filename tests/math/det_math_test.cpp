// Deterministic transcendental functions (tessera/math/det_math.h): float results within 1 ulp of
// the correctly rounded value over sweeps of 10^6 samples (the reference is long double libm,
// which tests may use), double results within stated bounds, and the HLSL edge cases.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>

#include <tessera/math/det_math.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::math_det_math_test {

using namespace tessera;

namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();
constexpr double kInf = std::numeric_limits<double>::infinity();

// SplitMix64: a fixed sample sequence on every platform.
struct Rng {
    std::uint64_t state;
    std::uint64_t next() {
        std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform(double lo, double hi) { return lo + (hi - lo) * double(next() >> 11) * 0x1.0p-53; }
};

// Distance in float ulps (ordered integer distance; same-sign finite values).
std::int64_t ulpDistance(float a, float b) {
    const auto ordered = [](float f) {
        const std::int32_t i = std::bit_cast<std::int32_t>(f);
        return i < 0 ? std::int64_t(std::numeric_limits<std::int32_t>::min()) - i : std::int64_t(i);
    };
    const std::int64_t d = ordered(a) - ordered(b);
    return d < 0 ? -d : d;
}

// Checks f(x) for floats against the long double reference rounded to float (correctly rounded
// up to the long double's own error, far below a float ulp). Returns the worst distance.
template <class F, class R>
std::int64_t worstUlpOver(int samples, Rng& rng, double lo, double hi, F f, R reference) {
    std::int64_t worst = 0;
    for (int i = 0; i < samples; ++i) {
        const float x = float(rng.uniform(lo, hi));
        const float expected = float(reference((long double)x));
        const float got = f(x);
        if (std::isinf(expected) || expected == 0.0f) continue;  // overflow / underflow edges tested apart
        const std::int64_t d = ulpDistance(got, expected);
        if (d > worst) worst = d;
    }
    return worst;
}

} // namespace

TEST_CASE("detLog2 (float): within 1 ulp over 10^6 positive floats of every exponent, subnormals included") {
    Rng rng{1};
    std::int64_t worst = 0;
    for (int i = 0; i < 1000000; ++i) {
        const std::uint32_t bits = std::uint32_t(rng.next() % 0x7F800000u);  // every positive finite float, 0 excluded below
        const float x = std::bit_cast<float>(bits);
        if (x == 0.0f) continue;
        const float expected = float(std::log2((long double)x));
        if (expected == 0.0f) continue;
        const std::int64_t d = ulpDistance(detLog2(x), expected);
        if (d > worst) worst = d;
    }
    CHECK(worst <= 1);
}

TEST_CASE("detExp2 (float): within 1 ulp over 10^6 samples from -149 to 128, subnormal results included") {
    Rng rng{2};
    CHECK(worstUlpOver(1000000, rng, -149.0, 128.0, [](float x) { return detExp2(x); },
                       [](long double x) { return std::exp2(x); }) <= 1);
}

TEST_CASE("detPow (float): within 1 ulp for the specular range (R.V in 0..1, power in 1..1448.15)") {
    Rng rng{3};
    std::int64_t worst = 0;
    for (int i = 0; i < 1000000; ++i) {
        const float x = float(rng.uniform(0.0, 1.0));
        const float y = float(rng.uniform(1.0, 1448.15466));
        const float expected = float(std::pow((long double)x, (long double)y));
        if (expected == 0.0f || x == 0.0f) continue;  // underflow to 0 is checked by the next case
        const std::int64_t d = ulpDistance(detPow(x, y), expected);
        if (d > worst) worst = d;
    }
    CHECK(worst <= 1);
}

TEST_CASE("detPow (float): within 1 ulp for x in 1e-3..1e3, y in -12..12, and exact underflow") {
    Rng rng{4};
    std::int64_t worst = 0;
    for (int i = 0; i < 1000000; ++i) {
        const float x = float(std::exp2(rng.uniform(-10.0, 10.0)));  // log-uniform
        const float y = float(rng.uniform(-12.0, 12.0));
        const float expected = float(std::pow((long double)x, (long double)y));
        const std::int64_t d = ulpDistance(detPow(x, y), expected);
        if (d > worst) worst = d;
    }
    CHECK(worst <= 1);
    CHECK(detPow(0.5f, 200.0f) == 0.0f);      // 2^-200: below the float range
    CHECK(detPow(0.5f, 140.0f) == 0x1p-140f);  // subnormal, exact
}

TEST_CASE("detCos / detSin / detTan (float): within 1 ulp over 10^6 samples in -10..10 and in -1e5..1e5") {
    Rng rng{5};
    for (const double range : {10.0, 1.0e5}) {
        CAPTURE(range);
        CHECK(worstUlpOver(1000000, rng, -range, range, [](float x) { return detCos(x); },
                           [](long double x) { return std::cos(x); }) <= 1);
        CHECK(worstUlpOver(1000000, rng, -range, range, [](float x) { return detSin(x); },
                           [](long double x) { return std::sin(x); }) <= 1);
        CHECK(worstUlpOver(300000, rng, -range, range, [](float x) { return detTan(x); },
                           [](long double x) { return std::tan(x); }) <= 1);
    }
    // Every angle of the demo's spot range 35..60 degrees (0.01 degree steps), as DoSpotCone uses it.
    std::int64_t worst = 0;
    for (int centi = 3500; centi <= 6000; ++centi) {
        const float radians = (float(centi) / 100.0f) * 0.0174532925f;
        const std::int64_t d = ulpDistance(detCos(radians), float(std::cos((long double)radians)));
        if (d > worst) worst = d;
    }
    CHECK(worst <= 1);
}

TEST_CASE("det_math double versions: relative error bounds against long double") {
    // log2, exp2, sin, cos: 4 double ulps; pow: (4 + 2|y log2 x|) ulps, since the rounding of
    // y * log2(x) is magnified by |y log2 x| * ln 2 in the result.
    Rng rng{6};
    const long double ulp = 0x1p-52L;
    long double worstLog = 0, worstExp = 0, worstCos = 0, worstSin = 0, worstPow = 0;
    for (int i = 0; i < 200000; ++i) {
        const double x = std::exp2(rng.uniform(-60.0, 60.0));
        worstLog = std::fmax(worstLog, std::fabs((detLog2(x) - std::log2((long double)x)) / std::log2((long double)x)) / ulp);
        const double e = rng.uniform(-60.0, 60.0);
        worstExp = std::fmax(worstExp, std::fabs((detExp2(e) - std::exp2((long double)e)) / std::exp2((long double)e)) / ulp);
        const double a = rng.uniform(-10.0, 10.0);
        worstCos = std::fmax(worstCos, std::fabs((detCos(a) - std::cos((long double)a)) / std::cos((long double)a)) / ulp);
        worstSin = std::fmax(worstSin, std::fabs((detSin(a) - std::sin((long double)a)) / std::sin((long double)a)) / ulp);
        const double px = rng.uniform(0.0, 1.0), py = rng.uniform(1.0, 1448.0);
        const long double ref = std::pow((long double)px, (long double)py);
        if (ref > 1e-300L) {
            const long double magnitude = std::fabs((long double)py * std::log2((long double)px));
            worstPow = std::fmax(worstPow, std::fabs((detPow(px, py) - ref) / ref) / ulp / (4.0L + 2.0L * magnitude));
        }
    }
    CHECK(worstLog <= 4.0L);
    CHECK(worstExp <= 4.0L);
    CHECK(worstCos <= 4.0L);
    CHECK(worstSin <= 4.0L);
    CHECK(worstPow <= 1.0L);
}

TEST_CASE("det_math edge cases follow the HLSL table (pow) and IEEE limits (log2, exp2)") {
    // log2: log2(0) = -inf, log2(<0) = NaN, powers of two exact.
    CHECK(detLog2(0.0f) == -kInfF);
    CHECK(detLog2(-0.0f) == -kInfF);
    CHECK(std::isnan(detLog2(-1.0f)));
    CHECK(std::isnan(detLog2(std::numeric_limits<float>::quiet_NaN())));
    CHECK(detLog2(kInfF) == kInfF);
    CHECK(detLog2(1.0f) == 0.0f);
    CHECK(detLog2(1024.0f) == 10.0f);
    CHECK(detLog2(0x1p-149f) == -149.0f);  // smallest subnormal
    CHECK(detLog2(0.125) == -3.0);
    // exp2: exact integers, limits.
    CHECK(detExp2(0.0f) == 1.0f);
    CHECK(detExp2(10.0f) == 1024.0f);
    CHECK(detExp2(-149.0f) == 0x1p-149f);
    CHECK(detExp2(-150.5f) == 0.0f);
    CHECK(detExp2(128.0f) == kInfF);
    CHECK(detExp2(-kInfF) == 0.0f);
    CHECK(detExp2(kInfF) == kInfF);
    CHECK(std::isnan(detExp2(std::numeric_limits<float>::quiet_NaN())));
    CHECK(detExp2(1023.0) == 0x1p1023);
    CHECK(detExp2(1024.0) == kInf);
    CHECK(detExp2(-1074.0) == 0x1p-1074);
    // pow: x < 0 -> NaN (even for y = 0); y == 0 -> 1; 0^y>0 = 0; 0^y<0 = inf; 1^y = 1.
    CHECK(std::isnan(detPow(-2.0f, 2.0f)));
    CHECK(std::isnan(detPow(-2.0f, 0.0f)));
    CHECK(detPow(5.0f, 0.0f) == 1.0f);
    CHECK(detPow(0.0f, 0.0f) == 1.0f);
    CHECK(detPow(0.0f, 3.0f) == 0.0f);
    CHECK(detPow(0.0f, -1.0f) == kInfF);
    CHECK(detPow(1.0f, 1e30f) == 1.0f);
    CHECK(detPow(kInfF, 2.0f) == kInfF);
    CHECK(detPow(kInfF, -2.0f) == 0.0f);
    CHECK(std::isnan(detPow(2.0f, std::numeric_limits<float>::quiet_NaN())));
    CHECK(detPow(2.0f, 10.0f) == 1024.0f);
    CHECK(detPow(0.25f, 0.5f) == 0.5f);
    // cos/sin/tan: exact zeros and ones, NaN for inf.
    CHECK(detCos(0.0f) == 1.0f);
    CHECK(detSin(0.0f) == 0.0f);
    CHECK(detTan(0.0f) == 0.0f);
    CHECK(std::isnan(detCos(kInfF)));
    CHECK(std::isnan(detSin(-kInfF)));
    CHECK(detCos(0.0174532925f * 60.0f) == doctest::Approx(0.5f).epsilon(1e-7));
}

} // namespace tessera_test::math_det_math_test
