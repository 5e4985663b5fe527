// ScreenToView (3dgep article §3.3.3) against geometric truth: random view-space points projected
// with a D3D projection and with the demo's GL-form projection (ERRATA #1), depth stored as D24
// or D32_FLOAT, reconstructed through the float inverse projection; the error is bounded
// analytically. Also the faithful pixel-corner sample point's half-pixel offset.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <string>

#include <glm/ext/matrix_clip_space.hpp>

#include <tessera/buffers/conversion.h>
#include <tessera/gbuffer/screen_to_view.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::gbuffer_screen_to_view_test {

using namespace tessera;

namespace {

constexpr double kU = 1.0 / 16777216.0;  // 2^-24: unit roundoff of binary32

enum class ProjectionForm { D3dZeroToOne, GlDemo };
enum class DepthFormat { D24, D32F };

// glm perspective (right-handed, view looks down -Z). GlDemo is glm 0.9.6 `perspective`, the
// demo's SetProjectionRH: [2][2] = -(f+n)/(f-n), [3][2] = -2fn/(f-n), [2][3] = -1, fed to D3D
// clipping 0 <= z <= w unchanged. D3dZeroToOne: [2][2] = f/(n-f), [3][2] = fn/(n-f).
glm::mat4 makeProjection(ProjectionForm form, float fovYRad, float aspect, float n, float f) {
    return form == ProjectionForm::GlDemo ? glm::perspectiveRH_NO(fovYRad, aspect, n, f)
                                          : glm::perspectiveRH_ZO(fovYRad, aspect, n, f);
}

// View distance d = -z_view of the plane the depth buffer calls 0: n for D3D; for the GL form
// z_ndc = 0 is z_view = -2fn/(f+n) (= -0.19998 for the demo's 0.1 / 1000).
double nearestDistance(ProjectionForm form, double n, double f) {
    return form == ProjectionForm::GlDemo ? 2.0 * f * n / (f + n) : n;
}

// Both projections map view distance d = -z to depth D = (A z + B) / (-z) = -A + B/d with
// A = P[2][2], B = P[3][2] (both negative), so |dD/dd| = |B| / d^2:
//   D3D: |dD/dd| = fn / ((f - n) d^2);   GL form: |dD/dd| = 2fn / ((f - n) d^2).
// The inverse's w row gives view.w = C1*D + C2 with C1 = 1/B, C2 = A/B, and view.z = -1, so
// d = 1 / |view.w|. Error bound, first order in every rounding:
//   float entries c1' = C1(1 + d1), c2' = C2(1 + d2), z row -1 * (1 + d3);
//   view.w computed: (C1 D (1 + d1)(1 + e1) + C2 (1 + d2))(1 + e2), |e_i| <= u, so
//   |dW| <= (|D| (|d1| + u) + |A| |d2|) / |B| + u |W|, and d = -z = 1/W gives
//   |dd| <= d^2 |dW| + d (u + |d3|) (the final division adds one more u).
// Depth storage adds dD_store to D, i.e. d^2 dD_store / |B| = dD_store / |dD/dd|:
//   D24: the float depth (<= u D) quantized to the nearest of 2^24 - 1 steps (<= 1/(2(2^24-1)))
//        and decoded (<= u D):         dD_store <= 1/(2 (2^24 - 1)) + 2 u D
//   D32F: the float depth:              dD_store <= u D
// Total:  |dd| <= (d^2 / |B|) (dD_store + |D| (|d1| + u) + |A| |d2|) + d (2u + |d3|).
// The dominant D24 term at the demo's n = 0.1, f = 1000 (GL form): d^2 * 1.5e-7 (1.5e-3 at
// d = 100, 0.15 at d = 1000); the D3D form is twice that. The float inverse's |A| |d2| term
// (|A| ~ 1, d2 a few ulp) is of the same size as the D24 step, so D32F barely helps.
struct InverseErrors {
    double d1, d2, d3;  // relative errors of the float w-row entries and the z-row -1
};

InverseErrors measureInverse(const glm::mat4& invProj, const glm::dmat4& projD) {
    const glm::dmat4 invExact = glm::inverse(projD);
    auto rel = [](double got, double want) { return std::fabs(got - want) / std::fabs(want); };
    return {rel(invProj[2][3], invExact[2][3]), rel(invProj[3][3], invExact[3][3]), rel(invProj[3][2], invExact[3][2])};
}

double distanceErrorBound(double d, double depth, DepthFormat format, const glm::dmat4& projD, const InverseErrors& e) {
    const double a = projD[2][2], b = projD[3][2];
    const double storeErr = format == DepthFormat::D24 ? 0.5 / 16777215.0 + 2.0 * kU * depth : kU * depth;
    const double firstOrder = d * d / std::fabs(b) * (storeErr + std::fabs(depth) * (e.d1 + kU) + std::fabs(a) * e.d2) +
                              d * (2.0 * kU + e.d3);
    return firstOrder * 1.01;  // 1 % for the second-order terms
}

std::string name(ProjectionForm f) { return f == ProjectionForm::GlDemo ? "GL-form (demo)" : "D3D [0,1]"; }
std::string name(DepthFormat f) { return f == DepthFormat::D24 ? "D24" : "D32F"; }

} // namespace

TEST_CASE("ScreenToView reconstructs view-space points within the analytic depth-quantization bound") {
    constexpr float kWidth = 1280.0f, kHeight = 720.0f, kNear = 0.1f, kFar = 1000.0f;
    const float fovY = glm::radians(45.0f);
    const glm::vec2 dims(kWidth, kHeight);
    for (const ProjectionForm form : {ProjectionForm::GlDemo, ProjectionForm::D3dZeroToOne}) {
        const glm::mat4 proj = makeProjection(form, fovY, kWidth / kHeight, kNear, kFar);
        const glm::mat4 invProj = glm::inverse(proj);  // DeferredLightingPass.cpp: glm::inverse in float
        const glm::dmat4 projD(proj);                   // the float matrix the rasterizer uses, exactly
        // The structure the bound relies on: the inverse's z row is (0, 0, 0, -1) and its w row
        // (0, 0, 1/B, A/B); these zeros come out exactly zero from glm::inverse.
        REQUIRE(invProj[0][2] == 0.0f);
        REQUIRE(invProj[1][2] == 0.0f);
        REQUIRE(invProj[2][2] == 0.0f);
        REQUIRE(invProj[0][3] == 0.0f);
        REQUIRE(invProj[1][3] == 0.0f);
        const InverseErrors invErr = measureInverse(invProj, projD);
        CHECK(invErr.d1 < 8 * kU);
        CHECK(invErr.d2 < 8 * kU);
        CHECK(invErr.d3 < 8 * kU);
        MESSAGE(name(form) << ": float inverse entry errors (ulp) d1 = " << invErr.d1 / kU << ", d2 = " << invErr.d2 / kU
                           << ", d3 = " << invErr.d3 / kU);
        const double dMin = nearestDistance(form, kNear, kFar), dMax = kFar;
        for (const DepthFormat format : {DepthFormat::D24, DepthFormat::D32F}) {
            std::mt19937_64 rng(20150501);
            std::uniform_real_distribution<double> unit(0.0, 1.0);
            double worstRatio = 0.0, worstAbsErr = 0.0, worstXyRel = 0.0;
            int count = 0;
            for (int i = 0; i < 20000; ++i) {
                // d log-uniform over the depth range (1.001 dMin .. 0.999 f), x/y over the frustum.
                const double d = dMin * 1.001 * std::pow(dMax * 0.999 / (dMin * 1.001), unit(rng));
                const double xNdc = unit(rng) * 2.0 - 1.0, yNdc = unit(rng) * 2.0 - 1.0;
                const glm::dvec4 posView(xNdc * d / projD[0][0], yNdc * d / projD[1][1], -d, 1.0);
                const glm::dvec4 posClip = projD * posView;
                const double depth = posClip.z / posClip.w;  // what the buffer should hold, exactly
                REQUIRE(depth >= 0.0);
                REQUIRE(depth <= 1.0);
                const double xWin = (posClip.x / posClip.w + 1.0) * 0.5 * kWidth;
                const double yWin = (1.0 - posClip.y / posClip.w) * 0.5 * kHeight;
                float stored = static_cast<float>(depth);
                if (format == DepthFormat::D24) stored = convert::d24ToDepth(convert::depthToD24(stored));
                const glm::vec4 got = screenToView(
                    glm::vec4(static_cast<float>(xWin), static_cast<float>(yWin), stored, 1.0f), dims, invProj);
                const double err = std::fabs(double(-got.z) - d);
                const double bound = distanceErrorBound(d, depth, format, projD, invErr);
                worstRatio = std::max(worstRatio, err / bound);
                worstAbsErr = std::max(worstAbsErr, err);
                // x and y scale with d: relative error of d plus a few ulp (window xy in float).
                const double xyErr = std::hypot(double(got.x) - posView.x, double(got.y) - posView.y);
                const double xyScale = std::hypot(posView.x, posView.y) + 1e-30;
                worstXyRel = std::max(worstXyRel, xyErr / xyScale - err / d);
                CHECK(got.w == 1.0f);
                ++count;
                if (err > bound) {
                    INFO(name(form) << " " << name(format) << ": d = " << d << " depth = " << depth << " err = " << err
                                    << " bound = " << bound);
                    CHECK(err <= bound);
                }
            }
            MESSAGE(name(form) << " " << name(format) << ": " << count << " points, worst |dd|/bound = " << worstRatio
                               << ", worst |dd| = " << worstAbsErr);
            CHECK(worstRatio <= 1.0);
            CHECK(worstRatio > 0.2);  // the bound is not vacuous: some points come close to it
            CHECK(worstXyRel < 1e-5);
        }
    }
}

TEST_CASE("D24 reconstruction error at the demo's settings grows as d^2 (GL form: 1.5e-7 d^2)") {
    // The bound's dominant term at n = 0.1, f = 1000: (f - n) d^2 / (2 f n) * 2^-25 for the GL
    // form; spot checks of the closed form at d = 1, 10, 100, 1000.
    const double n = 0.1, f = 1000.0, halfStep = 0.5 / 16777215.0;
    const double perD2 = (f - n) / (2.0 * f * n) * halfStep;
    CHECK(perD2 == doctest::Approx(1.49e-7).epsilon(0.01));
    CHECK(perD2 * 100.0 * 100.0 == doctest::Approx(1.49e-3).epsilon(0.01));
    CHECK(perD2 * 1000.0 * 1000.0 == doctest::Approx(0.149).epsilon(0.01));
}

TEST_CASE("ScreenToView with the GL-form projection: depth 0 is view z -2fn/(f+n), depth 1 is -f") {
    const glm::mat4 proj = glm::perspectiveRH_NO(glm::radians(45.0f), 1280.0f / 720.0f, 0.1f, 1000.0f);
    const glm::mat4 invProj = glm::inverse(proj);
    const glm::vec2 dims(1280.0f, 720.0f);
    // The Forward+ culling shader's nearClipVS = ScreenToView(float4(0, 0, 0, 1)).z.
    CHECK(screenToView(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f), dims, invProj).z == doctest::Approx(-0.19998).epsilon(1e-5));
    CHECK(screenToView(glm::vec4(0.0f, 0.0f, 1.0f, 1.0f), dims, invProj).z == doctest::Approx(-1000.0).epsilon(1e-3));
    // Screen centre maps to the view axis.
    const glm::vec4 centre = screenToView(glm::vec4(640.0f, 360.0f, 0.5f, 1.0f), dims, invProj);
    CHECK(centre.x == 0.0f);
    CHECK(centre.y == 0.0f);
    // Top-left screen corner is up-left in view space (window y down -> view y up).
    const glm::vec4 topLeft = screenToView(glm::vec4(0.0f, 0.0f, 0.5f, 1.0f), dims, invProj);
    CHECK(topLeft.x < 0.0f);
    CHECK(topLeft.y > 0.0f);
}

TEST_CASE("pixel sample points: int2(SV_Position.xy) is the pixel corner, the corrected path uses the centre") {
    for (std::uint32_t x : {0u, 1u, 17u, 1279u})
        for (std::uint32_t y : {0u, 5u, 719u}) {
            const glm::vec2 svPosition(float(x) + 0.5f, float(y) + 0.5f);
            CHECK(pixelFromSvPosition(svPosition) == glm::ivec2(int(x), int(y)));
            CHECK(samplePointWindow(x, y, PixelSamplePoint::Corner) == glm::vec2(float(x), float(y)));
            CHECK(samplePointWindow(x, y, PixelSamplePoint::Centre) == svPosition);
        }
}

TEST_CASE("the faithful corner sample displaces P by half a pixel's footprint at its depth") {
    // A surface point on the pixel-centre ray of pixel (px, py) at view distance d (depth stored
    // as D32F so that only the sample point differs). The G-buffer was rasterized at the pixel
    // centre; the demo reconstructs at the corner: P moves by -d/(W P[0][0]) in x and
    // +d/(H P[1][1]) in y, i.e. half a pixel at depth d (pixel size 2 d tan(fov/2) / H).
    constexpr float kWidth = 1280.0f, kHeight = 720.0f;
    const glm::mat4 proj = glm::perspectiveRH_NO(glm::radians(45.0f), kWidth / kHeight, 0.1f, 1000.0f);
    const glm::mat4 invProj = glm::inverse(proj);
    const glm::dmat4 projD(proj);
    const glm::vec2 dims(kWidth, kHeight);
    for (const double d : {1.0, 10.0, 100.0}) {
        for (const glm::uvec2 px : {glm::uvec2(0, 0), glm::uvec2(640, 360), glm::uvec2(1000, 77)}) {
            const double xNdc = (px.x + 0.5) / kWidth * 2.0 - 1.0, yNdc = 1.0 - (px.y + 0.5) / kHeight * 2.0;
            const glm::dvec4 posView(xNdc * d / projD[0][0], yNdc * d / projD[1][1], -d, 1.0);
            const glm::dvec4 posClip = projD * posView;
            const float depth = static_cast<float>(posClip.z / posClip.w);
            const glm::vec4 centre = reconstructPositionView(px.x, px.y, depth, dims, invProj, PixelSamplePoint::Centre);
            const glm::vec4 corner = reconstructPositionView(px.x, px.y, depth, dims, invProj, PixelSamplePoint::Corner);
            const double halfPixel = d * std::tan(glm::radians(22.5)) / kHeight;  // half of 2 d tan(fov/2) / H
            INFO("d = " << d << " pixel (" << px.x << ", " << px.y << ")");
            // Centre: the true point, within the float-depth reconstruction error (the bound of
            // the first test case: about 1.5e-7 d^2 from the float depth and inverse, 2 ulp d).
            const double tol = 3e-7 * d * d + 1e-6 * d;
            CHECK(std::fabs(centre.x - posView.x) <= tol);
            CHECK(std::fabs(centre.y - posView.y) <= tol);
            CHECK(std::fabs(centre.z - posView.z) <= tol);
            // Corner: shifted by exactly the half-pixel footprint (square pixels: x and y alike).
            CHECK(double(corner.x) - centre.x == doctest::Approx(-d / (kWidth * projD[0][0])).epsilon(1e-3));
            CHECK(double(corner.y) - centre.y == doctest::Approx(d / (kHeight * projD[1][1])).epsilon(1e-3));
            CHECK(double(corner.x) - centre.x == doctest::Approx(-halfPixel).epsilon(1e-3));
            CHECK(double(corner.y) - centre.y == doctest::Approx(halfPixel).epsilon(1e-3));
            CHECK(corner.z == centre.z);
        }
    }
}

} // namespace tessera_test::gbuffer_screen_to_view_test
