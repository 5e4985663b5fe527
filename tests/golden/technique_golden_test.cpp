// Golden images of every registered technique with its default options, asked of the registry
// (techniques()), never of a list of names: the default scene and Sponza with 64 large lights at
// 320x180, each rendered at 1 and 2 threads (bytes must agree) and compared exactly with
// golden/<scene>/<technique id>.png. A technique added to the registry is golden-tested here
// without a new test file; until its two images are committed the test fails naming the missing
// file (TESSERA_UPDATE_GOLDEN=1, outside CI, writes them). The made-up technique the registry test
// declares (support/grey_fill_technique.h) is registered here too, so a technique from outside the
// library is golden-tested by this loop like the built-in ones. Other options, scenes and sizes are pinned
// beside the technique's own properties (forward_golden_test, deferred_cookbook_golden_test, the
// *_scenes_test files, msaa_golden_test).
#include "support/bundled_scene.h"
#include "support/grey_fill_technique.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::golden_technique_golden_test {

using namespace tessera;

namespace {

std::size_t checkEveryTechnique(const std::string& scene) {
    test::registerGreyFill();
    std::size_t checked = 0;
    for (const TechniqueInfo& t : techniques()) {
        if (!t.build) continue;
        CAPTURE(t.id);
        test::checkSmallGolden(scene, std::string(t.id));
        ++checked;
    }
    return checked;
}

} // namespace

// The counts are the registry's ten built-in techniques plus the registered test-grey-fill: the loops
// really ran over all of them.
TEST_CASE("golden: default scene, every technique with its default options, 320x180") {
    CHECK(checkEveryTechnique("default") == 11);
}

TEST_CASE("golden: Sponza with 64 large lights, every technique with its default options, 320x180") {
    CHECK(checkEveryTechnique("sponza-large-lights") == 11);
}

} // namespace tessera_test::golden_technique_golden_test
