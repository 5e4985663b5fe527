// Per-pass frame times of the scene techniques on the 3dgep experiment (article §5): Sponza at
// 1280x720 with N generated lights (large: range 35-40, small: range 1-2), median over frames
// after a warm-up, at each thread count. Prints a markdown table; command and results in
// bench/RESULTS.md.
//
// Usage: technique_bench [--techniques forward,deferred] [--scenario large|small]
//                        [--lights 1,2,4,...] [--threads 1,2] [--frames 5] [--warmup 1]
//                        [--width 1280 --height 720] [--options '{"tileSize": 8}']
//                        [--msaa 4] (MSAA: adds the edge-pixel and per-sample shares)
//                        [--shadows] [--range 4,8]  (forward-plus-amd, GPU Pro 4 §5.6.2: every light
//                        casts ray-cast shadows; --range sets the generated lights' range; adds the
//                        rays, the ray-casting pass and rays per second per thread)
#include <algorithm>
#include <chrono>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <tessera/scene/scene_file.h>
#include <tessera/techniques/technique.h>

#include "bench_support.h"

namespace {

using namespace tessera;
using bench::median;
using bench::split;
using bench::splitUints;

} // namespace

int main(int argc, char** argv) {
    bench::useSteadyStateAllocator();
    std::vector<std::string> techniquesToRun = {"forward", "deferred"};
    std::string scenario = "large";
    std::vector<std::uint32_t> lightCounts = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512};
    std::vector<std::uint32_t> threadCounts = {1, 2};
    std::uint32_t frames = 5, warmup = 1, width = 1280, height = 720, msaa = 1;
    std::optional<nlohmann::json> options;  // --options: technique options for every technique run
    bool shadows = false;
    std::optional<glm::vec2> range;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--shadows") {
            shadows = true;
            continue;
        }
        if (i + 1 >= argc) {
            std::fprintf(stderr, "%s needs a value\n", a.c_str());
            return 2;
        }
        const std::string v = argv[++i];
        if (a == "--techniques") techniquesToRun = split(v, ',');
        else if (a == "--scenario") scenario = v;
        else if (a == "--lights") lightCounts = splitUints(a, v);
        else if (a == "--threads") threadCounts = splitUints(a, v);
        else if (a == "--frames") frames = std::max(1u, splitUints(a, v).at(0));
        else if (a == "--warmup") warmup = splitUints(a, v).at(0);
        else if (a == "--width") width = splitUints(a, v).at(0);
        else if (a == "--height") height = splitUints(a, v).at(0);
        else if (a == "--msaa") msaa = splitUints(a, v).at(0);
        else if (a == "--range") {
            const std::vector<std::string> ends = split(v, ',');
            if (ends.size() != 2) {
                std::fprintf(stderr, "--range: '%s' is not LO,HI\n", v.c_str());
                return 2;
            }
            range = glm::vec2(std::stof(ends[0]), std::stof(ends[1]));
        }
        else if (a == "--options") {
            options = nlohmann::json::parse(v, nullptr, false);
            if (options->is_discarded() || !options->is_object()) {
                std::fprintf(stderr, "--options: '%s' is not a JSON object\n", v.c_str());
                return 2;
            }
        }
        else {
            std::fprintf(stderr, "unknown option %s\n", a.c_str());
            return 2;
        }
    }
    if (scenario != "large" && scenario != "small") {
        std::fprintf(stderr, "--scenario: '%s' is not large or small\n", scenario.c_str());
        return 2;
    }
    for (const std::string& t : techniquesToRun) {
        const TechniqueInfo* info = findTechnique(t);
        if (!info || !info->build) {
            std::fprintf(stderr, "--techniques: '%s' is not an implemented technique\n", t.c_str());
            return 2;
        }
    }

    // One load with the largest count: a generator draws its lights one after another from one
    // PCG32 stream, so the first N of a count-M generator are exactly a count-N generator's lights.
    // TESSERA_SOURCE_DIR in the environment overrides the build's source tree (for running the
    // binary on another machine, bench/RESULTS.md).
    const char* sourceDirEnv = std::getenv("TESSERA_SOURCE_DIR");
    const std::filesystem::path file = std::filesystem::path(sourceDirEnv ? sourceDirEnv : TESSERA_SOURCE_DIR) / "scenes" /
                                       ("sponza-" + scenario + "-lights.json");
    SceneDescription desc = parseSceneFile(file);
    const std::uint32_t maxLights = lightCounts.empty() ? 0 : *std::max_element(lightCounts.begin(), lightCounts.end());
    for (auto& g : desc.generators) {
        g.count = maxLights;
        if (range) g.range = *range;
    }
    Camera camera;
    Scene scene = loadScene(desc, true, &camera);
    if (shadows)
        for (Light& l : scene.lights) l.castsShadows = true;
    const std::vector<Light> allLights = scene.lights;
    // The techniques measured together must agree on how textures are decoded.
    const TexturePolicy policy = findTechnique(techniquesToRun.at(0))->textures;
    for (const std::string& t : techniquesToRun)
        if (findTechnique(t)->textures != policy) {
            std::fprintf(stderr, "--techniques: '%s' decodes textures differently from '%s'; run them separately\n", t.c_str(),
                         techniquesToRun[0].c_str());
            return 2;
        }
    const SceneResources resources(scene, {}, policy);

    if (msaa > 1)
        std::printf("| technique | lights | threads | msaa | passes (median ms) | frame ms | edge pixels | PS calls per sample |\n"
                    "|---|---|---|---|---|---|---|---|\n");
    else if (shadows)
        std::printf("| technique | lights | threads | passes (median ms) | frame ms | shadow rays | occluded | M rays/s per thread |\n"
                    "|---|---|---|---|---|---|---|---|\n");
    else std::printf("| technique | lights | threads | passes (median ms) | frame ms |\n|---|---|---|---|---|\n");
    for (const std::string& technique : techniquesToRun)
        for (const std::uint32_t n : lightCounts)
            for (const std::uint32_t threads : threadCounts) {
                scene.lights.assign(allLights.begin(), allLights.begin() + std::min<std::size_t>(n, allLights.size()));
                Device device(DeviceConfig{64, threads});
                DrawStats stats;
                TechniqueContext ctx;
                ctx.device = &device;
                ctx.resources = &resources;
                ctx.camera = camera;
                ctx.width = width;
                ctx.height = height;
                ctx.sampleCount = msaa;
                ctx.options = options ? *options : technique == desc.technique ? desc.techniqueOptions : nlohmann::json::object();
                ctx.stats = &stats;
                std::optional<Frame> built;
                try {
                    built.emplace(buildTechnique(technique, ctx, file.string()));
                } catch (const std::exception& e) {
                    std::fprintf(stderr, "%s\n", e.what());
                    return 2;
                }
                const Frame& frame = *built;
                std::map<std::string, std::vector<double>> passMs;
                std::vector<std::string> order;
                std::vector<double> frameMs;
                // Warm-up frames are dropped, except that one over 2 s is kept as a measurement
                // and ends the warm-up: its first-touch costs are far below the run-to-run
                // spread, and the long sweeps stay affordable.
                std::uint32_t warmupLeft = warmup;
                std::uint32_t rayCounters[5] = {};  // "shadow.counters" of the last run
                while (frameMs.size() < frames) {
                    BufferRegistry registry;
                    const auto t0 = std::chrono::steady_clock::now();
                    const auto timings = frame.run(registry);
                    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
                    if (warmupLeft > 0) {
                        --warmupLeft;
                        if (ms < 2000.0) continue;
                        warmupLeft = 0;
                    }
                    frameMs.push_back(ms);
                    if (const Surface* c = registry.find("shadow.counters")) std::memcpy(rayCounters, c->bytes().data(), sizeof(rayCounters));
                    for (const PassTiming& t : timings) {
                        if (!passMs.count(t.name)) order.push_back(t.name);
                        passMs[t.name].push_back(t.milliseconds);
                    }
                }
                std::string passes;
                for (const std::string& name : order) {
                    char buf[96];
                    std::snprintf(buf, sizeof buf, "%s%s %.2f", passes.empty() ? "" : ", ", name.c_str(), median(passMs[name]));
                    passes += buf;
                }
                if (msaa > 1) {
                    // Counters summed over every run, so shares: edge pixels of those classified,
                    // per-sample pixel-shader calls of all calls.
                    const double edges = stats.edgeTestedPixels ? 100.0 * double(stats.edgePixels) / double(stats.edgeTestedPixels) : 0.0;
                    const double perSample = stats.psInvocations ? 100.0 * double(stats.psPerSample) / double(stats.psInvocations) : 0.0;
                    std::printf("| %s | %u | %u | %u | %s | %.2f | %.2f%% | %.2f%% |\n", technique.c_str(), n, threads, msaa, passes.c_str(),
                                median(frameMs), edges, perSample);
                } else if (shadows) {
                    const double rayMs = passMs.count("shadow-rays") ? median(passMs["shadow-rays"]) : 0.0;
                    const double perThread = rayMs > 0.0 ? double(rayCounters[0]) / (rayMs * 1e-3) / 1e6 / double(threads) : 0.0;
                    std::printf("| %s | %u | %u | %s | %.2f | %u | %u | %.2f |\n", technique.c_str(), n, threads, passes.c_str(),
                                median(frameMs), rayCounters[0], rayCounters[1], perThread);
                } else {
                    std::printf("| %s | %u | %u | %s | %.2f |\n", technique.c_str(), n, threads, passes.c_str(), median(frameMs));
                }
                std::fflush(stdout);
            }
    return 0;
}
