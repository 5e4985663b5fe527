// Golden images of bundled scenes through the `preview` technique: the glTF loader, textures
// with mips and sRGB, the camera and the alpha modes end to end. Each render is repeated at 1
// and 2 threads (bytes must agree) and compared exactly with golden/<scene>/preview.png.
#include "support/bundled_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::golden_scene_golden_test {

using namespace tessera;

namespace {

void checkScene(const std::string& scene) {
    test::checkGoldenAtOneAndTwoThreads(test::BundledScene(scene, 320, 180, findTechnique("preview")->textures), "preview");
}

} // namespace

TEST_CASE("golden: default scene (AlphaBlendModeTest + BoxTextured), preview, 320x180") { checkScene("default"); }

TEST_CASE("golden: Sponza, preview, 320x180") { checkScene("sponza-large-lights"); }

} // namespace tessera_test::golden_scene_golden_test
