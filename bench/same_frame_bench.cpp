// Same-frame benchmark: the bundled Sponza scenes through tessera and OpenGL 4.5 core (ports in
// bench/same_frame/) with the same camera, lights, textures, draw order and states, per technique
// and thread count: median ms per pass and frame, their ratio, and how GL's back buffer (and
// depth, stencil, Forward+ light lists) differ from tessera's exact ones. GL is Mesa llvmpipe
// (--gl-platform surfaceless, the default) or a GPU driver through EGL_EXT_platform_device
// (--gl-platform device: headless NVIDIA, say; its passes timed by GL_TIME_ELAPSED queries).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <tessera/io/image_writer.h>
#include <tessera/scene/phong_material.h>
#include <tessera/scene/scene_file.h>
#include <tessera/shading/phong_material_shader.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/technique.h>

#include "bench_support.h"
#include "../tests/support/depth_truth.h"
#include "same_frame/gl_context.h"
#include "same_frame/gl_renderer.h"

namespace {

using namespace tessera;
namespace fs = std::filesystem;
using samefr::Technique;

constexpr const char* kUsage = R"(usage: same_frame_bench [options]

Renders the same Sponza frame through tessera (precision exact) and GL 4.5 core (llvmpipe, or a
GPU with --gl-platform device) and prints, per technique and thread count, median ms per pass and
per frame of both, the ratio GL / tessera (> 1: tessera is faster), and the difference of GL's
back buffer from tessera's. Thread counts: --tessera-threads, else TESSERA_BENCH_THREADS="1,2"
(default; tessera's Device threads and llvmpipe's LP_NUM_THREADS alike; with --gl-platform
device GL runs once per technique and every thread count is compared with that run). Scenes:
$TESSERA_SCENES, else the source tree's scenes/ folder.

options:
  --gl-platform P          surfaceless (default): Mesa llvmpipe through EGL_MESA_platform_surfaceless,
                           pass times on the wall clock between glFinish calls; device: an EGL device
                           (EGL_EXT_platform_device), pass times from GL_TIME_ELAPSED queries (GPU
                           execution; the frame is their sum), glFinish wall times beside them
  --gl-device N            with device: the Nth EGL device (default: the first that is not a
                           software renderer)
  --tessera-threads LIST   tessera's thread counts, e.g. 1,2,4,8 (overrides TESSERA_BENCH_THREADS)
  --techniques LIST        forward,forward-plus,deferred (default: all three)
  --iterations N           timed frames after one warm-up frame, 1..1000 (default 3)
  --tile T                 tessera's tile size in px (DeviceConfig::tileSize), even, 8..1024 (default 64)
  --precision MODE         tessera's precision: exact (default) or fast (reference's double shading
                           is the yardstick, not a rival: compare it with `tessera diff`)
  --forward-lights N       sponza-large-lights light count for forward (default 64)
  --forward-plus-lights N  sponza-small-lights light count for forward-plus (default 1024)
  --deferred-lights N      sponza-small-lights light count for deferred (default 256)
  --fp-culling MODE        tessera's forward-plus "culling" option: binned (default, tessera's
                           row-parallel binning) or brute (the article's loop over every light
                           per tile, as the GLSL port runs it); the light lists are identical
  --sampler MODE           gl (default): llvmpipe's trilinear sampler; emulated: tessera's D3D11
                           sampling rules written in GLSL over texelFetch (diagnostic: shows
                           which image differences the sampler causes; its timings are not
                           comparable)
  --csv FILE               also write every row as CSV
  --dump DIR               write <technique>-t<threads>-{tessera,llvmpipe|gpu,diff}.png into DIR
  --depth-analysis FILE    forward and forward-plus: judge both D24 depth buffers against the
                           double-precision D3D11 depth (tests/support/depth_truth.h) of the
                           opaque geometry, print the histograms per class of difference, and
                           write the pixels that differ by more than 1 code (either side from
                           the truth, or the two from each other by more than 16) to FILE as CSV
  --help                   show this text
)";

struct Config {
    std::string id;          // tessera's technique id
    Technique technique;
    std::string scene;       // bundled scene name
    std::uint32_t lights;
};

struct Options {
    std::vector<std::string> techniques{"forward", "forward-plus", "deferred"};
    std::uint32_t iterations = 3;
    std::uint32_t tileSize = 64;  // px
    Precision precision = Precision::Exact;
    std::uint32_t forwardLights = 64, forwardPlusLights = 1024, deferredLights = 256;
    std::string csv, dumpDir, depthAnalysis;
    bool emulatedSampling = false;
    std::string forwardPlusCulling = "binned";
    samefr::GlPlatform platform = samefr::GlPlatform::Surfaceless;
    int glDevice = -1;
    std::string tesseraThreads;  // --tessera-threads, unparsed (checked against the platform)
};

[[noreturn]] void usageError(const std::string& message) {
    std::fprintf(stderr, "same_frame_bench: %s\n%s", message.c_str(), kUsage);
    std::exit(2);
}

std::uint32_t parseCount(const std::string& flag, const std::string& text, std::uint32_t lo, std::uint32_t hi) {
    const std::vector<std::uint32_t> v = bench::splitUints(flag, text);
    if (v.size() != 1 || v[0] < lo || v[0] > hi)
        usageError(flag + ": '" + text + "' is not a count in " + std::to_string(lo) + ".." + std::to_string(hi));
    return v[0];
}

Options parseArgs(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const auto value = [&]() -> std::string {
            if (i + 1 >= argc) usageError(a + " needs a value");
            return argv[++i];
        };
        if (a == "--help" || a == "-h") {
            std::fputs(kUsage, stdout);
            std::exit(0);
        } else if (a == "--techniques") {
            o.techniques = bench::split(value(), ',');
            for (const std::string& t : o.techniques)
                if (t != "forward" && t != "forward-plus" && t != "deferred")
                    usageError("--techniques: '" + t + "' is not forward, forward-plus or deferred");
        } else if (a == "--iterations") o.iterations = parseCount(a, value(), 1, 1000);
        else if (a == "--tile") o.tileSize = parseCount(a, value(), 8, 1024);
        else if (a == "--precision") {
            const std::string mode = value();
            if (mode == "exact") o.precision = Precision::Exact;
            else if (mode == "fast") o.precision = Precision::Fast;
            else usageError("--precision: '" + mode + "' is not exact or fast");
        }
        else if (a == "--forward-lights") o.forwardLights = parseCount(a, value(), 1, 1000000);
        else if (a == "--forward-plus-lights") o.forwardPlusLights = parseCount(a, value(), 1, 1000000);
        else if (a == "--deferred-lights") o.deferredLights = parseCount(a, value(), 1, 1000000);
        else if (a == "--fp-culling") {
            o.forwardPlusCulling = value();
            if (o.forwardPlusCulling != "binned" && o.forwardPlusCulling != "brute")
                usageError("--fp-culling: '" + o.forwardPlusCulling + "' is not binned or brute");
        } else if (a == "--sampler") {
            const std::string mode = value();
            if (mode != "gl" && mode != "emulated") usageError("--sampler: '" + mode + "' is not gl or emulated");
            o.emulatedSampling = mode == "emulated";
        } else if (a == "--gl-platform") {
            const std::string p = value();
            if (p != "surfaceless" && p != "device") usageError("--gl-platform: '" + p + "' is not surfaceless or device");
            o.platform = p == "device" ? samefr::GlPlatform::Device : samefr::GlPlatform::Surfaceless;
        } else if (a == "--gl-device") o.glDevice = int(parseCount(a, value(), 0, 1024));
        else if (a == "--tessera-threads") o.tesseraThreads = value();
        else if (a == "--csv") o.csv = value();
        else if (a == "--dump") o.dumpDir = value();
        else if (a == "--depth-analysis") o.depthAnalysis = value();
        else usageError("unknown option '" + a + "'");
    }
    if (o.glDevice >= 0 && o.platform != samefr::GlPlatform::Device) usageError("--gl-device needs --gl-platform device");
    return o;
}

// --tessera-threads LIST, else TESSERA_BENCH_THREADS="1,2,4" (default "1,2", as
// bench/raster_bench.cpp); bad entries exit 2. With llvmpipe the counts are LP_NUM_THREADS too.
std::vector<std::uint32_t> benchThreadCounts(const Options& o) {
    const char* env = std::getenv("TESSERA_BENCH_THREADS");
    const std::string source = !o.tesseraThreads.empty() ? "--tessera-threads" : "TESSERA_BENCH_THREADS";
    const std::string text = !o.tesseraThreads.empty() ? o.tesseraThreads : env ? env : "";
    if (text.empty()) return {1, 2};
    std::vector<std::uint32_t> counts = bench::splitUints(source, text);
    const bool llvmpipe = o.platform == samefr::GlPlatform::Surfaceless;
    const std::uint32_t most = llvmpipe ? 32 : 1024;
    for (std::uint32_t n : counts)
        if (n < 1 || n > most)
            usageError(source + ": " + std::to_string(n) + " is not in 1.." + std::to_string(most) +
                       (llvmpipe ? " (llvmpipe's LP_MAX_THREADS)" : ""));
    if (counts.empty()) usageError(source + ": no thread counts");
    return counts;
}

// Where the bundled scenes are: $TESSERA_SCENES (as the tessera CLI), else the source tree's.
fs::path scenesDir() {
    if (const char* env = std::getenv("TESSERA_SCENES"); env && *env) return env;
    return fs::path(TESSERA_SOURCE_DIR) / "scenes";
}

// A bundled scene loaded as `tessera render SCENE --lights N --technique ID` loads it
// (src/cli/render.cpp): scene file, generator counts overridden, camera, textures decoded per the
// technique's policy.
struct LoadedScene {
    SceneDescription desc;
    Camera camera;
    std::unique_ptr<Scene> scene;
    std::unique_ptr<SceneResources> resources;
};

std::unique_ptr<LoadedScene> loadBenchScene(const Config& c, const Options& opt) {
    auto s = std::make_unique<LoadedScene>();
    const fs::path file = scenesDir() / (c.scene + ".json");
    s->desc = parseSceneFile(file);
    s->desc.technique = c.id;
    for (LightGeneratorSpec& g : s->desc.generators) g.count = c.lights;
    if (c.technique == Technique::ForwardPlus && opt.forwardPlusCulling != "binned")
        s->desc.techniqueOptions["culling"] = opt.forwardPlusCulling;
    s->scene = std::make_unique<Scene>(tessera::loadScene(s->desc, true, &s->camera));
    s->resources = std::make_unique<SceneResources>(*s->scene, std::function<void(std::size_t, std::size_t)>{},
                                                    findTechnique(c.id)->textures);
    return s;
}

TechniqueContext contextFor(const LoadedScene& s, Device* device) {
    TechniqueContext ctx;
    ctx.device = device;
    ctx.resources = s.resources.get();
    ctx.camera = s.camera;
    ctx.width = s.desc.width;
    ctx.height = s.desc.height;
    ctx.options = s.desc.techniqueOptions;
    ctx.precision = s.desc.precision;
    ctx.sceneFile = s.desc.file.string();
    return ctx;
}

// Median ms per pass (in the order the passes ran) and of the per-frame sums.
struct Timings {
    std::vector<std::string> passes;
    std::map<std::string, double> passMs;
    double frameMs = 0.0;
};

// gpu: the passes' GL_TIME_ELAPSED times (PassTime::gpuMilliseconds), else their wall times.
Timings summarize(const std::vector<std::vector<samefr::PassTime>>& frames, bool gpu = false) {
    Timings t;
    std::map<std::string, std::vector<double>> samples;
    std::vector<double> totals;
    for (const auto& frame : frames) {
        double total = 0.0;
        for (const samefr::PassTime& p : frame) {
            if (samples.find(p.name) == samples.end()) t.passes.push_back(p.name);
            const double v = gpu ? p.gpuMilliseconds : p.milliseconds;
            samples[p.name].push_back(v);
            total += v;
        }
        totals.push_back(total);
    }
    for (const auto& [name, v] : samples) t.passMs[name] = bench::median(v);
    t.frameMs = bench::median(totals);
    return t;
}

struct Frame8 {
    std::uint32_t width = 0, height = 0;
    std::vector<std::uint8_t> rgba8;
    std::vector<std::uint32_t> depthCode;  // D24 code per pixel
    std::vector<std::uint8_t> stencil;
};

// Forward+ light lists: per tile (offset, count) and the global index list, opaque and
// transparent (tessera's "lightgrid.*" / "lightindex.*" buffers, or GL's storage buffers).
struct LightLists {
    std::vector<std::uint32_t> grid[2], index[2];
};

struct RunResult {
    Timings timings;
    Timings wallTimings;  // GL with timer queries: the glFinish wall times (timings: the queries')
    Frame8 image;
    LightLists lists;  // forward-plus only
};

std::vector<std::uint32_t> surfaceWords(const Surface& s) {
    std::vector<std::uint32_t> words(s.bytes().size() / sizeof(std::uint32_t));
    std::memcpy(words.data(), s.bytes().data(), words.size() * sizeof(std::uint32_t));
    return words;
}

RunResult runTessera(const LoadedScene& s, const Config& c, std::uint32_t threads, std::uint32_t iterations,
                     std::uint32_t tileSize, Precision precision) {
    Device device(DeviceConfig{tileSize, threads});
    TechniqueContext ctx = contextFor(s, &device);
    ctx.precision = precision;
    const tessera::Frame frame = buildTechnique(c.id, ctx, ctx.sceneFile);
    std::vector<std::vector<samefr::PassTime>> frames;
    RunResult r;
    BufferRegistry registry;  // cleared each frame; its storage is reused, as a GL renderer keeps its targets
    for (std::uint32_t i = 0; i <= iterations; ++i) {  // frame 0: warm-up, not timed
        registry.clear();
        const std::vector<PassTiming> timings = frame.run(registry);
        if (i > 0) {
            std::vector<samefr::PassTime> times;
            for (const PassTiming& t : timings) times.push_back({t.name, t.milliseconds});
            frames.push_back(std::move(times));
        }
        if (i == iterations) {
            const Surface& back = registry.get(kBackBufferName);
            const Surface& depth = registry.get("depth");
            r.image.width = back.width();
            r.image.height = back.height();
            r.image.rgba8.resize(back.bytes().size());
            std::memcpy(r.image.rgba8.data(), back.bytes().data(), back.bytes().size());
            for (std::uint32_t y = 0; y < depth.height(); ++y)
                for (std::uint32_t x = 0; x < depth.width(); ++x) {
                    std::uint32_t texel;
                    std::memcpy(&texel, depth.texel(x, y), sizeof texel);
                    r.image.depthCode.push_back(texel & 0xFFFFFFu);
                    r.image.stencil.push_back(depth.loadStencil(x, y));
                }
            if (c.technique == Technique::ForwardPlus) {
                r.lists.grid[0] = surfaceWords(registry.get("lightgrid.opaque"));
                r.lists.grid[1] = surfaceWords(registry.get("lightgrid.transparent"));
                r.lists.index[0] = surfaceWords(registry.get("lightindex.opaque"));
                r.lists.index[1] = surfaceWords(registry.get("lightindex.transparent"));
            }
        }
    }
    r.timings = summarize(frames);
    return r;
}

struct GlInfo {
    std::string vendor, renderer, version;
};

RunResult runGl(const LoadedScene& s, const Config& c, const samefr::GlContextOptions& contextOptions,
                std::uint32_t iterations, const samefr::GlOptions& options, GlInfo& info) {
    samefr::GlContext context(contextOptions);  // fresh display (llvmpipe: LP_NUM_THREADS = threads)
    info = {context.vendor(), context.renderer(), context.version()};
    const TechniqueContext ctx = contextFor(s, nullptr);
    // The technique's own setup with its default options (demo-gl projection, demo sampler, no
    // alpha test in the forward passes): camera matrices, texture set and view-space lights.
    const std::shared_ptr<ForwardPassSetup> setup =
        makeForwardPassSetup(ctx, ProjectionConvention::DemoGl, PhongSamplerChoice::Demo, false);
    samefr::GlRenderer gl(*s.resources, *setup, c.technique, options);
    std::vector<std::vector<samefr::PassTime>> frames;
    for (std::uint32_t i = 0; i <= iterations; ++i) {  // frame 0: warm-up (shader JIT, first touch)
        std::vector<samefr::PassTime> times = gl.renderFrame();
        if (i > 0) frames.push_back(std::move(times));
    }
    RunResult r;
    r.timings = summarize(frames, options.timerQueries);
    if (options.timerQueries) r.wallTimings = summarize(frames);
    const samefr::GlImages images = gl.readBack();
    r.image.width = setup->width;
    r.image.height = setup->height;
    r.image.rgba8 = images.rgba8;
    for (std::uint32_t packed : images.depthStencil) {
        r.image.depthCode.push_back(packed >> 8);
        r.image.stencil.push_back(std::uint8_t(packed & 0xFFu));
    }
    const samefr::GlLightLists lists = gl.readLightLists();
    r.lists.grid[0] = lists.opaqueGrid;
    r.lists.grid[1] = lists.transparentGrid;
    r.lists.index[0] = lists.opaqueIndex;
    r.lists.index[1] = lists.transparentIndex;
    return r;
}

// GL's image against tessera's, RGB only (the presented image ignores alpha).
struct DiffStats {
    int maxAbs = 0;                    // 8-bit codes, over R, G, B
    double rmse = 0.0;                 // codes, over every R, G, B value
    std::uint64_t differingPixels = 0; // any of R, G, B differs
    std::uint64_t coverageDiffers = 0; // the clear colour in one image and not in the other
    std::array<std::uint64_t, 5> byMaxDiff{};  // pixels whose largest R, G, B difference is 1, 2-3, 4-7, 8-15, >= 16
    std::uint64_t depthDiffers = 0;    // D24 codes differ
    std::uint64_t depthFar = 0;        // D24 codes differ by more than 16 (not interpolation rounding)
    std::uint32_t maxDepthCodeDiff = 0;
    std::uint64_t stencilDiffers = 0;
    std::uint64_t pixels = 0;
    // Forward+: tiles whose opaque / transparent light list (count and indices) differs.
    std::uint64_t tilesListDiffer[2] = {0, 0};
    std::uint64_t tiles = 0;
};

// Per tile, the (count, indices) of both lists; entries past a global list's end read 0, as the
// pixel shader reads them. Offsets may differ (GL's atomic order), contents may not.
void compareLists(const LightLists& tess, const LightLists& lp, DiffStats& d) {
    if (tess.grid[0].empty() || lp.grid[0].empty()) return;
    d.tiles = tess.grid[0].size() / 2;
    const auto entry = [](const std::vector<std::uint32_t>& list, std::uint64_t at) { return at < list.size() ? list[at] : 0u; };
    for (int which = 0; which < 2; ++which) {
        for (std::uint64_t tile = 0; tile < d.tiles; ++tile) {
            const std::uint32_t offsetA = tess.grid[which][tile * 2], countA = tess.grid[which][tile * 2 + 1];
            const std::uint32_t offsetB = lp.grid[which][tile * 2], countB = lp.grid[which][tile * 2 + 1];
            bool differs = countA != countB;
            for (std::uint32_t i = 0; i < countA && !differs; ++i)
                differs = entry(tess.index[which], std::uint64_t(offsetA) + i) != entry(lp.index[which], std::uint64_t(offsetB) + i);
            if (differs) ++d.tilesListDiffer[which];
        }
    }
}

DiffStats compare(const Frame8& tess, const Frame8& lp) {
    if (tess.width != lp.width || tess.height != lp.height) throw std::runtime_error("image sizes differ");
    // The clear colour's codes as tessera stores them (float -> UNORM of kDemoClearColor).
    Surface clear({1, 1, Format::R8G8B8A8_UNORM, 1});
    clear.clearColor(kDemoClearColor);
    std::uint8_t clearCode[4];
    std::memcpy(clearCode, clear.bytes().data(), 4);
    DiffStats d;
    d.pixels = std::uint64_t(tess.width) * tess.height;
    double sumSquares = 0.0;
    for (std::uint64_t p = 0; p < d.pixels; ++p) {
        const std::uint8_t* a = &tess.rgba8[p * 4];
        const std::uint8_t* b = &lp.rgba8[p * 4];
        bool clearA = true, clearB = true;
        int pixelMax = 0;
        for (int ch = 0; ch < 3; ++ch) {
            const int diff = std::abs(int(a[ch]) - int(b[ch]));
            pixelMax = std::max(pixelMax, diff);
            sumSquares += double(diff) * diff;
            clearA = clearA && a[ch] == clearCode[ch];
            clearB = clearB && b[ch] == clearCode[ch];
        }
        d.maxAbs = std::max(d.maxAbs, pixelMax);
        if (pixelMax > 0) {
            ++d.differingPixels;
            ++d.byMaxDiff[pixelMax < 2 ? 0 : pixelMax < 4 ? 1 : pixelMax < 8 ? 2 : pixelMax < 16 ? 3 : 4];
        }
        if (clearA != clearB) ++d.coverageDiffers;
        const std::uint32_t za = tess.depthCode[p], zb = lp.depthCode[p];
        if (za != zb) {
            ++d.depthDiffers;
            const std::uint32_t codes = za > zb ? za - zb : zb - za;
            d.maxDepthCodeDiff = std::max(d.maxDepthCodeDiff, codes);
            if (codes > 16) ++d.depthFar;
        }
        if (tess.stencil[p] != lp.stencil[p]) ++d.stencilDiffers;
    }
    d.rmse = std::sqrt(sumSquares / double(d.pixels * 3));
    return d;
}

void dumpImages(const fs::path& dir, const std::string& stem, const Frame8& tess, const Frame8& lp, const std::string& glName) {
    fs::create_directories(dir);
    const SurfaceDesc desc{tess.width, tess.height, Format::R8G8B8A8_UNORM, 1};
    Surface a(desc), b(desc), diff(desc);
    std::memcpy(a.bytes().data(), tess.rgba8.data(), tess.rgba8.size());
    std::memcpy(b.bytes().data(), lp.rgba8.data(), lp.rgba8.size());
    auto* out = reinterpret_cast<std::uint8_t*>(diff.bytes().data());
    for (std::size_t i = 0; i < tess.rgba8.size(); ++i)  // |difference| x 16, alpha opaque
        out[i] = i % 4 == 3 ? 255 : std::uint8_t(std::min(255, 16 * std::abs(int(tess.rgba8[i]) - int(lp.rgba8[i]))));
    writeSurface(withOpaqueAlpha(a), dir / (stem + "-tessera.png"));
    writeSurface(withOpaqueAlpha(b), dir / (stem + "-" + glName + ".png"));
    writeSurface(diff, dir / (stem + "-diff.png"));
}

struct Row {
    Config config;
    std::uint32_t threads = 0;
    Timings tessera, gl;  // gl: the GL side's times, llvmpipe's or the GPU's (timer queries)
    Timings glWall;       // GPU: glFinish wall times (empty with llvmpipe)
    DiffStats diff;
};

// How the tables name the GL side.
struct GlLabels {
    bool gpu = false;
    std::string name() const { return gpu ? "GPU" : "llvmpipe"; }
    std::string csvColumn() const { return gpu ? "gpu_ms" : "llvmpipe_ms"; }
};

// Decimals of every ms value printed: 2, or 3 with a GPU (passes of a few microseconds).
int gMsDecimals = 2;

std::string ms(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.*f", gMsDecimals, v);
    return text;
}

std::vector<std::string> passUnion(const Row& r) {
    std::vector<std::string> names = r.tessera.passes;
    for (const std::string& n : r.gl.passes)
        if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
    return names;
}

std::string lookup(const Timings& t, const std::string& pass) {
    const auto it = t.passMs.find(pass);
    return it == t.passMs.end() ? std::string("-") : ms(it->second);
}

std::string ratio(const Timings& tess, const Timings& lp, const std::string& pass) {
    const auto a = tess.passMs.find(pass), b = lp.passMs.find(pass);
    if (a == tess.passMs.end() || b == lp.passMs.end() || a->second <= 0.0) return "-";
    return ms(b->second / a->second);
}

void printTables(const std::vector<Row>& rows, const GlLabels& gl) {
    if (gl.gpu)
        std::printf("\n## Time per pass (median ms; GPU ms: GL_TIME_ELAPSED per pass, frame = their sum; ratio = GPU / "
                    "tessera, > 1: tessera faster; GPU wall ms: glFinish before and after each pass)\n\n"
                    "| technique | lights | threads | pass | tessera ms | GPU ms | ratio | GPU wall ms |\n"
                    "|---|---:|---:|---|---:|---:|---:|---:|\n");
    else
        std::printf("\n## Time per pass (median ms; ratio = llvmpipe / tessera, > 1: tessera faster)\n\n"
                    "| technique | lights | threads | pass | tessera ms | llvmpipe ms | ratio |\n"
                    "|---|---:|---:|---|---:|---:|---:|\n");
    for (const Row& r : rows) {
        for (const std::string& pass : passUnion(r)) {
            std::printf("| %s | %u | %u | %s | %s | %s | %s |", r.config.id.c_str(), r.config.lights, r.threads, pass.c_str(),
                        lookup(r.tessera, pass).c_str(), lookup(r.gl, pass).c_str(),
                        ratio(r.tessera, r.gl, pass).c_str());
            if (gl.gpu) std::printf(" %s |", lookup(r.glWall, pass).c_str());
            std::printf("\n");
        }
        std::printf("| %s | %u | %u | **frame** | **%s** | **%s** | **%s** |", r.config.id.c_str(), r.config.lights, r.threads,
                    ms(r.tessera.frameMs).c_str(), ms(r.gl.frameMs).c_str(),
                    ms(r.gl.frameMs / r.tessera.frameMs).c_str());
        if (gl.gpu) std::printf(" **%s** |", ms(r.glWall.frameMs).c_str());
        std::printf("\n");
    }
    std::printf("\n## %s back buffer against tessera's exact back buffer (R, G, B in 8-bit codes)\n\n", gl.name().c_str());
    std::printf("| technique | lights | threads | max abs | RMSE | differing px | by max diff 1 / 2-3 / 4-7 / 8-15 / 16+ | "
                "coverage differs px | depth differs px (> 16 codes; max) | stencil differs px | light lists differ (tiles, "
                "opaque / transparent) |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const Row& r : rows) {
        const DiffStats& d = r.diff;
        const std::string stencil = r.config.technique == Technique::Deferred ? std::to_string(d.stencilDiffers) : "-";
        const std::string lists = d.tiles == 0 ? std::string("-")
                                               : std::to_string(d.tilesListDiffer[0]) + " / " + std::to_string(d.tilesListDiffer[1]) +
                                                     " of " + std::to_string(d.tiles);
        const auto u = [](std::uint64_t v) { return (unsigned long long)v; };
        std::printf("| %s | %u | %u | %d | %.3f | %llu (%.2f%%) | %llu / %llu / %llu / %llu / %llu | %llu | %llu (%llu; %u) | %s | %s |\n",
                    r.config.id.c_str(), r.config.lights, r.threads, d.maxAbs, d.rmse, u(d.differingPixels),
                    100.0 * double(d.differingPixels) / double(d.pixels), u(d.byMaxDiff[0]), u(d.byMaxDiff[1]),
                    u(d.byMaxDiff[2]), u(d.byMaxDiff[3]), u(d.byMaxDiff[4]), u(d.coverageDiffers), u(d.depthDiffers),
                    u(d.depthFar), d.maxDepthCodeDiff, stencil.c_str(), lists.c_str());
    }
}

// With a GPU the GL column is gpu_ms (timer queries) and a last column gpu_wall_ms is added;
// llvmpipe's CSV is as before.
void writeCsv(const std::string& path, const std::vector<Row>& rows, const GlLabels& gl) {
    std::ofstream out(path);
    if (!out) throw std::runtime_error("cannot write " + path);
    out << "technique,scene,lights,threads,pass,tessera_ms," << gl.csvColumn()
        << ",ratio,max_abs_diff,rmse,differing_pixels,"
           "max_diff_1,max_diff_2_3,max_diff_4_7,max_diff_8_15,max_diff_16_up,coverage_differs_pixels,depth_differs_pixels,"
           "depth_differs_over_16_codes,max_depth_code_diff,stencil_differs_pixels,opaque_list_tiles_differ,"
           "transparent_list_tiles_differ"
        << (gl.gpu ? ",gpu_wall_ms" : "") << "\n";
    for (const Row& r : rows) {
        const std::string head = r.config.id + "," + r.config.scene + "," + std::to_string(r.config.lights) + "," +
                                 std::to_string(r.threads) + ",";
        for (const std::string& pass : passUnion(r)) {
            const std::string t = lookup(r.tessera, pass), l = lookup(r.gl, pass), q = ratio(r.tessera, r.gl, pass);
            out << head << pass << "," << (t == "-" ? "" : t) << "," << (l == "-" ? "" : l) << "," << (q == "-" ? "" : q)
                << ",,,,,,,,,,,,,,,";
            if (gl.gpu) {
                const std::string w = lookup(r.glWall, pass);
                out << "," << (w == "-" ? "" : w);
            }
            out << "\n";
        }
        const DiffStats& d = r.diff;
        out << head << "frame," << ms(r.tessera.frameMs) << "," << ms(r.gl.frameMs) << ","
            << ms(r.gl.frameMs / r.tessera.frameMs) << "," << d.maxAbs << "," << d.rmse << "," << d.differingPixels << ",";
        for (std::uint64_t n : d.byMaxDiff) out << n << ",";
        out << d.coverageDiffers << "," << d.depthDiffers << "," << d.depthFar << "," << d.maxDepthCodeDiff << ","
            << (r.config.technique == Technique::Deferred ? std::to_string(d.stencilDiffers) : std::string()) << ",";
        if (d.tiles > 0) out << d.tilesListDiffer[0] << "," << d.tilesListDiffer[1];
        else out << ",";
        if (gl.gpu) out << "," << ms(r.glWall.frameMs);
        out << "\n";
    }
}

// --depth-analysis: tessera's and GL's D24 codes against the double-precision truth of the
// opaque geometry (depth_truth.h), the class of each difference and the triangle behind it.
namespace dt = tessera::depth_truth;

// Where a pixel's truth came from: draw item, triangle, whether it was clipped.
struct Winner {
    std::int32_t item = -1;
    std::uint32_t triangle = 0;
    bool clipped = false;
};

// llvmpipe's depth plane as lp_state_setup.c builds it (init_args / calc_coef4): float window
// positions (the draw module's x * (1/w) * scale + translate), the plane's gradients from the
// unsnapped positions and a float 1/area, a0 extrapolated to the framebuffer origin's pixel
// centre, evaluated a0 + dzdx x + dzdy y at integer pixel coordinates (the order of the
// interpolator's sums is not modelled); then clamped to [0, 1] and converted as lp_bld_conv.c does. For unclipped triangles only (llvmpipe's clipper is not
// modelled).
std::uint32_t llvmpipeModel(const glm::vec4 c[3], float width, float height, std::int64_t px, std::int64_t py,
                            float* dzdxOut = nullptr, float* a0Out = nullptr) {
    float x[3], y[3], z[3];
    for (int i = 0; i < 3; ++i) {
        const float oow = 1.0f / c[i].w;
        x[i] = c[i].x * oow * (width * 0.5f) + width * 0.5f;
        y[i] = -c[i].y * oow * (height * 0.5f) + height * 0.5f;
        z[i] = c[i].z * oow;
    }
    const float x0c = x[0] - 0.5f, y0c = y[0] - 0.5f;
    const float dx01 = x[0] - x[1], dy01 = y[0] - y[1], dx20 = x[2] - x[0], dy20 = y[2] - y[0];
    const float e = dx01 * dy20, f = dy01 * dx20;
    const float ooa = 1.0f / (e - f);
    const float dx20o = dx20 * ooa, dy20o = dy20 * ooa, dx01o = dx01 * ooa, dy01o = dy01 * ooa;
    const float dz01 = z[0] - z[1], dz20 = z[2] - z[0];
    const float dzdx = dz01 * dy20o - dz20 * dy01o;
    const float dzdy = dz20 * dx01o - dz01 * dx20o;
    const float a0 = z[0] - (dzdx * x0c + dzdy * y0c);
    if (dzdxOut) *dzdxOut = dzdx;
    if (a0Out) *a0Out = a0;
    float zp = a0 + (dzdx * float(px) + dzdy * float(py));
    zp = std::min(std::max(zp, 0.0f), 1.0f);
    // lp_build_clamped_float_to_unsigned_norm for 24 bits (= mantissa + 1): the product
    // z * (2^24 - 1) in float, then rounded to an integer.
    const float scaled = zp * 16777215.0f;
    return std::uint32_t(std::nearbyint(scaled));
}

void depthAnalysis(const LoadedScene& s, const Config& c, std::uint32_t threads, const Frame8& tess, const Frame8& gl,
                   const std::string& csvPath) {
    if (c.technique == Technique::Deferred) {
        std::printf("\n(depth analysis: %s skipped: its G-buffer pass alpha-tests, which the truth does not model)\n", c.id.c_str());
        return;
    }
    const TechniqueContext ctx = contextFor(s, nullptr);
    const std::shared_ptr<ForwardPassSetup> setup =
        makeForwardPassSetup(ctx, ProjectionConvention::DemoGl, PhongSamplerChoice::Demo, false);
    const std::uint32_t w = setup->width, h = setup->height;
    const SceneResources& res = *s.resources;
    std::vector<std::uint32_t> truth(std::size_t(w) * h, dt::kFarCode);
    std::vector<Winner> winner(truth.size());
    const auto triangleClip = [&](const DrawItem& item, std::uint32_t tri, glm::vec4 out[3]) {
        const PrimitiveBuffer& prim = res.primitives()[item.primitive];
        const glm::mat4 viewFromObject = setup->viewFromWorld * item.worldFromObject;
        const PhongVS vs{setup->clipFromView * viewFromObject, viewFromObject};
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t index = prim.indices.empty() ? tri * 3 + k : prim.indices[tri * 3 + k];
            out[k] = vs(prim.vertices[index]).posClip;
        }
    };
    std::uint64_t trianglesClipped = 0;
    for (std::size_t k = 0; k < res.drawItems().size(); ++k) {
        const DrawItem& item = res.drawItems()[k];
        const PhongMaterial material = phongFromGltf(res.material(item.material));
        if (material.isTransparent()) continue;  // the transparent pass writes no depth
        const PrimitiveBuffer& prim = res.primitives()[item.primitive];
        const std::size_t count = (prim.indices.empty() ? prim.vertices.size() : prim.indices.size()) / 3;
        for (std::uint32_t tri = 0; tri < count; ++tri) {
            glm::vec4 cf[3];
            triangleClip(item, tri, cf);
            const glm::dvec4 cd[3] = {glm::dvec4(cf[0]), glm::dvec4(cf[1]), glm::dvec4(cf[2])};
            bool inside = true;
            for (const glm::dvec4& v : cd) inside = inside && v.z >= 0.0 && v.z <= v.w && v.w > 0.0;
            glm::dvec4 poly[12];
            const int n = dt::clip(cd, poly);
            if (!inside && n >= 3) ++trianglesClipped;
            for (int i = 1; i + 1 < n; ++i) {
                const glm::dvec4 fan[3] = {poly[0], poly[i], poly[i + 1]};
                dt::Triangle t;
                if (!dt::makeTriangle(fan, double(w), double(h), item.frontCounterClockwise, t)) continue;
                if (!material.doubleSided && !t.front) continue;  // cull back
                const std::int64_t minX = std::min({t.x[0], t.x[1], t.x[2]}), maxX = std::max({t.x[0], t.x[1], t.x[2]});
                const std::int64_t minY = std::min({t.y[0], t.y[1], t.y[2]}), maxY = std::max({t.y[0], t.y[1], t.y[2]});
                // pixel centres px * 256 + 128 in [min, max]
                const auto lo = [](std::int64_t v) { return v - 128 >= 0 ? (v - 128 + 255) / 256 : -((128 - v) / 256); };
                const auto hi = [](std::int64_t v) { return v - 128 >= 0 ? (v - 128) / 256 : -((128 - v + 255) / 256); };
                const std::int64_t x0 = std::max<std::int64_t>(0, lo(minX)), x1 = std::min<std::int64_t>(w - 1, hi(maxX));
                const std::int64_t y0 = std::max<std::int64_t>(0, lo(minY)), y1 = std::min<std::int64_t>(h - 1, hi(maxY));
                for (std::int64_t py = y0; py <= y1; ++py)
                    for (std::int64_t px = x0; px <= x1; ++px) {
                        double z;
                        if (!dt::depthAt(t, px, py, z)) continue;
                        const std::uint32_t code = dt::d24(std::min(std::max(z, 0.0), 1.0));
                        const std::size_t p = std::size_t(py) * w + std::size_t(px);
                        if (code < truth[p]) {
                            truth[p] = code;
                            winner[p] = {std::int32_t(k), tri, !inside};
                        }
                    }
            }
        }
    }
    // Classes by |tessera - GL|: 0, 1, 2..16, > 16; within each, each side's distance from the truth.
    const auto bucket = [](std::int64_t d) { d = d < 0 ? -d : d; return d == 0 ? 0 : d == 1 ? 1 : d <= 16 ? 2 : 3; };
    const char* names[4] = {"0", "1", "2-16", ">16"};
    std::uint64_t classCount[4] = {}, tessErr[4][4] = {}, glErr[4][4] = {}, clippedIn[4] = {}, coveredTruth[4] = {};
    std::int64_t tessMax = 0, glMax = 0;
    std::FILE* csv = csvPath.empty() ? nullptr : std::fopen(csvPath.c_str(), "w");
    if (!csvPath.empty() && !csv) throw std::runtime_error("cannot write " + csvPath);
    if (csv)
        std::fprintf(csv, "x,y,tessera,gl,truth,item,triangle,clipped,area_px2,dzdx_codes,dzdy_codes,a0,llvmpipe_model,"
                          "x0,y0,z0,x1,y1,z1,x2,y2,z2,clip0,clip1,clip2\n");
    std::uint64_t modelMatches = 0, modelTried = 0;
    for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) {
            const std::size_t p = std::size_t(y) * w + x;
            const std::int64_t a = tess.depthCode[p], b = gl.depthCode[p], t = truth[p];
            const int cls = bucket(a - b);
            ++classCount[cls];
            ++tessErr[cls][bucket(a - t)];
            ++glErr[cls][bucket(b - t)];
            tessMax = std::max(tessMax, std::abs(a - t));
            glMax = std::max(glMax, std::abs(b - t));
            if (winner[p].item >= 0) ++coveredTruth[cls];
            if (winner[p].clipped) ++clippedIn[cls];
            const bool interesting = std::abs(a - t) > 1 || std::abs(b - t) > 16 || std::abs(a - b) > 16;
            if (!interesting || !csv || winner[p].item < 0) continue;
            const Winner& win = winner[p];
            glm::vec4 cf[3];
            triangleClip(res.drawItems()[std::size_t(win.item)], win.triangle, cf);
            const glm::dvec4 cd[3] = {glm::dvec4(cf[0]), glm::dvec4(cf[1]), glm::dvec4(cf[2])};
            dt::Triangle tri;
            const bool whole = dt::makeTriangle(cd, double(w), double(h), true, tri);
            double dzdx = 0.0, dzdy = 0.0;
            if (whole) {  // the plane's gradients in codes per pixel
                const double x1 = double(tri.x[1] - tri.x[0]) / 256.0, y1 = double(tri.y[1] - tri.y[0]) / 256.0;
                const double x2 = double(tri.x[2] - tri.x[0]) / 256.0, y2 = double(tri.y[2] - tri.y[0]) / 256.0;
                const double z1 = tri.z[1] - tri.z[0], z2 = tri.z[2] - tri.z[0], det = x1 * y2 - x2 * y1;
                dzdx = (z1 * y2 - z2 * y1) / det * 16777215.0;
                dzdy = (x1 * z2 - x2 * z1) / det * 16777215.0;
            }
            float a0 = 0.0f;
            long long model = -1;
            if (!win.clipped) {
                model = llvmpipeModel(cf, float(w), float(h), x, y, nullptr, &a0);
                ++modelTried;
                if (std::llabs(model - b) <= 1) ++modelMatches;
            }
            std::fprintf(csv, "%u,%u,%lld,%lld,%lld,%d,%u,%d,%.6g,%.6g,%.6g,%.9g,%lld", x, y, (long long)a, (long long)b,
                         (long long)t, win.item, win.triangle, int(win.clipped), double(tri.area2) / 131072.0, dzdx, dzdy,
                         double(a0), model);
            for (int i = 0; i < 3; ++i)
                std::fprintf(csv, ",%.4f,%.4f,%.9f", double(tri.x[i]) / 256.0, double(tri.y[i]) / 256.0, tri.z[i]);
            for (int i = 0; i < 3; ++i)  // the vertex shader's float clip position, exactly (hex floats)
                std::fprintf(csv, ",%a %a %a %a", double(cf[i].x), double(cf[i].y), double(cf[i].z), double(cf[i].w));
            std::fprintf(csv, "\n");
        }
    if (csv) std::fclose(csv);
    std::printf("\n## Depth against the double-precision truth: %s, %u thread(s) (%llu opaque triangles clipped)\n\n",
                c.id.c_str(), threads, (unsigned long long)trianglesClipped);
    std::printf("| \\|tessera - GL\\| codes | pixels | truth covered | winner clipped | tessera - truth 0 / 1 / 2-16 / >16 | "
                "GL - truth 0 / 1 / 2-16 / >16 |\n|---|---:|---:|---:|---|---|\n");
    for (int k = 0; k < 4; ++k)
        std::printf("| %s | %llu | %llu | %llu | %llu / %llu / %llu / %llu | %llu / %llu / %llu / %llu |\n", names[k],
                    (unsigned long long)classCount[k], (unsigned long long)coveredTruth[k], (unsigned long long)clippedIn[k],
                    (unsigned long long)tessErr[k][0], (unsigned long long)tessErr[k][1], (unsigned long long)tessErr[k][2],
                    (unsigned long long)tessErr[k][3], (unsigned long long)glErr[k][0], (unsigned long long)glErr[k][1],
                    (unsigned long long)glErr[k][2], (unsigned long long)glErr[k][3]);
    std::printf("\nmax |tessera - truth| %lld codes, max |GL - truth| %lld codes; llvmpipe's float plane model "
                "(unclipped winners of the listed pixels) within 1 code of GL at %llu of %llu\n",
                (long long)tessMax, (long long)glMax, (unsigned long long)modelMatches, (unsigned long long)modelTried);
}

} // namespace

int main(int argc, char** argv) {
    const Options opt = parseArgs(argc, argv);
    const std::vector<std::uint32_t> threadCounts = benchThreadCounts(opt);
    const GlLabels labels{opt.platform == samefr::GlPlatform::Device};
    if (labels.gpu) gMsDecimals = 3;
    bench::useSteadyStateAllocator();
    std::vector<Config> configs;
    for (const std::string& t : opt.techniques) {
        if (t == "forward") configs.push_back({t, Technique::Forward, "sponza-large-lights", opt.forwardLights});
        if (t == "forward-plus") configs.push_back({t, Technique::ForwardPlus, "sponza-small-lights", opt.forwardPlusLights});
        if (t == "deferred") configs.push_back({t, Technique::Deferred, "sponza-small-lights", opt.deferredLights});
    }
    std::vector<Row> rows;
    GlInfo info;
    samefr::GlOptions glOptions;
    glOptions.emulatedSampling = opt.emulatedSampling;
    glOptions.timerQueries = labels.gpu;
    samefr::GlContextOptions contextOptions;
    contextOptions.platform = opt.platform;
    contextOptions.device = opt.glDevice;
    const std::string glName = labels.gpu ? "gpu" : "llvmpipe";
    try {
        for (const Config& c : configs) {
            std::fprintf(stderr, "loading %s with %u lights for %s...\n", c.scene.c_str(), c.lights, c.id.c_str());
            const std::unique_ptr<LoadedScene> scene = loadBenchScene(c, opt);
            RunResult gpu;  // a GPU's run, once per technique: thread counts are tessera's alone
            if (labels.gpu) {
                std::fprintf(stderr, "  %s: GPU...\n", c.id.c_str());
                gpu = runGl(*scene, c, contextOptions, opt.iterations, glOptions, info);
            }
            for (std::uint32_t threads : threadCounts) {
                std::fprintf(stderr, "  %s, %u thread(s): tessera...\n", c.id.c_str(), threads);
                RunResult tess = runTessera(*scene, c, threads, opt.iterations, opt.tileSize, opt.precision);
                RunResult llvmpipe;
                if (!labels.gpu) {
                    std::fprintf(stderr, "  %s, %u thread(s): llvmpipe...\n", c.id.c_str(), threads);
                    contextOptions.threads = threads;
                    llvmpipe = runGl(*scene, c, contextOptions, opt.iterations, glOptions, info);
                }
                const RunResult& lp = labels.gpu ? gpu : llvmpipe;
                Row row{c, threads, tess.timings, lp.timings, lp.wallTimings, compare(tess.image, lp.image)};
                compareLists(tess.lists, lp.lists, row.diff);
                if (!opt.depthAnalysis.empty())
                    depthAnalysis(*scene, c, threads, tess.image, lp.image,
                                  opt.depthAnalysis + (configs.size() > 1 ? "." + c.id : std::string()));
                if (!opt.dumpDir.empty())
                    dumpImages(opt.dumpDir, c.id + "-t" + std::to_string(threads), tess.image, lp.image, glName);
                rows.push_back(std::move(row));
            }
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "same_frame_bench: %s\n", e.what());
        return 1;
    }
    std::printf("# Same frame: tessera (%s) vs %s, 1280x720 Sponza, %u timed frames after 1 warm-up; tessera forward-plus "
                "culling %s%s\n",
                std::string(precisionName(opt.precision)).c_str(), info.renderer.c_str(), opt.iterations, opt.forwardPlusCulling.c_str(),
                opt.emulatedSampling ? ("; " + glName + " with --sampler emulated (diagnostic: times not comparable)").c_str() : "");
    std::printf("\nGL platform %s; GL_VENDOR %s; GL_RENDERER %s; GL_VERSION %s\n", labels.gpu ? "device" : "surfaceless",
                info.vendor.c_str(), info.renderer.c_str(), info.version.c_str());
    printTables(rows, labels);
    if (!opt.csv.empty()) writeCsv(opt.csv, rows, labels);
    return 0;
}
