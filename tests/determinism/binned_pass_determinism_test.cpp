// Binned passes (raster/draw_batch.h) against the same frames drawn one draw at a time: every
// technique of the registry on every bundled scene, binned at 7 threads on 8 px tiles and draw by
// draw at one thread on 64 px tiles, must leave every buffer of the frame with the same bytes and
// the same draw counters; and every draw but Killzone 2's light loop must really have been binned
// (an image cannot show that a pass fell back to drawing one draw at a time).
#include <set>

#include "support/bundled_scene.h"
#include "support/grey_fill_technique.h"
#include "support/surface_compare.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::determinism_binned_pass_determinism_test {

using namespace tessera;
using namespace tessera::test;

namespace {

// Techniques whose frames hold no draw (the grey fill is one compute pass).
const std::set<std::string> kNoBinnedPass{"test-grey-fill"};
// Every other frame draws everything through DrawBatch passes, except Killzone 2's light loop,
// which reads an occlusion query between a light's draws and so draws one draw at a time. (A draw
// of more than detail::kBatchTriangles triangles would also run at once; no bundled scene has one.)
const std::set<std::string> kSomeDrawsUnbinned{"deferred-killzone"};

void checkBinnedEqualsDrawByDraw(const std::string& sceneName, std::uint32_t samples) {
    for (const TechniqueInfo& t : techniques()) {
        if (!t.build || (samples > 1 && !t.msaa)) continue;
        const std::string id(t.id);
        INFO("scene " << sceneName << ", technique " << id << ", " << samples << "x");
        const BundledScene scene(sceneName, 160, 90, t.textures);
        DeviceConfig binnedConfig{8, 7}, byDrawConfig{64, 1};
        byDrawConfig.binPasses = false;
        DrawStats binned, byDraw;
        BufferRegistry a = scene.renderOn(binnedConfig, id, nullptr, &binned, Precision::Exact, samples);
        BufferRegistry b = scene.renderOn(byDrawConfig, id, nullptr, &byDraw, Precision::Exact, samples);
        REQUIRE(a.names() == b.names());
        for (const std::string& name : a.names()) {
            INFO("buffer " << name);
            CHECK(sameBytes(a.get(name), b.get(name)));
        }
        CHECK(binned.psInvocations == byDraw.psInvocations);
        CHECK(binned.samplesPassed == byDraw.samplesPassed);
        CHECK(binned.quads == byDraw.quads);
        CHECK(binned.setup.trianglesOut == byDraw.setup.trianglesOut);
        CHECK(binned.paths == byDraw.paths);
        CHECK(byDraw.binnedDraws == 0);
        std::uint64_t draws = 0;  // every draw counts once under its pipeline path
        for (const auto& [path, n] : binned.paths) draws += n;
        if (kNoBinnedPass.contains(id)) CHECK(binned.binnedDraws == 0);
        else {
            if (kSomeDrawsUnbinned.contains(id)) CHECK(binned.binnedDraws < draws);
            else CHECK(binned.binnedDraws == draws);
            CHECK(binned.binnedDraws > 0);
            CHECK(binned.binnedRuns < binned.binnedDraws);  // runs share their tile sweeps
        }
    }
}

} // namespace

TEST_CASE("determinism: binned passes equal draw-by-draw passes in every buffer, every technique and bundled scene") {
    registerGreyFill();
    for (const std::string& scene : bundledSceneNames()) checkBinnedEqualsDrawByDraw(scene, 1);
}

TEST_CASE("determinism: binned passes equal draw-by-draw passes at 4x MSAA, every technique that supports it") {
    registerGreyFill();
    checkBinnedEqualsDrawByDraw("sponza-small-lights", 4);
}

} // namespace tessera_test::determinism_binned_pass_determinism_test
