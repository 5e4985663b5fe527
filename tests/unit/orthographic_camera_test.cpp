// Orthographic cameras under every lighting technique's default options. The 3dgep demo never
// had one, so the GL-form matrix (orthoRH_NO) has no faithful use: under D3D11 clipping
// (0 <= z <= w) it would discard the nearer half of the depth range and, here, every pixel.
// projection3dgep gives orthographic cameras orthoRH_ZO under both conventions.
#include <doctest/doctest.h>

#include <tessera/techniques/forward.h>

#include "support/room_scene.h"

using namespace tessera;
using namespace tessera::test;

namespace {

// The room seen from the front and above through a 16 x 12 orthographic window: the floor and
// the wall fill the view, whose depth range (near 0.1, far 100) holds every surface in its
// first quarter, i.e. in the half that orthoRH_NO's z_ndc < 0 would clip.
TestScene orthographicRoom() {
    TestScene t = makeScene(defaultLights(), {0.0f, 3.0f, 8.0f});
    t.camera.projection = ProjectionKind::Orthographic;
    t.camera.xMag = 8.0f;
    t.camera.yMag = 6.0f;
    t.camera.nearZ = 0.1f;
    t.camera.farZ = 100.0f;
    return t;
}

std::uint32_t pixelsWithGeometry(const Surface& depth) {
    std::uint32_t n = 0;
    for (std::uint32_t y = 0; y < depth.height(); ++y)
        for (std::uint32_t x = 0; x < depth.width(); ++x) n += depth.loadDepth(x, y) < 1.0f;
    return n;
}

} // namespace

TEST_CASE("orthographic camera: every technique draws the room with its default projection") {
    const TestScene t = orthographicRoom();
    for (const char* technique : {"forward", "deferred", "deferred-killzone", "forward-plus", "forward-plus-amd", "preview"}) {
        CAPTURE(technique);
        Rendered r;
        render(t, technique, nlohmann::json::object(), r);
        const std::uint32_t covered = pixelsWithGeometry(r.get("depth"));
        MESSAGE(std::string(technique) << ": " << covered << " of " << kWidth * kHeight << " pixels hold geometry");
        // The floor and the wall cover the whole window but for the sky strip above the wall.
        CHECK(covered > kWidth * kHeight / 2);
    }
}

TEST_CASE("orthographic camera: demo-gl and d3d give the same matrix and the same image") {
    TestScene t = orthographicRoom();
    const glm::mat4 gl = projection3dgep(t.camera, 4.0f / 3.0f, ProjectionConvention::DemoGl);
    const glm::mat4 d3d = projection3dgep(t.camera, 4.0f / 3.0f, ProjectionConvention::D3d);
    CHECK(gl == d3d);
    // orthoRH_ZO: z_clip = -z_view / (f - n) - n / (f - n), so the near plane maps to 0, the far to 1.
    const glm::vec4 nearClip = d3d * glm::vec4(0.0f, 0.0f, -t.camera.nearZ, 1.0f);
    const glm::vec4 farClip = d3d * glm::vec4(0.0f, 0.0f, -t.camera.farZ, 1.0f);
    CHECK(nearClip.z == doctest::Approx(0.0f).epsilon(1e-6));
    CHECK(farClip.z == doctest::Approx(1.0f).epsilon(1e-6));
    for (const char* technique : {"forward", "forward-plus"}) {
        CAPTURE(technique);
        Rendered gl1, d3d1;
        render(t, technique, {{"projection", "demo-gl"}}, gl1);
        render(t, technique, {{"projection", "d3d"}}, d3d1);
        CHECK(sameBytes(gl1.back(), d3d1.back()));
    }
}
