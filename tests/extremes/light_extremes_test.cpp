// Extremes catalogue, lights: ranges from 1e-6 to 3e38, lights at the eye, on a tile plane, on
// a surface and behind the camera, spot angles of 0.01 and 89.99 degrees, 0 and 65,536 lights,
// all lights in one tile, zero intensity, and colour x intensity beyond binary32.
#include "extremes/extremes.h"
#include "extremes/scenes.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::extremes_light_extremes_test {

using namespace tessera;
using namespace tessera::test;
using namespace tessera::test::extremes;

namespace {

Light point(glm::vec3 positionWorld, float range, glm::vec3 color = {1.0f, 0.8f, 0.6f}) {
    return makeLight(LightType::Point, positionWorld, {0, 0, -1}, range, color);
}

Light spot(glm::vec3 positionWorld, glm::vec3 direction, float range, float angleDeg) {
    return makeLight(LightType::Spot, positionWorld, direction, range, {0.6f, 0.8f, 1.0f}, angleDeg);
}

} // namespace

TEST_CASE("lights: range 1e-6") {
    runCase("lights range 1e-6", withLights(room(), {point({0.0f, 1e-7f, 0.0f}, 1e-6f), point({-2.0f, 1.5f, 0.0f}, 5.0f)}));
}

TEST_CASE("lights: range 1e6") {
    runCase("lights range 1e6", withLights(room(), {point({0.0f, 2.0f, 0.0f}, 1e6f)}));
}

TEST_CASE("lights: range 1e38") {
    runCase("lights range 1e38", withLights(room(), {point({0.0f, 2.0f, 0.0f}, 1e38f)}));
}

TEST_CASE("lights: range 3e38") {
    // The corrected deferred's circumscribed sphere (3e38 x 1.02) times the projection's 2.4
    // overflowed: every volume vertex at infinity, the light lost on all 3072 pixels. Volumes
    // beyond 1e30 are scaled to twice the view's reach (LightVolumes::worldFromObject).
    runCase("lights range 3e38", withLights(room(), {point({0.0f, 2.0f, 0.0f}, 3e38f)}));
}

TEST_CASE("lights: a spot light of range 3e38") {
    runCase("lights spot range 3e38", withLights(room(), {spot({0.0f, 4.0f, 0.0f}, {0.0f, -1.0f, -0.2f}, 3e38f, 30.0f)}));
}

TEST_CASE("lights: a light at the eye") {
    const TestScene t = room();
    runCase("lights at the eye", withLights(t, {point(t.camera.positionWorld, 12.0f)}));
}

TEST_CASE("lights: a light on the central tile planes") {
    // On the view axis: x_view = 0 is the boundary between tile columns 1 and 2 of 64 px at 16 px
    // (and at 8 and 32 px), so the light's centre lies exactly on those tile side planes.
    const TestScene t = room();
    const glm::vec3 onAxisWorld = glm::vec3(glm::inverse(t.camera.viewFromWorld()) * glm::vec4(0.0f, 0.0f, -6.0f, 1.0f));
    runCase("lights on a tile plane", withLights(t, {point(onAxisWorld, 0.5f), point(onAxisWorld + glm::vec3(0.0f, -1.0f, 0.0f), 1.5f)}));
}

TEST_CASE("lights: a light behind the camera that reaches in front") {
    const TestScene t = room();
    runCase("lights behind the camera reaching", withLights(t, {point(t.camera.positionWorld + glm::vec3(0.0f, 0.0f, 3.0f), 14.0f)}));
}

TEST_CASE("lights: a light behind the camera that does not reach the view") {
    const TestScene t = room();
    runCase("lights behind the camera", withLights(t, {point(t.camera.positionWorld + glm::vec3(0.0f, 0.0f, 3.0f), 1.0f)}));
}

TEST_CASE("lights: a light exactly on the floor") {
    runCase("lights on a surface", withLights(room(), {point({0.5f, 0.0f, 0.5f}, 4.0f)}));
}

TEST_CASE("lights: spot angle 0.01 degrees") {
    runCase("lights spot 0.01", withLights(room(), {spot({0.0f, 4.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, 10.0f, 0.01f)}));
}

TEST_CASE("lights: spot angle 89.99 degrees") {
    runCase("lights spot 89.99", withLights(room(), {spot({0.0f, 4.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, 10.0f, 89.99f)}));
}

TEST_CASE("lights: a spot aimed exactly down -Z") {
    // glm 0.9.6's quat(u, v) gives the identity here (ERRATA #5): the faithful deferred's cone
    // points the wrong way, which is the source's behaviour; the corrected volume is exact.
    runCase("lights spot down -Z", withLights(room(), {spot({0.0f, 2.0f, 2.0f}, {0.0f, 0.0f, -1.0f}, 12.0f, 30.0f)}));
}

TEST_CASE("lights: no lights") {
    CaseOptions o;
    o.maxReferenceCodes = 0;
    runCase("lights none", withLights(room(), {}), o);
}

TEST_CASE("lights: zero intensity") {
    Light l = point({0.0f, 2.0f, 0.0f}, 8.0f);
    l.intensity = 0.0f;
    CaseOptions o;
    o.maxReferenceCodes = 0;
    runCase("lights zero intensity", withLights(room(), {l}), o);
}

TEST_CASE("lights: a grazing directional light") {
    runCase("lights grazing directional",
            withLights(room(), {makeLight(LightType::Directional, {0, 0, 0}, {1.0f, 0.0f, 0.0f}, 1.0f, {1.0f, 1.0f, 1.0f})}));
}

TEST_CASE("lights: 200 lights in one tile") {
    // Below AMD's 256-entry LIGHT_CAPACITY and the 3dgep demo's lists, so nothing overflows and
    // every equality holds; the lights sit inside one 8 px tile's frustum.
    const TestScene t = room();
    std::vector<Light> lights;
    for (int i = 0; i < 200; ++i) {
        const glm::vec3 posView(0.02f * float(i % 10) - 0.1f, 0.02f * float(i / 10 % 10) - 0.1f, -6.0f - 0.01f * float(i / 100));
        lights.push_back(point(glm::vec3(glm::inverse(t.camera.viewFromWorld()) * glm::vec4(posView, 1.0f)), 0.8f,
                               {0.002f * float(i), 0.3f, 0.1f}));
    }
    runCase("lights 200 in one tile", withLights(t, lights));
}

TEST_CASE("lights: 65,536 lights") {
    // The tiled techniques only (forward loops over every light per pixel: 2e8 evaluations per
    // frame at 64 x 48 is minutes under the sanitizers); small lights spread over the room.
    std::vector<Light> lights;
    for (int i = 0; i < 65536; ++i) {
        const float x = -9.5f + 19.0f * float(i % 256) / 255.0f, z = -5.5f + 15.0f * float(i / 256) / 255.0f;
        lights.push_back(point({x, 0.2f, z}, 0.15f, {0.5f + 0.5f * float(i % 3) / 2.0f, 0.5f, 0.4f}));
    }
    CaseOptions o;
    o.sizePx = {48, 32};
    o.techniques = {"forward-plus", "forward-plus-amd", "tiled-deferred"};
    o.equalities = false;
    o.threadAgreement = true;
    o.maxReferenceCodes = 255;  // forward is not rendered: no reference comparison (see the report)
    const TestScene t = withLights(room(), lights);
    for (const std::string& technique : o.techniques) {
        CAPTURE(technique);
        Rendered r;
        render(t, technique, nlohmann::json::object(), r, Precision::Exact, 2, o.sizePx);
        for (const std::string& buffer : r.registry.names()) CHECK(nonFiniteTexels(r.get(buffer)) == 0);
    }
}

TEST_CASE("lights: colour x intensity overflows") {
    Light l = point({0.0f, 2.0f, 0.0f}, 10.0f, {3e38f, 1.0f, 0.0f});
    l.intensity = 3e38f;
    // Refused before anything is built (checkFrameInputs): the product is +inf in binary32, and
    // 0 x inf in the lighting sums made NaN (tiled-deferred's lit buffer, light-prepass's light buffer).
    for (const std::string& technique : readyTechniques()) {
        Rendered r;
        CAPTURE(technique);
        CHECK_THROWS_WITH_AS(render(withLights(room(), {l}), technique, nlohmann::json::object(), r),
                             doctest::Contains("light 0: colour x intensity"), InputError);
    }
}

TEST_CASE("lights: colour x intensity just inside binary32") {
    // 1e19 x 1e19 = 1e38 per light: finite; the sums of two lights overflow to +inf in the
    // float lighting buffers (the true value exceeds binary32), never to NaN.
    Light a = point({-1.0f, 2.0f, 0.0f}, 10.0f, {1e19f, 1e19f, 1e19f});
    a.intensity = 1e19f;
    Light b = a;
    b.positionWorld = {1.0f, 2.0f, 0.0f};
    const TestScene t = withLights(room(), {a, b});
    for (const std::string& technique : readyTechniques()) {
        CAPTURE(technique);
        Rendered r;
        render(t, technique, nlohmann::json::object(), r);
        for (const std::string& buffer : r.registry.names()) {
            const Surface& s = r.get(buffer);
            if (formatInfo(s.format()).kind != FormatKind::Float) continue;
            int nan = 0;
            for (std::uint32_t y = 0; y < s.height(); ++y)
                for (std::uint32_t x = 0; x < s.width(); ++x) {
                    const glm::vec4 v = s.load(x, y);
                    for (std::uint32_t c = 0; c < formatInfo(s.format()).channels; ++c) nan += std::isnan(v[static_cast<int>(c)]);
                }
            CAPTURE(buffer);
            CHECK(nan == 0);
        }
    }
}

} // namespace tessera_test::extremes_light_extremes_test
