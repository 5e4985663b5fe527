// forward-plus-amd's one-bounce indirect light (GPU Pro 4 ch. 5 §5.5): the reflective shadow
// map against the geometry it sees, the N x N VPLs against the RSM texels they come from
// (count, position, direction, colour), the chapter's reflection formula (§10 item 10), and the
// image with indirect light off equal to forward-plus-amd's bit for bit.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <tessera/buffers/surface.h>
#include <tessera/errors/input_error.h>
#include <tessera/techniques/amd_vpl.h>
#include <tessera/techniques/technique.h>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_amd_vpl_test {

using namespace tessera;
using tessera::test::sameBytes;

namespace {

constexpr std::uint32_t kW = 96, kH = 64;  // px

glm::vec4 texel4(const Surface& s, std::uint32_t x, std::uint32_t y) {
    glm::vec4 v;
    std::memcpy(&v, s.texel(x, y), sizeof(v));
    return v;
}

// The room of support/room_scene.h (floor y = 0 colour (0.8, 0.7, 0.6), wall z = -6 colour
// (0.5, 0.6, 0.9)) with a point light, and a sun straight down marked indirect.
test::TestScene roomWithSun(bool indirect) {
    Light sun = test::makeLight(LightType::Directional, {0, 0, 0}, {0.0f, -1.0f, 0.0f}, 1.0f, {1.0f, 0.9f, 0.8f});
    sun.intensity = 2.0f;
    sun.indirect = indirect;
    return test::makeScene({test::makeLight(LightType::Point, {-2.0f, 1.5f, 0.0f}, {0, 0, -1}, 5.0f, {1.0f, 0.8f, 0.6f}), sun},
                           {0.0f, 3.0f, 8.0f}, 0.05f);
}

test::Rendered render(const test::TestScene& t, const nlohmann::json& options, std::uint32_t threads = 2) {
    test::Rendered out;
    test::render(t, "forward-plus-amd", options, out, Precision::Exact, threads, {kW, kH});
    return out;
}

} // namespace

TEST_CASE("vpl: grid texels and the chapter's reflected direction") {
    // Cell centres in integer arithmetic: (2 i + 1) * size / (2 N).
    CHECK(vplTexel(0, 0, 256, 16) == glm::uvec2(8, 8));
    CHECK(vplTexel(15, 3, 256, 16) == glm::uvec2(248, 56));
    CHECK(vplTexel(0, 2, 10, 3) == glm::uvec2(1, 8));   // 1 * 10 / 6 = 1, 5 * 10 / 6 = 8
    CHECK(vplTexel(1, 1, 10, 3) == glm::uvec2(5, 5));   // 3 * 10 / 6 = 5
    CHECK(vplTexel(0, 0, 1, 1) == glm::uvec2(0, 0));
    // GPU Pro 4 §10 item 10: N = (0, 1, 0), L = normalize(1, 1, 0) gives R = normalize(-1, 1, 0).
    // One RSM texel holding that normal, seen by a directional light travelling along -L.
    Surface position({1, 1, Format::R32G32B32A32_FLOAT, 1}), normal({1, 1, Format::R32G32B32A32_FLOAT, 1}),
        color({1, 1, Format::R32G32B32A32_FLOAT, 1});
    position.clearColor({2.0f, 0.0f, 3.0f, 1.0f});
    normal.clearColor({0.0f, 1.0f, 0.0f, 1.0f});
    color.clearColor({0.5f, 0.25f, 1.0f, 1.0f});
    RsmView view;
    view.directional = true;
    view.lightDirectionWorld = -glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f));
    VplOptions o;
    o.rsmSize = 1;
    o.grid = 1;
    o.intensity = 2.0f;
    o.normalOffset = 0.25f;
    const std::vector<Vpl> reflected = vplsFromRsm(position, normal, color, view, o);
    REQUIRE(reflected.size() == 1);
    CHECK(reflected[0].valid);
    CHECK(glm::length(reflected[0].directionWorld - glm::normalize(glm::vec3(-1.0f, 1.0f, 0.0f))) < 1e-6f);
    CHECK(reflected[0].positionWorld == glm::vec3(2.0f, 0.25f, 3.0f));  // + 0.25 N
    CHECK(reflected[0].color == glm::vec3(1.0f, 0.5f, 2.0f));           // x intensity / N^2 = x 2
    o.direction = VplDirection::Normal;
    CHECK(vplsFromRsm(position, normal, color, view, o)[0].directionWorld == glm::vec3(0.0f, 1.0f, 0.0f));
    // An empty texel (w = 0) makes a disabled VPL.
    position.clearColor(glm::vec4(0.0f));
    const Vpl empty = vplsFromRsm(position, normal, color, view, o)[0];
    CHECK(!empty.valid);
    CHECK(!vplLight(empty, o).enabled);
}

TEST_CASE("vpl: the RSM sees the room from the sun and every VPL is its texel") {
    const test::TestScene t = roomWithSun(true);
    test::Rendered r = render(t, {{"rsmSize", 64}, {"vplGrid", 8}, {"vplIntensity", 40}});
    const Surface& position = r.get("rsm.position");
    const Surface& normal = r.get("rsm.normal");
    const Surface& color = r.get("rsm.color");
    REQUIRE(position.width() == 64);
    // Looking straight down, the sun's RSM sees the floor (y = 0, up) and the wall's top edge on
    // edge: each drawn texel lies on one of the two quads with its normal and colour x light.
    const glm::vec3 light = glm::vec3(1.0f, 0.9f, 0.8f) * 2.0f;
    int floorTexels = 0;
    for (std::uint32_t y = 0; y < 64; ++y)
        for (std::uint32_t x = 0; x < 64; ++x) {
            const glm::vec4 p = texel4(position, x, y);
            if (p.w == 0.0f) continue;
            const glm::vec4 n = texel4(normal, x, y);
            const glm::vec4 c = texel4(color, x, y);
            if (std::fabs(p.y) < 1e-5f) {
                ++floorTexels;
                CHECK(n == glm::vec4(0.0f, 1.0f, 0.0f, 1.0f));
                CHECK(glm::vec3(c) == glm::vec3(0.8f, 0.7f, 0.6f) * light);
            } else {
                CHECK(std::fabs(p.z + 6.0f) < 1e-4f);  // the wall
            }
        }
    CHECK(floorTexels > 64 * 64 / 4);
    // 8 x 8 VPLs, each at its texel + 0.01 N, reflected direction, colour = texel x 40 / 64.
    const Surface& vplPos = r.get("vpl.position");
    const Surface& vplDir = r.get("vpl.direction");
    const Surface& vplCol = r.get("vpl.color");
    REQUIRE(vplPos.width() == 8);
    REQUIRE(vplPos.height() == 8);
    int valid = 0;
    for (std::uint32_t j = 0; j < 8; ++j)
        for (std::uint32_t i = 0; i < 8; ++i) {
            const glm::uvec2 tx = vplTexel(i, j, 64, 8);
            const glm::vec4 p = texel4(position, tx.x, tx.y);
            const glm::vec4 v = texel4(vplPos, i, j);
            CHECK(v.w == (p.w > 0.0f ? 1.0f : 0.0f));
            if (p.w == 0.0f) continue;
            ++valid;
            const glm::vec3 n(texel4(normal, tx.x, tx.y));
            CHECK(glm::vec3(v) == glm::vec3(p) + n * 0.01f);
            CHECK(glm::vec3(texel4(vplCol, i, j)) == glm::vec3(texel4(color, tx.x, tx.y)) * (40.0f / 64.0f));
            // Sun straight down: L = +Y; on the floor R = 2 (N.L) N - L = +Y.
            if (n.y == 1.0f) CHECK(glm::vec3(texel4(vplDir, i, j)) == glm::vec3(0.0f, 1.0f, 0.0f));
        }
    CHECK(valid >= 32);
    // The indirect term alone: non-negative, lit somewhere, zero on pixels no VPL reaches.
    const Surface& indirect = r.get("indirect");
    int lit = 0;
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x) {
            const glm::vec4 v = texel4(indirect, x, y);
            CHECK(v.x >= 0.0f);
            CHECK(std::isfinite(v.x));
            lit += v.x > 0.0f ? 1 : 0;
        }
    CHECK(lit > 500);
}

TEST_CASE("vpl: indirect off is forward-plus-amd bit for bit, and the same at 1, 2 and 7 threads") {
    test::Rendered plain = render(roomWithSun(false), {});
    test::Rendered off = render(roomWithSun(true), {{"indirect", "off"}});
    test::Rendered on = render(roomWithSun(true), {{"vplIntensity", 40}});
    CHECK(off.registry.find("rsm.position") == nullptr);
    CHECK(sameBytes(plain.back(), off.back()));
    CHECK(!sameBytes(plain.back(), on.back()));
    // Indirect light only adds: no channel of any pixel gets darker.
    int brighter = 0;
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x)
            for (int ch = 0; ch < 3; ++ch) {
                const auto a = std::to_integer<int>(plain.back().texel(x, y)[ch]);
                const auto b = std::to_integer<int>(on.back().texel(x, y)[ch]);
                CHECK(b >= a);
                brighter += b > a ? 1 : 0;
            }
    CHECK(brighter > 500);
    test::Rendered one = render(roomWithSun(true), {{"vplIntensity", 40}}, 1);
    test::Rendered seven = render(roomWithSun(true), {{"vplIntensity", 40}}, 7);
    for (const char* name : {"rsm.position", "rsm.color", "vpl.position", "vpl.color", "indirect", "backbuffer"}) {
        CAPTURE(name);
        CHECK(sameBytes(one.get(name), on.get(name)));
        CHECK(sameBytes(one.get(name), seven.get(name)));
    }
    const auto errorOf = [&](const nlohmann::json& options) -> std::string {
        try {
            render(roomWithSun(true), options);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    CHECK(errorOf({{"vplGrid", 32}, {"rsmSize", 16}}).find("/options/vplGrid") != std::string::npos);
    CHECK(errorOf({{"vplGrid", 129}}).find("/options/vplGrid") != std::string::npos);
    CHECK(errorOf({{"vplConeDeg", 90}}).find("/options/vplConeDeg") != std::string::npos);
    CHECK(errorOf({{"rsmSize", 0}}).find("/options/rsmSize") != std::string::npos);
    CHECK(errorOf({{"indirect", "on"}, {"shading", "3dgep"}}).find("/options/indirect") != std::string::npos);
    CHECK(errorOf({{"shading", "3dgep"}}).empty());  // "auto": no VPLs with the 3dgep shader
}

} // namespace tessera_test::techniques_amd_vpl_test
