// What `tessera probe` says each light added at a pixel (raster/pixel_watch.h LightTerm): the
// light loops' terms sum to the loop's result bit for bit, recording them changes no result, each
// "none" reason matches the geometry that causes it, and in whole frames the watched pixel's
// shader inputs and light terms agree with the camera and the lights across techniques.
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <set>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <tessera/inspect/pixel_history.h>
#include <tessera/shading/phong_lighting.h>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::shading_light_terms_test {

using namespace tessera;

namespace {

ViewLight<float> pointAt(glm::vec3 posView, float range) {
    ViewLight<float> l;
    l.type = LightType::Point;
    l.positionView = glm::vec4(posView, 1.0f);
    l.range = range;
    l.color = glm::vec4(0.9f, 0.7f, 0.5f, 1.0f);
    return l;
}

bool sameBits(const glm::vec4& a, const glm::vec4& b) {
    for (int c = 0; c < 4; ++c)
        if (std::bit_cast<std::uint32_t>(a[c]) != std::bit_cast<std::uint32_t>(b[c])) return false;
    return true;
}

} // namespace

TEST_CASE("light terms: each light's term or skip reason at a surface, the terms summing to doLighting's result bit for bit") {
    // A surface at view (0, 0, -5) facing the eye (+Z view). Lights, by construction:
    //  0 in range in front: adds light; 1 in front but 10 away with range 3: out of range;
    //  2 behind the surface (z = -8, N.L = -1): evaluated, adds 0 diffuse, "behind the surface";
    //  3 disabled; 4 a spot in front pointing away from the surface: cone factor 0;
    //  5 exactly at the end of its falloff (distance 2 == range 2: the strict > test shades it,
    //    attenuation 1 - smoothstep(1.5, 2, 2) = 0).
    const Vec4<float> posView(0.0f, 0.0f, -5.0f, 1.0f), normalView(0.0f, 0.0f, 1.0f, 0.0f);
    std::vector<ViewLight<float>> lights = {pointAt({0.5f, 0.5f, -3.0f}, 6.0f), pointAt({0.0f, 0.0f, 5.0f}, 3.0f),
                                            pointAt({0.0f, 0.0f, -8.0f}, 6.0f), pointAt({0.0f, 1.0f, -4.0f}, 6.0f),
                                            pointAt({0.0f, 0.0f, -3.0f}, 6.0f), pointAt({0.0f, 0.0f, -3.0f}, 2.0f)};
    lights[3].enabled = false;
    lights[4].type = LightType::Spot;
    lights[4].directionView = {0.0f, 0.0f, 1.0f, 0.0f};  // towards the eye, away from the surface
    lights[4].spotlightAngleDeg = 20.0f;
    const float specularPower = 30.0f;

    const LightingResult<float> plain = doLighting<float>(lights, specularPower, posView, normalView);
    std::vector<LightTerm> terms;
    setWatchedLightTerms(&terms);
    const LightingResult<float> traced = doLighting<float>(lights, specularPower, posView, normalView);
    setWatchedLightTerms(nullptr);
    CHECK(sameBits(plain.diffuse, traced.diffuse));  // recording changes nothing
    CHECK(sameBits(plain.specular, traced.specular));
    REQUIRE(terms.size() == lights.size());
    LightingResult<float> sum;  // the loop's own order and operations: += from +0
    for (const LightTerm& t : terms) {
        sum.diffuse += t.diffuse;
        sum.specular += t.specular;
    }
    CHECK(sameBits(sum.diffuse, plain.diffuse));
    CHECK(sameBits(sum.specular, plain.specular));

    CHECK(terms[0].skip == LightTerm::Skip::None);
    CHECK(terms[0].diffuse.x > 0.0f);
    CHECK(lightTermWhy(terms[0]).empty());
    CHECK(terms[0].distance == doctest::Approx(std::sqrt(0.5 * 0.5 * 2 + 4.0)));  // |(0.5, 0.5, 2)|

    CHECK(terms[1].skip == LightTerm::Skip::OutOfRange);
    CHECK(terms[1].distance == 10.0f);
    CHECK(terms[1].range == 3.0f);
    CHECK(lightTermWhy(terms[1]).rfind("out of range", 0) == 0);

    CHECK(terms[2].skip == LightTerm::Skip::None);
    CHECK(terms[2].nDotL == -1.0f);
    CHECK(terms[2].diffuse == glm::vec4(0.0f));
    CHECK(lightTermWhy(terms[2]).rfind("behind the surface", 0) == 0);

    CHECK(terms[3].skip == LightTerm::Skip::Disabled);
    CHECK(lightTermWhy(terms[3]) == "disabled");

    CHECK(terms[4].cone == 0.0f);  // cos(angle to the spot axis) = -1, far below cos(20 deg)
    CHECK(terms[4].nDotL == 1.0f);
    CHECK(lightTermWhy(terms[4]).rfind("outside the cone", 0) == 0);

    CHECK(terms[5].skip == LightTerm::Skip::None);
    CHECK(terms[5].distance == 2.0f);
    CHECK(terms[5].falloff == 0.0f);
    CHECK(lightTermWhy(terms[5]).rfind("at the end of its falloff", 0) == 0);

    // The listed loop (Forward+) names lights by their scene index, not their place in the list.
    std::vector<LightTerm> listed;
    const std::uint32_t list[] = {4, 0};
    setWatchedLightTerms(&listed);
    doLightingListed<float>(lights, 2, [&](std::uint32_t i) { return list[i]; }, specularPower, posView, normalView);
    setWatchedLightTerms(nullptr);
    REQUIRE(listed.size() == 2);
    CHECK(listed[0].light == 4);
    CHECK(listed[1].light == 0);
}

TEST_CASE("light terms: in whole frames the watched pixel's inputs sit on its ray and every technique names the same contributing lights") {
    const test::TestScene t = test::makeScene(test::defaultLights());
    const SceneResources resources(t.scene, {}, TexturePolicy::AllLinear);
    // Pixels on the floor and the wall (128x96, eye (0, 3, 8) looking at (0, 0.5, 0)).
    const std::vector<glm::uvec2> pixels = {{64, 80}, {30, 70}, {100, 60}, {64, 30}, {20, 20}, {110, 40}};
    struct Case {
        const char* technique;
        nlohmann::json options;
        bool dgep;  // the 3dgep lighting model (the same contributing lights as forward's)
    };
    const Case cases[] = {{"forward", nlohmann::json::object(), true},
                          {"forward-plus", nlohmann::json::object(), true},
                          {"deferred", nlohmann::json::object(), true},
                          {"tiled-deferred", {{"shading", "3dgep"}}, true},
                          {"tiled-deferred", nlohmann::json::object(), false},  // Intel's shading
                          {"forward-plus-amd", nlohmann::json::object(), false}};
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::set<std::uint32_t>> contributing;  // forward's
    int eventsWithTerms = 0;
    for (const Case& c : cases) {
        CAPTURE(c.technique);
        for (const glm::uvec2 px : pixels) {
            CAPTURE(px.x);
            CAPTURE(px.y);
            Device device(DeviceConfig{32, 2});
            PixelWatch watch{px.x, px.y, {}};
            device.setPixelWatch(&watch);
            TechniqueContext ctx;
            ctx.device = &device;
            ctx.resources = &resources;
            ctx.camera = t.camera;
            ctx.width = test::kWidth;
            ctx.height = test::kHeight;
            ctx.options = c.options;
            ctx.sceneFile = "memory.json";
            BufferRegistry registry;
            buildTechnique(c.technique, ctx, ctx.sceneFile).run(registry);
            std::set<std::uint32_t> lit;
            for (const PixelDrawEvent& e : watch.events) {
                if (!e.shaded) continue;
                // SV_Position is the pixel centre (per-pixel shading, no MSAA).
                CHECK(e.posWindow.x == float(px.x) + 0.5f);
                CHECK(e.posWindow.y == float(px.y) + 0.5f);
                if (std::string(c.technique) == "forward" && e.inputFields.size() == 6) {
                    // The interpolated posView lies on the pixel's ray: projected, it lands on the
                    // pixel centre (perspective-correct interpolation). Tolerance 2e-3 px: the room's
                    // quads are 20 units across, so the float barycentrics weigh vertex values ~20
                    // apart and cancel; the measured worst is 9e-4 px.
                    const glm::vec3 posView(e.inputs[0], e.inputs[1], e.inputs[2]);
                    const glm::mat4 clipFromView = glm::perspectiveRH_ZO(glm::radians(t.camera.fovYDeg),
                                                                         float(test::kWidth) / float(test::kHeight),
                                                                         t.camera.nearZ, t.camera.farZ);
                    const glm::vec4 clip = clipFromView * glm::vec4(posView, 1.0f);
                    const float xWindow = (clip.x / clip.w * 0.5f + 0.5f) * float(test::kWidth);
                    const float yWindow = (0.5f - clip.y / clip.w * 0.5f) * float(test::kHeight);
                    CHECK(std::abs(xWindow - e.posWindow.x) < 2e-3f);
                    CHECK(std::abs(yWindow - e.posWindow.y) < 2e-3f);
                    CHECK(std::string(e.inputFields[0].name) == "posView");
                }
                for (const LightTerm& term : e.lights) {
                    CAPTURE(term.light);
                    REQUIRE(term.light < t.scene.lights.size());
                    const Light& light = t.scene.lights[term.light];
                    if (light.type != LightType::Directional) {
                        // OutOfRange exactly when the distance the loop measured exceeds the range
                        // (AMD's spot range is its bounding sphere's radius, not the light's).
                        CHECK((term.skip == LightTerm::Skip::OutOfRange) == (term.distance > term.range));
                        if (c.dgep) CHECK(term.range == light.range);
                    }
                    if (term.diffuse != glm::vec4(0.0f)) lit.insert(term.light);
                }
                if (!e.lights.empty()) ++eventsWithTerms;
            }
            // Lights that add diffuse light here: a property of the surface and the lights, not of
            // the technique (the room has no surface within float rounding of a light's range).
            const auto key = std::make_pair(px.x, px.y);
            if (std::string(c.technique) == "forward") contributing[key] = lit;
            else if (c.dgep) CHECK(lit == contributing[key]);
        }
    }
    CHECK(eventsWithTerms >= 6 * 6);
    int lightsSeen = 0;
    for (const auto& [pixel, lights] : contributing) lightsSeen += int(lights.size());
    CHECK(lightsSeen >= 6);  // the pixels are lit: the comparison above is not of empty sets
}

} // namespace tessera_test::shading_light_terms_test
