// A bundled scene (scenes/<name>.json) loaded once at a chosen size, rendered through any
// technique at any thread count; the golden check the golden tests share (render at 1 and 2
// threads, require the same bytes, compare with golden/<scene>/<name>.png); and the opaque
// pass's shading points, the ground truth of the brute-force light-list tests.
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <tessera/scene/scene_file.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/technique.h>

#include "support/golden_check.h"
#include "support/surface_compare.h"

namespace tessera::test {

class BundledScene {
public:
    // width/height 0: the scene file's resolution. Colour textures decode per `policy` (a
    // technique's TexturePolicy; techniques with different policies need separate loads).
    // generatorCount: every light generator's count (what `tessera render --lights N` does).
    BundledScene(const std::string& name, std::uint32_t width, std::uint32_t height, TexturePolicy policy,
                 std::optional<std::uint32_t> generatorCount = std::nullopt)
        : name_(name) {
        desc_ = parseSceneFile(std::filesystem::path(TESSERA_SOURCE_DIR) / "scenes" / (name + ".json"));
        if (width != 0) desc_.width = width;
        if (height != 0) desc_.height = height;
        if (generatorCount)
            for (auto& generator : desc_.generators) generator.count = *generatorCount;
        loaded_ = sharedLoad(desc_, name, policy, generatorCount);
        camera_ = resolveCamera(desc_, loaded_->scene);  // the camera's aspect follows width/height
    }

    // A technique context for this scene on `device` with `options`.
    TechniqueContext context(Device& device, const nlohmann::json& options, Precision precision = Precision::Exact) const {
        TechniqueContext ctx;
        ctx.precision = precision;
        ctx.device = &device;
        ctx.resources = &loaded_->resources;
        ctx.camera = camera_;
        ctx.width = desc_.width;
        ctx.height = desc_.height;
        ctx.options = options;
        ctx.sceneFile = desc_.file.string();
        return ctx;
    }

    // The technique's frame run once. `options`: the scene file's options when the technique is
    // the file's own, else none, unless given.
    BufferRegistry render(const std::string& technique, std::uint32_t threads,
                          const nlohmann::json* options = nullptr, DrawStats* stats = nullptr,
                          Precision precision = Precision::Exact, std::uint32_t samples = 1) const {
        return renderOn(DeviceConfig{64, threads}, technique, options, stats, precision, samples);
    }
    // The same on a device configured as `config` (tile size, threads, binned passes).
    BufferRegistry renderOn(const DeviceConfig& config, const std::string& technique, const nlohmann::json* options = nullptr,
                            DrawStats* stats = nullptr, Precision precision = Precision::Exact, std::uint32_t samples = 1) const {
        Device device(config);
        DrawStats localStats;
        TechniqueContext ctx = context(
            device, options ? *options : technique == desc_.technique ? desc_.techniqueOptions : nlohmann::json::object(),
            precision);
        ctx.stats = stats ? stats : &localStats;
        ctx.sampleCount = samples;
        BufferRegistry registry;
        buildTechnique(technique, ctx, desc_.file.string()).run(registry);
        return registry;
    }

    const std::string& name() const { return name_; }
    const SceneDescription& description() const { return desc_; }
    const Scene& scene() const { return loaded_->scene; }
    const SceneResources& resources() const { return loaded_->resources; }
    const Camera& camera() const { return camera_; }

private:
    std::string name_;
    SceneDescription desc_;
    Camera camera_;
    // The scene and its decoded textures depend on the file, the texture policy and the light
    // count, not on the size: scenes built with the same three share one load (sharedLoad).
    struct Loaded {
        Loaded(const SceneDescription& desc, TexturePolicy policy)
            : scene(loadScene(desc, true, nullptr)), resources(scene, nullptr, policy) {}
        Scene scene;
        SceneResources resources;  // holds a pointer to `scene`: Loaded never moves (shared_ptr)
    };
    std::shared_ptr<const Loaded> loaded_;

    // The most recent loads, kept so that the tests of one executable decode each bundled scene's
    // textures once rather than once per test case and technique. Bounded: Sponza's decoded
    // textures take tens of MiB, more under AddressSanitizer.
    static std::shared_ptr<const Loaded> sharedLoad(const SceneDescription& desc, const std::string& name,
                                                    TexturePolicy policy, std::optional<std::uint32_t> generatorCount) {
        constexpr std::size_t kKeptLoads = 4;
        struct Entry {
            std::string name;
            TexturePolicy policy;
            std::optional<std::uint32_t> generatorCount;
            std::shared_ptr<const Loaded> loaded;
        };
        static std::vector<Entry> recent;  // most recently used last; doctest runs cases on one thread
        for (auto it = recent.begin(); it != recent.end(); ++it) {
            if (it->name == name && it->policy == policy && it->generatorCount == generatorCount) {
                Entry hit = std::move(*it);
                recent.erase(it);
                recent.push_back(std::move(hit));
                return recent.back().loaded;
            }
        }
        auto loaded = std::make_shared<const Loaded>(desc, policy);
        if (recent.size() == kKeptLoads) recent.erase(recent.begin());
        recent.push_back({name, policy, generatorCount, loaded});
        return loaded;
    }
};

// The names of the bundled scenes (scenes/*.json), sorted. Fails the calling test unless the
// three scenes the README lists are among them, so a loop over the names cannot pass by running
// over nothing (a moved scenes/ folder, a wrong TESSERA_SOURCE_DIR).
std::vector<std::string> bundledSceneNames();

// The bound stated for `key` in a test's table of measured bounds (false-positive ratios of the
// culling tests); fails the calling test when none is stated, so a new scene or option needs one.
inline double statedBound(const std::map<std::string, double>& bounds, const std::string& key) {
    const auto it = bounds.find(key);
    REQUIRE_MESSAGE(it != bounds.end(), "no bound stated for " << key);
    return it->second;
}

// The opaque pass's shading points: (posView, SV_Position.z) per pixel, w = -1 where no opaque
// geometry; the same draws and states as forward's OpaquePass (forward.h), with a pixel shader
// that writes the interpolated view position (bundled_scene.cpp: instantiated once).
Surface opaqueShadingPoints(const SceneResources& res, const ForwardPassSetup& setup, Device& device,
                            std::uint32_t width, std::uint32_t height);

// Renders `technique` at 1 and 2 threads, checks that the back buffers hold the same bytes, and
// compares the image with golden/<scene>/<goldenName>.png (goldenName defaults to the technique).
inline void checkGoldenAtOneAndTwoThreads(const BundledScene& scene, const std::string& technique,
                                          const std::string& goldenName = {}, std::uint32_t samples = 1) {
    BufferRegistry one = scene.render(technique, 1, nullptr, nullptr, Precision::Exact, samples);
    BufferRegistry two = scene.render(technique, 2, nullptr, nullptr, Precision::Exact, samples);
    CHECK(sameBytes(one.get(kBackBufferName), two.get(kBackBufferName)));
    if (samples > 1) CHECK(sameBytes(one.get(backBufferTarget(samples)), two.get(backBufferTarget(samples))));
    checkGolden(one.get(kBackBufferName), scene.name(), goldenName.empty() ? technique : goldenName);
}

// The per-technique golden of a bundled scene at 320x180 with the technique's default options,
// rendered at 1 and 2 threads (golden/<scene>/<technique>.png).
inline void checkSmallGolden(const std::string& scene, const std::string& technique) {
    const TechniqueInfo* info = findTechnique(technique);
    REQUIRE(info != nullptr);
    checkGoldenAtOneAndTwoThreads(BundledScene(scene, 320, 180, info->textures), technique);
}

} // namespace tessera::test
