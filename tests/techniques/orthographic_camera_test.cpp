// Orthographic cameras under every lighting technique's default options. The 3dgep demo never
// had one, so the GL-form matrix (orthoRH_NO) has no faithful use: under D3D11 clipping
// (0 <= z <= w) it would discard the nearer half of the depth range and, here, every pixel.
// projection3dgep gives orthographic cameras orthoRH_ZO under both conventions.
#include <doctest/doctest.h>

#include <cmath>

#include <tessera/buffers/conversion.h>
#include <tessera/errors/input_error.h>
#include <tessera/techniques/forward.h>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_orthographic_camera_test {

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

// glTF 2.0 §5.13 (camera.orthographic.znear ">= 0"): an orthographic near plane may be 0, on the
// eye. The depth is then zView / f (orthoRH_ZO: z_clip = -z_view / (f - n) - n / (f - n), the
// D3D11 convention z in [0, 1]); nothing divides by n. A perspective camera still refuses 0.
TEST_CASE("orthographic camera with near 0: every ortho-capable technique renders it, the corrected ones equal forward") {
    TestScene t = orthographicRoom();
    t.camera.nearZ = 0.0f;
    // tiled-deferred refuses every orthographic camera on purpose (Intel's tile planes are built
    // for a perspective projection); near 0 keeps that refusal, with its message.
    {
        Rendered r;
        CHECK_THROWS_WITH_AS(render(t, "tiled-deferred", nlohmann::json::object(), r), doctest::Contains("needs a perspective camera"), InputError);
    }
    for (const TechniqueInfo& info : techniques()) {
        if (!info.build || std::string_view(info.id) == "tiled-deferred") continue;
        CAPTURE(info.id);
        Rendered r;
        render(t, std::string(info.id), nlohmann::json::object(), r);
        CHECK(pixelsWithGeometry(r.get("depth")) > kWidth * kHeight / 2);
    }
    // The corrected culling keeps every light (the extremes catalogue's equalities).
    Rendered forward;
    render(t, "forward", {{"projection", "d3d"}}, forward);
    const std::vector<std::pair<const char*, nlohmann::json>> corrected{
        {"forward-plus", {{"projection", "d3d"}, {"lightLists", "unbounded"}}},
        {"deferred",
         {{"projection", "d3d"}, {"reconstruct", "centre"}, {"gbuffer", "float"}, {"position", "gbuffer"}, {"accumulate", "lighting"},
          {"lightVolumes", "circumscribed"}, {"volumeRotation", "robust"}}}};
    for (const auto& entry : corrected) {
        CAPTURE(entry.first);
        Rendered other;
        render(t, entry.first, entry.second, other);
        CHECK(sameBytes(forward.back(), other.back()));
    }
    Rendered binned, all;
    render(t, "forward-plus-amd", nlohmann::json::object(), binned);
    render(t, "forward-plus-amd", {{"lightLoop", "all-lights"}}, all);
    CHECK(sameBytes(binned.back(), all.back()));
}

TEST_CASE("orthographic camera with near 0: stored depth is the D3D11 ortho depth (zView - n) / (f - n), computed in double") {
    // One triangle facing the camera at view distance d (oneTriangle), camera at the origin
    // looking down -Z, near 0. Each pixel the triangle covers stores float((d - n) / (f - n)),
    // the formula evaluated in double and rounded once: f = 16 gives the exact 1/16, 10/16,
    // 15/16; f = 100 and d = 7 the rounded 0.07 (float(0.01) x 7 = 0.069999998.. rounds to the
    // same float as 0.07).
    struct Point {
        float farZ, distance;
    };
    for (const Point p : {Point{16.0f, 1.0f}, Point{16.0f, 10.0f}, Point{16.0f, 15.0f}, Point{100.0f, 7.0f}}) {
        CAPTURE(p.farZ);
        CAPTURE(p.distance);
        TestScene t;
        t.scene = oneTriangle(-p.distance);
        t.camera.projection = ProjectionKind::Orthographic;
        t.camera.xMag = 2.0f;
        t.camera.yMag = 1.5f;
        t.camera.nearZ = 0.0f;
        t.camera.farZ = p.farZ;
        const double nearZ = 0.0;
        const double zExact = (double(p.distance) - nearZ) / (double(p.farZ) - nearZ);
        const double kD24Max = 16777215.0;  // 2^24 - 1
        for (const char* technique : {"forward", "forward-plus", "deferred"}) {
            CAPTURE(technique);
            Rendered r;
            render(t, technique, nlohmann::json::object(), r);
            const Surface& depth = r.get("depth");
            // The triangle's centroid (0, -1/3) lands at pixel (64, 48 + 48 / 1.5 / 3) of 128 x 96:
            // (x / xMag + 1) / 2 * 128 = 64, (1 - y / yMag) / 2 * 96 = 58.67.
            const float expected = depth.desc().format == Format::D24_UNORM_S8_UINT
                                       ? convert::d24ToDepth(std::uint32_t(std::llround(zExact * kD24Max)))
                                       : float(zExact);
            CHECK(depth.loadDepth(64, 58) == expected);
            CHECK(depth.loadDepth(0, 0) == 1.0f);  // outside the triangle: the clear value
        }
    }
}

TEST_CASE("near 0 is refused for a perspective camera, with the reason") {
    TestScene t = makeScene(defaultLights());
    t.camera.nearZ = 0.0f;
    Rendered r;
    CHECK_THROWS_WITH_AS(render(t, "forward", nlohmann::json::object(), r),
                         doctest::Contains("/camera/near: 0 is not a positive normal binary32 number"), InputError);
    CHECK_THROWS_WITH_AS(render(t, "forward", nlohmann::json::object(), r),
                         doctest::Contains("only an orthographic camera may take near 0"), InputError);
}

} // namespace tessera_test::techniques_orthographic_camera_test
