// nearFarTerm (math/projection_terms.h): the perspective projection's -(k f n) / (f - n) keeps
// glm's bits for ordinary cameras and stays finite and correctly scaled where f n alone leaves
// the binary32 range (worlds scaled by 1e20 or 1e-20: the extremes catalogue's decades).
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include <glm/glm.hpp>

#include <tessera/math/projection_terms.h>
#include <tessera/techniques/forward.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::math_projection_terms_test {

using namespace tessera;

namespace {
// The term in double, for the relative error of the binary32 chain (three roundings: k f, x n,
// and the division; f - n is a fourth): within 4 x 2^-24 of it.
double termInDouble(double f, double n, double k) { return -(k * f * n) / (f - n); }
constexpr double kChainTolerance = 4.0 * 0x1p-24;  // relative
} // namespace

TEST_CASE("nearFarTerm: glm's bits for ordinary cameras, finite and scaled by 2^e beyond the normal range of f n") {
    // Ordinary cameras: exactly glm's -(f * n) / (f - n) and -(2 f n) / (f - n).
    for (const float n : {0.1f, 0.5f, 1.0f, 7.5f}) {
        for (const float f : {11.0f, 100.0f, 1000.0f, 1e5f}) {
            CAPTURE(n);
            CAPTURE(f);
            CHECK(nearFarTerm(f, n, 1.0f) == -(f * n) / (f - n));
            CHECK(nearFarTerm(f, n, 2.0f) == -(2.0f * f * n) / (f - n));
        }
    }
    // Orthographic near 0 never reaches the perspective term, but the PR&C ProjectionB takes it: -0.
    CHECK(nearFarTerm(100.0f, 0.0f, 1.0f) == 0.0f);
    // World scale 1e20 (near 1e19, far 1e22): f n = 1e41 > FLT_MAX, glm's term is -inf.
    // World scale 1e-20 (near 1e-21, far 1e-18): f n = 1e-39 < FLT_MIN, subnormal.
    struct Case {
        float f, n;
    };
    for (const Case c : {Case{1e22f, 1e19f}, Case{1e-18f, 1e-21f}, Case{3e38f, 1e30f}, Case{1e-30f, 1e-36f}}) {
        CAPTURE(c.f);
        CAPTURE(c.n);
        for (const float k : {1.0f, 2.0f}) {
            const float t = nearFarTerm(c.f, c.n, k);
            CHECK(std::isfinite(t));
            CHECK(std::fabs(t) >= std::numeric_limits<float>::min());
            const double expected = termInDouble(c.f, c.n, k);
            CHECK(std::fabs(double(t) - expected) <= kChainTolerance * std::fabs(expected));
        }
    }
}

TEST_CASE("projection3dgep at world scale 1e20 and 1e-20: every element and the inverse finite") {
    for (const float scale : {1e20f, 1e-20f}) {
        CAPTURE(scale);
        Camera camera;
        camera.nearZ = 0.1f * scale;
        camera.farZ = 100.0f * scale;
        for (const ProjectionConvention convention : {ProjectionConvention::DemoGl, ProjectionConvention::D3d}) {
            const glm::mat4 p = projection3dgep(camera, 4.0f / 3.0f, convention);
            const glm::mat4 inverse = glm::inverse(p);
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r) {
                    CHECK(std::isfinite(p[c][r]));
                    CHECK(std::isfinite(inverse[c][r]));
                }
        }
    }
}

} // namespace tessera_test::math_projection_terms_test
