// Golden images of the bundled scenes through `deferred` and `deferred-killzone` (3dgep article
// §3) with the faithful defaults: G-buffer formats, stencil light volumes, the demo's corner
// reconstruction and GL-form projection end to end. 320x180 at 1 and 2 threads (bytes must agree).
#include "support/bundled_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::golden_deferred_golden_test {

using namespace tessera;

TEST_CASE("golden: default scene, deferred, 320x180") {
    test::checkSmallGolden("default", "deferred");
}

TEST_CASE("golden: Sponza with 64 large lights, deferred, 320x180") {
    test::checkSmallGolden("sponza-large-lights", "deferred");
}

TEST_CASE("golden: default scene, deferred-killzone, 320x180") {
    test::checkSmallGolden("default", "deferred-killzone");
}

} // namespace tessera_test::golden_deferred_golden_test
