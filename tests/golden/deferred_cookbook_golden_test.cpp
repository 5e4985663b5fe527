// Golden images of the bundled scenes through `deferred-cookbook` (HLSL Development Cookbook ch. 2):
// its five corrections on (ERRATA #22-#26: the decode once, CULL_FRONT, the demo's spot scale, the
// pixel's cpPos, the stencil). 320x180 at 1 and 2 threads (bytes must agree); the faithful defaults'
// images are technique_golden_test's.
#include "support/bundled_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::golden_deferred_cookbook_golden_test {

using namespace tessera;

namespace {

const nlohmann::json kCorrected{{"specPowerUnpack", "once"},
                                {"volumeCull", "front"},
                                {"spotVolume", "demo"},
                                {"cpPos", "pixel"},
                                {"background", "stencil"}};

void checkCorrected(const std::string& scene) {
    const test::BundledScene s(scene, 320, 180, findTechnique("deferred-cookbook")->textures);
    const nlohmann::json options = kCorrected;
    BufferRegistry one = s.render("deferred-cookbook", 1, &options);
    BufferRegistry two = s.render("deferred-cookbook", 2, &options);
    CHECK(test::sameBytes(one.get(kBackBufferName), two.get(kBackBufferName)));
    test::checkGolden(one.get(kBackBufferName), s.name(),
                      "deferred-cookbook-corrected");
}

}  // namespace

TEST_CASE("golden: default scene, deferred-cookbook with every correction, 320x180") {
    checkCorrected("default");
}
TEST_CASE("golden: Sponza with 64 large lights, deferred-cookbook with every correction, 320x180") {
    checkCorrected("sponza-large-lights");
}

} // namespace tessera_test::golden_deferred_cookbook_golden_test
