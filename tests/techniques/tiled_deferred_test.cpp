// The `tiled-deferred` technique (Intel 2010 sample) on a small opaque scene
// built in memory: Intel's shading and G-buffer math by hand, the 3dgep comparison mode against
// forward and deferred bit for bit, and each option's faithful-vs-corrected difference (tile
// planes, normal storage, list capacity, tile size).
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <string>

#include <glm/gtc/quaternion.hpp>

#include <tessera/errors/input_error.h>
#include <tessera/techniques/technique.h>

#include "support/room_scene.h"
#include <tessera/techniques/tiled_deferred.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_tiled_deferred_test {

using namespace tessera;
using namespace tessera::test;

namespace {

// A tile's list: R32G32_UINT grid of (offset, stored count) into the R32_UINT indices.
std::vector<std::uint32_t> tileList(BufferRegistry& reg, std::uint32_t tx, std::uint32_t ty) {
    const Surface& grid = reg.get("tiles.grid");
    const Surface& indices = reg.get("tiles.lightIndices");
    const glm::uvec4 g = grid.loadUint(tx, ty);
    std::vector<std::uint32_t> list;
    const std::uint32_t row = indices.width();
    for (std::uint32_t k = 0; k < g.y; ++k) {
        const std::uint32_t at = g.x + k;
        list.push_back(indices.loadUint(at % row, at / row).x);
    }
    return list;
}

std::uint32_t appended(BufferRegistry& reg, std::uint32_t tx, std::uint32_t ty) {
    return reg.get("tiles.lightCount").loadUint(tx, ty).x;
}

const nlohmann::json kDgepExact = {{"shading", "3dgep"}, {"gbuffer", "float"}, {"position", "gbuffer"}};

std::string errorOf(const nlohmann::json& options) {
    Rendered r;
    try {
        render(makeScene(defaultLights()), "tiled-deferred", options, r);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("tiled-deferred: Intel's linstep and AccumulateBRDF by hand") {
    // linstep(end, begin, d) = saturate((d - end) / (begin - end)), end 10, begin 8:
    CHECK(intelLinstep(10.0f, 8.0f, 9.0f) == 0.5f);   // (9 - 10) / (8 - 10) = 0.5 exactly
    CHECK(intelLinstep(10.0f, 8.0f, 8.0f) == 1.0f);   // at begin: full
    CHECK(intelLinstep(10.0f, 8.0f, 7.0f) == 1.0f);   // 1.5 saturated
    CHECK(intelLinstep(10.0f, 8.0f, 10.0f) == 0.0f);  // at end: none
    // Left-handed view: P = (0, 0, 5) facing the eye (n = (0, 0, -1)), light at (0, 0, 3), d = 2:
    // attenuation 1; L = (0, 0, -1), N.L = 1; r = reflect(L, n) = L - 2 (n.L) n = (0, 0, 1);
    // V = normalize(P) = (0, 0, 1), R.V = 1, 1^25 = 1; lit = 0.5 * (1 + 0.9 * 1) = 0.95.
    IntelPointLight light{{0.0f, 0.0f, 3.0f}, 8.0f, {1.0f, 1.0f, 1.0f}, 10.0f};
    glm::vec3 lit(0.0f);
    intelAccumulateBrdf({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, -1.0f}, glm::vec3(0.5f), kIntelSpecularAmount, kIntelSpecularPower, light, lit);
    CHECK(lit.x == doctest::Approx(0.95).epsilon(1e-6));
    // The same light 9 units away (d = 9 in [begin, end)): attenuation 0.5, N.L = 1, R.V = 1:
    // lit = 0.5 * (0.5 + 0.9 * 0.5) = 0.475.
    light.positionView = {0.0f, 0.0f, -4.0f};
    lit = glm::vec3(0.0f);
    intelAccumulateBrdf({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, -1.0f}, glm::vec3(0.5f), kIntelSpecularAmount, kIntelSpecularPower, light, lit);
    CHECK(lit.x == doctest::Approx(0.475).epsilon(1e-6));
    // d = end exactly: `distanceToLight < attenuationEnd` fails, nothing is added.
    light.positionView = {0.0f, 0.0f, -5.0f};
    lit = glm::vec3(0.0f);
    intelAccumulateBrdf({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, -1.0f}, glm::vec3(0.5f), kIntelSpecularAmount, kIntelSpecularPower, light, lit);
    CHECK(lit.x == 0.0f);
    // A light behind the surface (N.L < 0) adds nothing even in range.
    light.positionView = {0.0f, 0.0f, 6.0f};
    lit = glm::vec3(0.0f);
    intelAccumulateBrdf({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, -1.0f}, glm::vec3(0.5f), kIntelSpecularAmount, kIntelSpecularPower, light, lit);
    CHECK(lit.x == 0.0f);
}

TEST_CASE("tiled-deferred: Intel's view position from depth and the spheremap normal round trip") {
    // D3DXMatrixPerspectiveFovLH-like: _11 = _22 = 1, n = 1, f = 101: _33 = f / (f - n) = 1.01,
    // _43 = -f n / (f - n) = -1.01. Depth z = 0.5: viewZ = -1.01 / (0.5 - 1.01) = 1.98039...
    glm::mat4 p(0.0f);
    p[0][0] = 1.0f;
    p[1][1] = 1.0f;
    p[2][2] = 1.01f;
    p[2][3] = 1.0f;
    p[3][2] = -1.01f;
    const glm::vec3 pos = positionViewFromDepthIntel(1, 0, 0.5f, {4, 2}, p);
    // Pixel (1, 0) of 4 x 2: positionScreen = (1.5 * 0.5 - 1, 0.5 * -1 + 1) = (-0.25, 0.5).
    const float z = -1.01f / (0.5f - 1.01f);
    CHECK(pos.z == z);
    CHECK(pos.x == -0.25f * z);
    CHECK(pos.y == 0.5f * z);
    // projectionLhFromRh: the RH matrix's third column negated (_33 = -m[2][2], _34 = 1).
    glm::mat4 rh(0.0f);
    rh[2][2] = -1.01f;
    rh[2][3] = -1.0f;
    rh[3][2] = -1.01f;
    const glm::mat4 lh = projectionLhFromRh(rh);
    CHECK(lh[2][2] == 1.01f);
    CHECK(lh[2][3] == 1.0f);
    CHECK(lh[3][2] == -1.01f);

    // n = (0, 0, -1) (facing the eye): p = sqrt(0 + 0 + 2^2) = 2, e = (0.5, 0.5) exactly in half;
    // f = 0.25 + 0.25, m = sqrt(1) = 1, n = (0, 0, 3 - 4): exact.
    const glm::vec3 facing = intelSpheremapRoundTrip({0.0f, 0.0f, -1.0f});
    CHECK(facing == glm::vec3(0.0f, 0.0f, -1.0f));
    // n = (0.6, 0, -0.8): e.x = 0.6 / sqrt(3.6) * 0.5 + 0.5 = 0.6581139 -> half 1348 * 2^-11 =
    // 0.65820313 (ulp 2^-11 in [0.5, 1)); |de| <= 2^-12 moves n by ~4 |de| sqrt(...) < 1e-3.
    const glm::vec3 tilted = intelSpheremapRoundTrip({0.6f, 0.0f, -0.8f});
    CHECK(tilted.x == doctest::Approx(0.6).epsilon(1e-3));
    CHECK(tilted.z == doctest::Approx(-0.8).epsilon(1e-3));
    CHECK(tilted.x != 0.6f);  // the half storage shows
}

TEST_CASE("tiled-deferred: 3dgep shading with float targets equals forward (d3d) bit for bit at every tile size") {
    // The tile list holds every light that reaches a pixel of the tile, in ascending index (the
    // scene order forward loops in); the lights it leaves out add exactly 0 in forward (out of
    // range: skipped; at d = range: attenuation 0). So DoLighting over the list sums the same
    // values in the same order, and the compose is forward's expression.
    const TestScene t = makeScene(defaultLights());
    Rendered forward, unlit;
    render(t, "forward", {{"projection", "d3d"}}, forward);
    render(makeScene({}), "forward", {{"projection", "d3d"}}, unlit);
    const Difference lit = compareRgba8(forward.back(), unlit.back());
    CHECK(lit.share() > 0.5);  // the lights do reach the image
    for (const int tileSize : {8, 16, 32}) {
        nlohmann::json o = kDgepExact;
        o["tileSize"] = tileSize;
        Rendered tiled;
        render(t, "tiled-deferred", o, tiled);
        const Difference d = compareRgba8(forward.back(), tiled.back());
        MESSAGE("tile " << tileSize << ": max " << d.maxCodes << " codes on " << d.pixelsDiffering << " pixels");
        CHECK(sameBytes(forward.back(), tiled.back()));
    }
}

TEST_CASE("tiled-deferred: 3dgep shading with the demo G-buffer equals deferred's light-sum compose bit for bit") {
    // Both read RGBA8 RT0-RT2 with the packed specular power and an interpolated P, sum the
    // lights in scene order in binary32 (deferred: ONE+ONE blends into float targets starting
    // from 0) and compose forward's expression: the same bits.
    const TestScene t = makeScene(defaultLights());
    Rendered deferred, tiled;
    render(t, "deferred",
           {{"projection", "d3d"}, {"position", "gbuffer"}, {"accumulate", "lighting"}, {"lightVolumes", "circumscribed"},
            {"volumeRotation", "robust"}},
           deferred);
    render(t, "tiled-deferred", {{"shading", "3dgep"}, {"position", "gbuffer"}}, tiled);
    const Difference d = compareRgba8(deferred.back(), tiled.back());
    MESSAGE("deferred (demo G-buffer, light sums) vs tiled-deferred 3dgep: max " << d.maxCodes << " codes on "
                                                                                << d.pixelsDiffering << " pixels");
    CHECK(sameBytes(deferred.back(), tiled.back()));
}

TEST_CASE("tiled-deferred: Intel 2010 planes keep a superset of the tile-frustum note's lists, the image is the same") {
    // c4 + c1 >= 0 admits tx >= g - 1 where c1 >= 0 admits tx >= g (tile_frustum.h): the 2010
    // frustum contains the note's, so every list is a superset; the extra lights are out of range
    // of every pixel of the tile and AccumulateBRDF adds nothing for them.
    std::vector<Light> lights = defaultLights();
    for (int i = 0; i < 12; ++i)  // small lights spread over the floor: per-tile lists differ
        lights.push_back(makeLight(LightType::Point, {-6.0f + float(i), 0.5f, -3.0f + 0.5f * float(i % 5)}, {0, 0, -1}, 1.2f,
                                   {0.5f, 0.5f, 0.5f}));
    const TestScene t = makeScene(lights);
    Rendered sample, seed;
    render(t, "tiled-deferred", nlohmann::json::object(), sample);
    render(t, "tiled-deferred", {{"tilePlanes", "tile"}}, seed);
    const Surface& grid = sample.registry.get("tiles.grid");
    int larger = 0, subsetViolations = 0;
    std::uint64_t sumSample = 0, sumSeed = 0;
    for (std::uint32_t ty = 0; ty < grid.height(); ++ty)
        for (std::uint32_t tx = 0; tx < grid.width(); ++tx) {
            const std::vector<std::uint32_t> a = tileList(sample.registry, tx, ty), b = tileList(seed.registry, tx, ty);
            for (const std::uint32_t i : b) subsetViolations += std::find(a.begin(), a.end(), i) == a.end();
            larger += a.size() > b.size();
            sumSample += a.size();
            sumSeed += b.size();
        }
    MESSAGE("lights per tile: sample2010 " << double(sumSample) / double(grid.width() * grid.height()) << ", tile "
                                          << double(sumSeed) / double(grid.width() * grid.height()) << "; " << larger
                                          << " tiles have more with sample2010");
    CHECK(subsetViolations == 0);
    CHECK(larger > 0);
    CHECK(sameBytes(sample.back(), seed.back()));
    CHECK(!sameBytes(sample.registry.get("heatmap"), seed.registry.get("heatmap")));
}

TEST_CASE("tiled-deferred: Intel's spheremap half normals differ from float normals by a few codes") {
    // Bound: e is rounded to half (|de| <= 2^-12 for e in [0.5, 1), 2^-13 below); n.xy = m (4e - 2)
    // and n.z = 3 - 8f move by at most ~8 |de| (m <= 1, |df/de| <= 1), so |dn| <= 2^-9 = 0.002.
    // N.L moves by <= 0.002 and R.V = x by <= 3 |dn| <= 0.006; x^25 moves by <= 25 x^24 * 0.006
    // <= 0.15 only near x = 1 (specular highlights). With albedo <= 1, color <= 1 per light and
    // 4 lights the 8-bit image moves by at most 255 * (4 * 0.002 + 4 * 0.9 * 0.15) ~ 140 codes in
    // theory; the smooth floor and wall here measure far less (printed).
    const TestScene t = makeScene(defaultLights());
    Rendered spheremap, plain;
    render(t, "tiled-deferred", nlohmann::json::object(), spheremap);
    render(t, "tiled-deferred", {{"normals", "float"}}, plain);
    const Difference d = compareRgba8(spheremap.back(), plain.back());
    MESSAGE("spheremap vs float normals: max " << d.maxCodes << " codes on " << d.share() * 100.0 << " % of pixels");
    CHECK(d.pixelsDiffering > 0);
    CHECK(d.maxCodes <= 140);
}

TEST_CASE("tiled-deferred: a list capacity below the tile's light count drops lights and reports the overflow") {
    const TestScene t = makeScene(defaultLights());
    Rendered capped, unbounded, defaults;
    render(t, "tiled-deferred", {{"tileListCapacity", 1}}, capped);
    render(t, "tiled-deferred", {{"tileListCapacity", "unbounded"}}, unbounded);
    render(t, "tiled-deferred", nlohmann::json::object(), defaults);
    const Surface& grid = capped.registry.get("tiles.grid");
    int overflowing = 0;
    for (std::uint32_t ty = 0; ty < grid.height(); ++ty)
        for (std::uint32_t tx = 0; tx < grid.width(); ++tx) {
            CHECK(tileList(capped.registry, tx, ty).size() == std::min<std::size_t>(appended(capped.registry, tx, ty), 1));
            overflowing += appended(capped.registry, tx, ty) > 1;
        }
    CHECK(overflowing > 0);
    CHECK(!sameBytes(capped.back(), defaults.back()));
    CHECK(sameBytes(unbounded.back(), defaults.back()));  // 4 lights: MAX_LIGHTS never overflows
}

TEST_CASE("tiled-deferred: the heat map and the grid agree, lists are ascending, 1 and 2 threads give the same bytes") {
    const TestScene t = makeScene(defaultLights());
    Rendered one, two;
    render(t, "tiled-deferred", nlohmann::json::object(), one, Precision::Exact, 1);
    render(t, "tiled-deferred", nlohmann::json::object(), two, Precision::Exact, 2);
    for (const char* name :
         {"backbuffer", "lit", "heatmap", "tiles.grid", "tiles.lightCount", "tiles.lightIndices", "tiles.depthRange"})
        CHECK_MESSAGE(sameBytes(one.registry.get(name), two.registry.get(name)), name);
    const Surface& heat = one.registry.get("heatmap");
    for (std::uint32_t y = 0; y < kHeight; ++y)
        for (std::uint32_t x = 0; x < kWidth; ++x) {
            const std::uint32_t n = appended(one.registry, x / kIntelTileDim, y / kIntelTileDim);
            REQUIRE(std::to_integer<std::uint32_t>(heat.texel(x, y)[0]) == std::min<std::uint32_t>(n, 255));
        }
    const Surface& grid = one.registry.get("tiles.grid");
    for (std::uint32_t ty = 0; ty < grid.height(); ++ty)
        for (std::uint32_t tx = 0; tx < grid.width(); ++tx) {
            const std::vector<std::uint32_t> list = tileList(one.registry, tx, ty);
            CHECK(std::is_sorted(list.begin(), list.end()));
            CHECK(std::adjacent_find(list.begin(), list.end()) == list.end());
        }
    CHECK(grid.width() == 8);   // ceil(128 / 16)
    CHECK(grid.height() == 6);  // ceil(96 / 16)
}

TEST_CASE("tiled-deferred: option values are InputErrors naming the key path, and every precision is accepted") {
    CHECK(errorOf({{"shading", "amd"}}).find("/options/shading") != std::string::npos);
    CHECK(errorOf({{"tileSize", 12}}).find("/options/tileSize") != std::string::npos);
    CHECK(errorOf({{"tileListCapacity", 0}}).find("/options/tileListCapacity") != std::string::npos);
    CHECK(errorOf({{"projection", "demo-gl"}}).find("/options/projection") != std::string::npos);
    CHECK(errorOf({{"lightVolumes", "inscribed"}}).find("/options/lightVolumes") != std::string::npos);
    CHECK(errorOf({{"tileSize", 32}, {"tilePlanes", "tile"}, {"normals", "float"}}).empty());
    for (const Precision p : {Precision::Reference, Precision::Fast}) {
        Rendered r;
        render(makeScene(defaultLights()), "tiled-deferred", nlohmann::json::object(), r, p);
        CHECK(r.registry.find(kBackBufferName) != nullptr);
        CHECK((r.registry.find(kReferenceBufferName) != nullptr) == (p == Precision::Reference));
    }
}

} // namespace tessera_test::techniques_tiled_deferred_test
