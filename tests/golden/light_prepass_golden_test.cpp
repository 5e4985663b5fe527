// Golden images of the bundled scenes through `light-prepass` (PR&C D3D11 ch. 11 §11.3) with the
// faithful defaults, 320x180 at 1 and 2 threads (bytes must agree).
#include "support/bundled_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::golden_light_prepass_golden_test {

using namespace tessera;

TEST_CASE("golden: default scene, light-prepass, 320x180") {
    test::checkSmallGolden("default", "light-prepass");
}

TEST_CASE("golden: Sponza with 64 large lights, light-prepass, 320x180") {
    test::checkSmallGolden("sponza-large-lights", "light-prepass");
}

} // namespace tessera_test::golden_light_prepass_golden_test
