// Golden images of the bundled scenes through `deferred-cookbook` (HLSL Development Cookbook ch. 2):
// the faithful defaults (the chapter's printed decode, the table's cull mode, the book's spot scale,
// per-vertex cpPos, no stencil) and every correction on. 320x180 at 1 and 2 threads (bytes must agree).
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

void checkCookbook(const std::string& scene, bool corrected) {
    const test::BundledScene s(scene, 320, 180, findTechnique("deferred-cookbook")->textures);
    const nlohmann::json options = corrected ? kCorrected : nlohmann::json::object();
    BufferRegistry one = s.render("deferred-cookbook", 1, &options);
    BufferRegistry two = s.render("deferred-cookbook", 2, &options);
    CHECK(test::sameBytes(one.get(kBackBufferName), two.get(kBackBufferName)));
    test::checkGolden(one.get(kBackBufferName), s.name(),
                      corrected ? "deferred-cookbook-corrected" : "deferred-cookbook");
}

}  // namespace

TEST_CASE("golden: default scene, deferred-cookbook, 320x180") {
    checkCookbook("default", false);
}
TEST_CASE("golden: default scene, deferred-cookbook with every correction, 320x180") {
    checkCookbook("default", true);
}
TEST_CASE("golden: Sponza with 64 large lights, deferred-cookbook, 320x180") {
    checkCookbook("sponza-large-lights", false);
}
TEST_CASE("golden: Sponza with 64 large lights, deferred-cookbook with every correction, 320x180") {
    checkCookbook("sponza-large-lights", true);
}

} // namespace tessera_test::golden_deferred_cookbook_golden_test
