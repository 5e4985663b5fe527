// Stored D24 depth against the double-precision D3D11 depth (support/depth_truth.h): the plane
// through the *snapped* vertex positions and their window z (D3D11.3 §3.4.1 "Coordinate
// Snapping": attribute interpolation is set up on the snapped positions), evaluated at the pixel
// centre, clamped to the viewport's [0, 1] and rounded to nearest into UNORM24.
//
// tessera's bound, derived: the truth takes the same binary32 window z per vertex as tessera, so
// tessera's errors are the barycentrics rounded once from exact integer edge values (<= 2^-25 each,
// times |z_k - z0|), the two products of z0 + l1 (z1 - z0) + l2 (z2 - z0) (<= 1/2 ulp of a value
// <= |z_k - z0|; the differences are exact by Sterbenz for depths within a factor of 2) and its two
// sums (<= 1/2 ulp of a value <= 1 each): at most one ulp plus 2^-24 max|z_k - z0|. For depths in
// [1/2, 1) one ulp is 2^-24 = 1.00000006 codes, so the exactly rounded codes may differ by 2 at
// worst. Measured: never more than 1, on the draws below and on every pixel of the Sponza frame's
// unclipped triangles; the tests pin that. A triangle clipped at the near plane adds the binary32
// rounding of the clipper's new vertices (2 codes measured on Sponza; the bound used for it here).
//
// llvmpipe (Mesa's lp_state_setup.c) sets the depth plane up from the *unsnapped* float window
// positions, in float, extrapolated to the framebuffer origin (a0 = z0 - (dzdx x0 + dzdy y0)), so
// on slivers and steep planes far from the origin its codes leave the D3D11 depth by hundreds of
// codes (same_frame_bench's Sponza frame: 628 of the 631 pixels more than 16 codes off). That is
// recorded here as a known difference, not a tolerance: the test requires it to be explained by the
// unsnapped plane. The frame's largest difference (165,198 codes) is coverage: llvmpipe clips
// triangles at the viewport, off the snapping grid, and covers a pixel centre on an edge that
// D3D11's rules leave out (the last test reproduces it); the next two (49,536 and 86,833 codes)
// are a nearer triangle covering in llvmpipe only, and one not traced (bench/RESULTS.md).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "gl_peer.h"
#include "support/depth_truth.h"
#include "support/test_draw.h"
#include "tessera_replay.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::conformance_llvmpipe_depth_test {

using namespace tessera;
using namespace tessera::test;
namespace dt = tessera::depth_truth;

namespace {

constexpr int kW = 1280, kH = 720;  // the same-frame benchmark's size: pixel coordinates up to 1279

// The draws below: every triangle in its own draw, depth LESS against a clear of 1.0, regions
// that do not overlap, so each pixel's stored code is its one triangle's.
struct DepthCase {
    std::vector<std::array<glm::vec4, 3>> triangles;  // clip space
};

peer::PeerFrame frameOf(const DepthCase& c) {
    peer::PeerFrame f;
    f.width = kW;
    f.height = kH;
    f.depthFormat = peer::DepthFormat::D24S8;
    f.clearDepth = 1.0f;
    for (const auto& t : c.triangles) {
        peer::PeerDraw d;
        for (const glm::vec4& v : t) d.posClip.push_back({v.x, v.y, v.z, v.w});
        d.colorPerTriangle.push_back({1.0f, 1.0f, 1.0f, 1.0f});
        f.draws.push_back(d);
    }
    return f;
}

// The truth of the frame: per pixel the code the D3D11 rules store (kFarCode where uncovered).
std::vector<std::uint32_t> truthOf(const DepthCase& c) {
    std::vector<std::uint32_t> codes(std::size_t(kW) * kH, dt::kFarCode);
    for (const auto& tri : c.triangles) {
        const glm::dvec4 in[3] = {glm::dvec4(tri[0]), glm::dvec4(tri[1]), glm::dvec4(tri[2])};
        glm::dvec4 poly[12];
        const int n = dt::clip(in, poly);
        for (int i = 1; i + 1 < n; ++i) {
            const glm::dvec4 fan[3] = {poly[0], poly[i], poly[i + 1]};
            dt::Triangle t;
            if (!dt::makeTriangle(fan, kW, kH, false, t)) continue;
            const std::int64_t x0 = std::max<std::int64_t>(0, std::min({t.x[0], t.x[1], t.x[2]}) / 256 - 1);
            const std::int64_t x1 = std::min<std::int64_t>(kW - 1, std::max({t.x[0], t.x[1], t.x[2]}) / 256 + 1);
            const std::int64_t y0 = std::max<std::int64_t>(0, std::min({t.y[0], t.y[1], t.y[2]}) / 256 - 1);
            const std::int64_t y1 = std::min<std::int64_t>(kH - 1, std::max({t.y[0], t.y[1], t.y[2]}) / 256 + 1);
            for (std::int64_t y = y0; y <= y1; ++y)
                for (std::int64_t x = x0; x <= x1; ++x) {
                    double z;
                    if (!dt::depthAt(t, x, y, z)) continue;
                    const std::uint32_t code = dt::d24(std::clamp(z, 0.0, 1.0));
                    std::uint32_t& stored = codes[std::size_t(y) * kW + std::size_t(x)];
                    stored = std::min(stored, code);
                }
        }
    }
    return codes;
}

std::uint32_t tesseraCode(const TesseraResult& r, int x, int y) {
    std::uint32_t texel;
    std::memcpy(&texel, r.ds.texel(std::uint32_t(x), std::uint32_t(y)), sizeof texel);
    return texel & 0xFFFFFFu;
}

glm::vec4 clipOf(double xWin, double yWin, double z, double w) {  // window px (y down), depth, clip w
    const double xn = xWin / (kW * 0.5) - 1.0, yn = 1.0 - yWin / (kH * 0.5);
    return glm::vec4(float(xn * w), float(yn * w), float(z * w), float(w));
}

// Slivers and steep planes, far from the origin and near it, depths near 1 (the GL-form
// projection's range) and mid-range, vertices off the 1/256 snapping grid; 4 x 8 regions of
// 160 x 90 px keep them apart.
DepthCase slivers(std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    DepthCase c;
    for (int region = 0; region < 32; ++region) {
        const double rx = (region % 8) * 160.0, ry = (region / 8) * 180.0;
        const double width = region % 4 == 0 ? 0.6 + u(rng) : region % 4 == 1 ? 2.0 + 3.0 * u(rng) : 8.0 + 40.0 * u(rng);
        const double x0 = rx + 20.0 + 60.0 * u(rng), y0 = ry + 150.0 + 20.0 * u(rng);
        const double base = region % 2 == 0 ? 0.9 + 0.09 * u(rng) : 0.3 + 0.2 * u(rng);
        const double span = 0.001 + 0.1 * u(rng);
        const double w = 0.5 + 4.0 * u(rng);
        c.triangles.push_back({clipOf(x0, y0, base, w), clipOf(x0 + width * u(rng), y0 - 140.0 * u(rng) - 5.0, base + span * u(rng), w),
                               clipOf(x0 + width, y0 + 3.0 * u(rng), base + span, w)});
    }
    return c;
}

// The depth at pixel (x, y)'s centre of the plane through the *unsnapped* window positions
// (llvmpipe's rule), in double, for the triangle of `c` whose snapped version covers the pixel.
double unsnappedDepth(const DepthCase& c, int x, int y) {
    for (const auto& tri : c.triangles) {
        const glm::dvec4 in[3] = {glm::dvec4(tri[0]), glm::dvec4(tri[1]), glm::dvec4(tri[2])};
        dt::Triangle t;
        double z;
        if (!dt::makeTriangle(in, kW, kH, false, t) || !dt::depthAt(t, x, y, z)) continue;
        double X[3], Y[3], Z[3];
        for (int i = 0; i < 3; ++i) {
            X[i] = (in[i].x / in[i].w + 1.0) * (kW * 0.5);
            Y[i] = (1.0 - in[i].y / in[i].w) * (kH * 0.5);
            Z[i] = in[i].z / in[i].w;
        }
        const double px = x + 0.5, py = y + 0.5;
        const double det = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
        const double l1 = ((px - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (py - Y[0])) / det;
        const double l2 = ((X[1] - X[0]) * (py - Y[0]) - (px - X[0]) * (Y[1] - Y[0])) / det;
        return Z[0] + l1 * (Z[1] - Z[0]) + l2 * (Z[2] - Z[0]);
    }
    return -1.0;
}

std::int64_t absDiff(std::int64_t a, std::int64_t b) { return a > b ? a - b : b - a; }

struct Deviation {
    std::int64_t maxTessera = 0, maxPeer = 0;
    int worstX = -1, worstY = -1;  // llvmpipe's worst pixel
    std::uint64_t covered = 0, coverageDiffers = 0, peerOver16 = 0;
};

Deviation measure(const DepthCase& c, const TesseraResult& t, const peer::PeerImage* g) {
    const std::vector<std::uint32_t> truth = truthOf(c);
    Deviation d;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const std::size_t i = std::size_t(y) * kW + std::size_t(x);
            const std::int64_t a = tesseraCode(t, x, y), want = truth[i];
            if (want == dt::kFarCode && a == dt::kFarCode) continue;
            ++d.covered;
            d.maxTessera = std::max(d.maxTessera, absDiff(a, want));
            if (!g) continue;
            const std::int64_t b = g->depthCode[i];
            if ((b == dt::kFarCode) != (a == dt::kFarCode)) {
                ++d.coverageDiffers;
                continue;
            }
            if (absDiff(b, want) > 16) ++d.peerOver16;
            if (absDiff(b, want) > d.maxPeer) {
                d.maxPeer = absDiff(b, want);
                d.worstX = x;
                d.worstY = y;
            }
        }
    return d;
}

} // namespace

TEST_CASE("depth: tessera's D24 codes stay within 1 code of the double-precision D3D11 depth on slivers and steep planes") {
    for (std::uint32_t seed = 1; seed <= 3; ++seed) {
        const DepthCase c = slivers(seed);
        const TesseraResult t = renderTessera(frameOf(c), 64);
        const Deviation d = measure(c, t, nullptr);
        INFO("seed " << seed << ": " << d.covered << " covered pixels, max |tessera - truth| " << d.maxTessera << " codes");
        CHECK(d.covered > 1000);
        CHECK(d.maxTessera <= 1);
        MESSAGE("seed " << seed << ": " << d.covered << " px, max |tessera - truth| " << d.maxTessera << " codes");
    }
}

TEST_CASE("llvmpipe depth: slivers far from the origin: llvmpipe's float plane from unsnapped positions (known difference), tessera on the snapped ones") {
    const DepthCase c = slivers(7);
    const peer::PeerFrame frame = frameOf(c);
    const TesseraResult t = renderTessera(frame, 64);
    const peer::PeerImage g = glPeer().render(frame);
    const Deviation d = measure(c, t, &g);
    INFO(d.covered << " px: max |tessera - truth| " << d.maxTessera << ", max |llvmpipe - truth| " << d.maxPeer << " at ("
                   << d.worstX << ", " << d.worstY << "), " << d.peerOver16 << " px by more than 16 codes");
    // Some slivers reach past the far plane (depths up to 1.09, clipped at z = w): where
    // llvmpipe's depth error lifts a pixel near the far plane to 1.0, its LESS test against the
    // clear (1.0) fails and only tessera writes it (1 pixel here, (1058, 149): tessera 16777199, at
    // the truth). Depth is compared where both wrote.
    MESSAGE(d.coverageDiffers << " px written by one side only");
    CHECK(d.maxTessera <= 1);
    // The known difference: llvmpipe leaves the D3D11 depth by more than interpolation rounding...
    CHECK(d.peerOver16 > 0);
    CHECK(d.maxPeer > 100);
    // ...which the unsnapped plane explains: at llvmpipe's worst pixel its code lies nearer that
    // plane's than the truth's (the rest is its float a0 at the framebuffer origin).
    const std::int64_t peerCode = g.depthCode[std::size_t(d.worstY) * kW + std::size_t(d.worstX)];
    const std::int64_t unsnapped = dt::d24(std::clamp(unsnappedDepth(c, d.worstX, d.worstY), 0.0, 1.0));
    INFO("at the worst pixel: llvmpipe " << peerCode << ", unsnapped plane " << unsnapped << ", max deviation " << d.maxPeer);
    CHECK(absDiff(peerCode, unsnapped) * 2 < d.maxPeer);
    MESSAGE(d.covered << " px: max |tessera - truth| " << d.maxTessera << " codes, max |llvmpipe - truth| " << d.maxPeer
                      << " codes, " << d.peerOver16 << " px over 16");
}

// Three of the Sponza frame's triangles (same_frame_bench's forward frame, 1280x720, the demo's
// GL-form projection; clip positions exactly as its vertex shader writes them, drawn in the
// frame's order):
// - draw 36's triangle 1, a sliver about 40,000 codes per pixel steep that crosses the left edge
//   (llvmpipe up to 67 codes off: the plane on the unsnapped positions);
// - draw 6's triangle 19, the floor, clipped at the near plane, and draw 134's triangles 500 and
//   2549, which share an edge from (1203.30, 728.97) to (1208.14, 690.44) px that crosses the
//   bottom of the viewport and runs through pixel (1206, 703)'s centre. Snapped, that edge is a
//   right edge of both, so neither covers the pixel and the floor's 16054544 is stored; llvmpipe
//   clips the triangles at the viewport's bottom edge (off the snapping grid: README, llvmpipe
//   differences), covers the pixel with them and stores their 15889346, 165,198 codes nearer (a
//   hundredth of the depth range): the frame's largest depth difference is a coverage difference
//   of a surface behind which the floor hides it from the coverage count.
TEST_CASE("llvmpipe depth: Sponza's worst triangles: tessera at the D3D11 depth, llvmpipe up to 165,198 codes off (known difference)") {
    struct Worst {
        const char* what;
        std::vector<std::array<glm::vec4, 3>> triangles;
        std::int64_t tesseraBound;  // 1 (measured), or 2 where a triangle is clipped (tessera's binary32 clipper)
        std::int64_t peerAtLeast;
    };
    const std::array<glm::vec4, 3> sliver = {glm::vec4(-0x1.d5f158p+1f, 0x1.c619d2p-1f, 0x1.a4b4c8p+1f, 0x1.be3836p+1f),
                                             glm::vec4(-0x1.4ffbf2p+1f, 0x1.45e5f4p-1f, 0x1.43961cp+1f, 0x1.5d1e7ep+1f),
                                             glm::vec4(-0x1.5052fap+1f, 0x1.b918d4p-1f, 0x1.a51fa4p+1f, 0x1.bea30ap+1f)};
    const std::array<glm::vec4, 3> edge500 = {glm::vec4(0x1.aa26eep+1f, -0x1.f03d6ap+1f, 0x1.caab9cp+1f, 0x1.e42d14p+1f),
                                              glm::vec4(0x1.aad9d8p+1f, -0x1.b95a06p+1f, 0x1.c7556p+1f, 0x1.e0d704p+1f),
                                              glm::vec4(0x1.a196cep+1f, -0x1.b6a4aep+1f, 0x1.cddffap+1f, 0x1.e7614ap+1f)};
    const std::array<glm::vec4, 3> edge2549 = {glm::vec4(0x1.aa26eep+1f, -0x1.f03d6ap+1f, 0x1.caab9cp+1f, 0x1.e42d14p+1f),
                                               glm::vec4(0x1.ad8fe8p+1f, -0x1.b6137cp+1f, 0x1.d094bap+1f, 0x1.ea15e8p+1f),
                                               glm::vec4(0x1.aad9d8p+1f, -0x1.b95a06p+1f, 0x1.c7556p+1f, 0x1.e0d704p+1f)};
    const std::array<glm::vec4, 3> floor = {glm::vec4(-0x1.07d6fap+3f, 0x1.279b8p-4f, 0x1.28d9d8p+4f, 0x1.2bfdc4p+4f),
                                            glm::vec4(0x1.0c284p+3f, -0x1.0ab728p+3f, -0x1.102d94p+3f, -0x1.09b968p+3f),
                                            glm::vec4(0x1.0ad9fap+3f, -0x1.1540a6p+2f, 0x1.434a4ep+2f, 0x1.50063cp+2f)};
    const Worst cases[] = {
        {"sliver (draw 36, triangle 1)", {sliver}, 1, 17},
        {"floor and an edge crossing the viewport's bottom (draw 6 triangle 19, draw 134 triangles 500, 2549)",
         {floor, edge500, edge2549}, 2, 100000},
    };
    for (const Worst& w : cases) {
        const std::string what = w.what;
        DepthCase c;
        c.triangles = w.triangles;
        const peer::PeerFrame frame = frameOf(c);
        const TesseraResult t = renderTessera(frame, 64);
        const peer::PeerImage g = glPeer().render(frame);
        const Deviation d = measure(c, t, &g);
        INFO(what << ": " << d.covered << " px, max |tessera - truth| " << d.maxTessera << ", max |llvmpipe - truth| " << d.maxPeer
                  << " at (" << d.worstX << ", " << d.worstY << ")");
        CHECK(d.covered > 100);
        CHECK(d.maxTessera <= w.tesseraBound);
        CHECK(d.maxPeer >= w.peerAtLeast);
        MESSAGE(what << ": " << d.covered << " px, max |tessera - truth| " << d.maxTessera << " codes, max |llvmpipe - truth| "
                     << d.maxPeer << " codes at (" << d.worstX << ", " << d.worstY << ")");
    }
}

} // namespace tessera_test::conformance_llvmpipe_depth_test
