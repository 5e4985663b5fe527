// Golden images of the bundled scenes through `deferred-classic` (PR&C D3D11 ch. 11) with the
// faithful defaults (a full-screen quad per light, the listings' unnormalized V), 320x180 at 1 and
// 2 threads (bytes must agree).
#include "support/bundled_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::golden_deferred_classic_golden_test {

using namespace tessera;

TEST_CASE("golden: default scene, deferred-classic, 320x180") {
    test::checkSmallGolden("default", "deferred-classic");
}

TEST_CASE("golden: Sponza with 64 large lights, deferred-classic, 320x180") {
    test::checkSmallGolden("sponza-large-lights", "deferred-classic");
}

} // namespace tessera_test::golden_deferred_classic_golden_test
