// Scene loading cost: Sponza (scenes/sponza, 262,249 triangles, 49 textures at 512 px) parsed
// and decoded through tinygltf + OpenImageIO, then every texture given its mip chain
// (SceneResources), at 1 and 2 threads; and the process's peak resident memory.
// Command and results: bench/RESULTS.md.
#include <benchmark/benchmark.h>

#include <filesystem>

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

} // namespace

BENCHMARK(BM_LoadSponzaWithoutImages)->Unit(benchmark::kMillisecond)->Iterations(5);
BENCHMARK(BM_LoadSponza)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();
BENCHMARK(BM_SponzaTexturesAndMips)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();
BENCHMARK_MAIN();
