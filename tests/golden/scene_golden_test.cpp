// Golden images of bundled scenes through the `preview` technique: the glTF loader, textures
// with mips and sRGB, the camera and the alpha modes end to end. Each render is repeated at 1
// and 2 threads (bytes must agree) and compared exactly with golden/<scene>/preview.png.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>

#include <tessera/scene/scene_file.h>
#include <tessera/techniques/technique.h>

#include "support/golden_check.h"

using namespace tessera;

namespace {

Surface renderBundled(const std::string& scene, std::uint32_t width, std::uint32_t height, std::uint32_t threads) {
    SceneDescription desc = parseSceneFile(std::filesystem::path(TESSERA_SOURCE_DIR) / "scenes" / (scene + ".json"));
    desc.width = width;
    desc.height = height;
    Camera camera;
    const Scene loaded = loadScene(desc, true, &camera);
    const SceneResources resources(loaded);
    Device device(DeviceConfig{64, threads});
    DrawStats stats;
    TechniqueContext ctx;
    ctx.device = &device;
    ctx.resources = &resources;
    ctx.camera = camera;
    ctx.width = width;
    ctx.height = height;
    ctx.stats = &stats;
    BufferRegistry registry;
    buildTechnique("preview", ctx, desc.file.string()).run(registry);
    return registry.get(kBackBufferName);
}

void checkScene(const std::string& scene, std::uint32_t width, std::uint32_t height) {
    const Surface one = renderBundled(scene, width, height, 1);
    const Surface two = renderBundled(scene, width, height, 2);
    CHECK(std::equal(one.bytes().begin(), one.bytes().end(), two.bytes().begin(), two.bytes().end()));
    test::checkGolden(one, scene, "preview");
}

} // namespace

TEST_CASE("golden: default scene (AlphaBlendModeTest + BoxTextured), preview, 320x180") { checkScene("default", 320, 180); }

TEST_CASE("golden: Sponza, preview, 320x180") { checkScene("sponza-large-lights", 320, 180); }
