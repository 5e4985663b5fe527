// glTF 2.0 §3.9.5 (Double Sided) in every technique: a double-sided quad seen from behind is lit
// with its normal reversed, so it equals the same quad built with the mirrored normal (and, within
// the interpolation's rounding, the quad with reversed winding seen from the front), and the N.L
// a technique records at a pixel is the one computed here from the geometry.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <tessera/raster/pixel_watch.h>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::scene_double_sided_test {

using namespace tessera;
using namespace tessera::test;

namespace {

// The quad z = 0, x and y in [-2, 2] (world units); the camera at (0, 0, -5) looks at the origin
// along +Z, so it sees the side the -Z normal points to.
constexpr float kEyeZWorld = -5.0f;
// A point light on the viewer's side, off the axis so N.L is neither 0 nor 1 (world units). Its
// range keeps the eye (4.15 away) outside its volume, which deferred-killzone (ERRATA #6) and the
// Cookbook's default volume culling need to light anything; it reaches most of the quad.
constexpr glm::vec3 kLightPosWorld{0.5f, 1.0f, -1.0f};
constexpr float kLightRange = 3.5f;  // world units

enum class Build {
    Back,      // normal +Z, counter-clockwise seen from +Z: the camera sees its back face
    Mirrored,  // the same triangles with normal -Z and tangent frame negated (still a back face)
    Front,     // reversed winding and normal -Z: the camera sees its front face
};

TestScene quadScene(Build build, bool doubleSided = true) {
    TestScene t;
    Material m;
    m.baseColorFactor = {0.8f, 0.7f, 0.6f, 1.0f};
    m.roughnessFactor = 0.5f;  // specular power 30 (phong_material.h): the reflection uses N too
    m.metallicFactor = 0.0f;
    m.doubleSided = doubleSided;
    t.scene.materials = {m};
    MeshPrimitive p = build == Build::Front ? quad({-2.0f, -2.0f, 0.0f}, {0.0f, 4.0f, 0.0f}, {4.0f, 0.0f, 0.0f}, 0)
                                            : quad({-2.0f, -2.0f, 0.0f}, {4.0f, 0.0f, 0.0f}, {0.0f, 4.0f, 0.0f}, 0);
    if (build == Build::Mirrored) {
        // binormal = cross(N, T.xyz) * T.w (glTF 2.0 §3.7.2.1): negating N, T.xyz and T.w negates it too.
        for (glm::vec3& n : p.normalsObject) n = -n;
        for (glm::vec4& tangent : p.tangentsObject) tangent = -tangent;
    }
    Mesh mesh;
    mesh.primitives.push_back(p);
    t.scene.meshes.push_back(mesh);
    t.scene.instances.push_back(MeshInstance{0, glm::mat4(1.0f), "quad"});
    t.scene.lights = {makeLight(LightType::Point, kLightPosWorld, {0, 0, 1}, kLightRange, {1.0f, 1.0f, 1.0f})};
    t.camera.positionWorld = {0.0f, 0.0f, kEyeZWorld};
    t.camera.orientationWorld = glm::quatLookAtRH(glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(0, 1, 0));
    t.camera.nearZ = 0.1f;
    t.camera.farZ = 100.0f;
    return t;
}

void keepNormals(TestScene& t) {
    for (Material& m : t.scene.materials) m.reverseBackFaceNormals = false;
}

struct Case {
    const char* technique;
    nlohmann::json options;
};

std::vector<Case> everyTechnique() {
    return {{"forward", nlohmann::json::object()},
            {"forward-plus", nlohmann::json::object()},
            {"forward-plus-amd", nlohmann::json::object()},
            {"deferred", nlohmann::json::object()},
            {"deferred-killzone", nlohmann::json::object()},
            {"tiled-deferred", nlohmann::json::object()},
            {"deferred-cookbook", {{"volumeCull", "front"}}},  // ERRATA #23: the table's CULL_BACK lights nothing inside the volume
            {"deferred-classic", nlohmann::json::object()},
            {"deferred-classic", {{"gbuffer", "optimized"}, {"normalEncoding", "safe"}}},  // ERRATA #29: printed is NaN at N = view Z
            {"light-prepass", nlohmann::json::object()},
            {"preview", nlohmann::json::object()}};
}

// Sum of the RGB codes over the back buffer: how much light the image holds.
long long lightIn(const Surface& s) {
    long long sum = 0;
    for (std::uint32_t y = 0; y < s.height(); ++y)
        for (std::uint32_t x = 0; x < s.width(); ++x)
            for (int c = 0; c < 3; ++c) sum += std::to_integer<int>(s.texel(x, y)[c]);
    return sum;
}

} // namespace

TEST_CASE("double-sided: a back face is lit as the mirrored normal, in every technique and precision") {
    for (const Case& c : everyTechnique()) {
        for (const Precision precision : {Precision::Exact, Precision::Fast, Precision::Reference}) {
            const std::string technique = c.technique;
            CAPTURE(technique);
            CAPTURE(c.options.dump());
            CAPTURE(int(precision));
            Rendered back, mirroredKept, front, backKept;
            render(quadScene(Build::Back), c.technique, c.options, back, precision);
            TestScene mirrored = quadScene(Build::Mirrored);
            keepNormals(mirrored);
            render(mirrored, c.technique, c.options, mirroredKept, precision);
            render(quadScene(Build::Front), c.technique, c.options, front, precision);
            TestScene unreversed = quadScene(Build::Back);
            keepNormals(unreversed);
            render(unreversed, c.technique, c.options, backKept, precision);

            // Reversing is an exact negation of the interpolated N, T and B: the same bytes as
            // varyings that arrive negated (same triangles, same barycentrics).
            CHECK(sameBytes(back.back(), mirroredKept.back()));
            // The truth: the quad with reversed winding seen from the front. Its barycentrics
            // weigh the same (constant) vertex values in another order, so the interpolated N,
            // posView and uv may differ in their last bits; after normalization and the lighting
            // model's few dozen float operations that is a relative error near 1e-6, which moves
            // an 8-bit code only where the value lies within 1e-6 * 255 of a rounding boundary:
            // at most 1 code, and at few pixels.
            const Difference d = compareRgba8(back.back(), front.back());
            CHECK(d.maxCodes <= 1);
            CHECK(d.pixelsDiffering <= int(d.pixels / 100));
            // With the normal kept the back face faces away from the light (N.L < 0): darker, except
            // preview, whose head light takes |N.V| and so lights both faces alike by design.
            if (std::string(c.technique) == "preview") CHECK(sameBytes(back.back(), backKept.back()));
            else CHECK(lightIn(backKept.back()) < lightIn(back.back()));
        }
    }
}

TEST_CASE("double-sided: a single-sided back face stays culled, and front faces do not change") {
    for (const Case& c : everyTechnique()) {
        CAPTURE(c.technique);
        // Single-sided: the back face is culled whatever the reversal setting says.
        Rendered culled, empty;
        render(quadScene(Build::Back, false), c.technique, c.options, culled);
        TestScene kept = quadScene(Build::Back, false);
        keepNormals(kept);
        render(kept, c.technique, c.options, empty);
        CHECK(sameBytes(culled.back(), empty.back()));
        // A front face of a double-sided material: the reversal setting changes nothing.
        Rendered frontReversed, frontKept;
        render(quadScene(Build::Front), c.technique, c.options, frontReversed);
        TestScene frontKeptScene = quadScene(Build::Front);
        keepNormals(frontKeptScene);
        render(frontKeptScene, c.technique, c.options, frontKept);
        CHECK(sameBytes(frontReversed.back(), frontKept.back()));
    }
}

TEST_CASE("double-sided: the N.L recorded at a back-face pixel is the geometric one") {
    // Pixel (40, 30) of 128 x 96: its centre (40.5, 30.5) is on the quad (which spans
    // 4 / (2 * 5 * tan(22.5 deg)) * 96 = 92.7 px vertically around the centre). Its ray meets
    // z = 0 at posWorld, computed below in double; the reversed normal is (0, 0, -1), so
    // N.L = -(L - P).z / |L - P| with L the light's world position.
    const glm::uvec2 px{40, 30};
    const TestScene t = quadScene(Build::Back);
    const double aspect = double(kWidth) / double(kHeight);
    const double tanHalf = std::tan(22.5 * 3.14159265358979323846 / 180.0);
    const double xNdc = (double(px.x) + 0.5) / double(kWidth) * 2.0 - 1.0;
    const double yNdc = 1.0 - (double(px.y) + 0.5) / double(kHeight) * 2.0;
    // The camera looks along +Z world with +Y up, so view +X (right) is world -X.
    const double xWorld = -xNdc * tanHalf * aspect * double(-kEyeZWorld);
    const double yWorld = yNdc * tanHalf * double(-kEyeZWorld);
    const glm::dvec3 toLight = glm::dvec3(kLightPosWorld) - glm::dvec3(xWorld, yWorld, 0.0);
    const double nDotLExpected = -toLight.z / glm::length(toLight);  // = 1 / |L - P|
    MESSAGE("N.L expected at (40, 30): " << nDotLExpected);

    // The techniques whose light loops record their terms (tessera probe): the 3dgep loop
    // (forward, forward-plus, deferred), Intel's (tiled-deferred) and AMD's (forward-plus-amd).
    // deferred reconstructs P at the pixel's centre (ERRATA #3: the demo's corner is half a pixel off).
    const Case cases[] = {{"forward", nlohmann::json::object()},
                          {"forward-plus", nlohmann::json::object()},
                          {"deferred", {{"reconstruct", "centre"}}},
                          {"tiled-deferred", nlohmann::json::object()},
                          {"forward-plus-amd", nlohmann::json::object()}};
    for (const Case& c : cases) {
        for (const bool reverse : {true, false}) {
            const std::string technique = c.technique;
            CAPTURE(technique);
            CAPTURE(reverse);
            TestScene scene = t;
            if (!reverse) keepNormals(scene);
            const SceneResources res(scene.scene, {}, TexturePolicy::AllLinear);
            Device device(DeviceConfig{32, 2});
            PixelWatch watch{px.x, px.y, {}};
            device.setPixelWatch(&watch);
            TechniqueContext ctx;
            ctx.device = &device;
            ctx.resources = &res;
            ctx.camera = scene.camera;
            ctx.width = kWidth;
            ctx.height = kHeight;
            ctx.options = c.options;
            ctx.sceneFile = "memory.json";
            BufferRegistry registry;
            buildTechnique(c.technique, ctx, ctx.sceneFile).run(registry);
            int terms = 0;
            for (const PixelDrawEvent& e : watch.events)
                for (const LightTerm& term : e.lights) {
                    ++terms;
                    // The lights' own float arithmetic (view transform, normalize of L - P and of N,
                    // P interpolated within 1e-4 world units of its ray: 2e-3 px at 0.04 units/px)
                    // puts N.L within 1e-4 / |L - P| = 5e-5 of the double value; 2e-4 leaves margin.
                    const double expected = reverse ? nDotLExpected : -nDotLExpected;
                    // Unreversed, the light is behind the surface; a loop that stops there may
                    // record no N.L (NaN), which is only the probe's record.
                    if (!reverse && std::isnan(term.nDotL)) continue;
                    CHECK(std::abs(double(term.nDotL) - expected) < 2e-4);
                }
            CHECK(terms >= 1);
        }
    }
}

} // namespace tessera_test::scene_double_sided_test
