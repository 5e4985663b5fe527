// Rasterizer throughput: tessera against Mesa llvmpipe on the same three workloads at 1920x1080
// (first timed on llvmpipe alone): 1M random right triangles with 3 px legs, 100k with 20 px legs
// (depth test LESS, RGBA8 + D32F_S8 like the peer), and a full-screen quad with depth off.
// Command, machine and results: bench/RESULTS.md; bench/run_raster_bench.sh builds and runs it.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <tessera/raster/device.h>
#include <tessera/shaders/block_shader.h>

#if TESSERA_HAVE_GL_PEER
#include <gl_peer.h>
#endif

namespace {

using namespace tessera;

constexpr std::uint32_t kWidth = 1920, kHeight = 1080;

struct BenchVertex {
    glm::vec4 posClip;
    glm::vec4 color;
};
struct FlatVaryings {
    glm::vec4 color;
};
struct BenchVS {
    using Varyings = FlatVaryings;
    VertexOutput<FlatVaryings> operator()(const BenchVertex& v) const { return {v.posClip, {v.color}}; }
};
// Flat colour: every vertex of a triangle carries the triangle's colour; the shader writes it.
struct FlatPS {
    using Varyings = FlatVaryings;
    static constexpr int kTargetCount = 1;
    void operator()(const PixelInput<FlatVaryings>& in, PixelOutput<1>& out) const { out.target[0] = in.varyings.color; }
    // The same copy over a block's lanes (llvmpipe's JIT shades 4x4 or 8x8 pixels per call too).
    void shadeBlock(const BlockInput& in, BlockOutput<1>& out) const {
        for (int c = 0; c < 4; ++c)
            std::memcpy(out.target[0] + c * kBlockLanes, in.varyings + c * kBlockLanes, kBlockLanes * sizeof(float));
    }
};

enum Workload : int { kTiny = 0, kMedium = 1, kFullScreen = 2, kTinyD24 = 3 };
const char* const kWorkloadNames[] = {"1M tris 3px", "100k tris 20px", "fullscreen quad", "1M tris 3px D24S8"};

// One workload as D3D clip-space triangles (w = 1; z in [0, 1)), one colour per triangle.
struct Scene {
    std::vector<BenchVertex> vertices;
    bool depthTest = true;
    double pixelsPerFrame = 0;  // nominal covered area (legs^2 / 2 per triangle, or W*H)
    std::uint32_t triangles() const { return std::uint32_t(vertices.size() / 3); }
};

glm::vec4 windowToClip(float xWin, float yWin, float z) {
    return glm::vec4(xWin / float(kWidth) * 2.0f - 1.0f, 1.0f - yWin / float(kHeight) * 2.0f, z, 1.0f);
}

Scene makeScene(int workload) {
    Scene s;
    if (workload == kFullScreen) {
        const glm::vec4 c(0.2f, 0.6f, 0.9f, 1.0f);
        const glm::vec4 p[4] = {{-1, 1, 0.5f, 1}, {1, 1, 0.5f, 1}, {-1, -1, 0.5f, 1}, {1, -1, 0.5f, 1}};
        for (int i : {0, 1, 2, 2, 1, 3}) s.vertices.push_back({p[i], c});
        s.depthTest = false;
        s.pixelsPerFrame = double(kWidth) * kHeight;
        return s;
    }
    const std::uint32_t count = workload == kMedium ? 100'000 : 1'000'000;
    const float leg = workload == kMedium ? 20.0f : 3.0f;
    std::mt19937 rng(1234);
    std::uniform_real_distribution<float> ux(0.0f, float(kWidth) - leg), uy(0.0f, float(kHeight) - leg), u01(0.0f, 1.0f);
    s.vertices.reserve(std::size_t(count) * 3);
    for (std::uint32_t i = 0; i < count; ++i) {
        const float x = ux(rng), y = uy(rng), z = u01(rng);
        const glm::vec4 c(u01(rng), u01(rng), u01(rng), 1.0f);
        s.vertices.push_back({windowToClip(x, y, z), c});
        s.vertices.push_back({windowToClip(x + leg, y, z), c});
        s.vertices.push_back({windowToClip(x, y + leg, z), c});
    }
    s.pixelsPerFrame = double(count) * leg * leg * 0.5;
    return s;
}

const Scene& scene(int workload) {
    static std::map<int, Scene> cache;
    auto it = cache.find(workload);
    if (it == cache.end()) it = cache.emplace(workload, makeScene(workload)).first;
    return it->second;
}

void setCounters(benchmark::State& state, const Scene& s) {
    const double frames = double(state.iterations());
    state.counters["Mtri/s"] = benchmark::Counter(frames * s.triangles() / 1e6, benchmark::Counter::kIsRate);
    state.counters["Mpix/s"] = benchmark::Counter(frames * s.pixelsPerFrame / 1e6, benchmark::Counter::kIsRate);
}

// tessera's tile size: $TESSERA_BENCH_TILE (px), else DeviceConfig's default.
std::uint32_t benchTileSize() {
    const char* env = std::getenv("TESSERA_BENCH_TILE");
    return env && *env ? std::uint32_t(std::strtoul(env, nullptr, 10)) : DeviceConfig{}.tileSize;
}

// Each iteration clears colour and depth-stencil and draws the workload: the clear is inside
// the timing, as it is in GlPeer::timeRender (clear + draws + glFinish).
void BM_Tessera(benchmark::State& state) {
    const int workload = int(state.range(0));
    const auto threads = std::uint32_t(state.range(1));
    const Scene& s = scene(workload);
    const Format dsFormat = workload == kTinyD24 ? Format::D24_UNORM_S8_UINT : Format::D32_FLOAT_S8X24_UINT;
    Surface color({kWidth, kHeight, Format::R8G8B8A8_UNORM, 1}), depth({kWidth, kHeight, dsFormat, 1});
    Device dev(DeviceConfig{benchTileSize(), threads});
    RenderTargets rt;
    rt.colors[0] = &color;
    rt.depthStencil = &depth;
    DrawState st;
    st.viewport = fullViewport(color);
    st.rasterizer.cullMode = CullMode::None;
    st.depthStencil.depthEnable = s.depthTest;
    st.depthStencil.depthFunc = ComparisonFunc::Less;
    for (auto _ : state) {
        color.clearColor(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
        depth.clearDepthStencil(true, 1.0f, true, 0);
        dev.draw(st, rt, std::span<const BenchVertex>(s.vertices), {}, BenchVS{}, FlatPS{});
        benchmark::DoNotOptimize(color.bytes().data());
    }
    setCounters(state, s);
}

#if TESSERA_HAVE_GL_PEER
peer::PeerFrame peerFrame(const Scene& s) {
    peer::PeerFrame f;
    f.width = int(kWidth);
    f.height = int(kHeight);
    f.clearColor = {0, 0, 0, 1};
    peer::PeerDraw d;
    d.depthEnable = s.depthTest;
    d.depthFunc = peer::Cmp::Less;
    d.cull = peer::Cull::None;
    for (std::size_t i = 0; i < s.vertices.size(); ++i) {
        const glm::vec4& p = s.vertices[i].posClip;
        d.posClip.push_back({p.x, p.y, p.z, p.w});
        if (i % 3 == 0) {
            const glm::vec4& c = s.vertices[i].color;
            d.colorPerTriangle.push_back({c.x, c.y, c.z, c.w});
        }
    }
    f.draws.push_back(std::move(d));
    return f;
}

// llvmpipe: a fresh peer per benchmark so that LP_NUM_THREADS (read when the display is
// initialised) takes effect. Each iteration is one GlPeer::timeRender(frame, 1) call: one
// untimed warm-up render, then one timed render (clear + draw + glFinish), reported as
// manual time.
void BM_Llvmpipe(benchmark::State& state) {
    const int workload = int(state.range(0));
    const std::string threads = std::to_string(state.range(1));
    setenv("LP_NUM_THREADS", threads.c_str(), 1);
    std::string why;
    std::optional<peer::GlPeer> gl = peer::GlPeer::create(&why);
    if (!gl) {
        state.SkipWithError(("no llvmpipe: " + why).c_str());
        return;
    }
    const Scene& s = scene(workload);
    const peer::PeerFrame frame = peerFrame(s);
    for (auto _ : state) state.SetIterationTime(gl->timeRender(frame, 1));
    setCounters(state, s);
    state.SetLabel(gl->renderer());
}
#endif

// Thread counts to measure: TESSERA_BENCH_THREADS="1,2,4,8,16" (default "1,2", this machine's
// cores). Bad entries are an error, not silently skipped.
std::vector<int> benchThreadCounts() {
    const char* env = std::getenv("TESSERA_BENCH_THREADS");
    if (!env || !*env) return {1, 2};
    std::vector<int> counts;
    std::string list(env);
    for (std::size_t start = 0; start <= list.size();) {
        const std::size_t end = std::min(list.find(',', start), list.size());
        const std::string item = list.substr(start, end - start);
        char* tail = nullptr;
        const long n = std::strtol(item.c_str(), &tail, 10);
        if (item.empty() || *tail != '\0' || n < 1 || n > 256) {
            std::fprintf(stderr, "TESSERA_BENCH_THREADS: '%s' is not a thread count in 1..256\n", item.c_str());
            std::exit(2);
        }
        counts.push_back(int(n));
        start = end + 1;
    }
    return counts;
}

// Iteration counts fixed so that a full run stays in a few minutes on 2 cores.
void registerAll(const std::vector<int>& threadCounts) {
    const int iterations[] = {5, 10, 30, 5};
    for (int w : {kTiny, kMedium, kFullScreen, kTinyD24})
        for (int t : threadCounts) {
            const std::string name = std::string("tessera/") + kWorkloadNames[w] + "/threads:" + std::to_string(t);
            benchmark::RegisterBenchmark(name.c_str(), BM_Tessera)
                ->Args({w, t})
                ->Iterations(iterations[w])
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();
        }
#if TESSERA_HAVE_GL_PEER
    for (int w : {kTiny, kMedium, kFullScreen})
        for (int t : threadCounts) {
            const std::string name = std::string("llvmpipe/") + kWorkloadNames[w] + "/threads:" + std::to_string(t);
            benchmark::RegisterBenchmark(name.c_str(), BM_Llvmpipe)
                ->Args({w, t})
                ->Iterations(iterations[w])
                ->Unit(benchmark::kMillisecond)
                ->UseManualTime();
        }
#endif
}

// Console output plus a record of seconds per frame by (engine, workload, threads), for the
// summary table printed after the run.
class SummaryReporter : public benchmark::ConsoleReporter {
public:
    std::map<std::string, double> secondsPerFrame;  // registered name -> s
    void ReportRuns(const std::vector<Run>& runs) override {
        ConsoleReporter::ReportRuns(runs);
        for (const Run& r : runs)
            if (!r.error_occurred && r.iterations > 0)
                secondsPerFrame[r.run_name.function_name] = r.real_accumulated_time / double(r.iterations);
    }
};

void printSummary(const std::map<std::string, double>& spf, const std::vector<int>& threadCounts) {
    std::printf("\n%-20s %3s | %9s %9s %9s | %9s %9s %9s | %6s\n", "workload", "thr", "tess ms", "Mtri/s", "Mpix/s",
                "llvmp ms", "Mtri/s", "Mpix/s", "ratio");
    for (int w : {kTiny, kMedium, kFullScreen, kTinyD24})
        for (int t : threadCounts) {
            const std::string suffix = std::string(kWorkloadNames[w]) + "/threads:" + std::to_string(t);
            const auto tess = spf.find("tessera/" + suffix);
            const auto lp = spf.find("llvmpipe/" + suffix);
            if (tess == spf.end() && lp == spf.end()) continue;
            const Scene& s = scene(w);
            auto row = [&](double sec) {
                std::printf(" %9.2f %9.2f %9.1f |", sec * 1e3, s.triangles() / sec / 1e6, s.pixelsPerFrame / sec / 1e6);
            };
            std::printf("%-20s %3d |", kWorkloadNames[w], t);
            if (tess != spf.end()) row(tess->second); else std::printf(" %29s |", "-");
            if (lp != spf.end()) row(lp->second); else std::printf(" %29s |", "-");
            // ratio > 1: tessera is faster (rate tessera / rate llvmpipe = time llvmpipe / time tessera).
            if (tess != spf.end() && lp != spf.end()) std::printf(" %6.2f", lp->second / tess->second);
            std::printf("\n");
        }
}

} // namespace

int main(int argc, char** argv) {
    const std::vector<int> threadCounts = benchThreadCounts();
    registerAll(threadCounts);
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    SummaryReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    printSummary(reporter.secondsPerFrame, threadCounts);
    benchmark::Shutdown();
    return 0;
}
