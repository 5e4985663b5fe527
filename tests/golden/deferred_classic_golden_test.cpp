// Golden images of the bundled scenes through `deferred-classic` (PR&C D3D11 ch. 11) with the
// faithful defaults (a full-screen quad per light, the listings' unnormalized V), 320x180 at 1 and
// 2 threads (bytes must agree).
#include "support/bundled_scene.h"

using namespace tessera;

namespace {

void checkSmall(const std::string& scene) {
    test::checkGoldenAtOneAndTwoThreads(test::BundledScene(scene, 320, 180, findTechnique("deferred-classic")->textures),
                                        "deferred-classic");
}

} // namespace

TEST_CASE("golden: default scene, deferred-classic, 320x180") { checkSmall("default"); }

TEST_CASE("golden: Sponza with 64 large lights, deferred-classic, 320x180") { checkSmall("sponza-large-lights"); }
