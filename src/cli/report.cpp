// The teaching report (report.h). Renders each ready technique once at a small size, writing the
// buffers every pass declares (viewable pictures: inspect/buffer_view.h) after that pass, then
// index.html beside them: no server, no network, no external scripts; opens from disk.
#include "commands.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <tessera/buffers/texel_codec.h>
#include <tessera/inspect/buffer_view.h>
#include <tessera/io/atomic_file.h>
#include <tessera/io/image_writer.h>
#include <tessera/errors/input_error.h>
#include <tessera/scene/default_lights.h>
#include <tessera/techniques/option_catalog.h>
#include <tessera/techniques/technique.h>

#include "arg_cursor.h"
#include "frame_runs.h"  // lightGridTileSize
#include "output_check.h"
#include "scene_args.h"

namespace tessera::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kReportUsage = R"(usage: tessera report [SCENE] --out DIR [options]

Renders SCENE (default: the bundled scene 'default') with every ready technique and writes
DIR/index.html: each technique's passes in order with the buffers each pass wrote (as viewable
pictures), what the pass does and where its source describes it, one light's deferred stencil
steps (unmark, shade), per-pass times, and every technique's difference from forward with the
errata that explain it. The page works from disk: no server, no network, no external scripts.

options:
  -o, --out DIR  the report's folder (created; its files are overwritten)
  --width W      width in px (default 480)
  --height H     height in px (default 270)
  --light I      the light whose deferred steps are shown (default: the first point or spot light whose
                 volume leaves the eye outside, so the stencil shows the trick)
  --threads N    worker threads, 0 = all cores (default 0)
  --help         show this text
)";


std::string html(std::string_view text) {
    std::string out;
    for (const char c : text) {
        if (c == '<') out += "&lt;";
        else if (c == '>') out += "&gt;";
        else if (c == '&') out += "&amp;";
        else if (c == '"') out += "&quot;";
        else out += c;
    }
    return out;
}

// Why a technique's image differs from forward's, from what the run itself says: what it counted
// as skipped or clamped (its FrameNotes, with their ERRATA.md rows), then every option of the
// catalogue that corrects an erratum and is left at its faithful value in this run (`options`:
// the ones the run was given). Nothing here is written per technique.
std::string differenceNote(std::string_view technique, const nlohmann::json& options, const FrameNotes& notes) {
    std::string out;
    const auto append = [&out](const std::string& part) { out += (out.empty() ? "" : "; ") + part; };
    for (const FrameNote& n : notes.list()) append(noteText(n));
    std::string faithful;
    for (const FaithfulChoice& c : faithfulChoices(techniqueOptions(technique), options))
        faithful += (faithful.empty() ? "" : ", ") + std::string(c.option->key) + "=" + c.value + " (#" + std::to_string(c.option->erratum) + ")";
    if (!faithful.empty()) append("faithful options in effect: " + faithful);
    return out.empty() ? "nothing counted; no faithful option with an erratum" : out + ".";
}

struct Shot {
    std::string file, rule, label;
};
struct PassReport {
    std::string name;
    std::string folder;  // where its pictures are, under the report's root
    double ms = 0.0;
    double bufferMiB = 0.0;  // every named buffer alive after the pass
    std::vector<std::string> reads, writes;
    std::vector<Shot> shots;
};
struct TechniqueReport {
    std::string id, source, summary;
    bool baseline = false;  // the image the others are compared against (kComparisonBaseline)
    std::string why;  // differenceNote of the run
    std::vector<PassReport> passes;
    std::vector<std::pair<std::string, std::vector<Shot>>> lightSteps;
    std::string finalFile;
    double maxAbs = 0, rmse = 0;
    std::uint64_t differing = 0;
};

// True when every stencil value of `s` (every pixel and sample) is the same: a technique that
// never touches the stencil leaves its clear value everywhere, a flat picture that teaches nothing.
bool stencilUniform(const Surface& s) {
    const std::uint8_t first = s.loadStencil(0, 0, 0);
    for (std::uint32_t y = 0; y < s.height(); ++y)
        for (std::uint32_t x = 0; x < s.width(); ++x)
            for (std::uint32_t i = 0; i < s.sampleCount(); ++i)
                if (s.loadStencil(x, y, i) != first) return false;
    return true;
}

// Writes `s` as a picture into dir/file and returns the shot (RGBA8 as stored with opaque alpha;
// others through viewBuffer). Empty file when nothing viewable. A stencil that holds one value
// everywhere gets no picture (the depth shot's rule says which value).
std::vector<Shot> pictures(const fs::path& root, const std::string& folder, const std::string& name, const Surface& s) {
    std::vector<Shot> shots;
    fs::create_directories(root / folder);
    if (s.format() == Format::R8G8B8A8_UNORM || s.format() == Format::R8G8B8A8_UNORM_SRGB) {
        const std::string file = folder + "/" + name + ".png";
        writeSurface(withOpaqueAlpha(s), root / file);
        shots.push_back({file, "the stored RGBA8 bytes, alpha shown opaque", name});
        return shots;
    }
    const bool hasStencil = formatInfo(s.format()).hasStencil;
    const bool flatStencil = hasStencil && s.width() > 0 && s.height() > 0 && stencilUniform(s);
    for (const ViewChannel channel : {ViewChannel::Depth, ViewChannel::Stencil}) {
        if (channel == ViewChannel::Stencil && (!hasStencil || flatStencil)) continue;
        const auto view = viewBuffer(name, s, channel);
        if (!view) continue;
        const std::string label = channel == ViewChannel::Stencil ? name + " (stencil)" : name;
        const std::string file = folder + "/" + name + (channel == ViewChannel::Stencil ? ".stencil" : "") + ".png";
        writeSurface(view->image, root / file);
        std::string rule = view->rule;
        if (channel == ViewChannel::Depth && flatStencil)
            rule += "; its stencil is " + std::to_string(s.loadStencil(0, 0, 0)) + " everywhere (no picture)";
        shots.push_back({file, rule, label});
    }
    // A few counters (lightlist.counters) have no picture: their values, in texel order.
    constexpr std::uint64_t kMaxPrintedValues = 64;
    if (shots.empty() && formatInfo(s.format()).kind == FormatKind::Uint && std::uint64_t(s.width()) * s.height() <= kMaxPrintedValues) {
        std::string values;
        for (std::uint32_t y = 0; y < s.height(); ++y)
            for (std::uint32_t x = 0; x < s.width(); ++x)
                values += (values.empty() ? "" : ", ") + std::to_string(decodeTexelUint(s.format(), s.texel(x, y)).x);
        shots.push_back({"", "values (channel 0, row by row): " + values, name});
    }
    return shots;
}

// Whether light `l`'s volume (a sphere of its range; a spot's cone of its range and half angle)
// holds the point `eyeWorld`, with 5% to spare for the volume meshes and the near plane.
bool volumeHoldsEye(const Light& l, glm::vec3 eyeWorld) {
    constexpr float kMargin = 1.05f;  // the circumscribed meshes reach 1.00114 x range; the near plane a little more
    const glm::vec3 toEye = eyeWorld - l.positionWorld;
    const float distance = glm::length(toEye);
    if (!(distance < l.range * kMargin)) return false;
    if (l.type != LightType::Spot || distance == 0.0f) return true;
    const float cosToEye = glm::dot(toEye / distance, l.directionWorld);
    return cosToEye > std::cos(glm::radians(std::min(90.0f, l.spotHalfAngleDeg * kMargin)));
}

std::string folderName(std::string text) {
    std::replace(text.begin(), text.end(), ' ', '-');
    return text;
}

void writeText(const fs::path& file, const std::string& text) {
    writeFileAtomically(file, std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()));
}

std::string shotsHtml(const std::vector<Shot>& shots) {
    std::string out = "<div class=\"shots\">\n";
    for (const Shot& s : shots)
        out += s.file.empty() ? "<figure><figcaption><b>" + html(s.label) + "</b><br>" + html(s.rule) + "</figcaption></figure>\n"
                              : "<figure><img src=\"" + html(s.file) + "\" alt=\"" + html(s.label) + "\"><figcaption><b>" + html(s.label) +
                                    "</b><br>" + html(s.rule) + "</figcaption></figure>\n";
    return out + "</div>\n";
}

// The technique's final image against forward's: max abs difference (codes), RMSE and differing pixels.
void differenceFromForward(const Surface& back, const Surface* forwardFinal, std::uint32_t width, std::uint32_t height,
                           TechniqueReport& tr) {
    double sumSquares = 0;
    for (std::uint32_t y = 0; y < height; ++y)
        for (std::uint32_t x = 0; x < width; ++x) {
            bool differs = false;
            for (int c = 0; c < 3; ++c) {
                const double d = std::abs(double(std::to_integer<int>(back.texel(x, y)[c])) -
                                          double(std::to_integer<int>(forwardFinal->texel(x, y)[c])));
                tr.maxAbs = std::max(tr.maxAbs, d);
                sumSquares += d * d;
                differs = differs || d > 0;
            }
            tr.differing += differs ? 1 : 0;
        }
    tr.rmse = std::sqrt(sumSquares / (3.0 * double(width) * double(height)));
}

// index.html: the difference table, then each technique's final image, passes and light steps.
std::string reportPage(const std::vector<TechniqueReport>& reports, const fs::path& sceneFile, const Scene& scene,
                       std::uint32_t width, std::uint32_t height, const std::optional<std::uint32_t>& chosenLight) {
    std::string page = R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>tessera report</title>
<style>
body { font-family: sans-serif; margin: 2em; max-width: 1400px; color: #222; }
h2 { border-top: 2px solid #888; padding-top: 0.6em; }
.shots { display: flex; flex-wrap: wrap; gap: 12px; }
figure { margin: 0; max-width: 320px; font-size: 0.8em; }
figure img { width: 320px; image-rendering: pixelated; border: 1px solid #ccc; }
table { border-collapse: collapse; } td, th { border: 1px solid #ccc; padding: 3px 8px; text-align: right; }
td:first-child, th:first-child { text-align: left; }
.pass { margin-left: 1em; } .meta { color: #666; font-size: 0.9em; }
</style>
<script>
// Records failed resources and, once loaded, how many images decoded, for tests and readers.
window.addEventListener('error', function () {
  var s = document.getElementById('status'); s.setAttribute('data-errors', String(Number(s.getAttribute('data-errors') || 0) + 1));
}, true);
window.addEventListener('load', function () {
  var images = Array.prototype.slice.call(document.images);
  var ok = images.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length;
  var s = document.getElementById('status');
  s.textContent = 'images ' + ok + '/' + images.length + ', errors ' + (s.getAttribute('data-errors') || 0);
});
</script></head><body>
)";
    page += "<h1>tessera: the techniques step by step</h1>\n<p class=\"meta\">Scene <code>" + html(sceneFile.string()) + "</code>, " +
            std::to_string(width) + "&times;" + std::to_string(height) + ", " + std::to_string(scene.lights.size()) +
            " lights, precision exact, faithful options. Sources: docs/sources.md; errata: ERRATA.md. " +
            "<span id=\"status\">loading</span></p>\n";
    page += "<h2>Difference from forward</h2>\n<table><tr><th>technique</th><th>max abs (codes)</th><th>RMSE</th><th>differing "
            "px</th><th>why (ERRATA.md)</th></tr>\n";
    for (const TechniqueReport& tr : reports) {
        if (tr.baseline) continue;
        char row[256];
        std::snprintf(row, sizeof(row), "<tr><td>%s</td><td>%.0f</td><td>%.3f</td><td>%llu (%.2f%%)</td>", tr.id.c_str(), tr.maxAbs,
                      tr.rmse, (unsigned long long)tr.differing, 100.0 * double(tr.differing) / (double(width) * height));
        page += row + std::string("<td style=\"text-align:left\">") + html(tr.why) + "</td></tr>\n";
    }
    page += "</table>\n";
    for (const TechniqueReport& tr : reports) {
        page += "<h2 id=\"" + html(tr.id) + "\">" + html(tr.id) + "</h2>\n<p>" + html(tr.summary) + " <span class=\"meta\">(" +
                html(tr.source) + ")</span></p>\n";
        page += shotsHtml({{tr.finalFile, "the back buffer after the last pass", "final image"}});
        for (const PassReport& p : tr.passes) {
            char ms[96];
            std::snprintf(ms, sizeof(ms), "%.2f ms; buffers alive %.2f MiB", p.ms, p.bufferMiB);
            std::string reads, writes;
            for (const std::string& r : p.reads) reads += (reads.empty() ? "" : ", ") + r;
            for (const std::string& w : p.writes) writes += (writes.empty() ? "" : ", ") + w;
            page += "<div class=\"pass\"><h3>" + html(p.name) + " <span class=\"meta\">" + ms + "</span></h3>\n<p>" +
                    html(std::string(passCaption(*findTechnique(tr.id), p.name))) + "</p>\n<p class=\"meta\">reads: " + html(reads.empty() ? "-" : reads) +
                    "; writes: " + html(writes.empty() ? "-" : writes) + "</p>\n" + shotsHtml(p.shots) + "</div>\n";
        }
        if (!tr.lightSteps.empty()) {
            page += "<div class=\"pass\"><h3>light " + std::to_string(*chosenLight) + ", step by step</h3>\n";
            for (const auto& [step, shots] : tr.lightSteps) page += "<h4>after " + html(step) + "</h4>\n" + shotsHtml(shots);
            page += "</div>\n";
        }
    }
    page += "</body></html>\n";
    return page;
}


} // namespace

int reportCommand(const std::vector<std::string_view>& args) {
    std::string sceneArg = "default", outDir;
    std::uint32_t width = 480, height = 270, threads = 0;
    std::optional<std::uint32_t> chosenLight;
    {
        bool sceneGiven = false;
        ArgCursor cursor(args);
        while (cursor.next()) {
            const std::string_view a = cursor.flag();
            const auto value = [&cursor] { return cursor.value(); };
            if (a == "--help" || a == "-h") {
                std::fputs(kReportUsage, stdout);
                return 0;
            }
            if (a == "--out" || a == "-o") outDir = std::string(value());
            else if (a == "--width") width = parseUint(a, value(), 8, 4096);
            else if (a == "--height") height = parseUint(a, value(), 8, 4096);
            else if (a == "--light") chosenLight = parseUint(a, value(), 0, 1000000);
            else if (a == "--threads") threads = parseUint(a, value(), 0, 256);
            else if (cursor.isOption()) throw UsageError("unknown option '" + std::string(a) + "'");
            else if (sceneGiven) throw UsageError("one scene only");
            else {
                sceneArg = std::string(a);
                sceneGiven = true;
            }
        }
        if (outDir.empty()) throw UsageError("--out DIR is required");
        requireOutputFolder("--out", outDir);  // before anything loads or renders
    }

    const fs::path sceneFile = resolveScene(sceneArg);
    const SceneDescription desc = describe(sceneFile);
    Camera camera;
    Scene scene = loadScene(desc, true, &camera);
    if (scene.lights.empty()) scene.lights = defaultLightRig(scene.bounds(), camera);
    // The default light shows the stencil trick: the first point or spot light whose volume leaves
    // the eye outside (a volume around the eye marks every pixel alike: one flat stencil colour),
    // else the first point or spot light.
    for (const bool eyeOutsideOnly : {true, false})
        for (std::size_t i = 0; i < scene.lights.size() && !chosenLight; ++i)
            if (scene.lights[i].type != LightType::Directional &&
                (!eyeOutsideOnly || !volumeHoldsEye(scene.lights[i], camera.positionWorld)))
                chosenLight = std::uint32_t(i);
    if (chosenLight && *chosenLight >= scene.lights.size())
        throw InputError("--light: " + std::to_string(*chosenLight) + " is not a light of " + sceneFile.string() + " (it has " +
                         std::to_string(scene.lights.size()) + ")");
    const SceneResources resources(scene, {}, TexturePolicy::AllLinear);
    const fs::path root(outDir);
    fs::create_directories(root);

    std::vector<TechniqueReport> reports;
    const Surface* forwardFinal = nullptr;
    BufferRegistry forwardRegistry;
    // The baseline first, so that every other technique has its image to be compared against;
    // inspection views (no light model) are left out.
    std::vector<const TechniqueInfo*> order;
    for (const bool baseline : {true, false})
        for (const TechniqueInfo& info : techniques())
            if (info.build && !(info.features & kInspectionView) && ((info.features & kComparisonBaseline) != 0) == baseline)
                order.push_back(&info);
    for (const TechniqueInfo* infoPtr : order) {
        const TechniqueInfo& info = *infoPtr;
        TechniqueReport tr;
        tr.id = std::string(info.id);
        tr.baseline = (info.features & kComparisonBaseline) != 0;
        tr.source = std::string(info.source);
        tr.summary = std::string(info.summary);
        std::fprintf(stderr, "tessera report: %s\n", tr.id.c_str());
        Device device(DeviceConfig{64, threads});
        DrawStats stats;
        TechniqueContext ctx;
        ctx.device = &device;
        ctx.resources = &resources;
        ctx.camera = camera;
        ctx.width = width;
        ctx.height = height;
        ctx.options = tr.id == desc.technique ? desc.techniqueOptions : nlohmann::json::object();
        ctx.stats = &stats;
        FrameNotes notes;
        ctx.notes = &notes;
        ctx.sceneFile = sceneFile.string();
        ctx.afterLightStep = [&](std::size_t light, std::string_view step, const BufferRegistry& reg) {
            if (!chosenLight || light != *chosenLight) return;
            const std::string folder = tr.id + "/light-" + std::to_string(light) + "-" + std::string(step);
            std::vector<Shot> shots = pictures(root, folder, "depth", *reg.find("depth"));
            const std::string target = reg.find("accumulation") ? "accumulation" : std::string(kBackBufferName);
            for (Shot& s : pictures(root, folder, target, *reg.find(target))) shots.push_back(s);
            tr.lightSteps.push_back({std::string(step), shots});
        };
        const Frame frame = buildTechnique(info.id, ctx, sceneFile.string());
        BufferRegistry registry;
        std::size_t passIndex = 0;
        const std::vector<PassTiming> timings = frame.run(registry, [&](const Pass& pass, const BufferRegistry& reg) {
            PassReport pr{pass.name, {}, 0.0, 0.0, pass.reads, pass.writes, {}};
            for (const std::string& name : reg.names()) pr.bufferMiB += double(reg.find(name)->bytes().size()) / (1024.0 * 1024.0);
            const std::string folder = tr.id + "/" + std::to_string(passIndex++) + "-" + folderName(pass.name);
            pr.folder = folder;
            for (const std::string& name : pass.writes)
                if (const Surface* s = reg.find(name))
                    for (Shot& shot : pictures(root, folder, name, *s)) pr.shots.push_back(shot);
            tr.passes.push_back(std::move(pr));
        });
        for (std::size_t i = 0; i < timings.size() && i < tr.passes.size(); ++i) tr.passes[i].ms = timings[i].milliseconds;
        // The tiled techniques' light grids as counts over the final image (as --dump's view/
        // *.overlay.png), beside the pass that wrote them: the image exists only at the frame's end.
        SceneDescription tiled = desc;
        tiled.technique = tr.id;
        tiled.techniqueOptions = ctx.options;
        if (const std::uint32_t tileSize = lightGridTileSize(tiled); tileSize > 0)
            for (PassReport& pr : tr.passes)
                for (const std::string& name : pr.writes) {
                    const Surface* grid = registry.find(name);
                    if (name.rfind("lightgrid", 0) != 0 || !grid) continue;
                    const auto overlay = overlayTileCounts(*grid, tileSize, registry.get(kBackBufferName));
                    if (!overlay) continue;
                    const std::string file = pr.folder + "/" + name + ".overlay.png";
                    writeSurface(overlay->image, root / file);
                    pr.shots.push_back({file, overlay->rule, name + " over the final image"});
                }
        tr.why = differenceNote(info.id, ctx.options, notes);
        tr.finalFile = tr.id + "/final.png";
        const Surface& back = registry.get(kBackBufferName);
        writeSurface(withOpaqueAlpha(back), root / tr.finalFile);
        if (tr.baseline && !forwardFinal) {
            forwardRegistry = std::move(registry);
            forwardFinal = forwardRegistry.find(kBackBufferName);
        } else if (forwardFinal) {
            differenceFromForward(back, forwardFinal, width, height, tr);
        }
        reports.push_back(std::move(tr));
    }

    const std::string page = reportPage(reports, sceneFile, scene, width, height, chosenLight);
    writeText(root / "index.html", page);
    std::printf("wrote %s (%zu techniques)\n", (root / "index.html").string().c_str(), reports.size());
    return 0;
}

} // namespace tessera::cli
