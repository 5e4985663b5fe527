// `forward-plus` on every bundled scene (scenes/*.json, 320x180): the SPEC's Forward+ invariants
// — the opaque image equals forward's bit for bit, every light that reaches a pixel is in that
// pixel's tile list (brute force over pixels and lights), binned culling equals the brute-force
// loop, the culling outputs are identical at 1 and 2 threads — and the golden images.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <set>

#include <tessera/scene/scene_file.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/forward_plus.h>
#include <tessera/techniques/technique.h>

#include "support/bundled_scene.h"
#include "support/golden_check.h"

#include "support/surface_compare.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::golden_forward_plus_scenes_test {

using namespace tessera;

namespace {

using test::sameBytes;
using test::differingPixels;

constexpr std::uint32_t kWidth = 320, kHeight = 180;

// Loaded once per scene for all the cases of this file. "NAME@N": the scene with every light
// generator's count set to N (what `tessera render --lights N` does).
const test::BundledScene& loaded(const std::string& name) {
    static std::map<std::string, std::unique_ptr<test::BundledScene>> cache;
    auto& slot = cache[name];
    if (!slot) {
        const std::size_t at = name.find('@');
        std::optional<std::uint32_t> count;
        if (at != std::string::npos) count = static_cast<std::uint32_t>(std::stoul(name.substr(at + 1)));
        slot = std::make_unique<test::BundledScene>(name.substr(0, at), kWidth, kHeight, TexturePolicy::AllLinear, count);
    }
    return *slot;
}

// Runs the technique's passes, all of them or all but the last ("transparent").
void run(const std::string& scene, const std::string& technique, const nlohmann::json& options, BufferRegistry& registry,
         std::uint32_t threads = 2, bool withoutTransparent = false) {
    const test::BundledScene& s = loaded(scene);
    Device device(DeviceConfig{64, threads});
    const Frame frame = buildTechnique(technique, s.context(device, options), s.description().file.string());
    Frame partial;
    for (const Pass& pass : frame.passes())
        if (!(withoutTransparent && pass.name == "transparent")) partial.add(pass);
    partial.run(registry);
}

struct ListCheck {
    std::uint64_t pixels = 0, reaching = 0, missing = 0;
    std::uint64_t listed = 0;  // (pixel, listed light) pairs: reaching + false positives
    double listedPerReaching() const { return reaching ? double(listed) / double(reaching) : 0.0; }
};

// For every covered pixel and every light whose contribution there is not exactly zero by
// distance and cone alone (enabled; directional, or length(PositionVS - P) <= Range with
// DoAttenuation > 0, and for spots DoSpotCone > 0), the light must be in the pixel's opaque tile
// list. (N.L and the specular term are left out: the culling is geometric, so this only asks
// for more lights than strictly necessary.)
// Upper bounds on (pixel, listed light) pairs per (pixel, reaching light) pair for the
// conservativeness test below (coneTest corrected, 320x180). Measured on commit 0a61d5f:
// see the values in each comment; each bound is the measured ratio plus 10% (the scenes, lights
// and culling are deterministic, so the margin only absorbs deliberate scene edits). A culler that
// keeps every light gives ratios of 3-100x.
double listedPerReachingBound(const std::string& scene, int tileSize) {
    static const std::map<std::string, double> bounds = {
        {"default/8", 1.23},               // measured 1.1185 (the 4 lights reach nearly every tile)
        {"default/16", 1.23},              // 1.1185
        {"default/32", 1.23},              // 1.1185
        {"sponza-large-lights/8", 1.48},   // 1.3451
        {"sponza-large-lights/16", 1.49},  // 1.3553
        {"sponza-large-lights/32", 1.52},  // 1.3810
        {"sponza-small-lights/8", 21.3},   // 19.384 (799 reaching pairs; no culling lists every light)
        {"sponza-small-lights/16", 30.7},  // 27.875
        {"sponza-small-lights/32", 79.0},  // 71.770
        {"sponza-sun/8", 1.47},            // 1.3338 (measured on the commit that added the scene)
        {"sponza-sun/16", 1.61},           // 1.4576
        {"sponza-sun/32", 2.31},           // 2.0976
    };
    return test::statedBound(bounds, scene + "/" + std::to_string(tileSize));
}

ListCheck checkOpaqueLists(const std::string& scene, const nlohmann::json& options) {
    const test::BundledScene& s = loaded(scene);
    Device device(DeviceConfig{64, 2});
    const TechniqueContext ctx = s.context(device, options);
    const bool d3d = options.contains("projection") && options["projection"] == "d3d";
    const auto setup = makeForwardPassSetup(ctx, d3d ? ProjectionConvention::D3d : ProjectionConvention::DemoGl,
                                            PhongSamplerChoice::Demo, false);
    const Surface positions = test::opaqueShadingPoints(s.resources(), *setup, device, kWidth, kHeight);
    BufferRegistry reg;
    run(scene, "forward-plus", options, reg, 2, true);
    const Surface& grid = reg.get("lightgrid.opaque");
    const Surface& list = reg.get("lightindex.opaque");
    const std::uint32_t tile = options.contains("tileSize") ? options["tileSize"].get<std::uint32_t>() : 16u;
    const std::span<const ViewLight<float>> lights = setup->lightsExact;
    ListCheck check;
    for (std::uint32_t y = 0; y < kHeight; ++y)
        for (std::uint32_t x = 0; x < kWidth; ++x) {
            const glm::vec4 p = positions.load(x, y);
            if (p.w < 0.0f) continue;  // no opaque geometry
            ++check.pixels;
            const glm::uvec2 cell(grid.loadUint(x / tile, y / tile));
            std::set<std::uint32_t> listed;
            for (std::uint32_t i = 0; i < cell.y; ++i) {
                const std::uint32_t e = cell.x + i;
                listed.insert(list.loadUint(e % list.width(), e / list.width()).x);
            }
            check.listed += listed.size();
            for (std::uint32_t l = 0; l < lights.size(); ++l) {
                const ViewLight<float>& light = lights[l];
                if (!light.enabled) continue;
                if (light.type != LightType::Directional) {
                    const Vec4<float> toLight = light.positionView - p;
                    const float distance = hlsl::length(toLight);
                    if (distance > light.range || doAttenuation(light, distance) <= 0.0f) continue;
                    if (light.type == LightType::Spot && doSpotCone(light, toLight / distance) <= 0.0f) continue;
                }
                ++check.reaching;
                if (!listed.count(l)) ++check.missing;
            }
        }
    return check;
}

} // namespace

TEST_CASE("forward-plus scenes: on opaque geometry the image equals forward's bit for bit") {
    for (const std::string& scene : test::bundledSceneNames()) {
        for (const char* projection : {"demo-gl", "d3d"}) {
            CAPTURE(scene);
            CAPTURE(projection);
            BufferRegistry forward, plus;
            run(scene, "forward", {{"projection", projection}}, forward, 2, true);
            run(scene, "forward-plus", {{"projection", projection}, {"coneTest", "corrected"}}, plus, 2, true);
            const int differing = differingPixels(forward.get(kBackBufferName), plus.get(kBackBufferName));
            MESSAGE(scene << " " << std::string(projection) << ": " << differing << " pixels differ from forward");
            CHECK(differing == 0);
        }
    }
}

TEST_CASE("forward-plus scenes: every light that reaches a pixel is in its tile's opaque list") {
    for (const std::string& scene : test::bundledSceneNames()) {
        for (const int tile : {8, 16, 32}) {
            CAPTURE(scene);
            CAPTURE(tile);
            const ListCheck c = checkOpaqueLists(scene, {{"tileSize", tile}, {"coneTest", "corrected"}});
            MESSAGE(scene << " tile " << tile << ": " << c.pixels << " pixels, " << c.reaching << " (pixel, light) pairs, "
                          << c.missing << " missing, " << c.listed << " listed = " << c.listedPerReaching() << " per reaching pair");
            CHECK(c.pixels > 0);
            CHECK(c.reaching > 0);
            CHECK(c.missing == 0);
            // The culler must cull: listed pairs over reaching pairs stays under the bound measured
            // for this scene and tile size (kListedPerReachingBound, with its margin).
            CHECK(c.listedPerReaching() <= listedPerReachingBound(scene, tile));
        }
    }
}

TEST_CASE("forward-plus scenes: 1024 small lights in Sponza, every light that reaches a pixel is listed") {
    // The article's small-lights scenario (range 1..2) with 1024 lights: many tiles, many lists.
    const ListCheck c = checkOpaqueLists("sponza-small-lights@1024", {{"coneTest", "corrected"}});
    MESSAGE("sponza-small-lights@1024: " << c.pixels << " pixels, " << c.reaching << " (pixel, light) pairs, " << c.missing
                                         << " missing");
    CHECK(c.reaching > 10000);
    CHECK(c.missing == 0);
    BufferRegistry forward, plus;
    run("sponza-small-lights@1024", "forward", {}, forward, 2, true);
    run("sponza-small-lights@1024", "forward-plus", {{"coneTest", "corrected"}}, plus, 2, true);
    CHECK(differingPixels(forward.get(kBackBufferName), plus.get(kBackBufferName)) == 0);
}

TEST_CASE("forward-plus scenes: the article's cone test (coneTest demo) drops no light here") {
    // ERRATUM (culling/plane.h coneInsidePlane): m = cross(cross(N, d), d) is not normalized, so Q
    // falls short of the cone's rim and a cone that reaches into a tile can be culled
    // (tests/culling/culling_property_test.cpp). Measured on these scenes: it never happens, so the
    // faithful default equals forward as well. Missing lights and differing pixels must agree.
    for (const std::string scene : {"default", "sponza-large-lights", "sponza-small-lights@1024"}) {
        CAPTURE(scene);
        const ListCheck faithful = checkOpaqueLists(scene, {});
        BufferRegistry forward, plus;
        run(scene, "forward", {}, forward, 2, true);
        run(scene, "forward-plus", {}, plus, 2, true);
        const int differing = differingPixels(forward.get(kBackBufferName), plus.get(kBackBufferName));
        MESSAGE(scene << " coneTest demo: " << faithful.missing << " of " << faithful.reaching
                      << " (pixel, light) pairs missing; " << differing << " pixels differ from forward");
        CHECK(faithful.missing == 0);
        CHECK(differing == 0);
    }
}

TEST_CASE("forward-plus scenes: binned culling equals the brute-force loop, outputs equal at 1 and 2 threads") {
    for (const std::string& scene : test::bundledSceneNames()) {
        CAPTURE(scene);
        BufferRegistry binned, brute, one;
        run(scene, "forward-plus", {}, binned, 2);
        run(scene, "forward-plus", {{"culling", "brute"}}, brute, 2);
        run(scene, "forward-plus", {}, one, 1);
        for (const char* name : {"lightgrid.opaque", "lightgrid.transparent", "lightindex.opaque", "lightindex.transparent",
                                 "heatmap", "lightlist.counters", "backbuffer"}) {
            CAPTURE(name);
            CHECK(sameBytes(binned.get(name), brute.get(name)));
            CHECK(sameBytes(binned.get(name), one.get(name)));
        }
    }
}

} // namespace tessera_test::golden_forward_plus_scenes_test
