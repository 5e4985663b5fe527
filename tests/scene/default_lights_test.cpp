// The default light rig (scene/default_lights.h): two point lights whose range keeps every
// point of the scene's bounds where the 3dgep attenuation is still 1, placed from the camera.
#include <doctest/doctest.h>

#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include <tessera/scene/default_lights.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::scene_default_lights_test {

using namespace tessera;

TEST_CASE("default light rig: a key and a fill point light whose range covers the bounds at full attenuation") {
    Bounds bounds;
    bounds.extend({-2.0f, 0.0f, -3.0f});
    bounds.extend({4.0f, 5.0f, 1.0f});
    Camera camera;
    camera.positionWorld = {1.0f, 2.0f, 12.0f};
    camera.orientationWorld = glm::angleAxis(glm::radians(30.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    const std::vector<Light> rig = defaultLightRig(bounds, camera);
    REQUIRE(rig.size() == 2);
    const float diagonal = glm::length(bounds.maxWorld - bounds.minWorld);  // sqrt(36 + 25 + 16) = sqrt(77)
    CHECK(diagonal == doctest::Approx(std::sqrt(77.0)));
    const glm::vec3 right = camera.orientationWorld * glm::vec3(1, 0, 0), up = camera.orientationWorld * glm::vec3(0, 1, 0);
    CHECK(glm::length(rig[0].positionWorld - (camera.positionWorld + (up - right) * (0.5f * diagonal))) < 1e-5f);
    CHECK(rig[0].intensity == 1.0f);
    CHECK(rig[1].intensity == 0.5f);
    for (const Light& l : rig) {
        CAPTURE(l.name);
        CHECK(l.type == LightType::Point);
        float farthest = 0.0f;
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 c((corner & 1) ? 4.0f : -2.0f, (corner & 2) ? 5.0f : 0.0f, (corner & 4) ? 1.0f : -3.0f);
            const float d = glm::length(c - l.positionWorld);
            farthest = std::max(farthest, d);
            CHECK(d <= 0.75f * l.range * (1.0f + 1e-6f));  // 1 - smoothstep(0.75 range, range, d) == 1
        }
        CHECK(0.75f * l.range == doctest::Approx(farthest).epsilon(1e-6));  // no larger than needed
    }
    CHECK(defaultLightRig(Bounds{}, camera).empty());
}

} // namespace tessera_test::scene_default_lights_test
