// Self-test of the llvmpipe peer (tests/peer): checks that the D3D11 -> GL mapping in
// gl_peer.cpp really reproduces D3D conventions — top-left fill rule, row order, front face and
// culling, two-sided stencil (ops, compare direction, masks), depth clamp, occlusion counts.
// All geometry uses w = 1 and window coordinates on multiples of 1/2, so nothing rounds.
#include <doctest/doctest.h>

#include "gl_peer.h"

#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::conformance_gl_peer_selftest_test {

using namespace tessera::peer;

namespace {

// Frame size: powers of two so that window <-> NDC conversion is exact for half-pixel values.
constexpr int kWidth = 64;
constexpr int kHeight = 32;

GlPeer& sharedPeer() {
    static std::string why;
    static std::optional<GlPeer> peer = GlPeer::create(&why);
    if (!peer) FAIL("llvmpipe peer unavailable: " << why);
    return *peer;
}

struct PxWindow {
    float x, y;
};

// D3D viewport (0, 0, W, H, 0, 1): xWindow = (xNdc + 1) * W/2, yWindow = (1 - yNdc) * H/2 (y down).
// Inverted with w = 1: xClip = 2*xWindow/W - 1, yClip = 1 - 2*yWindow/H. For W = 64, H = 32
// and xWindow, yWindow multiples of 1/2 these are multiples of 1/64 and 1/32: exact in binary32.
std::array<float, 4> posClipFromWindow(PxWindow p, float zNdc) {
    return {2.0f * p.x / float(kWidth) - 1.0f, 1.0f - 2.0f * p.y / float(kHeight), zNdc, 1.0f};
}

void addTriangle(PeerDraw& draw, PxWindow a, PxWindow b, PxWindow c, float zNdc = 0.5f,
                 std::array<float, 4> color = {1, 1, 1, 1}) {
    draw.posClip.push_back(posClipFromWindow(a, zNdc));
    draw.posClip.push_back(posClipFromWindow(b, zNdc));
    draw.posClip.push_back(posClipFromWindow(c, zNdc));
    draw.colorPerTriangle.push_back(color);
}

PeerFrame makeFrame() {
    PeerFrame frame;
    frame.width = kWidth;
    frame.height = kHeight;
    return frame;
}

std::size_t at(int x, int y) { return static_cast<std::size_t>(y) * kWidth + static_cast<std::size_t>(x); }

// Counts pixels where ok(x, y) is false and describes the first one.
int countMismatches(const std::function<bool(int, int)>& ok, std::string* first) {
    int bad = 0;
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            if (!ok(x, y) && bad++ == 0) *first = "x=" + std::to_string(x) + " y=" + std::to_string(y);
        }
    }
    return bad;
}

// The reference triangle, clockwise in D3D's y-down window (top-left, top-right, bottom-left).
// Top edge (0,0)-(8,0) and left edge x = 0 contain no pixel centres; the hypotenuse
// x + y = 8 is a right edge, so the centres on it (x + y = 6 in pixel indices) are excluded:
// covered <=> x + y <= 6, 28 pixels, all in rows 0..6 (the top of the D3D image).
constexpr PxWindow kCwA{0, 0}, kCwB{8, 0}, kCwC{0, 8};
constexpr int kRefTrianglePixels = 28;
bool inRefTriangle(int x, int y) { return x + y <= 6; }

} // namespace

TEST_CASE("gl_peer: the renderer is llvmpipe") {
    const std::string name = sharedPeer().renderer();
    MESSAGE("GL_RENDERER = " << name);
    CHECK(name.find("llvmpipe") != std::string::npos);
}

TEST_CASE("gl_peer: square on pixel centres covers 10..19 x 10..19 exactly once (top-left rule)") {
    // Window corners (10.5,10.5)..(20.5,20.5): every boundary and the diagonal pass through
    // pixel centres. D3D top-left rule: the left (x = 10.5) and top (y = 10.5) edges are in,
    // right and bottom out, and the shared diagonal belongs to exactly one triangle.
    PeerFrame frame = makeFrame();
    PeerDraw draw;
    draw.additiveBlend = true;
    draw.depthEnable = false;
    draw.stencilEnable = true;   // stencil as a hit counter: IncrSat per covering triangle
    draw.front.passOp = draw.back.passOp = StencilOp::IncrSat;
    const std::array<float, 4> red{0.2f, 0, 0, 0};  // 0.2 * 255 = 51; two hits would give 102
    addTriangle(draw, {10.5f, 10.5f}, {20.5f, 10.5f}, {10.5f, 20.5f}, 0.5f, red);
    addTriangle(draw, {20.5f, 10.5f}, {20.5f, 20.5f}, {10.5f, 20.5f}, 0.5f, red);
    frame.draws.push_back(draw);
    const PeerImage img = sharedPeer().render(frame);

    const auto inside = [](int x, int y) { return x >= 10 && x <= 19 && y >= 10 && y <= 19; };
    std::string first;
    const int bad = countMismatches(
        [&](int x, int y) {
            const std::uint8_t hits = img.stencil[at(x, y)];
            const std::uint8_t red8 = img.rgba8[4 * at(x, y)];
            return inside(x, y) ? (hits == 1 && red8 == 51) : (hits == 0 && red8 == 0);
        },
        &first);
    INFO("first mismatch at " << first);
    CHECK(bad == 0);
    CHECK(img.samplesPassed == 100);
}

TEST_CASE("gl_peer: D3D row 0 is read-back row 0, hypotenuse excluded as a right edge") {
    PeerFrame frame = makeFrame();
    PeerDraw draw;
    addTriangle(draw, kCwA, kCwB, kCwC, 0.5f, {1, 0, 0, 1});
    frame.draws.push_back(draw);
    const PeerImage img = sharedPeer().render(frame);

    std::string first;
    const int bad = countMismatches(
        [&](int x, int y) {
            const bool covered = img.rgba8[4 * at(x, y)] == 255;
            const float depth = img.depth[at(x, y)];
            return inRefTriangle(x, y) ? (covered && depth == 0.5f) : (!covered && depth == 1.0f);
        },
        &first);
    INFO("first mismatch at " << first);
    CHECK(bad == 0);
    CHECK(img.rgba8[4 * at(0, 0)] == 255);               // top-left corner of the D3D image
    CHECK(img.rgba8[4 * at(0, kHeight - 1)] == 0);       // bottom row untouched
    CHECK(img.samplesPassed == kRefTrianglePixels);
}

TEST_CASE("gl_peer: front face and culling follow D3D (winding in y-down window space)") {
    // D3D11_RASTERIZER_DESC::FrontCounterClockwise = false: clockwise on the render target
    // (y down) is front. kCwA-kCwB-kCwC is clockwise there; the reversed order is CCW.
    for (const bool clockwise : {true, false}) {
        for (const bool frontCcw : {false, true}) {
            for (const Cull cull : {Cull::None, Cull::Front, Cull::Back}) {
                PeerFrame frame = makeFrame();
                PeerDraw draw;
                draw.cull = cull;
                draw.frontCounterClockwise = frontCcw;
                if (clockwise) addTriangle(draw, kCwA, kCwB, kCwC);
                else addTriangle(draw, kCwA, kCwC, kCwB);
                frame.draws.push_back(draw);
                const bool isFront = clockwise != frontCcw;
                const bool drawn = cull == Cull::None || (isFront ? cull != Cull::Front : cull != Cull::Back);
                const PeerImage img = sharedPeer().render(frame);
                INFO("clockwise=" << clockwise << " frontCCW=" << frontCcw << " cull=" << int(cull));
                CHECK(img.samplesPassed == (drawn ? kRefTrianglePixels : 0));
            }
        }
    }
}

namespace {

// A D3D-clockwise triangle on the left and a D3D-counter-clockwise one on the right, no
// culling, stencil on, depth off. Returns the stencil at one pixel inside each.
struct TwoSided {
    std::uint8_t atCw, atCcw, outside;
};
TwoSided renderTwoSided(const PeerDraw& state, std::uint8_t clearStencil) {
    PeerFrame frame = makeFrame();
    frame.clearStencil = clearStencil;
    PeerDraw draw = state;
    draw.cull = Cull::None;
    draw.depthEnable = false;
    draw.stencilEnable = true;
    addTriangle(draw, {0, 0}, {8, 0}, {0, 8});      // clockwise on screen
    addTriangle(draw, {32, 0}, {32, 8}, {40, 0});   // counter-clockwise on screen
    frame.draws.push_back(draw);
    const PeerImage img = sharedPeer().render(frame);
    return {img.stencil[at(1, 1)], img.stencil[at(33, 1)], img.stencil[at(20, 20)]};
}

} // namespace

TEST_CASE("gl_peer: two-sided stencil ops land on D3D front/back faces") {
    struct Case {
        std::uint8_t clear;
        StencilOp frontPass, backPass;
        std::uint8_t ref;
        bool frontCcw;
        std::uint8_t expectCw, expectCcw;
    };
    const Case cases[] = {
        {5, StencilOp::IncrSat, StencilOp::DecrSat, 0, false, 6, 4},
        {5, StencilOp::IncrSat, StencilOp::DecrSat, 0, true, 4, 6},   // front = CCW now
        {255, StencilOp::IncrSat, StencilOp::Incr, 0, false, 255, 0},  // saturate vs wrap
        {0, StencilOp::Decr, StencilOp::DecrSat, 0, false, 255, 0},    // wrap vs saturate
        {0x0F, StencilOp::Invert, StencilOp::Replace, 0x3C, false, 0xF0, 0x3C},
        {7, StencilOp::Zero, StencilOp::Keep, 0, false, 0, 7},
    };
    for (const Case& c : cases) {
        PeerDraw state;
        state.frontCounterClockwise = c.frontCcw;
        state.stencilRef = c.ref;
        state.front.passOp = c.frontPass;
        state.back.passOp = c.backPass;
        const TwoSided got = renderTwoSided(state, c.clear);
        INFO("clear=" << int(c.clear) << " front=" << int(c.frontPass) << " back=" << int(c.backPass)
                      << " frontCCW=" << c.frontCcw);
        CHECK(int(got.atCw) == int(c.expectCw));
        CHECK(int(got.atCcw) == int(c.expectCcw));
        CHECK(int(got.outside) == int(c.clear));
    }
}

TEST_CASE("gl_peer: stencil compare is (ref & readMask) FUNC (stored & readMask)") {
    struct Case {
        std::uint8_t stored, ref, readMask;
        Cmp func;
        bool pass;
    };
    const Case cases[] = {
        {1, 2, 0xFF, Cmp::Greater, true},       // 2 > 1: ref on the left
        {1, 2, 0xFF, Cmp::Less, false},
        {3, 0x12, 0x0F, Cmp::Greater, false},   // 0x02 > 0x03
        {3, 0x12, 0x0F, Cmp::Less, true},
        {3, 0x13, 0x0F, Cmp::Equal, true},
        {3, 0x13, 0xFF, Cmp::Equal, false},
        {5, 5, 0xFF, Cmp::GreaterEqual, true},
        {5, 4, 0xFF, Cmp::GreaterEqual, false},
        {5, 6, 0xFF, Cmp::LessEqual, false},
        {5, 6, 0xFF, Cmp::NotEqual, true},
        {5, 5, 0xFF, Cmp::Never, false},
        {5, 5, 0xFF, Cmp::Always, true},
    };
    for (const Case& c : cases) {
        PeerDraw state;
        state.stencilRef = c.ref;
        state.stencilReadMask = c.readMask;
        state.front.func = state.back.func = c.func;
        state.front.passOp = state.back.passOp = StencilOp::IncrSat;
        state.front.failOp = state.back.failOp = StencilOp::Zero;
        const TwoSided got = renderTwoSided(state, c.stored);
        const int expect = c.pass ? c.stored + 1 : 0;
        INFO("stored=" << int(c.stored) << " ref=" << int(c.ref) << " mask=" << int(c.readMask)
                       << " func=" << int(c.func));
        CHECK(int(got.atCw) == expect);
        CHECK(int(got.atCcw) == expect);
    }
}

TEST_CASE("gl_peer: stencil write mask and depth-fail op") {
    PeerDraw masked;
    masked.stencilRef = 0x0F;
    masked.stencilWriteMask = 0x3C;
    masked.front.passOp = masked.back.passOp = StencilOp::Replace;
    const TwoSided got = renderTwoSided(masked, 0xF0);
    CHECK(int(got.atCw) == 0xCC);   // (0xF0 & ~0x3C) | (0x0F & 0x3C)
    CHECK(int(got.atCcw) == 0xCC);

    for (const Cmp depthFunc : {Cmp::Less, Cmp::Greater}) {
        PeerFrame frame = makeFrame();
        frame.clearDepth = 0.25f;
        frame.clearStencil = 3;
        PeerDraw draw;
        draw.depthFunc = depthFunc;   // triangle z = 0.5 vs stored 0.25
        draw.stencilEnable = true;
        draw.stencilRef = 9;
        draw.front.depthFailOp = StencilOp::Replace;
        draw.front.passOp = StencilOp::IncrSat;
        addTriangle(draw, kCwA, kCwB, kCwC);
        frame.draws.push_back(draw);
        const PeerImage img = sharedPeer().render(frame);
        const bool depthPasses = depthFunc == Cmp::Greater;
        INFO("depthFunc=" << int(depthFunc));
        CHECK(int(img.stencil[at(1, 1)]) == (depthPasses ? 4 : 9));
        CHECK(img.depth[at(1, 1)] == (depthPasses ? 0.5f : 0.25f));
        CHECK(img.samplesPassed == (depthPasses ? kRefTrianglePixels : 0));
    }
}

TEST_CASE("gl_peer: depthClipEnable=false clamps depth, true clips") {
    struct Case {
        float zNdc;
        bool depthClip;
        bool drawn;
        float expectDepth;
    };
    const Case cases[] = {
        {-0.5f, false, true, 0.0f},
        {1.5f, false, true, 1.0f},
        {-0.5f, true, false, 0.5f},
        {1.5f, true, false, 0.5f},
        {0.25f, true, true, 0.25f},
    };
    for (const Case& c : cases) {
        PeerFrame frame = makeFrame();
        frame.clearDepth = 0.5f;   // distinguishable from both clamp values
        PeerDraw draw;
        draw.depthClipEnable = c.depthClip;
        draw.depthFunc = Cmp::Always;
        addTriangle(draw, kCwA, kCwB, kCwC, c.zNdc, {0, 1, 0, 1});
        frame.draws.push_back(draw);
        const PeerImage img = sharedPeer().render(frame);
        INFO("z=" << c.zNdc << " depthClip=" << c.depthClip);
        std::string first;
        const int bad = countMismatches(
            [&](int x, int y) {
                const bool covered = img.rgba8[4 * at(x, y) + 1] == 255;
                const bool expectCovered = c.drawn && inRefTriangle(x, y);
                const float expectDepth = expectCovered ? c.expectDepth : 0.5f;
                return covered == expectCovered && img.depth[at(x, y)] == expectDepth;
            },
            &first);
        INFO("first mismatch at " << first);
        CHECK(bad == 0);
        CHECK(img.samplesPassed == (c.drawn ? kRefTrianglePixels : 0));
    }
}

TEST_CASE("gl_peer: colour write mask off still counts samples and writes depth") {
    PeerFrame frame = makeFrame();
    frame.clearColor = {0, 0, 1, 1};
    PeerDraw draw;
    draw.colorWrite = false;
    addTriangle(draw, kCwA, kCwB, kCwC, 0.5f, {1, 0, 0, 1});
    frame.draws.push_back(draw);
    const PeerImage img = sharedPeer().render(frame);
    CHECK(int(img.rgba8[4 * at(1, 1)]) == 0);
    CHECK(int(img.rgba8[4 * at(1, 1) + 2]) == 255);
    CHECK(img.depth[at(1, 1)] == 0.5f);
    CHECK(img.samplesPassed == kRefTrianglePixels);
}

TEST_CASE("gl_peer: timeRender returns a positive median") {
    PeerFrame frame = makeFrame();
    PeerDraw draw;
    addTriangle(draw, kCwA, kCwB, kCwC);
    frame.draws.push_back(draw);
    const double seconds = sharedPeer().timeRender(frame, 3);
    CHECK(std::isfinite(seconds));
    CHECK(seconds > 0.0);
    CHECK(seconds < 1.0);
}

} // namespace tessera_test::conformance_gl_peer_selftest_test
