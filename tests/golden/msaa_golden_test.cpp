// Golden images of the default scene through every technique at 4x MSAA (320x180, the techniques'
// default options, 1 and 2 threads must give the same resolved and multisampled bytes). The
// per-sample properties these images rest on are tested against ray-cast truth in
// tests/techniques/msaa_deferred_test.cpp; these pin the whole frames. Every bundled scene through every
// technique at 2x (the Sponza scenes with 16 generated lights) checks that MSAA works everywhere.
#include "support/bundled_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::golden_msaa_golden_test {

using namespace tessera;

TEST_CASE("golden: default scene, every technique at 4x MSAA, 320x180") {
    for (const TechniqueInfo& t : techniques()) {
        if (!t.build || !t.msaa) continue;
        CAPTURE(t.id);
        const test::BundledScene scene("default", 320, 180, t.textures);
        test::checkGoldenAtOneAndTwoThreads(scene, std::string(t.id), "msaa4-" + std::string(t.id), 4);
    }
}

TEST_CASE("msaa: every technique renders every bundled scene at 2x (160x90), the same bytes at 1 and 2 threads, no NaN stored") {
    for (const std::string& name : test::bundledSceneNames()) {
        for (const TechniqueInfo& t : techniques()) {
            if (!t.build || !t.msaa) continue;
            CAPTURE(name);
            CAPTURE(t.id);
            const test::BundledScene scene(name, 160, 90, t.textures, 16);
            const nlohmann::json options = nlohmann::json::object();
            BufferRegistry one = scene.render(std::string(t.id), 1, &options, nullptr, Precision::Exact, 2);
            BufferRegistry two = scene.render(std::string(t.id), 2, &options, nullptr, Precision::Exact, 2);
            CHECK(test::sameBytes(one.get(backBufferTarget(2)), two.get(backBufferTarget(2))));
            const Surface& resolved = one.get(kBackBufferName);
            CHECK(resolved.sampleCount() == 1);
            std::size_t nan = 0;
            for (std::uint32_t y = 0; y < resolved.height(); ++y)
                for (std::uint32_t x = 0; x < resolved.width(); ++x) {
                    const glm::vec4 v = resolved.load(x, y);
                    nan += (v.x != v.x || v.y != v.y || v.z != v.z) ? 1 : 0;
                }
            CHECK(nan == 0);
        }
    }
}

} // namespace tessera_test::golden_msaa_golden_test
