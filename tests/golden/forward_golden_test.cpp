// Golden images of the bundled scenes through the `forward` technique (3dgep article §2): the
// Phong material gathering, every light per pixel, the demo's projection and pass states end to
// end. The 320x180 renders run at 1 and 2 threads (bytes must agree); the one full-size Sponza
// view (1280x720, the article's resolution, 64 large lights) runs once, at 2 threads.
#include "support/bundled_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::golden_forward_golden_test {

using namespace tessera;

TEST_CASE("golden: default scene, forward, 320x180") {
    test::checkSmallGolden("default", "forward");
}

TEST_CASE("golden: Sponza with 64 large lights, forward, 320x180") {
    test::checkSmallGolden("sponza-large-lights", "forward");
}

TEST_CASE("golden: Sponza with 64 large lights, forward, 1280x720") {
    const test::BundledScene sponza("sponza-large-lights", 1280, 720, findTechnique("forward")->textures);
    BufferRegistry buffers = sponza.render("forward", 2);
    test::checkGolden(buffers.get(kBackBufferName), "sponza-large-lights", "forward-1280x720");
}

} // namespace tessera_test::golden_forward_golden_test
