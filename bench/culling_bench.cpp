// Light-culling benchmark of the tiled techniques on the 3dgep experiment
// (3dgep article §5: Sponza, 1280x720, N large or small lights) by tile size and thread count: median
// pass times after a warm-up, lights per tile and the false-positive rate. Prints a markdown
// table; command and results in bench/RESULTS.md.
//
// Usage: culling_bench [--techniques forward-plus,forward-plus-amd] [--scenario large|small|both]
//                      [--lights 1,2,4,...,16384] [--tile-sizes 8,16,32] [--threads 1,2]
//                      [--frames 5] [--warmup 1] [--width 1280 --height 720]
//                      [--through culling|frame] [--fp on|off] [--hash on|off] [--option KEY=V1|V2 ...]
//   --through culling   run the passes up to the culling pass only (the first pass whose name
//                       contains "cull"); frame ms is then the sum of those passes.
//   --option KEY=V1|V2  a technique option swept over the values (JSON, else a string), e.g.
//                       --option culling=binned|brute; repeatable (all combinations).
//   --hash on           two extra columns: FNV-1a of the grids, lists and counters, and of the heat map.
//   A technique that is not implemented, or rejects an option, gets a row saying so.
// False positives (geometric truth): a light in a tile's opaque list that reaches no pixel of
// the tile, where "reaches" is the support of the light's attenuation times spot factor
// (phong_lighting.h: distance < Range, and for a spot dot(DirectionVS, P - PositionVS) >
// |P - PositionVS| cos(SpotlightAngle)), P the pixel centre's view position rebuilt from the
// depth buffer (screenToView), N.L ignored; pixels at depth 1 (nothing drawn) reach nothing.
// Computed once per row, in double, from the last measured frame's buffers; lists are read
// from "lightgrid.opaque" / "lightindex.opaque" ("-" where a technique has no such buffers).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include <tessera/gbuffer/screen_to_view.h>
#include <tessera/scene/scene_file.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/technique.h>

#include "bench_support.h"

namespace {

using namespace tessera;
using bench::median;
using bench::split;
using bench::splitUints;

nlohmann::json optionValue(const std::string& text) {
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception&) {
        return text;  // a bare word: a string option
    }
}

std::uint32_t loadUint(const Surface& s, std::uint32_t x, std::uint32_t y, std::uint32_t component) {
    std::uint32_t v;
    std::memcpy(&v, s.texel(x, y) + component * sizeof(std::uint32_t), sizeof(v));
    return v;
}

struct ListStats {
    bool valid = false;
    double meanOpaque = 0.0, meanTransparent = 0.0;   // lights per tile (grid counts)
    std::uint32_t maxOpaque = 0, maxTransparent = 0;
    double falsePositiveRate = -1.0;                   // of the stored opaque entries; < 0: not computed
};

// True when the light's attenuation (and spot factor) is non-zero at view position p
// (phong_lighting.h doAttenuation, doSpotCone), in double.
bool reaches(const ViewLight<float>& light, const glm::dvec3& p) {
    if (!light.enabled) return false;
    if (light.type == LightType::Directional) return true;
    const glm::dvec3 toP = p - glm::dvec3(light.positionView);
    const double distance = glm::length(toP);
    if (!(distance < double(light.range))) return false;
    if (light.type == LightType::Point) return true;
    const double cosCone = std::cos(double(light.spotlightAngleDeg) * (3.14159265358979323846 / 180.0));
    return glm::dot(glm::dvec3(light.directionView), toP) > distance * cosCone;
}

// Lights per tile from the grids and, with fp, the false-positive rate of the opaque lists.
ListStats listStats(const BufferRegistry& reg, const ForwardPassSetup& setup, bool fp) {
    ListStats st;
    const Surface* gridO = reg.find("lightgrid.opaque");
    const Surface* gridT = reg.find("lightgrid.transparent");
    const Surface* listO = reg.find("lightindex.opaque");
    const Surface* depth = reg.find("depth");
    if (!gridO || !gridT || !listO || !depth || gridO->format() != Format::R32G32_UINT) return st;
    st.valid = true;
    const std::uint32_t tilesX = gridO->width(), tilesY = gridO->height();
    // The tile edge (px): the smallest T with ceil(W / T) x ceil(H / T) tiles = the grid's size.
    std::uint32_t tileSize = 1;
    while (tileSize < 1024 && ((setup.width + tileSize - 1) / tileSize != tilesX || (setup.height + tileSize - 1) / tileSize != tilesY))
        ++tileSize;
    const std::uint64_t tileCount = std::uint64_t{tilesX} * tilesY;
    std::uint64_t sumO = 0, sumT = 0;
    for (std::uint32_t ty = 0; ty < tilesY; ++ty)
        for (std::uint32_t tx = 0; tx < tilesX; ++tx) {
            const std::uint32_t o = loadUint(*gridO, tx, ty, 1), t = loadUint(*gridT, tx, ty, 1);
            sumO += o;
            sumT += t;
            st.maxOpaque = std::max(st.maxOpaque, o);
            st.maxTransparent = std::max(st.maxTransparent, t);
        }
    st.meanOpaque = double(sumO) / double(tileCount);
    st.meanTransparent = double(sumT) / double(tileCount);
    if (!fp) return st;

    const std::uint64_t listEntries = std::uint64_t{listO->width()} * listO->height();
    const glm::vec2 dims(float(setup.width), float(setup.height));
    const glm::mat4 inverseProjection = glm::inverse(setup.clipFromView);
    std::atomic<std::uint64_t> stored{0}, falsePositives{0};
    tbb::parallel_for(std::uint32_t(0), tilesY, [&](std::uint32_t ty) {
        std::vector<glm::dvec3> points;
        std::uint64_t rowStored = 0, rowFalse = 0;
        for (std::uint32_t tx = 0; tx < tilesX; ++tx) {
            points.clear();
            for (std::uint32_t y = ty * tileSize; y < std::min((ty + 1) * tileSize, setup.height); ++y)
                for (std::uint32_t x = tx * tileSize; x < std::min((tx + 1) * tileSize, setup.width); ++x) {
                    const float d = depth->loadDepth(x, y);
                    if (d < 1.0f)
                        points.emplace_back(screenToView(glm::vec4(float(x) + 0.5f, float(y) + 0.5f, d, 1.0f), dims, inverseProjection));
                }
            const std::uint32_t offset = loadUint(*gridO, tx, ty, 0), count = loadUint(*gridO, tx, ty, 1);
            for (std::uint32_t i = 0; i < count; ++i) {
                const std::uint64_t at = std::uint64_t{offset} + i;
                if (at >= listEntries) break;  // past the global list: not stored
                const std::uint32_t lightIndex =
                    loadUint(*listO, std::uint32_t(at % listO->width()), std::uint32_t(at / listO->width()), 0);
                if (lightIndex >= setup.lightsExact.size()) continue;
                ++rowStored;
                const ViewLight<float>& light = setup.lightsExact[lightIndex];
                rowFalse += std::none_of(points.begin(), points.end(), [&](const glm::dvec3& p) { return reaches(light, p); });
            }
        }
        stored += rowStored;
        falsePositives += rowFalse;
    });
    st.falsePositiveRate = stored.load() ? double(falsePositives.load()) / double(stored.load()) : 0.0;
    return st;
}

struct Variant {
    nlohmann::json options;  // the swept options of this row
    std::string label;       // "culling=brute, ..." or "-"
};

std::vector<Variant> variants(const std::vector<std::pair<std::string, std::vector<std::string>>>& sweeps) {
    std::vector<Variant> out{{nlohmann::json::object(), ""}};
    for (const auto& [key, values] : sweeps) {
        std::vector<Variant> next;
        for (const Variant& v : out)
            for (const std::string& value : values) {
                Variant w = v;
                w.options[key] = optionValue(value);
                char label[512];  // snprintf: GCC 12's -Wrestrict misfires on short string appends
                std::snprintf(label, sizeof label, "%s%s%s=%s", w.label.c_str(), w.label.empty() ? "" : ", ", key.c_str(),
                              value.c_str());
                w.label = label;
                next.push_back(w);
            }
        out = next;
    }
    for (Variant& v : out)
        if (v.label.empty()) v.label.assign(1, '-');  // not = "-": GCC 12 -Wrestrict false positive
    return out;
}

} // namespace

int main(int argc, char** argv) {
    bench::useSteadyStateAllocator();
    std::vector<std::string> techniquesToRun = {"forward-plus"};
    std::vector<std::string> scenarios = {"large", "small"};
    std::vector<std::uint32_t> lightCounts = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384};
    std::vector<std::uint32_t> tileSizes = {8, 16, 32};
    std::vector<std::uint32_t> threadCounts = {1, 2};
    std::vector<std::pair<std::string, std::vector<std::string>>> sweeps;
    std::uint32_t frames = 5, warmup = 1, width = 1280, height = 720;
    bool throughCulling = false, fp = true, hash = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (i + 1 >= argc) {
            std::fprintf(stderr, "%s needs a value\n", a.c_str());
            return 2;
        }
        const std::string v = argv[++i];
        if (a == "--techniques") techniquesToRun = split(v, ',');
        else if (a == "--scenario") scenarios = v == "both" ? std::vector<std::string>{"large", "small"} : std::vector<std::string>{v};
        else if (a == "--lights") lightCounts = splitUints(a, v);
        else if (a == "--tile-sizes") tileSizes = splitUints(a, v);
        else if (a == "--threads") threadCounts = splitUints(a, v);
        else if (a == "--frames") frames = std::max(1u, splitUints(a, v).at(0));
        else if (a == "--warmup") warmup = splitUints(a, v).at(0);
        else if (a == "--width") width = splitUints(a, v).at(0);
        else if (a == "--height") height = splitUints(a, v).at(0);
        else if (a == "--through" && (v == "culling" || v == "frame")) throughCulling = v == "culling";
        else if (a == "--fp" && (v == "on" || v == "off")) fp = v == "on";
        else if (a == "--hash" && (v == "on" || v == "off")) hash = v == "on";
        else if (a == "--option" && v.find('=') != std::string::npos && v.find('=') > 0)
            sweeps.emplace_back(v.substr(0, v.find('=')), split(v.substr(v.find('=') + 1), '|'));
        else {
            std::fprintf(stderr, "unknown option or value: %s %s\n", a.c_str(), v.c_str());
            return 2;
        }
    }
    for (const std::string& s : scenarios)
        if (s != "large" && s != "small") {
            std::fprintf(stderr, "--scenario: '%s' is not large, small or both\n", s.c_str());
            return 2;
        }
    const std::vector<Variant> optionVariants = variants(sweeps);
    const std::uint32_t maxLights = lightCounts.empty() ? 0 : *std::max_element(lightCounts.begin(), lightCounts.end());

    std::printf("| technique | scenario | lights | tile | threads | options | culling ms | frame ms%s | passes (median ms) | "
                "opaque mean / max per tile | transparent mean / max | false positives |\n"
                "|---|---|---|---|---|---|---|---|---|---|---|---|\n",
                throughCulling ? " (to culling)" : "");
    std::fflush(stdout);
    for (const std::string& scenario : scenarios) {
        // One load with the largest count: the generator's first N lights are a count-N
        // generator's lights (technique_bench.cpp). TESSERA_SOURCE_DIR in the environment
        // overrides the build's source tree (bench/RESULTS.md).
        const char* sourceDirEnv = std::getenv("TESSERA_SOURCE_DIR");
        const std::filesystem::path file = std::filesystem::path(sourceDirEnv ? sourceDirEnv : TESSERA_SOURCE_DIR) / "scenes" /
                                           ("sponza-" + scenario + "-lights.json");
        SceneDescription desc = parseSceneFile(file);
        for (auto& g : desc.generators) g.count = maxLights;
        Camera camera;
        Scene scene = loadScene(desc, true, &camera);
        const std::vector<Light> allLights = scene.lights;
        std::map<TexturePolicy, std::unique_ptr<SceneResources>> resourcesByPolicy;

        for (const std::string& technique : techniquesToRun) {
            const TechniqueInfo* info = findTechnique(technique);
            const auto row = [&](std::uint32_t n, const std::string& tile, std::uint32_t threads, const std::string& options,
                                 const std::string& rest) {
                std::printf("| %s | %s | %u | %s | %u | %s | %s |\n", technique.c_str(), scenario.c_str(), n, tile.c_str(), threads,
                            options.c_str(), rest.c_str());
                std::fflush(stdout);
            };
            if (!info || !info->build) {
                row(0, "-", 0, "-", "not implemented | - | - | - | - | -");
                continue;
            }
            const bool hasTileSize = findOption(info->id, "tileSize") != nullptr;
            const std::vector<std::uint32_t> tiles = hasTileSize ? tileSizes : std::vector<std::uint32_t>{0};
            std::unique_ptr<SceneResources>& resources = resourcesByPolicy[info->textures];
            if (!resources) resources = std::make_unique<SceneResources>(scene, std::function<void(std::size_t, std::size_t)>{}, info->textures);

            for (const std::uint32_t n : lightCounts)
                for (const std::uint32_t tile : tiles)
                    for (const Variant& variant : optionVariants)
                        for (const std::uint32_t threads : threadCounts) {
                            const std::string tileText = tile ? std::to_string(tile) : "default";
                            scene.lights.assign(allLights.begin(), allLights.begin() + std::min<std::size_t>(n, allLights.size()));
                            Device device(DeviceConfig{64, threads});
                            DrawStats stats;
                            TechniqueContext ctx;
                            ctx.device = &device;
                            ctx.resources = resources.get();
                            ctx.camera = camera;
                            ctx.width = width;
                            ctx.height = height;
                            ctx.options = desc.techniqueOptions.is_object() ? desc.techniqueOptions : nlohmann::json::object();
                            if (tile) ctx.options["tileSize"] = tile;
                            for (const auto& [key, value] : variant.options.items()) ctx.options[key] = value;
                            ctx.stats = &stats;
                            ctx.sceneFile = file.string();
                            Frame frame;
                            try {
                                const Frame full = buildTechnique(technique, ctx, file.string());
                                for (const Pass& pass : full.passes()) {
                                    frame.add(pass);
                                    if (throughCulling && pass.name.find("cull") != std::string::npos) break;
                                }
                            } catch (const std::exception& e) {
                                row(n, tileText, threads, variant.label, std::string("not run: ") + e.what() + " | - | - | - | - | -");
                                continue;
                            }
                            std::map<std::string, std::vector<double>> passMs;
                            std::vector<std::string> order;
                            std::vector<double> frameMs, cullMs;
                            std::unique_ptr<BufferRegistry> last;
                            std::uint32_t warmupLeft = warmup;
                            while (frameMs.size() < frames) {
                                auto registry = std::make_unique<BufferRegistry>();
                                const auto timings = frame.run(*registry);
                                if (warmupLeft > 0) {
                                    --warmupLeft;
                                    continue;
                                }
                                double sum = 0.0, cull = 0.0;
                                for (const PassTiming& t : timings) {
                                    if (!passMs.count(t.name)) order.push_back(t.name);
                                    passMs[t.name].push_back(t.milliseconds);
                                    sum += t.milliseconds;
                                    if (t.name.find("cull") != std::string::npos) cull += t.milliseconds;
                                }
                                frameMs.push_back(sum);
                                cullMs.push_back(cull);
                                // Only the last frame's buffers are kept (for the list statistics):
                                // a frame's buffers are freed before the next frame allocates, as
                                // in technique_bench, so the allocator can reuse their pages.
                                if (frameMs.size() == frames) last = std::move(registry);
                            }
                            std::string passes;
                            for (const std::string& name : order) {
                                char buf[96];
                                std::snprintf(buf, sizeof buf, "%s%s %.2f", passes.empty() ? "" : ", ", name.c_str(), median(passMs[name]));
                                passes += buf;
                            }
                            // The technique's default projection: demo-gl, except forward-plus-amd
                            // with its own shading, which culls and draws with the D3D matrix
                            // (forward_plus_amd.h).
                            const bool amdShading =
                                technique == "forward-plus-amd" && ctx.options.value("shading", std::string("amd")) == "amd";
                            const std::string defaultProjection = amdShading ? "d3d" : "demo-gl";
                            const ProjectionConvention projection = ctx.options.value("projection", defaultProjection) == "d3d"
                                                                        ? ProjectionConvention::D3d
                                                                        : ProjectionConvention::DemoGl;
                            const std::shared_ptr<ForwardPassSetup> setup =
                                makeForwardPassSetup(ctx, projection, PhongSamplerChoice::Demo, false);
                            ListStats ls;
                            device.execute([&] { ls = listStats(*last, *setup, fp); });
                            char fpText[32] = "-";
                            if (ls.falsePositiveRate >= 0.0) std::snprintf(fpText, sizeof fpText, "%.1f %%", ls.falsePositiveRate * 100.0);
                            char rest[1024];
                            if (ls.valid)
                                std::snprintf(rest, sizeof rest, "%.2f | %.2f | %s | %.2f / %u | %.2f / %u | %s", median(cullMs),
                                              median(frameMs), passes.c_str(), ls.meanOpaque, ls.maxOpaque, ls.meanTransparent,
                                              ls.maxTransparent, fpText);
                            else
                                std::snprintf(rest, sizeof rest, "%.2f | %.2f | %s | - | - | -", median(cullMs), median(frameMs),
                                              passes.c_str());
                            std::string restText = rest;
                            if (hash) {  // FNV-1a 64 of the grids, lists and counters, and of the heat map
                                const auto fnv = [&](std::initializer_list<const char*> names) {
                                    std::uint64_t h = 1469598103934665603ull;
                                    bool any = false;
                                    for (const char* name : names)
                                        if (const Surface* s = last->find(name)) {
                                            any = true;
                                            for (const std::byte b : s->bytes()) h = (h ^ std::uint64_t(b)) * 1099511628211ull;
                                        }
                                    char text[24] = "-";
                                    if (any) std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
                                    return std::string(text);
                                };
                                restText += " | " + fnv({"lightgrid.opaque", "lightgrid.transparent", "lightindex.opaque",
                                                         "lightindex.transparent", "lightlist.counters"}) +
                                            " | " + fnv({"heatmap"});
                            }
                            row(n, tileText, threads, variant.label, restText);
                        }
        }
    }
    return 0;
}
