// Rasterization rules against Mesa llvmpipe, per pixel and per sample, on draws built to sit on
// the decision boundaries: vertices and edges exactly on pixel centres, pixel edges, tile edges
// and 4x sample points; vertices on and between the 1/256 px snapping grid; every depth function
// with and without stencil on D24S8 and D32FS8; blending, write masks and scissor; 1 and 4
// samples; several tessera tile sizes. Every comparison is exact unless a bound says otherwise.
//
// Why exact comparison is sound here (both sides must compute the same snapped vertices):
// * The target is 256x256, so NDC <-> window is x_win = (x_ndc + 1) * 128: a multiply by a
//   power of two and an add. A window coordinate k / 1024 px with |k| < 2^20 gives
//   x_ndc = k / 2^17 - 1, at most 21 significant bits: exact in binary32, and exact back
//   again, whichever order or fused operations each implementation uses.
// * Clip w is a power of two (x_clip = x_ndc * w, divided back exactly).
// * tessera snaps round(256 x) (fixed_point.h); llvmpipe snaps round(256 (x - 0.5)) (0.5 px is
//   128 units, an exact shift). Off a tie (k mod 4 != 2 on the 1/1024 grid) both give the same
//   nearest integer. Exact ties (k mod 4 == 2) are rounded differently: see the tie test case.
// * Constant depth per triangle with dyadic values; colours are multiples of 1/255 and blends
//   that only add, subtract, take min/max or multiply by 0/1 stay exact in both (8-bit UNORM).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <random>
#include <sstream>

#include "gl_peer.h"
#include "support/test_draw.h"
#include "tessera_replay.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::conformance_llvmpipe_raster_rules_test {

using namespace tessera;
using namespace tessera::test;

namespace {

constexpr int kSize = 256;            // px, target side (power of two, see the file comment)
constexpr float kSizeF = 256.0f;
constexpr std::uint32_t kTileSizes[] = {8, 16, 64};  // px, tessera DeviceConfig::tileSize values compared

// D3D11 standard 4x pattern (D3D11.3 §19.2.4), 1/16 px from the pixel centre; llvmpipe's
// lp_sample_pos_4x is the same set in the same order (gl_peer.cpp).
constexpr int kSample4[4][2] = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};

glm::vec2 samplePos(int x, int y, int s, int samples) {
    if (samples == 1) return {float(x) + 0.5f, float(y) + 0.5f};
    return {float(x) + 0.5f + float(kSample4[s][0]) / 16.0f, float(y) + 0.5f + float(kSample4[s][1]) / 16.0f};
}

void addTriangle(peer::PeerDraw& d, const glm::vec2 p[3], float z, float w, const std::array<float, 4>& color) {
    for (int i = 0; i < 3; ++i) {
        const glm::vec4 c = windowToClip(p[i].x, p[i].y, kSizeF, kSizeF, z, w);
        d.posClip.push_back({c.x, c.y, c.z, c.w});
    }
    d.colorPerTriangle.push_back(color);
}

std::array<float, 4> color255(int r, int g, int b, int a) {  // multiples of 1/255: exact codes in both
    return {float(r) / 255.0f, float(g) / 255.0f, float(b) / 255.0f, float(a) / 255.0f};
}

std::array<float, 4> randomColor(std::mt19937& rng) {
    std::uniform_int_distribution<int> k(0, 255);
    return color255(k(rng), k(rng), k(rng), k(rng));
}

// A counting draw: every covered sample increments stencil (saturating) and adds its triangle's
// colour (ONE + ONE blending), depth test off, no culling.
peer::PeerDraw countingDraw() {
    peer::PeerDraw d;
    d.depthEnable = false;
    d.stencilEnable = true;
    d.front = d.back = {peer::StencilOp::Keep, peer::StencilOp::Keep, peer::StencilOp::IncrSat, peer::Cmp::Always};
    d.additiveBlend = true;
    return d;
}

// Vertices stay inside the viewport: llvmpipe clips x/y against the viewport whenever a depth
// buffer is bound (no guard band outside its "linear" path), and the clip points it computes
// are not on the 1/256 grid; tessera's guard band never clips here.
glm::vec2 inside(glm::vec2 v) { return glm::clamp(v, glm::vec2(0.0f), glm::vec2(kSizeF)); }

// ---- tessera side -------------------------------------------------------------------------

// ---- comparison ---------------------------------------------------------------------------

struct Tolerance {
    int color = 0;      // 8-bit codes per channel
    double depth = 0;   // D32: absolute; D24: codes (a read-back bound is added for MSAA D24)
};

struct Mismatch {
    int count = 0;
    std::string first;
};

std::uint32_t tesseraD24Code(const Surface& ds, int x, int y, int s) {
    std::uint32_t v;
    std::memcpy(&v, ds.texel(std::uint32_t(x), std::uint32_t(y), std::uint32_t(s)), 4);
    return v & 0xFFFFFFu;
}

// Compares colour, stencil and depth of every sample; describes the first mismatch.
Mismatch compareImages(const TesseraResult& t, const peer::PeerImage& g, const peer::PeerFrame& frame, Tolerance tol) {
    Mismatch m;
    const int n = frame.samples;
    const bool d24 = frame.depthFormat == peer::DepthFormat::D24S8;
    const double d24Tol = tol.depth + (g.depthCodeExact ? 0.0 : 1.0);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            for (int s = 0; s < n; ++s) {
                const std::size_t i = (std::size_t(y) * kSize + std::size_t(x)) * std::size_t(n) + std::size_t(s);
                const std::byte* texel = t.color.texel(std::uint32_t(x), std::uint32_t(y), std::uint32_t(s));
                std::ostringstream why;
                for (int ch = 0; ch < 4; ++ch) {
                    const int a = std::to_integer<int>(texel[ch]), b = g.rgba8[i * 4 + std::size_t(ch)];
                    if (std::abs(a - b) > tol.color) why << " colour[" << ch << "] tessera " << a << " llvmpipe " << b;
                }
                const int st = t.ds.loadStencil(std::uint32_t(x), std::uint32_t(y), std::uint32_t(s)), sg = g.stencil[i];
                if (st != sg) why << " stencil tessera " << st << " llvmpipe " << sg;
                if (d24) {
                    const double a = tesseraD24Code(t.ds, x, y, s), b = g.depthCode[i];
                    if (std::fabs(a - b) > d24Tol) why << " D24 code tessera " << a << " llvmpipe " << b;
                } else {
                    const double a = t.ds.loadDepth(std::uint32_t(x), std::uint32_t(y), std::uint32_t(s)), b = g.depth[i];
                    if (std::fabs(a - b) > tol.depth) why << " depth tessera " << a << " llvmpipe " << b;
                }
                if (!why.str().empty() && m.count++ == 0) {
                    std::ostringstream f;
                    f << "pixel (" << x << "," << y << ") sample " << s << ":" << why.str();
                    m.first = f.str();
                }
            }
    return m;
}

std::string describe(const peer::PeerFrame& f, std::uint32_t tile) {
    std::ostringstream o;
    o << (f.depthFormat == peer::DepthFormat::D24S8 ? "D24S8" : "D32FS8") << ", " << f.samples << " sample(s), tile " << tile << " px";
    return o.str();
}

// Renders the frame with llvmpipe once and with tessera at every tile size; all must match.
// Returns the llvmpipe image for further checks.
peer::PeerImage checkFrame(const peer::PeerFrame& frame, const char* what, Tolerance tol = {}) {
    const peer::PeerImage g = glPeer().render(frame);
    for (std::uint32_t tile : kTileSizes) {
        const TesseraResult t = renderTessera(frame, tile);
        const Mismatch m = compareImages(t, g, frame, tol);
        INFO(std::string(what) << " (" << describe(frame, tile) << "): " << m.count << " mismatching samples, first at " << m.first);
        CHECK(m.count == 0);
        INFO(std::string(what) << " (" << describe(frame, tile) << "): samples passed tessera " << t.samplesPassed << " llvmpipe " << g.samplesPassed);
        CHECK(t.samplesPassed == g.samplesPassed);
    }
    return g;
}

peer::PeerFrame newFrame(int samples, peer::DepthFormat format = peer::DepthFormat::D32FS8) {
    peer::PeerFrame f;
    f.width = f.height = kSize;
    f.samples = samples;
    f.depthFormat = format;
    f.clearColor = {0.0f, 0.0f, 0.0f, 0.0f};
    f.clearDepth = 1.0f;
    f.clearStencil = 0;
    return f;
}

// A rectangle [x0,x1) x [y0,y1) split into an nx x ny grid, each cell cut along a random
// diagonal. Interior vertices move by a random multiple of `jitterStep` px up to `jitter` px
// (jitter < a quarter of a cell, so no triangle folds); boundary vertices stay on the boundary,
// so the union is exactly the rectangle.
void gridMesh(peer::PeerDraw& d, std::mt19937& rng, float x0, float y0, float x1, float y1, int nx, int ny, float jitter,
              float jitterStep, float clipW) {
    std::vector<glm::vec2> v;
    const int steps = jitterStep > 0 ? int(jitter / jitterStep) : 0;
    std::uniform_int_distribution<int> j(-steps, steps);
    for (int b = 0; b <= ny; ++b)
        for (int a = 0; a <= nx; ++a) {
            glm::vec2 p{x0 + (x1 - x0) * float(a) / float(nx), y0 + (y1 - y0) * float(b) / float(ny)};
            if (a > 0 && a < nx) p.x += float(j(rng)) * jitterStep;
            if (b > 0 && b < ny) p.y += float(j(rng)) * jitterStep;
            v.push_back(p);
        }
    std::bernoulli_distribution flip(0.5);
    for (int b = 0; b < ny; ++b)
        for (int a = 0; a < nx; ++a) {
            const std::size_t i0 = std::size_t(b * (nx + 1) + a), i1 = i0 + 1, i2 = i0 + std::size_t(nx + 1), i3 = i2 + 1;
            const glm::vec2 t0[3] = {v[i0], v[i1], v[i3]}, t1[3] = {v[i0], v[i3], v[i2]};
            const glm::vec2 u0[3] = {v[i0], v[i1], v[i2]}, u1[3] = {v[i1], v[i3], v[i2]};
            const bool f = flip(rng);
            addTriangle(d, f ? t0 : u0, 0.5f, clipW, color255(1, 0, 0, 0));
            addTriangle(d, f ? t1 : u1, 0.5f, clipW, color255(1, 0, 0, 0));
        }
}

// A fan around `c` through n ring points at radius r, ring points rounded to `grid` px.
void fanMesh(peer::PeerDraw& d, glm::vec2 c, float r, int n, float grid, double phase) {
    std::vector<glm::vec2> ring;
    for (int i = 0; i < n; ++i) {
        const double a = phase + 2.0 * 3.14159265358979323846 * i / n;
        ring.push_back({std::round(float(c.x + r * std::cos(a)) / grid) * grid, std::round(float(c.y + r * std::sin(a)) / grid) * grid});
    }
    for (int i = 0; i < n; ++i) {
        const glm::vec2 t[3] = {c, ring[std::size_t(i)], ring[std::size_t((i + 1) % n)]};
        addTriangle(d, t, 0.5f, 1.0f, color255(1, 0, 0, 0));
    }
}

struct Rect {
    float x0, y0, x1, y1;
};

// Top-left rule for an axis-aligned rectangle: its left and top edges are top-left edges,
// so a sample at (sx, sy) is inside when x0 <= sx < x1 and y0 <= sy < y1 (D3D11.3 §15.? "Triangle
// Rasterization Rules": a sample on a top or left edge is covered, on a right or bottom edge not).
bool inRect(const Rect& r, glm::vec2 p) { return r.x0 <= p.x && p.x < r.x1 && r.y0 <= p.y && p.y < r.y1; }

} // namespace

TEST_CASE("llvmpipe rules: edges on pixel centres, pixel edges, tile edges and sample points cover each sample once") {
    for (int samples : {1, 4}) {
        std::mt19937 rng(77);
        peer::PeerFrame frame = newFrame(samples);
        // Rectangles (px), disjoint, each tiled by a grid mesh:
        const Rect centres{8.5f, 8.5f, 72.5f, 72.5f};       // vertices on pixel centres (4 px cells, no jitter)
        const Rect edges{80.0f, 8.0f, 144.0f, 72.0f};       // vertices on pixel and tile edges, interior jitter on 1/8 px
        const Rect samplesRect{152.375f, 8.125f, 247.875f, 71.625f};  // edges through 4x sample points (1/8 px grid)
        const Rect fine{8.25f, 80.75f, 120.5f, 143.25f};    // jitter on the 1/256 grid, clip w = 4
        peer::PeerDraw a = countingDraw();
        gridMesh(a, rng, centres.x0, centres.y0, centres.x1, centres.y1, 16, 16, 0.0f, 0.0f, 1.0f);
        peer::PeerDraw b = countingDraw();
        gridMesh(b, rng, edges.x0, edges.y0, edges.x1, edges.y1, 8, 8, 1.5f, 0.125f, 2.0f);
        peer::PeerDraw c = countingDraw();
        gridMesh(c, rng, samplesRect.x0, samplesRect.y0, samplesRect.x1, samplesRect.y1, 12, 8, 1.0f, 0.125f, 0.5f);
        peer::PeerDraw e = countingDraw();
        gridMesh(e, rng, fine.x0, fine.y0, fine.x1, fine.y1, 20, 10, 1.2f, 1.0f / 256.0f, 4.0f);
        // Fans (convex or star-shaped unions; counted for double coverage): centres on a pixel
        // centre, on a tile corner (64, 192 with 8/16/64 px tiles), on a sample point.
        peer::PeerDraw f = countingDraw();
        fanMesh(f, {160.5f, 112.5f}, 28.0f, 40, 0.5f, 0.0);
        fanMesh(f, {64.0f, 192.0f}, 40.0f, 8, 1.0f, 0.0);          // spokes along the tile edges
        fanMesh(f, {160.375f, 200.125f}, 30.0f, 100, 0.125f, 0.1);
        fanMesh(f, {222.5f, 120.5f}, 20.0f, 6, 0.5f, 0.3);
        frame.draws = {a, b, c, e, f};
        const peer::PeerImage g = checkFrame(frame, "edges on centres, pixel, tile and sample edges");
        // Watertightness, independent of llvmpipe: no sample counted twice anywhere, every sample
        // inside a rectangle counted once, none outside the meshes' area.
        int over = 0, rectWrong = 0;
        std::string firstBad;
        const Rect rects[] = {centres, edges, samplesRect, fine};
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x)
                for (int s = 0; s < samples; ++s) {
                    const int count = g.stencil[(std::size_t(y) * kSize + std::size_t(x)) * std::size_t(samples) + std::size_t(s)];
                    if (count > 1) ++over;
                    const glm::vec2 p = samplePos(x, y, s, samples);
                    bool inAny = false;
                    for (const Rect& r : rects) inAny = inAny || inRect(r, p);
                    if (p.y < 76.0f || (p.x < 124.0f && p.y < 148.0f)) {   // the rectangles' band
                        if (count != (inAny ? 1 : 0) && rectWrong++ == 0) {
                            std::ostringstream o;
                            o << "(" << x << "," << y << ") sample " << s << " count " << count;
                            firstBad = o.str();
                        }
                    }
                }
        INFO(samples << " sample(s): first wrong rectangle sample " << firstBad);
        CHECK(over == 0);
        CHECK(rectWrong == 0);
    }
}

TEST_CASE("llvmpipe rules: vertices on the 1/256 grid and between grid points snap alike") {
    // Random small triangles on the 1/1024 px grid, never on a tie (k mod 4 != 2), plus probe
    // triangles whose vertical left edge sits 3/1024 px right of a pixel centre: round to nearest
    // puts it 1/256 px right of the centre (centre not covered), flooring puts it exactly on the
    // centre (covered, a left edge); and 1/1024 px left of it: nearest gives the centre itself.
    for (int samples : {1, 4}) {
        std::mt19937 rng(4096);
        peer::PeerFrame frame = newFrame(samples);
        std::uniform_int_distribution<int> pos(8 * 1024, 248 * 1024), reach(-6 * 1024, 6 * 1024);
        const auto offTie = [](int k) { return (k & 3) == 2 ? k + 1 : k; };
        for (int drawIndex = 0; drawIndex < 4; ++drawIndex) {
            peer::PeerDraw d = countingDraw();
            d.stencilEnable = drawIndex % 2 == 0;
            d.additiveBlend = false;
            for (int t = 0; t < 600; ++t) {
                const int cx = pos(rng), cy = pos(rng);
                glm::vec2 p[3];
                for (glm::vec2& v : p) v = {float(offTie(cx + reach(rng))) / 1024.0f, float(offTie(cy + reach(rng))) / 1024.0f};
                addTriangle(d, p, 0.5f, float(1 << (t % 3)), randomColor(rng));
            }
            frame.draws.push_back(d);
        }
        peer::PeerDraw probes = countingDraw();
        for (int i = 0; i < 32; ++i) {
            const float cx = 10.5f + 7.0f * float(i), cy = 250.5f;
            const float dx = (i % 2 == 0 ? 3.0f : -1.0f) / 1024.0f;
            const glm::vec2 p[3] = {{cx + dx, cy - 3.0f}, {cx + 4.0f, cy}, {cx + dx, cy + 3.0f}};
            addTriangle(probes, p, 0.5f, 1.0f, color255(0, 0, 255, 255));
        }
        frame.draws.push_back(probes);
        checkFrame(frame, "1/1024 px vertices off the ties");
    }
}

TEST_CASE("llvmpipe rules: exact snapping ties round to nearest even in both") {
    // Vertices at (2m + 1/2) / 256 px: exactly halfway between two 16.8 values, the lower one even.
    // D3D11 data conversion rules ("Data Conversion Rules", float -> fixed point): round to nearest
    // even. tessera: std::nearbyint in the default rounding mode (fixed_point.h). llvmpipe 22.3 on
    // x86-64: calc_fixed_position (lp_setup_tri.c) converts 256 * (x - 0.5) with _mm_cvtps_epi32,
    // which rounds by MXCSR, nearest even by default (its scalar subpixel_snap, util_iround =
    // (int)(f + 0.5f), would round these ties up; measured: it is not the path taken). The
    // -0.5 px offset is 128 units, even, so the tie goes to the same neighbour either way.
    // Checked: tessera and llvmpipe agree on the tie frame, both equal llvmpipe drawing the
    // vertices pre-rounded down (to even), and pre-rounding up does change the coverage (so a
    // round-half-up snap in either would be seen).
    for (int samples : {1, 4}) {
        std::mt19937 rng(1919);
        std::uniform_int_distribution<int> pos(16 * 128, 240 * 128), reach(-5 * 128, 5 * 128);
        peer::PeerFrame tie = newFrame(samples), down = newFrame(samples), up = newFrame(samples);
        peer::PeerDraw dt = countingDraw(), dd = countingDraw(), du = countingDraw();
        for (int t = 0; t < 1500; ++t) {
            const int cx = pos(rng), cy = pos(rng);
            glm::vec2 pt[3], pd[3], pu[3];
            for (int i = 0; i < 3; ++i) {
                const int mx = cx + reach(rng), my = cy + reach(rng);  // units of 2/256 px
                pt[i] = {(float(2 * mx) + 0.5f) / 256.0f, (float(2 * my) + 0.5f) / 256.0f};
                pd[i] = {float(2 * mx) / 256.0f, float(2 * my) / 256.0f};
                pu[i] = {float(2 * mx + 1) / 256.0f, float(2 * my + 1) / 256.0f};
            }
            addTriangle(dt, pt, 0.5f, 1.0f, color255(1, 0, 0, 0));
            addTriangle(dd, pd, 0.5f, 1.0f, color255(1, 0, 0, 0));
            addTriangle(du, pu, 0.5f, 1.0f, color255(1, 0, 0, 0));
        }
        tie.draws = {dt};
        down.draws = {dd};
        up.draws = {du};
        const peer::PeerImage gTie = checkFrame(tie, "vertices on exact snapping ties");
        const peer::PeerImage gDown = glPeer().render(down);
        const TesseraResult tTie = renderTessera(tie, 16), tUp = renderTessera(up, 16);
        const Mismatch evenRule = compareImages(tTie, gDown, tie, {});
        INFO(samples << " sample(s): tessera on ties vs llvmpipe on rounded-down vertices: " << evenRule.count << ", first " << evenRule.first);
        CHECK(evenRule.count == 0);
        const Mismatch upRule = compareImages(tUp, gTie, tie, {});
        MESSAGE(samples << " sample(s): rounding the ties up instead would change " << upRule.count << " samples");
        CHECK(upRule.count > 0);
    }
}

TEST_CASE("llvmpipe rules: every depth function with stencil off and on, D24S8 and D32FS8") {
    const float depths[] = {0.125f, 0.25f, 0.375f, 0.5f, 0.625f, 0.75f, 0.875f};  // dyadic
    for (peer::DepthFormat format : {peer::DepthFormat::D32FS8, peer::DepthFormat::D24S8}) {
        for (int samples : {1, 4}) {
            std::mt19937 rng(31337);
            peer::PeerFrame frame = newFrame(samples, format);
            frame.clearDepth = 0.5f;
            frame.clearStencil = 0x40;
            // A base layer of depths and stencil values to test against.
            peer::PeerDraw base;
            base.depthFunc = peer::Cmp::Always;
            base.stencilEnable = true;
            base.front = base.back = {peer::StencilOp::Keep, peer::StencilOp::Keep, peer::StencilOp::Replace, peer::Cmp::Always};
            base.stencilRef = 0x41;
            std::uniform_int_distribution<int> grid(0, 256 * 4);
            for (int t = 0; t < 60; ++t) {
                glm::vec2 p[3];
                const float cx = float(grid(rng)) / 4.0f, cy = float(grid(rng)) / 4.0f;
                for (glm::vec2& v : p) v = inside({cx + float(grid(rng) % 240 - 120) / 4.0f, cy + float(grid(rng) % 240 - 120) / 4.0f});
                addTriangle(base, p, depths[rng() % 7], 1.0f, randomColor(rng));
            }
            frame.draws.push_back(base);
            auto op = [&] { return peer::StencilOp(std::uniform_int_distribution<int>(0, 7)(rng)); };
            auto cmp = [&] { return peer::Cmp(std::uniform_int_distribution<int>(0, 7)(rng)); };
            for (int func = 0; func < 8; ++func)
                for (int stencil = 0; stencil < 2; ++stencil) {
                    peer::PeerDraw d;
                    d.depthFunc = peer::Cmp(func);
                    d.depthWrite = (func + stencil) % 2 == 0;
                    d.stencilEnable = stencil == 1;
                    d.front = {op(), op(), op(), cmp()};
                    d.back = {op(), op(), op(), cmp()};
                    d.stencilRef = std::uint8_t(rng());
                    d.stencilReadMask = func % 3 == 0 ? std::uint8_t(rng()) : 0xFF;
                    d.stencilWriteMask = func % 3 == 1 ? std::uint8_t(rng()) : 0xFF;
                    d.cull = peer::Cull(func % 3);
                    d.frontCounterClockwise = func % 2 == 1;
                    for (int t = 0; t < 24; ++t) {
                        glm::vec2 p[3];
                        const float cx = float(grid(rng)) / 4.0f, cy = float(grid(rng)) / 4.0f;
                        for (glm::vec2& v : p) v = inside({cx + float(grid(rng) % 160 - 80) / 4.0f, cy + float(grid(rng) % 160 - 80) / 4.0f});
                        addTriangle(d, p, depths[rng() % 7], float(1 << (t % 3)), randomColor(rng));
                    }
                    frame.draws.push_back(d);
                }
            checkFrame(frame, "depth functions x stencil");
        }
    }
}

TEST_CASE("llvmpipe rules: blending, colour write masks and scissor rectangles") {
    for (int samples : {1, 4}) {
        std::mt19937 rng(2718);
        peer::PeerFrame exact = newFrame(samples), rounded = newFrame(samples);
        exact.clearColor = rounded.clearColor = {64.0f / 255.0f, 128.0f / 255.0f, 192.0f / 255.0f, 1.0f};
        std::uniform_int_distribution<int> grid(0, 256 * 8), side(0, 256);
        // Factors whose products are exact in 8-bit UNORM: 0 and 1, and the blend factor set to
        // 0 or 1 per channel; every op (MIN/MAX ignore the factors in both APIs).
        const peer::BlendFactor exactFactors[] = {peer::BlendFactor::Zero, peer::BlendFactor::One, peer::BlendFactor::BlendFactor,
                                                  peer::BlendFactor::InvBlendFactor};
        const peer::BlendFactor anyFactors[] = {peer::BlendFactor::SrcColor, peer::BlendFactor::InvSrcColor, peer::BlendFactor::SrcAlpha,
                                                peer::BlendFactor::InvSrcAlpha, peer::BlendFactor::DestAlpha, peer::BlendFactor::InvDestAlpha,
                                                peer::BlendFactor::DestColor, peer::BlendFactor::InvDestColor};
        for (int drawIndex = 0; drawIndex < 24; ++drawIndex) {
            for (peer::PeerFrame* frame : {&exact, &rounded}) {
                peer::PeerDraw d;
                d.depthEnable = false;
                d.stencilEnable = true;  // coverage counted exactly even where colours may round
                d.front = d.back = {peer::StencilOp::Keep, peer::StencilOp::Keep, peer::StencilOp::Incr, peer::Cmp::Always};
                d.blend.enable = drawIndex % 6 != 5;
                const bool isExact = frame == &exact;
                auto factor = [&] { return isExact ? exactFactors[rng() % 4] : anyFactors[rng() % 8]; };
                d.blend.src = factor();
                d.blend.dst = factor();
                d.blend.srcAlpha = isExact ? factor() : peer::BlendFactor(rng() % 2);
                d.blend.dstAlpha = isExact ? factor() : peer::BlendFactor::InvSrcAlpha;
                d.blend.op = peer::BlendOp(rng() % 5);
                d.blend.opAlpha = peer::BlendOp(rng() % 5);
                d.blendFactor = {float(rng() % 2), float(rng() % 2), float(rng() % 2), float(rng() % 2)};
                d.colorWriteMask = drawIndex % 4 == 3 ? std::uint8_t(rng() % 16) : std::uint8_t(0xF);
                // Scissor: random, tile-aligned, odd, empty and target-sized rectangles. With 4
                // samples, llvmpipe 22.3.6 was measured to keep samples of the pixel column left of
                // the rectangle and the row above it (those whose position lies within half a pixel
                // of the edge), where the scissor test is per pixel (D3D11.3 §15.? "Scissor Test";
                // OpenGL 4.5 core §14.9.2): an llvmpipe defect, so the scissor is compared at 1
                // sample only.
                d.scissorEnable = samples == 1 && drawIndex % 3 != 0;
                const int l = side(rng), tp = side(rng);
                switch (drawIndex % 4) {
                case 0: d.scissor = {l, tp, std::min(256, l + side(rng)), std::min(256, tp + side(rng))}; break;
                case 1: d.scissor = {(l / 16) * 16, (tp / 16) * 16, (l / 16) * 16 + 64, (tp / 16) * 16 + 48}; break;
                case 2: d.scissor = {l | 1, tp | 1, (l | 1) + 1, 256}; break;
                default: d.scissor = {l, tp, l, tp + 10}; break;  // empty
                }
                for (int t = 0; t < 30; ++t) {
                    glm::vec2 p[3];
                    const float cx = float(grid(rng)) / 8.0f, cy = float(grid(rng)) / 8.0f;
                    for (glm::vec2& v : p) v = inside({cx + float(grid(rng) % 800 - 400) / 8.0f, cy + float(grid(rng) % 800 - 400) / 8.0f});
                    addTriangle(d, p, 0.5f, 1.0f, randomColor(rng));
                }
                frame->draws.push_back(d);
            }
        }
        checkFrame(exact, "blending with exact factors, write masks, scissor");
        // Products of two 8-bit values are rounded by each implementation in its own way (tessera
        // in float, rounded once on the store; llvmpipe in 8-bit fixed point, each product rounded):
        // measured up to 2 codes apart, so 3 codes per channel. Coverage stays exact (stencil).
        checkFrame(rounded, "blending with rounded products, write masks, scissor", Tolerance{3, 0});
    }
}

} // namespace tessera_test::conformance_llvmpipe_raster_rules_test
