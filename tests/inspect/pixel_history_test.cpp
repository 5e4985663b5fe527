// Pixel history (inspect/pixel_history.h) on every technique: recorded after every pass and every
// light step, its last value of each buffer equals the final buffer at random pixels, its events
// follow pass order, and the tiled techniques' tile view lists exactly the tile's stored lights.
#include <doctest/doctest.h>

#include <random>
#include <string>
#include <vector>

#include <tessera/inspect/pixel_history.h>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::inspect_pixel_history_test {

using namespace tessera;

TEST_CASE("pixel history: for every technique the last recorded value of each buffer is the final buffer's, in pass order") {
    const test::TestScene t = test::makeScene(test::defaultLights());
    const SceneResources resources(t.scene, {}, TexturePolicy::AllLinear);
    std::mt19937 rng(5);
    int pixelsChecked = 0, tiled = 0;
    for (const char* technique : {"preview", "forward", "deferred", "deferred-killzone", "forward-plus", "forward-plus-amd",
                                  "tiled-deferred"}) {
        CAPTURE(technique);
        Device device(DeviceConfig{32, 2});
        std::vector<PixelHistory> histories;
        for (int i = 0; i < 6; ++i) histories.emplace_back(std::uint32_t(rng() % test::kWidth), std::uint32_t(rng() % test::kHeight));
        TechniqueContext ctx;
        ctx.device = &device;
        ctx.resources = &resources;
        ctx.camera = t.camera;
        ctx.width = test::kWidth;
        ctx.height = test::kHeight;
        ctx.sceneFile = "memory.json";
        ctx.afterLightStep = [&](std::size_t light, std::string_view step, const BufferRegistry& reg) {
            for (PixelHistory& h : histories) h.record("lights", reg, static_cast<long long>(light), step);
        };
        const Frame frame = buildTechnique(technique, ctx, ctx.sceneFile);
        BufferRegistry registry;
        frame.run(registry, [&](const Pass& pass, const BufferRegistry& reg) {
            for (PixelHistory& h : histories) h.record(pass.name, reg);
        });
        std::vector<std::string> passOrder;
        for (const Pass& p : frame.passes()) passOrder.push_back(p.name);
        for (PixelHistory& h : histories) {
            const std::uint32_t x = h.x(), y = h.y();
            CAPTURE(x);
            CAPTURE(y);
            h.addTileInfo(registry, std::string(technique) == "forward-plus-amd" ? 8u : 16u);
            // Every full-size buffer of the final registry, as the history last saw it.
            int buffers = 0;
            for (const std::string& name : registry.names()) {
                const Surface& s = *registry.find(name);
                if (s.width() != test::kWidth || s.height() != test::kHeight) continue;
                CAPTURE(name);
                REQUIRE(h.last().contains(name));
                CHECK(h.last()[name] == pixelValue(s, x, y));
                ++buffers;
            }
            CHECK(buffers >= 2);
            CHECK(h.last().contains(std::string(kBackBufferName)));
            // Events in pass order (passes may repeat an event only by light step within "lights").
            std::size_t at = 0;
            for (const auto& e : h.events()) {
                const auto it = std::find(passOrder.begin() + std::ptrdiff_t(at), passOrder.end(), e["pass"].get<std::string>());
                REQUIRE(it != passOrder.end());
                at = std::size_t(it - passOrder.begin());
            }
            if (!h.tile().is_null()) {
                ++tiled;
                CHECK(h.tile()["lights"].size() == h.tile()["listCount"].get<std::size_t>());
                for (const auto& l : h.tile()["lights"]) CHECK(l.get<std::uint32_t>() < t.scene.lights.size());
            }
            ++pixelsChecked;
        }
    }
    CHECK(pixelsChecked == 7 * 6);
    CHECK(tiled == 3 * 6);  // forward-plus, forward-plus-amd and tiled-deferred have light lists per tile
}

} // namespace tessera_test::inspect_pixel_history_test
