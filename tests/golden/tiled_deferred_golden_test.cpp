// Golden images of the bundled scenes through `tiled-deferred` (Intel 2010 sample) with the
// faithful defaults: 16x16 tiles, the 2010 sample's side planes, Intel's shading
// and spheremap normal storage. 320x180 at 1 and 2 threads (bytes must agree).
#include "support/bundled_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::golden_tiled_deferred_golden_test {

using namespace tessera;

TEST_CASE("golden: default scene, tiled-deferred, 320x180") {
    test::checkSmallGolden("default", "tiled-deferred");
}

TEST_CASE("golden: Sponza with 64 large lights, tiled-deferred, 320x180") {
    test::checkSmallGolden("sponza-large-lights", "tiled-deferred");
}

} // namespace tessera_test::golden_tiled_deferred_golden_test
