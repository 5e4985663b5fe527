// The `forward` technique on scenes built in memory: the demo's projection erratum (OpenGL-form
// matrix under D3D clipping moves the near plane from 0.1 to 0.19998) against the corrected
// "d3d" option, option and precision errors, per-draw variant counts, the reference buffer.
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <string>

#include <tessera/errors/input_error.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/technique.h>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_forward_test {

using namespace tessera;

namespace {

// One triangle at view z = `zView` covering the whole 16x16 view (camera at the origin looking
// down -Z, 45 degrees, near 0.1, far 1000), normal towards the eye, glTF default material.
Scene triangleAt(float zView) { return test::oneTriangle(zView); }

struct Rendered {
    BufferRegistry registry;
    std::map<std::string, std::uint64_t> variants;
};

void render(const Scene& scene, const nlohmann::json& options, Rendered& out, Precision precision = Precision::Exact) {
    const SceneResources resources(scene);
    Device device(DeviceConfig{64, 1});
    TechniqueContext ctx;
    ctx.device = &device;
    ctx.resources = &resources;
    ctx.width = 16;
    ctx.height = 16;
    ctx.options = options;
    ctx.precision = precision;
    ctx.variantCounts = &out.variants;
    ctx.sceneFile = "memory.json";
    buildTechnique("forward", ctx, ctx.sceneFile).run(out.registry);
}

std::string errorOf(const nlohmann::json& options, Precision precision = Precision::Exact) {
    Rendered r;
    try {
        render(triangleAt(-1.0f), options, r, precision);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("forward: demo-gl clips a triangle at view z = -0.15 (effective near -0.19998), d3d draws it") {
    // demo-gl: z_clip = -(f+n)/(f-n) z - 2fn/(f-n) = 1.0002 * 0.15 - 0.20002 = -0.05 < 0: clipped
    // by D3D's 0 <= z. d3d: z_clip = f/(n-f) z - fn/(f-n) = 1.0001 * 0.15 - 0.10001 = +0.05: drawn.
    const Scene scene = triangleAt(-0.15f);
    Rendered faithful, corrected;
    render(scene, nlohmann::json::object(), faithful);
    render(scene, {{"projection", "d3d"}}, corrected);
    const glm::vec4 clear = faithful.registry.get("backbuffer").load(8, 8);
    CHECK(clear.x == doctest::Approx(0.39f).epsilon(0.003));   // the clear colour: nothing drawn
    CHECK(faithful.registry.get("depth").loadDepth(8, 8) == 1.0f);
    // Drawn: no lights, so ambient only: (1,1,1) base colour x GlobalAmbient (0.1, 0.1, 0.15).
    const glm::vec4 drawn = corrected.registry.get("backbuffer").load(8, 8);
    CHECK(drawn.x == doctest::Approx(0.1f).epsilon(0.02));
    CHECK(drawn.z == doctest::Approx(0.15f).epsilon(0.02));
    // Beyond 0.19998 both draw.
    Rendered farther;
    render(triangleAt(-0.25f), nlohmann::json::object(), farther);
    CHECK(farther.registry.get("backbuffer").load(8, 8).x == doctest::Approx(0.1f).epsilon(0.02));
}

TEST_CASE("forward: the demo-gl depth buffer holds GL NDC z, the d3d one D3D depth") {
    // View z = -1: GL NDC z = (1.0002 - 0.20002) / 1 = 0.80018; D3D depth = 1.0001 - 0.10001 = 0.90009.
    Rendered gl, d3d;
    render(triangleAt(-1.0f), nlohmann::json::object(), gl);
    render(triangleAt(-1.0f), {{"projection", "d3d"}}, d3d);
    CHECK(gl.registry.get("depth").loadDepth(8, 8) == doctest::Approx(0.80018f).epsilon(1e-5));
    CHECK(d3d.registry.get("depth").loadDepth(8, 8) == doctest::Approx(0.90009f).epsilon(1e-5));
    CHECK(projection3dgep(Camera{}, 1.0f, ProjectionConvention::DemoGl)[3][2] ==
          doctest::Approx(-2.0f * 1000.0f * 0.1f / 999.9f));
}

TEST_CASE("forward: option values are InputErrors naming the key path, and every precision is accepted") {
    CHECK(errorOf({{"projection", "vulkan"}}).find("memory.json: /options/projection: \"vulkan\" is not one of demo-gl | d3d") !=
          std::string::npos);
    CHECK(errorOf({{"alphaTest", "yes"}}).find("/options/alphaTest") != std::string::npos);
    CHECK(errorOf({{"sampler", 3}}).find("/options/sampler") != std::string::npos);
    CHECK(errorOf({{"shadows", true}}).find("/options/shadows") != std::string::npos);
    CHECK(errorOf(nlohmann::json::object(), Precision::Fast).empty());
    CHECK(errorOf(nlohmann::json::object(), Precision::Reference).empty());
}

TEST_CASE("forward: variants are counted per draw, reference adds backbuffer.reference") {
    Rendered exact, reference;
    render(triangleAt(-1.0f), nlohmann::json::object(), exact);
    CHECK(exact.variants == std::map<std::string, std::uint64_t>{{"exact:none", 1}});
    render(triangleAt(-1.0f), nlohmann::json::object(), reference, Precision::Reference);
    CHECK(reference.variants == std::map<std::string, std::uint64_t>{{"reference:generic(none)", 1}});
    const Surface& ref = reference.registry.get("backbuffer.reference");
    CHECK(ref.format() == Format::R32G32B32A32_FLOAT);
    // Unquantized: ambient (1 x 0.1) exactly as double 0.1 rounded to float, vs 26/255 in RGBA8.
    CHECK(ref.load(8, 8).x == float(double(0.1f) * 1.0));
    CHECK(reference.registry.get("backbuffer").load(8, 8) == exact.registry.get("backbuffer").load(8, 8));
}

} // namespace tessera_test::techniques_forward_test
