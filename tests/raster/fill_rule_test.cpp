// Fill rule: seeded random meshes that share edges must cover every pixel inside exactly
// once and none outside (D3D11 top-left rule), and single edges placed on a pixel centre or a
// fraction of a snapping step beside it must cover the hand-derived pixels (ties, rounding).
// Coverage is counted with ONE+ONE blending into an R32_FLOAT target (exact below 2^24).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "support/test_draw.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::raster_fill_rule_test {

using namespace tessera;
using namespace tessera::test;

namespace {

constexpr std::uint32_t kSize = 256;   // px; a power of two keeps window <-> NDC exact
constexpr float kSizeF = float(kSize);

struct Mesh {
    std::vector<ColorVertex> vertices;
    std::vector<std::uint32_t> indices;
};

// A rectangle [x0,x1) x [y0,y1) (window px, on the 1/256 grid) split into a jittered
// nx x ny grid with a random diagonal per cell. Boundary vertices only move along the
// boundary, so the union of the triangles is exactly the rectangle. The jitter must stay
// below a quarter of the cell size so that no triangle folds over its neighbour.
Mesh jitteredGrid(std::mt19937& rng, float x0, float y0, float x1, float y1, int nx, int ny, float jitterPx,
                  float clipW) {
    Mesh m;
    std::uniform_real_distribution<float> jitter(-jitterPx, jitterPx);
    auto q = [](float v) { return std::round(v * 256.0f) / 256.0f; };  // onto the 16.8 grid
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
            float x = x0 + (x1 - x0) * float(i) / float(nx);
            float y = y0 + (y1 - y0) * float(j) / float(ny);
            if (i > 0 && i < nx) x += jitter(rng);
            if (j > 0 && j < ny) y += jitter(rng);
            m.vertices.push_back({windowToClip(q(x), q(y), kSizeF, kSizeF, 0.5f, clipW), {1, 1, 1, 1}});
        }
    std::bernoulli_distribution flip(0.5);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const std::uint32_t a = std::uint32_t(j * (nx + 1) + i), b = a + 1, c = a + std::uint32_t(nx + 1), d = c + 1;
            if (flip(rng)) m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
            else m.indices.insert(m.indices.end(), {a, b, c, b, d, c});
        }
    return m;
}

// Expected coverage of the rectangle: pixel centre c is inside when x0 <= c.x < x1 and
// y0 <= c.y < y1 (left and top edges are top-left edges, right and bottom are not).
std::vector<float> expectedRect(float x0, float y0, float x1, float y1) {
    std::vector<float> e(kSize * kSize, 0.0f);
    for (std::uint32_t y = 0; y < kSize; ++y)
        for (std::uint32_t x = 0; x < kSize; ++x) {
            const float cx = float(x) + 0.5f, cy = float(y) + 0.5f;
            if (x0 <= cx && cx < x1 && y0 <= cy && cy < y1) e[y * kSize + x] = 1.0f;
        }
    return e;
}

struct Result {
    int wrong = 0;
    std::uint32_t firstX = 0, firstY = 0;
    float got = 0, want = 0;
};

Result compareCounts(const Surface& s, const std::vector<float>& expected) {
    Result r;
    for (std::uint32_t y = 0; y < kSize; ++y)
        for (std::uint32_t x = 0; x < kSize; ++x) {
            const float got = s.load(x, y).x, want = expected[y * kSize + x];
            if (got != want && r.wrong++ == 0) r = {1, x, y, got, want};
        }
    return r;
}

std::size_t drawCount(Device& dev, Surface& target, const Mesh& m, CullMode cull = CullMode::None) {
    DrawState st = countingState(target);
    st.rasterizer.cullMode = cull;
    RenderTargets rt;
    rt.colors[0] = &target;
    dev.draw(st, rt, std::span<const ColorVertex>(m.vertices), std::span<const std::uint32_t>(m.indices), PassThroughVS{}, ColorPS{});
    return m.indices.size() / 3;
}

} // namespace

TEST_CASE("fill rule: jittered grids, pixel-centre grids, tile borders and off-screen meshes cover exactly once") {
    Device dev(DeviceConfig{16, 2});
    std::mt19937 rng(20261122);
    std::size_t triangles = 0;
    struct RectCase { float x0, y0, x1, y1; int nx, ny; float jitter; float clipW; const char* what; };
    const RectCase cases[] = {
        {8.5f, 8.5f, 120.5f, 100.5f, 24, 20, 0.9f, 1.0f, "edges on pixel centres"},
        {16.0f, 32.0f, 240.0f, 224.0f, 28, 24, 1.6f, 1.0f, "edges on tile borders (16 px tiles)"},
        {-300.25f, -77.75f, 400.125f, 333.5f, 40, 30, 3.0f, 1.0f, "mesh extends past the viewport"},
        {3.3984375f, 200.0078125f, 251.00390625f, 255.99609375f, 60, 8, 0.9f, 2.0f, "thin strip, clip w = 2"},
        {0.5f, 0.5f, 255.5f, 255.5f, 50, 50, 0.0f, 0.5f, "vertices on pixel centres (no jitter), w = 0.5"},
    };
    for (const RectCase& c : cases) {
        Surface target(SurfaceDesc{kSize, kSize, Format::R32_FLOAT, 1});
        const Mesh m = jitteredGrid(rng, c.x0, c.y0, c.x1, c.y1, c.nx, c.ny, c.jitter, c.clipW);
        triangles += drawCount(dev, target, m);
        const Result r = compareCounts(target, expectedRect(c.x0, c.y0, c.x1, c.y1));
        INFO(std::string(c.what) << ": first wrong pixel (" << r.firstX << "," << r.firstY << ") count " << r.got << " want " << r.want);
        CHECK(r.wrong == 0);
    }
    // Fans: a centre vertex and a ring of vertices; union is the ring polygon. Checked
    // for double coverage only, and total coverage against the reference below.
    for (int fan = 0; fan < 40; ++fan) {
        Surface target(SurfaceDesc{kSize, kSize, Format::R32_FLOAT, 1});
        std::uniform_real_distribution<float> pos(20.0f, 236.0f), rad(5.0f, 180.0f);
        const float cx = std::round(pos(rng) * 256) / 256, cy = std::round(pos(rng) * 256) / 256;
        const int n = 3 + fan * 7;
        Mesh m;
        m.vertices.push_back({windowToClip(cx, cy, kSizeF, kSizeF)});
        const float r = rad(rng);
        for (int i = 0; i < n; ++i) {
            const double a = 2.0 * 3.14159265358979 * i / n;
            const float x = std::round(float(cx + r * std::cos(a)) * 256) / 256, y = std::round(float(cy + r * std::sin(a)) * 256) / 256;
            m.vertices.push_back({windowToClip(x, y, kSizeF, kSizeF)});
        }
        for (int i = 0; i < n; ++i)
            m.indices.insert(m.indices.end(), {0u, std::uint32_t(1 + i), std::uint32_t(1 + (i + 1) % n)});
        triangles += drawCount(dev, target, m);
        int over = 0, innerMissing = 0;
        for (std::uint32_t y = 0; y < kSize; ++y)
            for (std::uint32_t x = 0; x < kSize; ++x) {
                const float v = target.load(x, y).x;
                if (v > 1.0f) ++over;
                // Pixels well inside the inscribed circle (cos(pi/n) r, minus 1 px) must be hit.
                const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
                if (d < r * std::cos(3.14159265358979 / n) - 1.0 && v != 1.0f) ++innerMissing;
            }
        CHECK(over == 0);
        CHECK(innerMissing == 0);
    }
    MESSAGE("fill-rule triangles drawn: " << triangles);
    CHECK(triangles >= 10000);
}

TEST_CASE("fill rule: a mesh crossing the near plane stays watertight after clipping") {
    Device dev(DeviceConfig{32, 2});
    Surface target(SurfaceDesc{kSize, kSize, Format::R32_FLOAT, 1});
    std::mt19937 rng(7);
    // A grid whose NDC depth runs from -0.6 (behind the near plane) to 1.0 across x; the
    // clipped boundary is the line z = 0, at 3/8 of the width (x_win = 96 px).
    Mesh m = jitteredGrid(rng, 0.0f, 0.0f, 256.0f, 256.0f, 32, 32, 2.0f, 1.0f);
    for (ColorVertex& v : m.vertices) v.posClip.z = (v.posClip.x + 1.0f) * 0.8f - 0.6f;
    drawCount(dev, target, m);
    int over = 0, missing = 0, leaked = 0;
    for (std::uint32_t y = 0; y < kSize; ++y)
        for (std::uint32_t x = 0; x < kSize; ++x) {
            const float v = target.load(x, y).x;
            if (v > 1.0f) ++over;
            if (x >= 97 && v != 1.0f) ++missing;  // 1 px margin around x = 96 for jitter-free z
            if (x <= 94 && v != 0.0f) ++leaked;
        }
    CHECK(over == 0);
    CHECK(missing == 0);
    CHECK(leaked == 0);
}

namespace {

// One probe: a thin triangle with one axis-aligned edge of the given kind placed `offset1024`
// px/1024 from the centre (cx, cy) of pixel (px, py); the other two edges pass 3-4 px away.
enum class EdgeKind { Left, Top, Right, Bottom };
struct Probe {
    EdgeKind kind;
    int offset1024;   // edge position minus the pixel centre, in 1/1024 px (x for Left/Right, y for Top/Bottom)
    float expected;   // hand-derived coverage of the probed pixel (derivation at the test case)
    const char* what;
};

} // namespace

TEST_CASE("fill rule: hand-derived coverage of edges on and beside pixel centres (ties and 16.8 rounding)") {
    // Derivation. Window coordinates c + k/1024 px with c a pixel centre (n + 1/2) are exact in
    // binary32 and through the 256x256 viewport (power-of-two scale). Snapping to 1/256 px
    // rounds to nearest, ties to even (D3D11 "Data Conversion Rules": float -> fixed point is
    // round-to-nearest-even; fixed_point.h): 256c = 256n + 128 is even, so
    //   k = +3 -> +4 (the nearest step is 1/256 px past the centre)   floor would give 0
    //   k = +2 -> 0  (a tie, to the even neighbour: the centre)        round-half-up gives +4
    //   k = +1 -> 0                                                     ceil would give +4
    //   k =  0 -> 0
    // Top-left rule (D3D11.3 §15.? "Triangle Rasterization Rules"): a sample exactly on a left
    // or top edge is covered, on a right or bottom edge it is not. So, for the probed pixel centre:
    //   left edge at snapped x:   covered <=> x <= c        top edge:    covered <=> y <= c
    //   right edge at snapped x:  covered <=> c <  x        bottom edge: covered <=> c <  y
    // which gives the expected column below. A flipped top or left tie fails the k = 0 and
    // k = +2 rows of that edge; floor snapping fails the k = +3 rows; ceil fails k = +1.
    const Probe probes[] = {
        {EdgeKind::Left, 0, 1.0f, "left edge on the centre (tie: covered)"},
        {EdgeKind::Left, 3, 0.0f, "left edge 3/1024 px right (snaps 1/256 px right: not covered)"},
        {EdgeKind::Left, 2, 1.0f, "left edge 2/1024 px right (a snapping tie, to even: on the centre)"},
        {EdgeKind::Left, -1, 1.0f, "left edge 1/1024 px left (snaps onto the centre)"},
        {EdgeKind::Top, 0, 1.0f, "top edge on the centre (tie: covered)"},
        {EdgeKind::Top, 3, 0.0f, "top edge 3/1024 px below (snaps 1/256 px below: not covered)"},
        {EdgeKind::Top, 2, 1.0f, "top edge 2/1024 px below (a snapping tie, to even: on the centre)"},
        {EdgeKind::Right, 0, 0.0f, "right edge on the centre (tie: not covered)"},
        {EdgeKind::Right, 1, 0.0f, "right edge 1/1024 px right (snaps onto the centre)"},
        {EdgeKind::Right, 3, 1.0f, "right edge 3/1024 px right (snaps 1/256 px right: covered)"},
        {EdgeKind::Bottom, 0, 0.0f, "bottom edge on the centre (tie: not covered)"},
        {EdgeKind::Bottom, 1, 0.0f, "bottom edge 1/1024 px below (snaps onto the centre)"},
        {EdgeKind::Bottom, 3, 1.0f, "bottom edge 3/1024 px below (snaps 1/256 px below: covered)"},
    };
    for (std::uint32_t tile : {8u, 64u}) {
        Device dev(DeviceConfig{tile, 2});
        Surface target(SurfaceDesc{kSize, kSize, Format::R32_FLOAT, 1});
        Mesh m;
        struct At { std::uint32_t x, y; };
        std::vector<At> probed;
        for (std::size_t i = 0; i < std::size(probes); ++i) {
            // Probed pixel: on a 16 px lattice, so tile borders (8 and 64 px) pass beside it.
            const std::uint32_t px = 8 + 16 * std::uint32_t(i % 15), py = 8 + 16 * std::uint32_t(i / 15) + (tile == 8 ? 0u : 7u);
            const float cx = float(px) + 0.5f, cy = float(py) + 0.5f, e = float(probes[i].offset1024) / 1024.0f;
            glm::vec2 v[3];  // clockwise in window space (y down)
            switch (probes[i].kind) {
            case EdgeKind::Left: v[0] = {cx + e, cy - 3}; v[1] = {cx + e + 4, cy}; v[2] = {cx + e, cy + 3}; break;
            case EdgeKind::Top: v[0] = {cx - 3, cy + e}; v[1] = {cx + 3, cy + e}; v[2] = {cx, cy + e + 4}; break;
            case EdgeKind::Right: v[0] = {cx + e - 4, cy}; v[1] = {cx + e, cy - 3}; v[2] = {cx + e, cy + 3}; break;
            case EdgeKind::Bottom: v[0] = {cx, cy + e - 4}; v[1] = {cx + 3, cy + e}; v[2] = {cx - 3, cy + e}; break;
            }
            for (const glm::vec2& p : v) {
                m.indices.push_back(std::uint32_t(m.vertices.size()));
                m.vertices.push_back({windowToClip(p.x, p.y, kSizeF, kSizeF)});
            }
            probed.push_back({px, py});
        }
        drawCount(dev, target, m);
        for (std::size_t i = 0; i < std::size(probes); ++i) {
            const float got = target.load(probed[i].x, probed[i].y).x;
            INFO("tile " << tile << " px, pixel (" << probed[i].x << "," << probed[i].y << "): " << probes[i].what << ": count " << got
                         << ", expected " << probes[i].expected);
            CHECK(got == probes[i].expected);
        }
    }
}

} // namespace tessera_test::raster_fill_rule_test
