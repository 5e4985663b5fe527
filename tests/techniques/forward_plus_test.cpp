// The `forward-plus` technique on small scenes built in memory: options and errors, the
// faithful overflow of the demo's light lists (local 1024, global numTiles * 200) with its
// counters and its effect on the image, the unbounded lists that drop nothing, the equality
// with forward, and determinism of every culling output at 1, 2 and 7 threads.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include <tessera/errors/input_error.h>
#include <tessera/techniques/forward_plus.h>
#include <tessera/techniques/technique.h>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_forward_plus_test {

using namespace tessera;

namespace {

using test::sameBytes;
using test::quad;

// 64 x 48 px with 16 px tiles: 4 x 3 = 12 tiles, so the demo's global lists hold 12 * 200 = 2400
// entries each.
constexpr std::uint32_t kWidth = 64, kHeight = 48;

// The room of support/room_scene.h with the wall lifted off the floor (no shared depths).
test::TestScene makeScene(const std::vector<Light>& lights) { return test::makeScene(lights, {0.0f, 3.0f, 8.0f}, 0.05f); }

Light pointLight(glm::vec3 position, float range, glm::vec3 color) {
    Light l;
    l.type = LightType::Point;
    l.positionWorld = position;
    l.range = range;
    l.color = color;
    return l;
}

// Lights beside the camera (eye (0, 3, 8)) whose spheres cross the eye's plane view z = 0, where
// the projected bounds of a sphere stop being monotone: an earlier binning dropped
// transparent-list tiles of such lights (found by bench/culling_bench.cpp with 16384 small
// lights in Sponza: 106.86 vs 108.91 lights per tile).
void appendLightsBesideCamera(std::vector<Light>& lights) {
    for (int k = 0; k < 24; ++k) {
        const float a = float(k) * 0.9f;
        lights.push_back(pointLight({2.5f * std::cos(a), 3.0f + 1.5f * std::sin(a), 8.0f + float(k % 5 - 2) * 0.5f},
                                    1.0f + float(k % 4) * 0.5f, {1.0f, 1.0f, 1.0f}));
    }
}

// Light 0 is enabled but lies 10^4 units away with range 1: it reaches no pixel, so wherever the
// pixel shader reads index 0 from an overflowed list it adds nothing. Lights 1..n are dim point
// lights with range 1000 around the room: each covers the whole view, so every tile lists every
// one of them (opaque and transparent).
std::vector<Light> overflowLights(std::size_t n) {
    std::vector<Light> lights{pointLight({1.0e4f, 0.0f, 0.0f}, 1.0f, {1.0f, 1.0f, 1.0f})};
    for (std::size_t i = 1; i <= n; ++i) {
        const float a = float(i) * 0.37f;
        lights.push_back(pointLight({6.0f * std::cos(a), 2.0f + float(i % 5), 6.0f * std::sin(a) - 2.0f}, 1000.0f,
                                    {0.0004f * float(i % 7), 0.0003f, 0.0005f}));
    }
    return lights;
}

using test::Rendered;

// 64 x 48 px renders of the room.
void renderRoom(const test::TestScene& scene, const std::string& technique, const nlohmann::json& options, Rendered& out,
                std::uint32_t threads = 2, Precision precision = Precision::Exact) {
    test::render(scene, technique, options, out, precision, threads, {kWidth, kHeight});
}

bool samePixel(const Surface& a, const Surface& b, std::uint32_t x, std::uint32_t y) {
    return std::memcmp(a.texel(x, y), b.texel(x, y), a.bytesPerTexel()) == 0;
}

// Pixels of tile (tx, ty) (16 px tiles) where a and b differ.
int tileDifferences(const Surface& a, const Surface& b, std::uint32_t tx, std::uint32_t ty) {
    int n = 0;
    for (std::uint32_t y = ty * 16; y < std::min(kHeight, ty * 16 + 16); ++y)
        for (std::uint32_t x = tx * 16; x < std::min(kWidth, tx * 16 + 16); ++x) n += samePixel(a, b, x, y) ? 0 : 1;
    return n;
}

std::string errorOf(const nlohmann::json& options, Precision precision = Precision::Exact) {
    Rendered r;
    try {
        renderRoom(makeScene(overflowLights(2)), "forward-plus", options, r, 2, precision);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("forward-plus: options are validated with the key path") {
    CHECK(errorOf({{"tileSize", 12}}).find("/options/tileSize") != std::string::npos);
    CHECK(errorOf({{"tileSize", "16"}}).find("/options/tileSize") != std::string::npos);
    CHECK(errorOf({{"lightLists", "big"}}).find("/options/lightLists") != std::string::npos);
    CHECK(errorOf({{"coneTest", "exact"}}).find("/options/coneTest") != std::string::npos);
    CHECK(errorOf({{"culling", "fast"}}).find("/options/culling") != std::string::npos);
    CHECK(errorOf({{"bogus", 1}}).find("/options/bogus") != std::string::npos);
    CHECK(errorOf({}, Precision::Reference).empty());
    CHECK(errorOf({}, Precision::Fast).empty());
    CHECK(errorOf({{"tileSize", 8}, {"lightLists", "unbounded"}, {"coneTest", "corrected"}, {"culling", "brute"}}).empty());
}

TEST_CASE("forward-plus: the demo's lists overflow faithfully and the counters say by how much") {
    // 1100 lights that every tile lists (plus light 0, listed nowhere): each tile's count is 1100.
    // Local lists keep 1024, so every one of the 12 tiles drops 1100 - 1024 = 76 appends:
    // tilesOverLocal 12, droppedLocal 12 * 76 = 912. Offsets in row-major order are 1100 k; the
    // global list holds 12 * 200 = 2400: tiles 0 and 1 fit (0..2199), tile 2 (2200..3299) keeps
    // 200 entries and drops 900, tiles 3..11 drop all 1100: tilesOverGlobal 10,
    // droppedGlobal 900 + 9 * 1100 = 10800, requested 12 * 1100 = 13200.
    const test::TestScene scene = makeScene(overflowLights(1100));
    Rendered plus;
    renderRoom(scene, "forward-plus", {{"projection", "d3d"}}, plus);
    const ForwardPlusCounters c = readForwardPlusCounters(plus.registry);
    for (const LightListCounters* l : {&c.opaque, &c.transparent}) {
        CHECK(l->requested == 13200);
        CHECK(l->capacity == 2400);
        CHECK(l->tilesOverLocal == 12);
        CHECK(l->droppedLocal == 912);
        CHECK(l->tilesOverGlobal == 10);
        CHECK(l->droppedGlobal == 10800);
        CHECK(l->maxTileCount == 1100);
        CHECK(l->nonEmptyTiles == 12);
    }
    // The grid keeps the full count; the copy writes 0 for the 76 entries past the local list.
    const Surface& grid = plus.get("lightgrid.opaque");
    const Surface& list = plus.get("lightindex.opaque");
    const auto entry = [&](std::uint32_t e) { return list.loadUint(e % list.width(), e / list.width()).x; };
    CHECK(grid.loadUint(1, 0).x == 1100);
    CHECK(grid.loadUint(1, 0).y == 1100);
    CHECK(entry(1100) == 1);      // tile 1's list starts with light 1 (light 0 is culled)
    CHECK(entry(1100 + 1023) == 1024);
    CHECK(entry(1100 + 1024) == 0);  // past the local list

    // The image: tiles 0 and 1 are lit by lights 1..1024 (then light 0 76 times, which reaches
    // nothing): forward with lights 0..1024. Tile 2 by the 200 entries that fit: forward with
    // lights 0..200. Tiles 3..11 read index 0 everywhere: lit by nothing, the unlit image (the
    // article's black tiles).
    std::vector<Light> first1025(scene.scene.lights.begin(), scene.scene.lights.begin() + 1025);
    std::vector<Light> first201(scene.scene.lights.begin(), scene.scene.lights.begin() + 201);
    Rendered forward1025, forward201, unlit;
    renderRoom(makeScene(first1025), "forward", {{"projection", "d3d"}}, forward1025);
    renderRoom(makeScene(first201), "forward", {{"projection", "d3d"}}, forward201);
    renderRoom(makeScene({}), "forward", {{"projection", "d3d"}}, unlit);
    const Surface& back = plus.get(kBackBufferName);
    CHECK(tileDifferences(back, forward1025.get(kBackBufferName), 0, 0) == 0);
    CHECK(tileDifferences(back, forward1025.get(kBackBufferName), 1, 0) == 0);
    CHECK(tileDifferences(back, forward201.get(kBackBufferName), 2, 0) == 0);
    for (std::uint32_t t = 3; t < 12; ++t) CHECK(tileDifferences(back, unlit.get(kBackBufferName), t % 4, t / 4) == 0);
    // ... and the lights do change those tiles (otherwise the checks above say little).
    CHECK(tileDifferences(unlit.get(kBackBufferName), forward1025.get(kBackBufferName), 3, 0) > 200);
}

TEST_CASE("forward-plus: unbounded lists drop nothing and the image equals forward's") {
    const test::TestScene scene = makeScene(overflowLights(1100));
    Rendered plus, forward;
    renderRoom(scene, "forward-plus", {{"projection", "d3d"}, {"lightLists", "unbounded"}}, plus);
    renderRoom(scene, "forward", {{"projection", "d3d"}}, forward);
    const ForwardPlusCounters c = readForwardPlusCounters(plus.registry);
    for (const LightListCounters* l : {&c.opaque, &c.transparent}) {
        CHECK(l->requested == 13200);  // 12 tiles x 1100 lights
        CHECK(l->capacity >= l->requested);
        CHECK(l->tilesOverLocal == 0);
        CHECK(l->droppedLocal == 0);
        CHECK(l->tilesOverGlobal == 0);
        CHECK(l->droppedGlobal == 0);
    }
    CHECK(sameBytes(plus.get(kBackBufferName), forward.get(kBackBufferName)));
}

TEST_CASE("forward-plus: light grid, index lists, frustums and heat map are identical at 1, 2 and 7 threads") {
    // 400 small lights spread over the room (ranges 0.5..2.5): tiles get different counts, so
    // the row-major offsets depend on every tile before them.
    std::vector<Light> lights;
    for (int i = 0; i < 400; ++i) {
        const float a = float(i) * 2.3999632f;  // golden angle, rad
        const float r = 0.5f + 9.0f * float(i) / 400.0f;
        Light l = pointLight({r * std::cos(a), 0.3f + float(i % 9) * 0.5f, r * std::sin(a) - 2.0f}, 0.5f + float(i % 5) * 0.5f,
                             {1.0f, 0.5f, 0.25f});
        if (i % 3 == 0) {
            l.type = LightType::Spot;
            l.directionWorld = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
            l.spotHalfAngleDeg = 20.0f + float(i % 40);
        }
        lights.push_back(l);
    }
    appendLightsBesideCamera(lights);
    const test::TestScene scene = makeScene(lights);
    for (const int tile : {8, 16, 32}) {
        CAPTURE(tile);
        Rendered one, two, seven;
        const nlohmann::json options{{"tileSize", tile}};
        renderRoom(scene, "forward-plus", options, one, 1);
        renderRoom(scene, "forward-plus", options, two, 2);
        renderRoom(scene, "forward-plus", options, seven, 7);
        for (const char* name : {"frustums", "lightgrid.opaque", "lightgrid.transparent", "lightindex.opaque",
                                 "lightindex.transparent", "heatmap", "lightlist.counters", "backbuffer"}) {
            CAPTURE(name);
            CHECK(sameBytes(one.get(name), two.get(name)));
            CHECK(sameBytes(one.get(name), seven.get(name)));
        }
        const ForwardPlusCounters c = readForwardPlusCounters(one.registry);
        CHECK(c.opaque.nonEmptyTiles > 0);
        CHECK(c.opaque.requested > 0);
    }
}

TEST_CASE("forward-plus: binned culling gives the brute-force loop's lists") {
    std::vector<Light> lights;
    for (int i = 0; i < 300; ++i) {
        const float a = float(i) * 0.7f;
        Light l = pointLight({7.0f * std::cos(a), float(i % 11) * 0.4f - 0.5f, 9.0f * std::sin(a) - 1.0f}, 0.3f + float(i % 13) * 0.4f,
                             {1.0f, 1.0f, 1.0f});
        if (i % 2 == 0) {
            l.type = LightType::Spot;
            l.directionWorld = glm::normalize(glm::vec3(std::sin(a), -0.5f, std::cos(a)));
            l.spotHalfAngleDeg = 10.0f + float(i % 60);
        }
        lights.push_back(l);
    }
    appendLightsBesideCamera(lights);
    // Spots around the eye (and crossing its plane), wide and narrow, in every direction: the
    // binned path decides most side planes from the cone's bounding sphere and the near, far and
    // min planes from per-light terms (forward_plus_detail.h SpotCullTerms); the brute path runs
    // coneInsideFrustum itself.
    for (int k = 0; k < 80; ++k) {
        const float a = float(k) * 1.3f;
        Light l = pointLight({3.0f * std::cos(a), 3.0f + 2.0f * std::sin(a * 0.7f), 6.0f + float(k % 9) * 0.6f},
                             0.5f + float(k % 12) * 0.5f, {1.0f, 1.0f, 1.0f});
        l.type = LightType::Spot;
        l.directionWorld = glm::normalize(glm::vec3(std::sin(a * 2.1f), std::cos(a * 1.7f), std::sin(a * 0.9f) + 0.01f));
        l.spotHalfAngleDeg = 2.0f + float(k * 7 % 87);
        lights.push_back(l);
    }
    const test::TestScene scene = makeScene(lights);
    for (const std::string coneTest : {"demo", "corrected"}) {
        for (const int tile : {8, 16, 32}) {
            CAPTURE(coneTest);
            CAPTURE(tile);
            Rendered binned, brute;
            renderRoom(scene, "forward-plus", {{"tileSize", tile}, {"coneTest", coneTest}}, binned);
            renderRoom(scene, "forward-plus", {{"tileSize", tile}, {"coneTest", coneTest}, {"culling", "brute"}}, brute);
            for (const char* name : {"lightgrid.opaque", "lightgrid.transparent", "lightindex.opaque", "lightindex.transparent"}) {
                CAPTURE(name);
                CHECK(sameBytes(binned.get(name), brute.get(name)));
            }
            CHECK(readForwardPlusCounters(binned.registry).transparent.requested > 0);
        }
    }
}

TEST_CASE("forward-plus: heat-map gradient: 1-10 lights blue, 20-30 green, 50 and more red") {
    // u = n / 50, texel space t = 5u - 0.5 over blue, cyan, green, yellow, red (forward_plus.h).
    CHECK(forwardPlusHeatMapColor(1) == glm::vec4(0.0f, 0.0f, 1.0f, 1.0f));  // t = -0.4, clamped to texel 0
    const glm::vec4 ten = forwardPlusHeatMapColor(10);                      // t = 0.5: half blue, half cyan
    CHECK(ten.z == 1.0f);
    CHECK(ten.y == doctest::Approx(0.5f));
    CHECK(forwardPlusHeatMapColor(25) == glm::vec4(0.0f, 1.0f, 0.0f, 1.0f));  // t = 2: green
    CHECK(forwardPlusHeatMapColor(50) == glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));  // t = 4.5, clamped to red
    CHECK(forwardPlusHeatMapColor(5000) == glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
}

} // namespace tessera_test::techniques_forward_plus_test
