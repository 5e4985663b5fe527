// The raster's `fast` path (DrawState::precision): float barycentrics and the float RGBA8
// encode. It must run (its images are not exact's bytes), keep coverage exactly (a fill-rule
// matter, not a precision one), and stay within a stated error of exact.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <tessera/raster/device.h>
#include <tessera/raster/output_merger.h>

#include "support/test_draw.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::precision_fast_raster_test {

using namespace tessera;
using test::ColorVertex;

namespace {
constexpr std::uint32_t kSize = 96;  // px

// Random triangles with random vertex colours and depths, drawn without depth test into a
// target of `format`.
Surface drawRandom(Precision precision, Format format, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> pos(-10.0f, float(kSize) + 10.0f), unit(0.0f, 1.0f);
    std::vector<ColorVertex> vertices;
    for (int t = 0; t < 200; ++t)
        for (int k = 0; k < 3; ++k)
            vertices.push_back({test::windowToClip(pos(rng), pos(rng), float(kSize), float(kSize), unit(rng), 0.5f + unit(rng)),
                                glm::vec4(unit(rng), unit(rng), unit(rng), 1.0f)});
    Surface target({kSize, kSize, format, 1});
    target.clearColor(glm::vec4(0.0f));
    DrawState st;
    st.rasterizer.cullMode = CullMode::None;
    st.depthStencil.depthEnable = false;
    st.viewport = fullViewport(target);
    st.precision = precision;
    RenderTargets rt;
    rt.colors[0] = &target;
    Device device(DeviceConfig{16, 2});
    device.draw(st, rt, std::span<const ColorVertex>(vertices), {}, test::PassThroughVS{}, test::ColorPS{});
    return target;
}
} // namespace

TEST_CASE("fast raster: float barycentrics stay within 1e-5 of exact's, coverage unchanged, and the path runs") {
    const Surface exact = drawRandom(Precision::Exact, Format::R32G32B32A32_FLOAT, 7);
    const Surface fast = drawRandom(Precision::Fast, Format::R32G32B32A32_FLOAT, 7);
    const Surface again = drawRandom(Precision::Fast, Format::R32G32B32A32_FLOAT, 7);
    int differing = 0;
    float maxError = 0.0f;
    bool sameCoverage = true;
    for (std::uint32_t y = 0; y < kSize; ++y)
        for (std::uint32_t x = 0; x < kSize; ++x) {
            const glm::vec4 e = exact.load(x, y), f = fast.load(x, y);
            sameCoverage = sameCoverage && ((e.w == 0.0f) == (f.w == 0.0f));
            for (int c = 0; c < 3; ++c) maxError = std::max(maxError, std::abs(e[c] - f[c]));
            differing += e != f ? 1 : 0;
        }
    MESSAGE("fast vs exact: " << differing << " of " << kSize * kSize << " pixels differ, max " << maxError);
    CHECK(sameCoverage);
    CHECK(differing > 0);  // the fast path ran
    // Bound: colours in [0, 1] interpolated with barycentrics off by a few float ulp (float(E) *
    // float(1/area) instead of one rounding of the double product), then the perspective
    // divide: a few 1e-7 relative, 1e-5 with a wide margin.
    CHECK(maxError <= 1e-5f);
    CHECK(std::memcmp(fast.bytes().data(), again.bytes().data(), fast.bytes().size()) == 0);  // deterministic
}

TEST_CASE("fast RGBA8 encode: at most one code from the exact encode, on every float in [-0.5, 1.5] of a dense sweep") {
    int maxDiff = 0, differing = 0;
    for (float x = -0.5f; x <= 1.5f; x = std::nextafter(x, 2.0f) + 1e-7f) {
        std::byte e[4], f[4];
        writeColorRgba8Unorm(e, glm::vec4(x));
        writeColorRgba8UnormFast(f, glm::vec4(x));
        const int d = std::abs(std::to_integer<int>(e[0]) - std::to_integer<int>(f[0]));
        maxDiff = std::max(maxDiff, d);
        differing += d != 0 ? 1 : 0;
    }
    MESSAGE(differing << " inputs encode differently");
    CHECK(maxDiff <= 1);
}

} // namespace tessera_test::precision_fast_raster_test
