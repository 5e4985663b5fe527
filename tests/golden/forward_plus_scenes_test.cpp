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

#include "support/golden_check.h"

#include "support/surface_compare.h"

using namespace tessera;

namespace {

using test::sameBytes;
using test::differingPixels;

constexpr std::uint32_t kWidth = 320, kHeight = 180;

std::vector<std::string> bundledScenes() {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(TESSERA_SOURCE_DIR) / "scenes"))
        if (entry.path().extension() == ".json" && entry.path().filename() != "scene.schema.json")
            names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

struct LoadedScene {
    SceneDescription desc;
    Camera camera;
    std::unique_ptr<Scene> scene;
    std::unique_ptr<SceneResources> resources;
};

// Loaded once per scene for all the cases of this file. "NAME@N": the scene with every light
// generator's count set to N (what `tessera render --lights N` does).
const LoadedScene& loaded(const std::string& name) {
    static std::map<std::string, std::unique_ptr<LoadedScene>> cache;
    auto& slot = cache[name];
    if (!slot) {
        slot = std::make_unique<LoadedScene>();
        const std::size_t at = name.find('@');
        slot->desc = parseSceneFile(std::filesystem::path(TESSERA_SOURCE_DIR) / "scenes" / (name.substr(0, at) + ".json"));
        if (at != std::string::npos)
            for (auto& generator : slot->desc.generators) generator.count = static_cast<std::uint32_t>(std::stoul(name.substr(at + 1)));
        slot->desc.width = kWidth;
        slot->desc.height = kHeight;
        slot->scene = std::make_unique<Scene>(loadScene(slot->desc, true, &slot->camera));
        slot->resources = std::make_unique<SceneResources>(*slot->scene, std::function<void(std::size_t, std::size_t)>{}, TexturePolicy::AllLinear);
    }
    return *slot;
}

TechniqueContext contextFor(const LoadedScene& s, Device& device, const nlohmann::json& options) {
    TechniqueContext ctx;
    ctx.device = &device;
    ctx.resources = s.resources.get();
    ctx.camera = s.camera;
    ctx.width = kWidth;
    ctx.height = kHeight;
    ctx.options = options;
    ctx.sceneFile = s.desc.file.string();
    return ctx;
}

// Runs the technique's passes, all of them or all but the last ("transparent").
void run(const std::string& scene, const std::string& technique, const nlohmann::json& options, BufferRegistry& registry,
         std::uint32_t threads = 2, bool withoutTransparent = false) {
    const LoadedScene& s = loaded(scene);
    Device device(DeviceConfig{64, threads});
    const Frame frame = buildTechnique(technique, contextFor(s, device, options), s.desc.file.string());
    Frame partial;
    for (const Pass& pass : frame.passes())
        if (!(withoutTransparent && pass.name == "transparent")) partial.add(pass);
    partial.run(registry);
}

// The interpolated posView the forward opaque pass shades at each pixel: the same draws and
// states as forward's OpaquePass, with a pixel shader that writes (posView, 1).
struct PositionPS {
    using Varyings = PhongVaryings;
    static constexpr int kTargetCount = 1;
    void operator()(const PixelInput<PhongVaryings>& in, PixelOutput<1>& out) const {
        out.target[0] = glm::vec4(in.varyings.posView, 1.0f);
    }
};

Surface opaquePositions(const LoadedScene& s, const ForwardPassSetup& setup, Device& device) {
    Surface position({kWidth, kHeight, Format::R32G32B32A32_FLOAT, 1});
    position.clearColor(glm::vec4(0.0f));  // w = 0: no geometry
    Surface depth({kWidth, kHeight, Format::D24_UNORM_S8_UINT, 1});
    depth.clearDepthStencil(true, 1.0f, true, 0);
    RenderTargets rt;
    rt.colors[0] = &position;
    rt.depthStencil = &depth;
    const SceneResources& res = *s.resources;
    for (const DrawItem& item : res.drawItems()) {
        const PhongMaterial material = phongFromGltf(res.material(item.material));
        if (material.isTransparent()) continue;
        DrawState st;
        st.viewport = Viewport{0.0f, 0.0f, float(kWidth), float(kHeight), 0.0f, 1.0f};
        st.rasterizer.frontCounterClockwise = item.frontCounterClockwise;
        st.rasterizer.cullMode = material.doubleSided ? CullMode::None : CullMode::Back;
        const glm::mat4 viewFromObject = setup.viewFromWorld * item.worldFromObject;
        const PhongVS vs{setup.clipFromView * viewFromObject, viewFromObject};
        const PrimitiveBuffer& prim = res.primitives()[item.primitive];
        device.draw(st, rt, std::span<const SceneVertex>(prim.vertices), prim.indices, vs, PositionPS{});
    }
    return position;
}

struct ListCheck {
    std::uint64_t pixels = 0, reaching = 0, missing = 0;
};

// For every covered pixel and every light whose contribution there is not exactly zero by
// distance and cone alone (enabled; directional, or length(PositionVS - P) <= Range with
// DoAttenuation > 0, and for spots DoSpotCone > 0), the light must be in the pixel's opaque tile
// list. (N.L and the specular term are left out: the culling is geometric, so this only asks
// for more lights than strictly necessary.)
ListCheck checkOpaqueLists(const std::string& scene, const nlohmann::json& options) {
    const LoadedScene& s = loaded(scene);
    Device device(DeviceConfig{64, 2});
    const TechniqueContext ctx = contextFor(s, device, options);
    const bool d3d = options.contains("projection") && options["projection"] == "d3d";
    const auto setup = makeForwardPassSetup(ctx, d3d ? ProjectionConvention::D3d : ProjectionConvention::DemoGl,
                                            PhongSamplerChoice::Demo, false);
    const Surface positions = opaquePositions(s, *setup, device);
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
            if (p.w == 0.0f) continue;
            ++check.pixels;
            const glm::uvec2 cell(grid.loadUint(x / tile, y / tile));
            std::set<std::uint32_t> listed;
            for (std::uint32_t i = 0; i < cell.y; ++i) {
                const std::uint32_t e = cell.x + i;
                listed.insert(list.loadUint(e % list.width(), e / list.width()).x);
            }
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
    for (const std::string& scene : bundledScenes()) {
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
    for (const std::string& scene : bundledScenes()) {
        for (const int tile : {8, 16, 32}) {
            CAPTURE(scene);
            CAPTURE(tile);
            const ListCheck c = checkOpaqueLists(scene, {{"tileSize", tile}, {"coneTest", "corrected"}});
            MESSAGE(scene << " tile " << tile << ": " << c.pixels << " pixels, " << c.reaching << " (pixel, light) pairs, "
                          << c.missing << " missing");
            CHECK(c.pixels > 0);
            CHECK(c.reaching > 0);
            CHECK(c.missing == 0);
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
    // ERRATUM (math/plane.h coneInsidePlane): m = cross(cross(N, d), d) is not normalized, so Q
    // falls short of the cone's rim and a cone that reaches into a tile can be culled
    // (tests/unit/culling_property_test.cpp). Measured on these scenes: it never happens, so the
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
    for (const std::string& scene : bundledScenes()) {
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

TEST_CASE("golden: default scene, forward-plus, 320x180") {
    BufferRegistry reg;
    run("default", "forward-plus", {}, reg, 2);
    test::checkGolden(reg.get(kBackBufferName), "default", "forward-plus");
}

TEST_CASE("golden: Sponza with 64 large lights, forward-plus, 320x180") {
    BufferRegistry reg;
    run("sponza-large-lights", "forward-plus", {}, reg, 2);
    test::checkGolden(reg.get(kBackBufferName), "sponza-large-lights", "forward-plus");
}
