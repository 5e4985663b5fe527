// Golden image of the built-in scene (the README's picture): rendered at 1, 2 and 7 threads,
// compared exactly with golden/builtin/<name>.png (support/golden_check.h: a missing golden
// fails; a mismatch writes actual, expected and diff images and prints the worst pixel). To
// accept new output on purpose: TESSERA_UPDATE_GOLDEN=1 ctest -R golden, then review and commit.
#include <doctest/doctest.h>

#include <algorithm>

#include <tessera/techniques/builtin_scene.h>
#include "support/golden_check.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::golden_builtin_golden_test {

using namespace tessera;

namespace {

Surface renderBuiltin(std::uint32_t threads, std::uint32_t samples) {
    Device device(DeviceConfig{64, threads});
    DrawStats stats;
    BufferRegistry registry;
    BuiltinSceneOptions opt;
    opt.sampleCount = samples;
    buildBuiltinScene(device, opt, stats).run(registry);
    return registry.get("backbuffer");
}

} // namespace

TEST_CASE("golden: built-in scene, 1 sample, identical at 1, 2 and 7 threads") {
    const Surface one = renderBuiltin(1, 1);
    test::checkGolden(one, "builtin", "forward");
    for (const std::uint32_t threads : {2u, 7u}) {
        const Surface other = renderBuiltin(threads, 1);
        CHECK(std::equal(one.bytes().begin(), one.bytes().end(), other.bytes().begin(), other.bytes().end()));
    }
}

TEST_CASE("golden: built-in scene, 4x MSAA resolved") {
    test::checkGolden(renderBuiltin(2, 4), "builtin", "forward-msaa4");
}

} // namespace tessera_test::golden_builtin_golden_test
