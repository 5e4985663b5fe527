// Throughput against the machine's own limits, measured in one run: the light loop in light-pixel
// evaluations per second (fast's SIMD loop, exact's float loop, reference's double loop) beside
// the core's measured peak of vector multiply-adds, and the clears' fill rate (buffers/fill.h)
// beside memset and a copy on the same buffer. Prints Markdown; see bench/RESULTS.md.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "throughput_bench.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>
#include <hwy/targets.h>

// The core's multiply-add peak, compiled per SIMD target and dispatched like the library's
// kernels: 12 independent accumulator chains, enough to cover FMA latency x ports on current
// x86 cores. Returns vector MulAdds per second; lanes = floats per vector.
HWY_BEFORE_NAMESPACE();
namespace peak::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
double MulAddsPerSecond(std::size_t* lanes) {
    const hn::ScalableTag<float> d;
    *lanes = hn::Lanes(d);
    constexpr int kChains = 12;
    constexpr long kIterations = 20'000'000;
    double best = 1e30;
    float sink = 0.0f;
    for (int r = 0; r < 3; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        hn::Vec<decltype(d)> acc[kChains];
        for (int c = 0; c < kChains; ++c) acc[c] = hn::Set(d, float(c) * 1e-3f);
        const auto m = hn::Set(d, 0.999999f), a = hn::Set(d, 1e-7f);
        for (long i = 0; i < kIterations; ++i)
            for (int c = 0; c < kChains; ++c) acc[c] = hn::MulAdd(acc[c], m, a);
        for (int c = 0; c < kChains; ++c) sink += hn::GetLane(acc[c]);
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    if (sink == 12345.0f) std::puts("");  // keeps the loop
    return double(kIterations) * kChains / best;
}
const char* Target() { return hwy::TargetName(HWY_TARGET); }
} // namespace peak::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace peak {
HWY_EXPORT(MulAddsPerSecond);
HWY_EXPORT(Target);
} // namespace peak

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <tessera/buffers/fill.h>
#include <tessera/shading/fast_lighting.h>
#include <tessera/shading/phong_lighting.h>

#include "bench_support.h"

using namespace tessera;

namespace {

using Clock = std::chrono::steady_clock;

template <class F>
double bestSeconds(int repeats, F&& f) {
    double best = 1e30;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = Clock::now();
        f();
        best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
    }
    return best;
}

struct Surfaces {
    std::vector<glm::vec3> posView, normalView;
};

Surfaces makeSurfaces(std::size_t count) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    Surfaces s;
    for (std::size_t i = 0; i < count; ++i) {
        s.posView.emplace_back(u(rng), u(rng), -5.0f + u(rng));
        glm::vec3 n(u(rng), u(rng), 1.0f);
        s.normalView.push_back(glm::normalize(n));
    }
    return s;
}

// Half point, half spot lights around the surfaces, every one in range (range 100 view units),
// so every light is evaluated in full at every pixel: the loop's worst and steady case.
std::vector<ViewLight<float>> makeLights(std::size_t count) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-2.0f, 2.0f);
    std::vector<ViewLight<float>> lights(count);
    for (std::size_t i = 0; i < count; ++i) {
        ViewLight<float>& l = lights[i];
        l.positionView = glm::vec4(u(rng), u(rng), -3.0f + u(rng), 1.0f);
        l.directionView = glm::vec4(glm::normalize(glm::vec3(u(rng) * 0.2f, u(rng) * 0.2f, -1.0f)), 0.0f);
        l.type = i % 2 == 0 ? LightType::Point : LightType::Spot;
        l.range = 100.0f;
        l.spotlightAngleDeg = 60.0f;
        l.color = glm::vec4(0.5f, 0.6f, 0.7f, 1.0f);
        cacheSpotCone(l);
    }
    return lights;
}

template <class F>
double lightEvalsPerSecond(unsigned threads, const Surfaces& s, std::size_t lightCount, F&& shadeOne) {
    tbb::task_arena arena{int(threads)};
    float sink = 0.0f;
    const double seconds = bestSeconds(3, [&] {
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.posView.size(), 64), [&](const tbb::blocked_range<std::size_t>& r) {
                float local = 0.0f;
                for (std::size_t i = r.begin(); i != r.end(); ++i) local += shadeOne(s.posView[i], s.normalView[i]);
                if (local == 12345.0f) sink += local;
            });
        });
    });
    if (sink == 1.0f) std::puts("");
    return double(s.posView.size()) * double(lightCount) / seconds;
}

void lightLoopTable(const std::vector<unsigned>& threads) {
    constexpr std::size_t kPixels = 16384, kLights = 256;
    constexpr float kPower = 32.0f;
    const Surfaces s = makeSurfaces(kPixels);
    const std::vector<ViewLight<float>> lightsF = makeLights(kLights);
    std::vector<ViewLight<double>> lightsD;
    for (const ViewLight<float>& l : lightsF) {
        ViewLight<double> d;
        d.positionView = glm::dvec4(l.positionView);
        d.directionView = glm::dvec4(l.directionView);
        d.color = glm::dvec4(l.color);
        d.spotlightAngleDeg = l.spotlightAngleDeg;
        d.range = l.range;
        d.type = l.type;
        cacheSpotCone(d);
        lightsD.push_back(d);
    }
    const FastLightSet fast = FastLightSet::build(lightsF);
    std::size_t lanes = 0;
    const double peak = HWY_DYNAMIC_DISPATCH(peak::MulAddsPerSecond)(&lanes);

    std::printf("## Light loop: light-pixel evaluations per second\n\n");
    std::printf("%zu pixels x %zu lights (half point, half spot, all in range, specular power %.0f).\n", kPixels, kLights,
                double(kPower));
    std::printf("Peak multiply-adds measured on one core (%zu-lane %s vectors): %.2f G vector FMA/s = %.1f G lane-FMA/s.\n\n",
                lanes, HWY_DYNAMIC_DISPATCH(peak::Target)(), peak / 1e9, peak * double(lanes) / 1e9);
    std::printf("| mode | threads | G light-pixel evals/s | ns per eval per core |\n|---|---:|---:|---:|\n");
    for (const unsigned t : threads) {
        const double fastRate = lightEvalsPerSecond(t, s, kLights, [&](const glm::vec3& p, const glm::vec3& n) {
            return fastLighting(fast, kPower, p, n, true).diffuse.x;
        });
        const double exactRate = lightEvalsPerSecond(t, s, kLights, [&](const glm::vec3& p, const glm::vec3& n) {
            return doLighting<float>(lightsF, kPower, glm::vec4(p, 1.0f), glm::vec4(n, 0.0f)).diffuse.x;
        });
        const double refRate = lightEvalsPerSecond(t, s, kLights, [&](const glm::vec3& p, const glm::vec3& n) {
            return float(doLighting<double>(lightsD, double(kPower), glm::dvec4(p, 1.0), glm::dvec4(n, 0.0)).diffuse.x);
        });
        for (const auto& [name, rate] : {std::pair{"fast", fastRate}, {"exact", exactRate}, {"reference", refRate}})
            std::printf("| %s | %u | %.3f | %.2f |\n", name, t, rate / 1e9, 1e9 * double(t) / rate);
    }
    std::printf("\n");
}

void fillTable(const std::vector<unsigned>& threads) {
    constexpr std::size_t kBytes = std::size_t(256) << 20;  // 256 MiB: far beyond every cache
    std::vector<std::byte> buffer(kBytes), source(kBytes);
    std::memset(buffer.data(), 1, kBytes);  // first touch outside the timing
    std::memset(source.data(), 2, kBytes);
    // D24_UNORM_S8_UINT depth-only clear: keep the stencil byte (the masked path), and a full
    // overwrite (the clear of a colour target).
    const std::byte keepDepth[4] = {std::byte{0}, std::byte{0}, std::byte{0}, std::byte{0xFF}};
    const std::byte setDepth[4] = {std::byte{0xFF}, std::byte{0xFF}, std::byte{0xFF}, std::byte{0}};
    const std::byte keepNone[4] = {};
    const std::byte setColor[4] = {std::byte{0x1A}, std::byte{0x33}, std::byte{0x4D}, std::byte{0xFF}};
    std::printf("## Fill rate against this machine's memory bandwidth\n\n");
    std::printf("A %zu MiB buffer; GB/s = bytes written / best of 5. memset and copy run in the same arena, split into\n"
                "the same 64 KiB blocks as maskedFill, so all rows use the same threads.\n\n",
                kBytes >> 20);
    std::printf("| threads | maskedFill overwrite GB/s | maskedFill keep-stencil GB/s | memset GB/s | copy GB/s (written) | overwrite / memset |\n");
    std::printf("|---:|---:|---:|---:|---:|---:|\n");
    constexpr std::size_t kBlock = 64 * 1024;
    for (const unsigned t : threads) {
        tbb::task_arena arena{int(t)};
        auto rate = [&](auto&& body) { return double(kBytes) / bestSeconds(5, [&] { arena.execute(body); }) / 1e9; };
        const double overwrite = rate([&] { maskedFill(buffer, keepNone, setColor, 4); });
        const double keep = rate([&] { maskedFill(buffer, keepDepth, setDepth, 4); });
        const double set = rate([&] {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kBytes / kBlock), [&](const tbb::blocked_range<std::size_t>& r) {
                std::memset(buffer.data() + r.begin() * kBlock, 3, (r.end() - r.begin()) * kBlock);
            });
        });
        const double copy = rate([&] {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kBytes / kBlock), [&](const tbb::blocked_range<std::size_t>& r) {
                std::memcpy(buffer.data() + r.begin() * kBlock, source.data() + r.begin() * kBlock, (r.end() - r.begin()) * kBlock);
            });
        });
        std::printf("| %u | %.2f | %.2f | %.2f | %.2f | %.2f |\n", t, overwrite, keep, set, copy, overwrite / set);
    }
    std::printf("\n");
}

} // namespace

int main() {
    bench::useSteadyStateAllocator();
    std::vector<unsigned> threads;
    for (const std::string& t : bench::split(std::getenv("TESSERA_BENCH_THREADS") ? std::getenv("TESSERA_BENCH_THREADS") : "1,2", ','))
        threads.push_back(unsigned(std::stoul(t)));
    lightLoopTable(threads);
    fillTable(threads);
    return 0;
}
#endif  // HWY_ONCE
