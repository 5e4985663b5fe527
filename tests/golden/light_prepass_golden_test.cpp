// Golden images of the bundled scenes through `light-prepass` (PR&C D3D11 ch. 11 §11.3) with the
// faithful defaults, 320x180 at 1 and 2 threads (bytes must agree).
#include "support/bundled_scene.h"

using namespace tessera;

namespace {

void checkSmall(const std::string& scene) {
    test::checkGoldenAtOneAndTwoThreads(test::BundledScene(scene, 320, 180, findTechnique("light-prepass")->textures),
                                        "light-prepass");
}

} // namespace

TEST_CASE("golden: default scene, light-prepass, 320x180") { checkSmall("default"); }

TEST_CASE("golden: Sponza with 64 large lights, light-prepass, 320x180") { checkSmall("sponza-large-lights"); }
