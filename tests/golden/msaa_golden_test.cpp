// Golden images of the default scene through every technique at 4x MSAA (320x180, the techniques'
// default options, 1 and 2 threads must give the same resolved and multisampled bytes). The
// per-sample properties these images rest on are tested against ray-cast truth in
// tests/unit/msaa_deferred_test.cpp; these pin the whole frames.
#include "support/bundled_scene.h"

using namespace tessera;

TEST_CASE("golden: default scene, every technique at 4x MSAA, 320x180") {
    for (const TechniqueInfo& t : techniques()) {
        if (!t.build || !t.msaa) continue;
        CAPTURE(t.id);
        const test::BundledScene scene("default", 320, 180, t.textures);
        test::checkGoldenAtOneAndTwoThreads(scene, std::string(t.id), "msaa4-" + std::string(t.id), 4);
    }
}
