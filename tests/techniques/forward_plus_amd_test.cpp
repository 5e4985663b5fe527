// The `forward-plus-amd` technique on a small scene built in memory: option errors naming
// /options/KEY, LIGHT_CAPACITY 256 overflow counted in "lightlist.counters" and shown white in
// the radar heat map, identical buffers at 1, 2 and 7 threads, and the spot light's bounding
// sphere (spotBoundingSphere) against sampled points of the lit sector.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include <tessera/errors/input_error.h>
#include <tessera/shading/tile_heat_colors.h>
#include <tessera/techniques/amd_light_culling.h>
#include <tessera/techniques/forward_plus.h>
#include <tessera/techniques/forward_plus_amd.h>
#include <tessera/techniques/technique.h>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_forward_plus_amd_test {

using namespace tessera;

namespace {

using test::sameBytes;
using test::quad;

// 64 x 48 px with 8 px tiles: 8 x 6 = 48 tiles, none partial.
constexpr std::uint32_t kWidth = 64, kHeight = 48;
constexpr std::uint32_t kTiles = (kWidth / 8) * (kHeight / 8);

// The room of support/room_scene.h (floor, wall lifted off it, camera at (0, 3, 8)): every tile
// has geometry, so every tile runs the light test.
test::TestScene makeScene(const std::vector<Light>& lights) { return test::makeScene(lights, {0.0f, 3.0f, 8.0f}, 0.05f); }

// n point lights of range 1000 around the room (every tile's slab and side planes lie well
// inside each sphere); withSpots: every 3rd one a spot of half angle 30 deg pointing down.
std::vector<Light> bigLights(std::size_t n, bool withSpots = false) {
    std::vector<Light> lights;
    for (std::size_t i = 0; i < n; ++i) {
        Light l;
        const float a = float(i) * 0.37f;
        l.positionWorld = {6.0f * std::cos(a), 2.0f + float(i % 5), 6.0f * std::sin(a) - 2.0f};
        l.range = 1000.0f;
        l.color = {0.0004f * float(i % 7), 0.0003f, 0.0005f};
        if (withSpots && i % 3 == 2) {
            l.type = LightType::Spot;
            l.directionWorld = {0.0f, -1.0f, 0.0f};
            l.spotHalfAngleDeg = 30.0f;
        }
        lights.push_back(l);
    }
    return lights;
}

// A 64 x 48 px forward-plus-amd render of the room.
BufferRegistry renderRoom(const test::TestScene& scene, const nlohmann::json& options, std::uint32_t threads = 2) {
    test::Rendered out;
    test::render(scene, "forward-plus-amd", options, out, Precision::Exact, threads, {kWidth, kHeight});
    return std::move(out.registry);
}

std::string errorOf(const nlohmann::json& options) {
    try {
        renderRoom(makeScene(bigLights(2)), options);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("forward-plus-amd: options are validated with the key path") {
    CHECK(errorOf({}).empty());
    CHECK(errorOf({{"shading", "3dgep"}, {"culling", "min-max"}, {"projection", "d3d"}}).empty());
    CHECK(errorOf({{"culling", "2.5d"}}).find("/options/culling") != std::string::npos);
    CHECK(errorOf({{"shading", 3}}).find("/options/shading") != std::string::npos);
    CHECK(errorOf({{"halfZ", "yes"}}).find("/options/halfZ") != std::string::npos);
    CHECK(errorOf({{"halfZ", true}, {"shading", "3dgep"}}).find("/options/halfZ") != std::string::npos);
    CHECK(errorOf({{"projection", "gl"}}).find("/options/projection") != std::string::npos);
    CHECK(errorOf({{"tileSize", 16}}).find("/options/tileSize") != std::string::npos);
    CHECK(errorOf({{"lightLoop", "all-lights"}}).empty());
    CHECK(errorOf({{"lightLoop", "brute"}}).find("/options/lightLoop") != std::string::npos);
}

TEST_CASE("forward-plus-amd: LIGHT_CAPACITY 256 overflow is counted and the radar map turns white") {
    // 300 lights that all reach every tile (range 1000 around a 20-unit room): each of the 48
    // tiles finds 300, keeps 256 and drops 44, so 48 * 44 = 2112 lights are dropped and the pool
    // holds 48 * 256 = 12288 entries. The radar colour of a count above the maximum is white.
    BufferRegistry reg = renderRoom(makeScene(bigLights(300)), {});
    const ForwardPlusCounters c = readForwardPlusCounters(reg);
    CHECK(c.opaque.tilesOverLocal == kTiles);
    CHECK(c.opaque.droppedLocal == kTiles * (300 - kAmdLightCapacity));
    CHECK(c.opaque.maxTileCount == 300);
    CHECK(c.opaque.requested == kTiles * kAmdLightCapacity);
    CHECK(c.transparent.tilesOverLocal == kTiles);
    const Surface& radar = reg.get("heatmap.radar");
    std::uint32_t texel = 0;
    std::memcpy(&texel, radar.texel(kWidth / 2, kHeight / 2), sizeof(texel));
    CHECK(texel == 0xFFFFFFFFu);
    // 256 lights: exactly full, nothing dropped, the "at max" light purple.
    BufferRegistry full = renderRoom(makeScene(bigLights(256)), {});
    const ForwardPlusCounters f = readForwardPlusCounters(full);
    CHECK(f.opaque.tilesOverLocal == 0);
    CHECK(f.opaque.droppedLocal == 0);
    std::memcpy(&texel, full.get("heatmap.radar").texel(0, 0), sizeof(texel));
    CHECK(texel == rgba8FromColor(kAmdRadarAtMax));
    // Half-Z: both lists of a tile overflow on their own; row 2 counts list B.
    BufferRegistry halfZ = renderRoom(makeScene(bigLights(300)), {{"halfZ", true}});
    CHECK(readForwardPlusCounters(halfZ).opaque.tilesOverLocal == kTiles);
    const Surface& countersSurface = halfZ.get("lightlist.counters");
    LightListCounters far{};
    std::memcpy(&far, countersSurface.texel(0, 2), sizeof(far));
    CHECK(far.tilesOverLocal == kTiles);
    CHECK(far.droppedLocal == kTiles * (300 - kAmdLightCapacity));
}

TEST_CASE("forward-plus-amd: every buffer is identical at 1, 2 and 7 threads") {
    const test::TestScene scene = makeScene(bigLights(40, true));
    for (const nlohmann::json& options : {nlohmann::json::object(), nlohmann::json{{"halfZ", true}},
                                          nlohmann::json{{"shading", "3dgep"}, {"culling", "min-max"}}}) {
        CAPTURE(options.dump());
        BufferRegistry one = renderRoom(scene, options, 1);
        for (const std::uint32_t threads : {2u, 7u}) {
            BufferRegistry other = renderRoom(scene, options, threads);
            for (const std::string& name : one.names()) {
                CAPTURE(name);
                CHECK(sameBytes(one.get(name), other.get(name)));
            }
        }
    }
}

TEST_CASE("forward-plus-amd: the spot bounding sphere holds the lit sector and is tight") {
    // Sector: apex at the origin, axis +z, radius R = 5, half angle theta. Sample the rim, the cap
    // and the side edges; every sample must lie within the sphere, and the farthest sample must be
    // at the radius (1e-4 relative: the sphere is the smallest one, up to float rounding and the
    // 2^-20 round-up).
    const float range = 5.0f;
    for (const float thetaDeg : {5.0f, 30.0f, 45.0f, 50.0f, 80.0f, 120.0f}) {
        CAPTURE(thetaDeg);
        const SpotBoundingSphere b = spotBoundingSphere(range, thetaDeg);
        const glm::dvec3 centre(0.0, 0.0, double(b.centerOffset));
        const double theta = double(thetaDeg) * 3.14159265358979323846 / 180.0;
        double farthest = 0.0;
        for (int i = 0; i <= 64; ++i) {       // angle to the axis, 0..theta
            const double phi = theta * double(i) / 64.0;
            for (int j = 0; j <= 16; ++j) {   // distance from the apex, 0..R
                const double s = double(range) * double(j) / 16.0;
                const glm::dvec3 p(s * std::sin(phi), 0.0, s * std::cos(phi));  // rotational symmetry: one meridian
                const double d = glm::length(p - centre);
                farthest = std::max(farthest, d);
                CHECK(d <= double(b.radius));
            }
        }
        CHECK(farthest >= double(b.radius) * (1.0 - 1e-4));
        if (thetaDeg <= 45.0f) CHECK(b.radius == doctest::Approx(b.centerOffset).epsilon(1e-5));  // apex on the sphere
    }
    // theta = 30 deg: R / (2 cos 30) = 5 / 1.7320508 = 2.8867513.
    CHECK(spotBoundingSphere(5.0f, 30.0f).radius == doctest::Approx(2.8867513).epsilon(1e-6));
    // theta = 60 deg: R sin 60 = 4.3301270 at R cos 60 = 2.5 from the apex.
    CHECK(spotBoundingSphere(5.0f, 60.0f).radius == doctest::Approx(4.3301270).epsilon(1e-6));
    CHECK(spotBoundingSphere(5.0f, 60.0f).centerOffset == doctest::Approx(2.5).epsilon(1e-6));
}

} // namespace tessera_test::techniques_forward_plus_amd_test
