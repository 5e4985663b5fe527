// Golden images of the bundled scenes through `tiled-deferred` (Intel 2010 tiled deferred, seed
// 004) with the faithful defaults: 16x16 tiles, the 2010 sample's side planes, Intel's shading
// and spheremap normal storage. 320x180 at 1 and 2 threads (bytes must agree).
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>

#include <tessera/scene/scene_file.h>
#include <tessera/techniques/technique.h>

#include "support/golden_check.h"

using namespace tessera;

namespace {

Surface renderScene(const std::string& scene, const std::string& technique, std::uint32_t threads) {
    SceneDescription desc = parseSceneFile(std::filesystem::path(TESSERA_SOURCE_DIR) / "scenes" / (scene + ".json"));
    desc.width = 320;
    desc.height = 180;
    Camera camera;
    const Scene loaded = loadScene(desc, true, &camera);
    const SceneResources resources(loaded, {}, findTechnique(technique)->textures);
    Device device(DeviceConfig{64, threads});
    DrawStats stats;
    TechniqueContext ctx;
    ctx.device = &device;
    ctx.resources = &resources;
    ctx.camera = camera;
    ctx.width = desc.width;
    ctx.height = desc.height;
    ctx.stats = &stats;
    ctx.sceneFile = desc.file.string();
    BufferRegistry registry;
    buildTechnique(technique, ctx, desc.file.string()).run(registry);
    return registry.get(kBackBufferName);
}

void checkAtOneAndTwoThreads(const std::string& scene, const std::string& technique) {
    const Surface one = renderScene(scene, technique, 1);
    const Surface two = renderScene(scene, technique, 2);
    CHECK(std::equal(one.bytes().begin(), one.bytes().end(), two.bytes().begin(), two.bytes().end()));
    test::checkGolden(one, scene, technique);
}

} // namespace

TEST_CASE("golden: default scene, tiled-deferred, 320x180") { checkAtOneAndTwoThreads("default", "tiled-deferred"); }

TEST_CASE("golden: Sponza with 64 large lights, tiled-deferred, 320x180") {
    checkAtOneAndTwoThreads("sponza-large-lights", "tiled-deferred");
}
