// Extremes catalogue, lights: ranges from 1e-6 to 3e38, lights at the eye, on a tile plane and
// behind the camera, spot angles of 0.01 and 89.99 degrees, 0 and 65,536 lights, all lights in
// one tile, and colour x intensity beyond binary32.
#include "extremes/extremes.h"
#include "extremes/scenes.h"

using namespace tessera;
using namespace tessera::test;
using namespace tessera::test::extremes;

TEST_CASE("lights: range 3e38") {
    runCase("lights range 3e38", withLights(room(), {makeLight(LightType::Point, {0.0f, 2.0f, 0.0f}, {0, 0, -1}, 3e38f, {1.0f, 0.8f, 0.6f})}));
}

TEST_CASE("lights: range 1e38") {
    runCase("lights range 1e38", withLights(room(), {makeLight(LightType::Point, {0.0f, 2.0f, 0.0f}, {0, 0, -1}, 1e38f, {1.0f, 0.8f, 0.6f})}));
}

TEST_CASE("lights: colour x intensity overflows") {
    Light l = makeLight(LightType::Point, {0.0f, 2.0f, 0.0f}, {0, 0, -1}, 10.0f, {1.0f, 0.8f, 0.6f});
    l.intensity = 3e38f;
    l.color = {3e38f, 1.0f, 0.0f};
    // Refused before anything is built (checkFrameInputs): the product is +inf in binary32, and
    // 0 x inf in the lighting sums made NaN (tiled-deferred's lit buffer, light-prepass's light buffer).
    for (const std::string& technique : readyTechniques()) {
        Rendered r;
        CAPTURE(technique);
        CHECK_THROWS_WITH_AS(render(withLights(room(), {l}), technique, nlohmann::json::object(), r),
                             doctest::Contains("light 0: colour x intensity"), InputError);
    }
}
