// The one full-size golden: Sponza through `forward` (3dgep article §2) at 1280x720, the article's
// resolution, with 64 large lights, rendered once at 2 threads. The 320x180 goldens of every
// technique are technique_golden_test's.
#include "support/bundled_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::golden_forward_golden_test {

using namespace tessera;

TEST_CASE("golden: Sponza with 64 large lights, forward, 1280x720") {
    const test::BundledScene sponza("sponza-large-lights", 1280, 720, findTechnique("forward")->textures);
    BufferRegistry buffers = sponza.render("forward", 2);
    test::checkGolden(buffers.get(kBackBufferName), "sponza-large-lights", "forward-1280x720");
}

} // namespace tessera_test::golden_forward_golden_test
