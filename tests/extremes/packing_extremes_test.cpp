// Extremes catalogue, packing: specular powers 0, 1e-3, 1, 250.1 and 1e4 through every packing
// (3dgep's log2/10.5 in RGBA8, the Cookbook's linear range as intended and as printed), NaN and
// Inf through every stored format (D3D11.3 §3.2.2, §3.2.3), and depths a few D24 steps from 1.0.
#include <cmath>
#include <limits>

#include <tessera/buffers/conversion.h>
#include <tessera/buffers/texel_codec.h>
#include <tessera/gbuffer/cookbook_gbuffer.h>
#include <tessera/gbuffer/specular_power_packing.h>

#include "extremes/extremes.h"
#include "extremes/scenes.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::extremes_packing_extremes_test {

using namespace tessera;
using namespace tessera::test;
using namespace tessera::test::extremes;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
const float kNaN = std::numeric_limits<float>::quiet_NaN();

// One power through both packings: the stored code, and the power the lighting pass sees.
void checkPower(float power) {
    CAPTURE(power);
    // 3dgep: code round(255 log2(p) / 10.5), clamped; the round trip lies in [1, 2^10.5] and
    // within 1.44% of p inside that range (specular_power_packing.h derives the bound).
    const std::uint8_t code = specularPowerCode(power);
    const float back = roundTripSpecularPower(power);
    CHECK(std::isfinite(back));
    CHECK(back >= 1.0f);
    CHECK(back <= kMaxPackedSpecularPower);
    if (power >= 1.0f && power <= kMaxPackedSpecularPower) CHECK(std::fabs(back / power - 1.0f) <= 0.014374f);
    if (power <= 1.0f) CHECK(code == 0);
    if (power >= kMaxPackedSpecularPower) CHECK(code == 255);
    // Cookbook: (p - 0.1) / 250 stored as UNORM: code 0 below 0.1, 255 from 250.1 up; the
    // intended decode 0.1 + 250 n lies in [0.1, 250.1] within half a code (0.49) of clamp(p).
    const std::uint8_t cookbook = cookbookSpecPowerCode(power);
    const float decoded = unpackCookbookSpecPower(convert::unormToFloat(cookbook, 8));
    CHECK(std::isfinite(decoded));
    CHECK(decoded >= kCookbookSpecPowerMin);
    CHECK(decoded <= kCookbookSpecPowerMin + kCookbookSpecPowerRange + 1e-4f);
    const float clamped = std::min(std::max(power, kCookbookSpecPowerMin), kCookbookSpecPowerMin + kCookbookSpecPowerRange);
    if (!std::isnan(power)) CHECK(std::fabs(decoded - clamped) <= 0.5f * kCookbookSpecPowerRange / 255.0f + 1e-4f);
    else CHECK(cookbook == 0);  // NaN -> code 0 -> the minimum 0.1
    // As printed (ERRATA): 0.1 + 250 x 251 n: finite, up to 62750.1.
    const float printed = unpackCookbookSpecPowerAsPrinted(convert::unormToFloat(cookbook, 8));
    CHECK(std::isfinite(printed));
    CHECK(printed <= 62750.2f);
}

} // namespace

TEST_CASE("packing: specular power 0") {
    checkPower(0.0f);
    CHECK(roundTripSpecularPower(0.0f) == 1.0f);  // log2(0) = -inf stores code 0, which unpacks to exactly 1
    CHECK(cookbookSpecPowerCode(0.0f) == 0);
}

TEST_CASE("packing: specular power 1e-3") { checkPower(1e-3f); }

TEST_CASE("packing: specular power 1") {
    checkPower(1.0f);
    CHECK(specularPowerCode(1.0f) == 0);  // log2(1) = 0 exactly
}

TEST_CASE("packing: specular power 250.1 (the Cookbook's maximum)") {
    checkPower(250.1f);
    CHECK(cookbookSpecPowerCode(250.1f) == 255);
}

TEST_CASE("packing: specular power 1e4 (beyond every range)") {
    checkPower(1e4f);
    CHECK(roundTripSpecularPower(1e4f) == kMaxPackedSpecularPower);
}

TEST_CASE("packing: specular power NaN and +inf") {
    checkPower(kNaN);
    checkPower(kInf);
    CHECK(specularPowerCode(kNaN) == 0);      // NaN -> 0 (D3D11.3 §3.2.3.6)
    CHECK(specularPowerCode(kInf) == 255);    // +inf saturates
}

TEST_CASE("packing: NaN texels through every format") {
    // D3D11.3: float -> UNORM / SNORM / sRGB: NaN -> 0 (§3.2.3.4, §3.2.3.6, §3.2.3.8); float16,
    // float11/10 and float32 keep NaN (§3.2.2); the depth formats store it as 0 (D24) or NaN (D32).
    for (int f = 1; f <= static_cast<int>(Format::R32G32B32A32_UINT); ++f) {
        const Format format = static_cast<Format>(f);
        const FormatInfo& info = formatInfo(format);
        if (info.kind == FormatKind::Uint || info.kind == FormatKind::DepthStencil) continue;
        CAPTURE(info.name);
        std::byte texel[16] = {};
        encodeTexel(format, glm::vec4(kNaN), texel);
        const glm::vec4 back = decodeTexel(format, texel);
        for (std::uint32_t c = 0; c < info.channels; ++c) {
            const float v = back[static_cast<int>(c)];
            if (info.kind == FormatKind::Float) CHECK(std::isnan(v));
            else CHECK(v == 0.0f);
        }
    }
    CHECK(convert::depthToD24(kNaN) == 0u);
}

TEST_CASE("packing: +inf and -inf texels through every format") {
    for (int f = 1; f <= static_cast<int>(Format::R32G32B32A32_UINT); ++f) {
        const Format format = static_cast<Format>(f);
        const FormatInfo& info = formatInfo(format);
        if (info.kind == FormatKind::Uint || info.kind == FormatKind::DepthStencil) continue;
        CAPTURE(info.name);
        for (const float sign : {1.0f, -1.0f}) {
            CAPTURE(sign);
            std::byte texel[16] = {};
            encodeTexel(format, glm::vec4(sign * kInf), texel);
            const glm::vec4 back = decodeTexel(format, texel);
            for (std::uint32_t c = 0; c < info.channels; ++c) {
                const float v = back[static_cast<int>(c)];
                if (info.kind == FormatKind::Unorm) CHECK(v == (sign > 0 ? 1.0f : 0.0f));       // clamp to [0, 1]
                else if (info.kind == FormatKind::Snorm) CHECK(v == sign);                        // clamp to [-1, 1]
                else if (format == Format::R11G11B10_FLOAT) CHECK(v == (sign > 0 ? kInf : 0.0f));  // no sign bit: -inf -> 0
                else CHECK(v == sign * kInf);                                                     // half, float32 keep inf
            }
        }
    }
    CHECK(convert::depthToD24(kInf) == 0xFFFFFFu);
    CHECK(convert::depthToD24(-kInf) == 0u);
}

TEST_CASE("packing: depths a few D24 steps from 1.0") {
    // Codes 2^24 - 1 - k for depth 1 - k / (2^24 - 1): each maps to its own code, and 1 - 1e-9
    // (a third of a step) rounds to the top code, the cleared value.
    for (std::uint32_t k = 0; k <= 4; ++k) {
        const float depth = static_cast<float>(1.0 - double(k) / 16777215.0);
        CAPTURE(k);
        CHECK(convert::depthToD24(depth) == 0xFFFFFFu - k);
        CHECK(convert::d24ToDepth(0xFFFFFFu - k) == depth);
    }
    CHECK(convert::depthToD24(static_cast<float>(1.0 - 1e-9)) == 0xFFFFFFu);
}

TEST_CASE("packing: a wall 3 D24 steps in front of the far plane is drawn, the far plane itself is not") {
    // Camera at the origin looking down -z, near 1, far 16: view z of depth d is
    // z = n f / (f - d (f - n)) (D3D depth, inverted). A wall at depth 1 - 3 steps stores a code
    // below the cleared 2^24 - 1 and passes forward's LESS test; the wall at z = -f is clipped.
    const double n = 1.0, f = 16.0, step = 1.0 / 16777215.0;
    const auto zAt = [&](double depth) { return static_cast<float>(-(n * f / (f - depth * (f - n)))); };
    for (const int steps : {3, 0}) {
        const bool drawn = steps > 0;
        CAPTURE(steps);
        TestScene t;
        t.scene = oneTriangle(zAt(1.0 - steps * step));
        t.scene.meshes[0].primitives[0].positionsObject = {{-100.0f, -100.0f, zAt(1.0 - steps * step)},
                                                           {100.0f, -100.0f, zAt(1.0 - steps * step)},
                                                           {0.0f, 100.0f, zAt(1.0 - steps * step)}};
        t.scene.lights = {makeLight(LightType::Directional, {0, 0, 0}, {0, 0, -1}, 1.0f, {1, 1, 1})};
        t.camera.nearZ = 1.0f;
        t.camera.farZ = 16.0f;
        Rendered r;
        render(t, "forward", {{"projection", "d3d"}}, r, Precision::Exact, 2, {16, 16});
        const std::uint32_t code = convert::depthToD24(r.get("depth").loadDepth(8, 8));
        CHECK((code < 0xFFFFFFu) == drawn);
        if (drawn) CHECK(code >= 0xFFFFFFu - 4u);
    }
}

} // namespace tessera_test::extremes_packing_extremes_test
