// The 3dgep G-buffer's specular-power packing (3dgep article §3.1.1.4): log2(p)/10.5 stored in an
// R8G8B8A8_UNORM alpha, unpacked as exp2(a * 10.5). Checks the derived round-trip error bound
// over the whole range and the edge cases p <= 1, 0, negative, NaN and saturation.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include <tessera/buffers/conversion.h>
#include <tessera/buffers/surface.h>
#include <tessera/gbuffer/specular_power_packing.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::gbuffer_specular_power_packing_test {

using namespace tessera;

namespace {

// Bound derivation. The target stores k = round_half_up(255 * a), a = log2(p) / 10.5, so for
// a in [0, 1] |k / 255 - a| <= 1/510 and the unpacked p' = 2^(10.5 k / 255) satisfies
// |log2 p' - log2 p| <= 10.5 / 510. Hence p'/p in [2^(-10.5/510), 2^(10.5/510)]:
//   relative error <= 2^(10.5/510) - 1 = 0.014374 (above), 1 - 2^(-10.5/510) = 0.014170 (below).
// The float evaluation (detLog2, one division, one multiply, detExp2: each within 1 ulp) adds
// a few float ulps (< 1e-6 relative) on top; near a rounding boundary it can also pick the
// neighbouring code, which stays within 10.5/510 + (a few ulp of a) in log2. Slack: 1e-5.
const double kLogHalfStep = 10.5 / 510.0;                       // log2 of the worst factor
const double kRelErrBound = std::exp2(kLogHalfStep) - 1.0;      // 0.0143737...
const double kSlack = 1e-5;

} // namespace

TEST_CASE("specular power: pack and unpack follow log2(p)/10.5 and exp2(a*10.5)") {
    CHECK(packSpecularPower(1.0f) == 0.0f);
    CHECK(packSpecularPower(2.0f) == doctest::Approx(1.0 / 10.5).epsilon(1e-7));
    CHECK(packSpecularPower(1024.0f) == doctest::Approx(10.0 / 10.5).epsilon(1e-7));
    CHECK(unpackSpecularPower(0.0f) == 1.0f);
    // 2^10.5 = 1448.1546878...; the header's constant is the nearest float.
    CHECK(double(kMaxPackedSpecularPower) == doctest::Approx(std::exp2(10.5)).epsilon(1e-7));
    CHECK(unpackSpecularPower(1.0f) == doctest::Approx(kMaxPackedSpecularPower).epsilon(2e-7));
    // One code step is a factor 2^(10.5/255) = 1.0290 (the header's comment).
    const double step = double(unpackSpecularPower(convert::unormToFloat(1, 8)));
    CHECK(step == doctest::Approx(std::exp2(10.5 / 255.0)).epsilon(1e-6));
    CHECK(step == doctest::Approx(1.0290).epsilon(1e-4));
}

TEST_CASE("specular power: the stored-code round trip is within 2^(10.5/510) - 1 = 1.44% over [1, 1448.15]") {
    CHECK(kRelErrBound == doctest::Approx(0.0143737).epsilon(1e-5));
    // Dense sweep in log space: 2^20 + 1 powers from 1 to 2^10.5 (about 12k per code).
    const int n = 1 << 20;
    double worstAbove = 0.0, worstBelow = 0.0;
    int codesSeen[256] = {};
    for (int i = 0; i <= n; ++i) {
        const float p = static_cast<float>(std::exp2(10.5 * double(i) / double(n)));
        if (!(p >= 1.0f && p <= kMaxPackedSpecularPower)) continue;
        const double got = double(roundTripSpecularPower(p));
        const double rel = got / double(p) - 1.0;
        worstAbove = std::max(worstAbove, rel);
        worstBelow = std::max(worstBelow, -rel);
        ++codesSeen[specularPowerCode(p)];
    }
    MESSAGE("round trip over [1, 1448.15]: worst relative error above " << worstAbove << ", below " << worstBelow);
    CHECK(worstAbove <= kRelErrBound + kSlack);
    CHECK(worstBelow <= (1.0 - std::exp2(-kLogHalfStep)) + kSlack);
    // The bound is tight: the sweep reaches within 1% of it on both sides.
    CHECK(worstAbove > 0.99 * kRelErrBound);
    CHECK(worstBelow > 0.99 * (1.0 - std::exp2(-kLogHalfStep)));
    // Every code 0..255 is used (the packing spans the full UNORM range).
    int unused = 0;
    for (int c : codesSeen) unused += c == 0;
    CHECK(unused == 0);
}

TEST_CASE("specular power: the code is the D3D11 float->UNORM8 conversion of the packed value") {
    // Through a real R8G8B8A8_UNORM surface store (the G-buffer target's own conversion).
    Surface specular(SurfaceDesc{1, 1, Format::R8G8B8A8_UNORM, 1});
    for (const float p : {1.0f, 1.5f, 2.0f, 8.0f, 16.0f, 32.0f, 64.0f, 100.0f, 128.0f, 256.0f, 1000.0f, 1448.0f}) {
        specular.store(0, 0, 0, glm::vec4(0.0f, 0.0f, 0.0f, packSpecularPower(p)));
        const float aStored = specular.load(0, 0).w;
        INFO("p = " << p);
        CHECK(aStored == convert::unormToFloat(specularPowerCode(p), 8));
        CHECK(unpackSpecularPower(aStored) == roundTripSpecularPower(p));
    }
}

TEST_CASE("specular power: p <= 1, 0, negative and NaN store code 0 and unpack to 1") {
    // log2(p) <= 0 -> a <= 0 -> UNORM 0 (D3D11.3 §3.2.3.6: c < 0 -> 0) -> exp2(0) = 1.
    for (const float p : {1.0f, 0.999f, 0.5f, 1e-30f, std::numeric_limits<float>::denorm_min()}) {
        INFO("p = " << p);
        CHECK(packSpecularPower(p) <= 0.0f);
        CHECK(specularPowerCode(p) == 0);
        CHECK(roundTripSpecularPower(p) == 1.0f);
    }
    // p = 0: log2 = -inf -> a = -inf -> UNORM 0.
    CHECK(packSpecularPower(0.0f) == -std::numeric_limits<float>::infinity());
    CHECK(specularPowerCode(0.0f) == 0);
    CHECK(roundTripSpecularPower(0.0f) == 1.0f);
    // p < 0 (the 3dgep Material default SpecularPower = -1) and NaN: log2 = NaN -> UNORM 0
    // (D3D11.3 §3.2.3.6: NaN -> 0).
    for (const float p : {-1.0f, -1000.0f, std::numeric_limits<float>::quiet_NaN()}) {
        INFO("p = " << p);
        CHECK(std::isnan(packSpecularPower(p)));
        CHECK(specularPowerCode(p) == 0);
        CHECK(roundTripSpecularPower(p) == 1.0f);
    }
    // The unpacked 1 fails the shaders' `SpecularPower > 1.0f` gate; such materials also get
    // specular colour 0 in the G-buffer (demo PS_Geometry), so no specular either way. But powers in
    // (1, 2^(10.5/510)) = (1, 1.01437) pass the gate yet store code 0 and come back as 1.
    const float justAboveOne = 1.0143f;
    CHECK(justAboveOne > 1.0f);
    CHECK(specularPowerCode(justAboveOne) == 0);
    CHECK_FALSE(roundTripSpecularPower(justAboveOne) > 1.0f);
    CHECK(specularPowerCode(1.0145f) == 1);
}

TEST_CASE("specular power: powers above 2^10.5 saturate to code 255 = 1448.15") {
    for (const float p : {1448.16f, 2048.0f, 1e6f, std::numeric_limits<float>::max(), std::numeric_limits<float>::infinity()}) {
        INFO("p = " << p);
        CHECK(specularPowerCode(p) == 255);
        CHECK(roundTripSpecularPower(p) == unpackSpecularPower(1.0f));
    }
}

} // namespace tessera_test::gbuffer_specular_power_packing_test
