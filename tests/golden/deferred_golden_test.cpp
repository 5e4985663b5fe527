// Golden images of the bundled scenes through `deferred` and `deferred-killzone` (3dgep article
// §3) with the faithful defaults: G-buffer formats, stencil light volumes, the demo's corner
// reconstruction and GL-form projection end to end. 320x180 at 1 and 2 threads (bytes must agree).
#include "support/bundled_scene.h"

using namespace tessera;

namespace {

void checkSmall(const std::string& scene, const std::string& technique) {
    test::checkGoldenAtOneAndTwoThreads(test::BundledScene(scene, 320, 180, findTechnique(technique)->textures), technique);
}

} // namespace

TEST_CASE("golden: default scene, deferred, 320x180") { checkSmall("default", "deferred"); }

TEST_CASE("golden: Sponza with 64 large lights, deferred, 320x180") { checkSmall("sponza-large-lights", "deferred"); }

TEST_CASE("golden: default scene, deferred-killzone, 320x180") { checkSmall("default", "deferred-killzone"); }
