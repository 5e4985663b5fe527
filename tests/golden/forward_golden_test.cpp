// Golden images of the bundled scenes through the `forward` technique (3dgep, seed 000): the
// Phong material gathering, every light per pixel, the demo's projection and pass states end to
// end. The 320x180 renders run at 1 and 2 threads (bytes must agree); the one full-size Sponza
// view (1280x720, the article's resolution, 64 large lights) runs once, at 2 threads.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>

#include <tessera/scene/scene_file.h>
#include <tessera/techniques/technique.h>

#include "support/golden_check.h"

using namespace tessera;

namespace {

Surface renderForward(const std::string& scene, std::uint32_t width, std::uint32_t height, std::uint32_t threads) {
    SceneDescription desc = parseSceneFile(std::filesystem::path(TESSERA_SOURCE_DIR) / "scenes" / (scene + ".json"));
    desc.width = width;
    desc.height = height;
    Camera camera;
    const Scene loaded = loadScene(desc, true, &camera);
    const SceneResources resources(loaded, {}, findTechnique("forward")->textures);
    Device device(DeviceConfig{64, threads});
    DrawStats stats;
    TechniqueContext ctx;
    ctx.device = &device;
    ctx.resources = &resources;
    ctx.camera = camera;
    ctx.width = width;
    ctx.height = height;
    ctx.options = desc.techniqueOptions;
    ctx.stats = &stats;
    ctx.sceneFile = desc.file.string();
    BufferRegistry registry;
    buildTechnique("forward", ctx, desc.file.string()).run(registry);
    return registry.get(kBackBufferName);
}

void checkAtOneAndTwoThreads(const std::string& scene) {
    const Surface one = renderForward(scene, 320, 180, 1);
    const Surface two = renderForward(scene, 320, 180, 2);
    CHECK(std::equal(one.bytes().begin(), one.bytes().end(), two.bytes().begin(), two.bytes().end()));
    test::checkGolden(one, scene, "forward");
}

} // namespace

TEST_CASE("golden: default scene, forward, 320x180") { checkAtOneAndTwoThreads("default"); }

TEST_CASE("golden: Sponza with 64 large lights, forward, 320x180") { checkAtOneAndTwoThreads("sponza-large-lights"); }

TEST_CASE("golden: Sponza with 64 large lights, forward, 1280x720") {
    test::checkGolden(renderForward("sponza-large-lights", 1280, 720, 2), "sponza-large-lights", "forward-1280x720");
}
