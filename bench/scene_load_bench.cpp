// Scene loading cost: Sponza (scenes/sponza, 262,249 triangles, 49 textures at 512 px) parsed
// and decoded through tinygltf + OpenImageIO, then every texture given its mip chain
// (SceneResources), at 1 and 2 threads; and the process's peak resident memory. And a scene file
// of N explicit lights (up to the documented 1,000,000), parsed and loaded: linear in N.
// Command and results: bench/RESULTS.md.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include <sys/resource.h>
#include <tbb/global_control.h>

#include <tessera/scene/scene_file.h>
#include <tessera/scene/scene_resources.h>

namespace {

using namespace tessera;

const std::filesystem::path kSponza = std::filesystem::path(TESSERA_SOURCE_DIR) / "scenes" / "sponza-large-lights.json";

double peakRssMiB() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;  // Linux: ru_maxrss in KiB
}

void BM_LoadSponza(benchmark::State& state) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(state.range(0)));
    const SceneDescription desc = parseSceneFile(kSponza);
    std::size_t triangles = 0;
    for (auto _ : state) {
        const Scene scene = loadScene(desc, true);
        triangles = scene.triangleCount();
        benchmark::DoNotOptimize(triangles);
    }
    state.counters["triangles"] = double(triangles);
    state.counters["peakRssMiB"] = peakRssMiB();
}

void BM_LoadSponzaWithoutImages(benchmark::State& state) {
    const SceneDescription desc = parseSceneFile(kSponza);
    for (auto _ : state) benchmark::DoNotOptimize(loadScene(desc, false).triangleCount());
    state.counters["peakRssMiB"] = peakRssMiB();
}

void BM_SponzaTexturesAndMips(benchmark::State& state) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(state.range(0)));
    const Scene scene = loadScene(parseSceneFile(kSponza), true);
    std::size_t bytes = 0, textures = 0;
    for (auto _ : state) {
        const SceneResources resources(scene);
        bytes = resources.textureBytes();
        textures = resources.textureCount();
    }
    state.counters["textures"] = double(textures);
    state.counters["textureMiB"] = double(bytes) / (1024.0 * 1024.0);
    state.counters["peakRssMiB"] = peakRssMiB();
}

// A scene file of `count` explicit point lights, as `tessera info` reads it: no models, every
// light with a name, position, range, colour and intensity (about 110 bytes each: 1,000,000
// lights make a 110 MB file). Positions from a fixed integer sequence, so the text is the same
// on every run.
std::string explicitLightsFile(std::size_t count) {
    // One small model (a scene file needs at least one): the Box's load is a constant next to the lights'.
    const std::string box = (std::filesystem::path(TESSERA_SOURCE_DIR) / "scenes" / "khronos" / "Box" / "glTF" / "Box.gltf").string();
    std::string text = R"({"models": [{"path": ")" + box + R"("}], "camera": {"position": [0, 3, 8], "target": [0, 0, 0]}, "lights": [)";
    text.reserve(count * 120 + 200);
    for (std::size_t i = 0; i < count; ++i) {
        if (i) text += ",\n";
        const int x = int(i % 200) - 100, y = int(i / 200 % 100), z = int(i / 20000 % 200) - 100;  // a 200x100x200 grid, units
        text += R"({"type": "point", "name": "light )" + std::to_string(i) + R"(", "position": [)" + std::to_string(x) + ".25, " +
                std::to_string(y) + ".5, " + std::to_string(z) + R"(.75], "range": 1.5, "color": [1, 0.5, 0.25], "intensity": 1})";
    }
    text += "]}";
    return text;
}

void BM_LoadExplicitLights(benchmark::State& state) {
    const std::size_t count = std::size_t(state.range(0));
    const std::string text = explicitLightsFile(count);
    std::size_t lights = 0;
    for (auto _ : state) {
        const SceneDescription desc = parseSceneJson(text, "lights.json");
        lights = loadScene(desc, false).lights.size();
        benchmark::DoNotOptimize(lights);
    }
    state.counters["lights"] = double(lights);
    state.counters["fileMB"] = double(text.size()) / 1e6;
    state.counters["peakRssMiB"] = peakRssMiB();
}

} // namespace

BENCHMARK(BM_LoadExplicitLights)->Arg(90000)->Arg(270000)->Arg(1000000)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_LoadSponzaWithoutImages)->Unit(benchmark::kMillisecond)->Iterations(5);
BENCHMARK(BM_LoadSponza)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();
BENCHMARK(BM_SponzaTexturesAndMips)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();
BENCHMARK_MAIN();
