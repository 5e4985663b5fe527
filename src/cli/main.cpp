// The `tessera` command: `render` draws a scene file (or a glTF, or the built-in scene) with a
// technique and writes the back buffer; `list` shows techniques and bundled scenes; `options`
// lists each technique's options; `info` describes a scene; `diff` compares two images (diff.cpp).
// Exit codes: 0 success, 1 failure while rendering, 2 bad usage or bad input.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>

#include <tbb/task_arena.h>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

#include <tessera/inspect/buffer_view.h>
#include <tessera/io/atomic_file.h>
#include <tessera/raster/quad_block.h>
#include <tessera/io/image_writer.h>
#include <tessera/io/input_error.h>
#include <tessera/io/json_depth.h>
#include <tessera/scene/default_lights.h>
#include <tessera/frame/memory_limit.h>
#include <tessera/scene/depth_precision.h>
#include <tessera/scene/scene_file.h>
#include <tessera/state/viewport.h>
#include <tessera/techniques/option_catalog.h>
#include <tessera/techniques/technique.h>

#include <tessera/techniques/builtin_scene.h>
#include "diff.h"
#include "report.h"
#include "render_args.h"
#include "scene_args.h"
#include <tessera/inspect/pixel_history.h>
#include "progress.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using tessera::OptionInfo;

constexpr const char* kUsage = R"(usage: tessera <command> [options]

commands:
  render [SCENE]  render a scene and write the back buffer (default: the bundled scene 'default')
  list            list techniques and bundled scenes
  options [TECH]  list the options of every technique (or of TECH): values, faithful default,
                  correction, erratum
  probe SCENE X Y the history of one pixel through the frame (render's flags apply; --json)
  info SCENE      describe a scene: triangles, materials, lights, bounds, memory
  report [SCENE] --out DIR  an HTML page walking through every technique's passes and buffers
  diff A B        compare two images: max abs difference, RMSE, PSNR, differing pixels
  help [COMMAND]  show this text, or the command's options
  --version       print the version

SCENE is a scene file (.json), a glTF file (.gltf/.glb), the name of a bundled scene
(see `tessera list`), or `builtin` (a generated scene that needs no files).
`tessera <command> --help` lists the command's options.
)";

constexpr const char* kProbeUsage = R"(usage: tessera probe SCENE X Y [render options] [--json]

Renders SCENE as `tessera render` does and prints the history of window pixel (X, Y), in pass and
draw order: every primitive that covered it (coverage, depth and stencil outcome, the shader's
inputs and output, what each light added or why it added nothing, the texels before and after),
every buffer's value there after each pass and light step, and for the tiled techniques the
pixel's tile (depth range, frustum planes, light list, lights culled).
  --json        the same as one JSON object, for tools
Every option of `tessera render` applies (see `tessera help render`); nothing is written unless
--out or --dump is given.
)";

constexpr const char* kRenderUsage = R"(usage: tessera render [SCENE] [options]

Renders SCENE (default: the bundled scene 'default') with its technique and writes the back
buffer: PNG stores the 8-bit bytes as rendered, EXR the decoded values (half or float).

options:
  --technique ID    technique to use instead of the scene file's (see `tessera list`)
  --option KEY=VALUE  a technique option, over the scene file's (repeatable; VALUE is JSON, or a
                    bare word taken as a string: --option coneTest=corrected --option tileSize=32);
                    checked against the technique before anything loads (see `tessera options`)
  --out FILE        output image, .png or .exr (default: tessera.png): the back buffer as stored, alpha
                    included (as the goldens and --dump keep it); with --precision reference the double
                    result (PNG: rounded once to 8 bits, EXR: its float values)
  --exr TYPE        EXR pixel type: half or float (default: float)
  --width W         width in px, 1..16384 (default: the scene file's)
  --height H        height in px, 1..16384 (default: the scene file's)
  --precision MODE  reference, exact or fast (default: the scene file's, else exact)
  --lights N        light count of every generator in the scene file, 0..1000000 (all of them
                    together at most 1000000)
  --memory-limit G  refuse, before allocating, a render whose scene and frame buffers would need more
                    than G GiB (default: 3/4 of the memory this process may use: the least of physical
                    memory, the cgroup's memory.max and RLIMIT_AS); exit code 2, nothing written
  --threads N       worker threads, 0 = all cores (default 0)
  --tile T          tile size in px, even, 8..1024 (default 64)
  --scalar-raster   rasterize every quad on the scalar path instead of 8x8 SIMD blocks (the same
                    bytes; for comparing speed, and as the oracle the tests hold the SIMD path to)
  --msaa S          samples per pixel, 1, 2, 4 or 8 (default 1); techniques without MSAA refuse more
  --dump DIR        also write every named buffer into DIR (<name>.png/.exr/.tif, stencil as <name>.stencil.png),
                    a viewable picture of each in DIR/view/ (depth stretched, stencil and integers through
                    palettes with a colour bar) and DIR/manifest.json (passes, buffers, formats, decode rules,
                    camera, options, command line)
  --dump-after PASS[,PASS]  with --dump: also the buffers as they stand after each named pass, in
                    DIR/after-<PASS>/ (the pass names are `pass` lines of --stats)
  --dump-lights I[,J]  with --dump, deferred and deferred-killzone: also the buffers after each step of
                    light I (scene order, from 0): DIR/light-I-unmark/ and DIR/light-I-shade/ (Killzone:
                    -mark, -count, -shade), so the stencil can be watched being marked and cleared
  --exposure E      scale of float colour buffers in DIR/view/ (default 1)
  --probe X,Y       print the history of window pixel (X, Y): each primitive that covered it (draw,
                    coverage, depth test, shader output, texels before/after), every buffer's value
                    there after each pass and light step where it changed, and for the tiled
                    techniques the pixel's tile, depth range, frustum planes and light list
  --json            with --probe: the history as one JSON object
  --repeat N        render the frame N times after loading once, 1..100000 (default 1); --stats then
                    prints each pass's and the frame's median over the N runs; the last run is written
  --warmup K        render K untimed frames before the N timed ones, 0..100000 (default 0)
  --no-output       render but write no file (timing and --stats only); not with --out or --dump
  --no-default-lights  a scene without any light stays unlit under a lighting technique (by default
                    it gets a key and a fill point light from the camera, announced on stderr)
  --double-sided-normals reverse|keep  back faces of double-sided glTF materials: lit with the normal
                    and tangent frame reversed, as glTF 2.0 §3.9.5 requires (reverse, default), or with
                    the front face's normal (keep: such back faces come out unlit, for comparison)
  --stats           print load, per-pass and frame times, draw counters, peak memory (peak RSS) and the
                    FNV-1a 64 hash of each written file
  --progress        show a progress bar even when stderr is not a terminal
  --quiet           print nothing on success (no progress bar, no warnings or note about what the
                    technique skipped or clamped; --dump's manifest.json keeps them under "notes")
  --help            show this text
)";

constexpr const char* kListUsage = R"(usage: tessera list

Lists the techniques (with their source and whether they are implemented) and the bundled
scenes (scene files in the scenes folder; TESSERA_SCENES overrides where that is).
)";

constexpr const char* kOptionsUsage = R"(usage: tessera options [TECHNIQUE]

Lists the options each technique accepts (in a scene file's "options" object, or with
`tessera render --option KEY=VALUE`): the values, the default (faithful to the source), the
correcting value where the option corrects an erratum, the ERRATA.md row, and what it changes.
)";

constexpr const char* kInfoUsage = R"(usage: tessera info SCENE

Loads SCENE without decoding images and prints its triangles, meshes, instances, materials,
textures, cameras, lights by type, world bounds and an estimate of the memory a render needs.
)";

using tessera::cli::applyOptionArgs;
using tessera::cli::parseRenderArgs;
using tessera::cli::RenderOptions;
using tessera::cli::UsageError;

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

using tessera::cli::bundledScenesDir;
using tessera::cli::describe;
using tessera::cli::resolveScene;

void warn(const std::string& text) { std::fprintf(stderr, "tessera: warning: %s\n", text.c_str()); }

// Output paths checked before anything loads or renders: --out's folder exists and is writable,
// --dump is a folder (or can become one). A render that would fail at its end fails now.
void checkOutputPaths(const RenderOptions& o) {
    if (o.noOutput) return;
    std::error_code ec;
    const fs::path out(o.out);
    const fs::path outDir = out.has_parent_path() ? out.parent_path() : fs::path(".");
    if (!fs::is_directory(outDir, ec)) throw UsageError("--out: '" + o.out + "': the folder '" + outDir.string() + "' does not exist");
    if (access(outDir.c_str(), W_OK) != 0) throw UsageError("--out: '" + o.out + "': the folder '" + outDir.string() + "' is not writable");
    if (fs::is_directory(out, ec)) throw UsageError("--out: '" + o.out + "' is a folder");
    if (!o.dumpDir.empty()) {
        const fs::path dump(o.dumpDir);
        if (fs::exists(dump, ec) && !fs::is_directory(dump, ec))
            throw UsageError("--dump: '" + o.dumpDir + "' exists and is not a folder");
        fs::path existing = dump;  // the deepest existing ancestor must be writable
        while (!existing.empty() && !fs::exists(existing, ec)) existing = existing.has_parent_path() ? existing.parent_path() : fs::path(".");
        if (existing.empty()) existing = ".";
        if (access(existing.c_str(), W_OK) != 0)
            throw UsageError("--dump: '" + o.dumpDir + "': '" + existing.string() + "' is not writable");
    }
}

// The back buffer's pixels saturated to white (R = G = B = 255 in an 8-bit back buffer; every
// sample with MSAA resolved): light past what the sources' 8-bit target holds, clipped.
std::uint64_t saturatedPixels(const tessera::BufferRegistry& registry) {
    const tessera::Surface* back = registry.find(tessera::kBackBufferName);
    if (!back || (back->format() != tessera::Format::R8G8B8A8_UNORM && back->format() != tessera::Format::R8G8B8A8_UNORM_SRGB)) return 0;
    std::uint64_t n = 0;
    for (std::uint32_t y = 0; y < back->height(); ++y)
        for (std::uint32_t x = 0; x < back->width(); ++x) {
            const std::byte* t = back->texel(x, y);
            n += (t[0] == std::byte{255} && t[1] == std::byte{255} && t[2] == std::byte{255}) ? 1u : 0u;
        }
    return n;
}

// The frame's notes (frame/frame_notes.h) on stderr: one warning per kind a technique skipped or
// clamped, with the count, the ERRATA.md row and what changes it; then one note naming what
// visibly changes this image (the visible kinds, and pixels saturated to white) and the options
// that correct it. Nothing about the technique is compared here: the records say it all.
void printFrameNotes(const std::string& technique, const tessera::FrameNotes& notes, const tessera::BufferRegistry& registry) {
    std::vector<std::string> visible, remedies;
    for (const tessera::FrameNote& n : notes.list()) {
        warn(technique + ": " + tessera::noteText(n));
        if (!n.visible) continue;
        const std::size_t cut = n.what.find_first_of(":(");
        std::string label = std::to_string(n.count) + " " + (cut == std::string::npos ? n.what : n.what.substr(0, cut));
        while (!label.empty() && label.back() == ' ') label.pop_back();
        if (n.erratum) label += " (#" + std::to_string(n.erratum) + ")";
        visible.push_back(label);
        if (!n.remedy.empty() && std::find(remedies.begin(), remedies.end(), n.remedy) == remedies.end()) remedies.push_back(n.remedy);
    }
    if (const std::uint64_t saturated = saturatedPixels(registry))
        visible.push_back(std::to_string(saturated) + " pixels saturated to white (light past the 8-bit back buffer's 1.0, clipped; "
                                                      "the sources have no tone mapping)");
    if (visible.empty()) return;
    std::string text = "what changes this image visibly: ";
    for (std::size_t i = 0; i < visible.size(); ++i) text += (i ? "; " : "") + visible[i];
    if (!remedies.empty()) {
        text += ". Corrected:";
        for (const std::string& r : remedies) text += " " + r;
    }
    std::fprintf(stderr, "tessera: note: %s (ERRATA.md, README \"Warnings\")\n", text.c_str());
}

// One written file and the FNV-1a 64 hash of its bytes (io/atomic_file.h), for --stats.
struct WrittenFile {
    std::string path;
    std::uint64_t hash;
};

// How a dumped file decodes, for the manifest.
std::string decodeRule(tessera::Format format, const std::string& file) {
    const tessera::FormatInfo& info = tessera::formatInfo(format);
    const std::string name(info.name);
    if (info.hasDepth)
        return name + ": depth as float32 in " + file + " (D24: code / (2^24 - 1), exact in float32); stencil codes 0..255 in the .stencil.png";
    if (format == tessera::Format::R8G8B8A8_UNORM) return name + ": the stored bytes; value = code / 255";
    if (format == tessera::Format::R8G8B8A8_UNORM_SRGB) return name + ": the stored bytes; RGB decode sRGB -> linear, A = code / 255";
    if (info.kind == tessera::FormatKind::Uint) return name + ": uint32 per channel as stored (TIFF)";
    return name + ": each channel decoded to float32 (EXR), the value a shader Load returns";
}

// Writes every buffer of `registry` into `dir` (exact files, plus viewable pictures in
// `dir`/view/ when `views`) and describes them in `buffers` (the manifest's entries).
void dumpRegistry(const tessera::BufferRegistry& registry, const fs::path& dir, const RenderOptions& o, bool views,
                  std::vector<WrittenFile>& written, nlohmann::json& buffers) {
    fs::create_directories(dir);
    if (views) fs::create_directories(dir / "view");
    for (const std::string& name : registry.names()) {
        const tessera::Surface& s = *registry.find(name);
        const std::string file = name + tessera::losslessExtension(s.format());
        written.push_back({(dir / file).string(), tessera::writeSurface(s, dir / file)});
        nlohmann::json entry{{"name", name},
                             {"format", std::string(tessera::formatInfo(s.format()).name)},
                             {"width", s.width()},
                             {"height", s.height()},
                             {"samples", s.sampleCount()},
                             {"file", file},
                             {"decode", decodeRule(s.format(), file)}};
        if (tessera::formatInfo(s.format()).hasStencil) {
            const std::string stencil = name + ".stencil.png";
            written.push_back({(dir / stencil).string(), tessera::writeStencil(s, dir / stencil)});
            entry["stencilFile"] = stencil;
        }
        if (views) {
            nlohmann::json viewEntries = nlohmann::json::array();
            const auto addView = [&](tessera::ViewChannel channel, const std::string& suffix) {
                const auto view = tessera::viewBuffer(name, s, channel, o.exposure);
                if (!view) return;
                const std::string viewFile = "view/" + name + suffix + ".png";
                written.push_back({(dir / viewFile).string(), tessera::writeSurface(view->image, dir / viewFile)});
                viewEntries.push_back({{"file", viewFile}, {"rule", view->rule}});
            };
            addView(tessera::ViewChannel::Depth, "");
            if (tessera::formatInfo(s.format()).hasStencil) addView(tessera::ViewChannel::Stencil, ".stencil");
            if (name.rfind("gbuffer.", 0) == 0) {
                addView(tessera::ViewChannel::Rgb, ".rgb");      // the colour without the data in alpha
                addView(tessera::ViewChannel::Alpha, ".alpha");  // opacity, packed power, specular intensity
            }
            // Light counts over the image (the tiled techniques' grids; --tile-size of the technique).
            const tessera::Surface* back = registry.find(tessera::kBackBufferName);
            if (name.rfind("lightgrid", 0) == 0 && back && o.viewTileSize)
                if (const auto overlay = tessera::overlayTileCounts(s, o.viewTileSize, *back)) {
                    const std::string viewFile = "view/" + name + ".overlay.png";
                    written.push_back({(dir / viewFile).string(), tessera::writeSurface(overlay->image, dir / viewFile)});
                    viewEntries.push_back({{"file", viewFile}, {"rule", overlay->rule}});
                }
            if (!viewEntries.empty()) entry["views"] = viewEntries;
        }
        buffers.push_back(entry);
    }
}

// The image --out writes: the back buffer as stored (alpha included, as the goldens and --dump keep
// it, so a render of a golden's command line is that golden byte for byte). With precision
// reference, the double result instead: for PNG "backbuffer.reference" rounded once to the back
// buffer's 8-bit format (the UNORM clamp and encode of storeAsUnorm), for EXR the float values.
tessera::Surface outputImage(const tessera::BufferRegistry& registry, const std::string& out) {
    const tessera::Surface& back = *registry.find(tessera::kBackBufferName);
    const tessera::Surface* reference = registry.find(tessera::kReferenceBufferName);
    if (!reference) return back;
    if (fs::path(out).extension() == ".exr") return *reference;
    tessera::Surface rounded(back.desc());
    tessera::storeAsUnorm(*reference, rounded);
    return rounded;
}

// --dump's folder, filled out of sight: every dump (the final buffers, --dump-after's and
// --dump-lights' folders, manifest.json) is written into a hidden staging folder inside the
// deepest existing ancestor of DIR, and moved into DIR only when the render succeeded (renamed
// when DIR does not exist, else merged into it entry by entry). A render that fails removes the
// staging folder: DIR stays absent or as it was.
class DumpStaging {
public:
    // Points o.dumpDir at the staging folder (nothing is created yet).
    explicit DumpStaging(RenderOptions& o) {
        if (o.dumpDir.empty()) return;
        mTarget = fs::path(o.dumpDir).lexically_normal();
        if (mTarget.filename().empty()) mTarget = mTarget.parent_path();
        std::error_code ec;
        fs::path existing = mTarget.has_parent_path() ? mTarget.parent_path() : fs::path(".");
        while (!existing.empty() && !fs::exists(existing, ec)) existing = existing.has_parent_path() ? existing.parent_path() : fs::path(".");
        if (existing.empty()) existing = ".";
        mStaging = existing / (".tessera-dump.partial-" + std::to_string(::getpid()) + "-" + std::to_string(Clock::now().time_since_epoch().count()));
        o.dumpDir = mStaging.string();
    }
    DumpStaging(const DumpStaging&) = delete;
    DumpStaging& operator=(const DumpStaging&) = delete;
    ~DumpStaging() {
        std::error_code ec;
        if (!mStaging.empty()) fs::remove_all(mStaging, ec);
    }
    // Moves the staged dump into place (after everything else was written).
    void commit() {
        if (mStaging.empty() || mCommitted) return;
        std::error_code ec;
        if (!fs::exists(mStaging, ec)) fs::create_directories(mStaging);
        if (mTarget.has_parent_path()) fs::create_directories(mTarget.parent_path());
        if (!fs::exists(mTarget, ec)) fs::rename(mStaging, mTarget);
        else moveInto(mStaging, mTarget);
        mCommitted = true;
    }
    // `text` (an error message) with the staging folder named as DIR, the folder the user gave.
    std::string named(std::string text) const {
        if (mStaging.empty()) return text;
        const std::string staging = mStaging.string(), target = mTarget.string();
        for (std::size_t at = text.find(staging); at != std::string::npos; at = text.find(staging, at + target.size()))
            text.replace(at, staging.size(), target);
        return text;
    }
    // A written path under the staging folder as it reads after commit.
    std::string finalPath(const std::string& path) const {
        if (mStaging.empty()) return path;
        const std::string staging = mStaging.string();
        if (path.compare(0, staging.size(), staging) != 0) return path;
        return mTarget.string() + path.substr(staging.size());
    }

private:
    static void moveInto(const fs::path& from, const fs::path& to) {
        for (const fs::directory_entry& e : fs::directory_iterator(from)) {
            const fs::path dest = to / e.path().filename();
            std::error_code ec;
            if (e.is_directory() && fs::is_directory(dest, ec)) {
                moveInto(e.path(), dest);
                continue;
            }
            if (fs::is_directory(dest, ec)) fs::remove_all(dest);
            fs::rename(e.path(), dest);
        }
    }
    fs::path mTarget, mStaging;
    bool mCommitted = false;
};
DumpStaging* gDumpStaging = nullptr;  // render's, while it runs

// What a render wrote: the image, then with --dump every buffer, their views and manifest.json
// (`manifest` holds the scene, technique, camera, options and command line; the passes and
// buffers are added here).
std::vector<WrittenFile> writeOutputs(const tessera::BufferRegistry& registry, const RenderOptions& o,
                                      nlohmann::json manifest) {
    std::vector<WrittenFile> written;
    if (o.noOutput) return written;
    const tessera::Surface image = outputImage(registry, o.out);
    if (o.dumpDir.empty()) {
        written.push_back({o.out, tessera::writeSurface(image, o.out, o.exrType)});
        return written;
    }
    nlohmann::json buffers = nlohmann::json::array();
    dumpRegistry(registry, o.dumpDir, o, true, written, buffers);
    manifest["buffers"] = buffers;
    manifest["image"] = o.out;
    // Paths and the command line are bytes, not necessarily UTF-8: those bytes become U+FFFD in
    // the manifest (a plain dump() throws on them, after every image was written).
    const std::string text = manifest.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
    const fs::path manifestFile = fs::path(o.dumpDir) / "manifest.json";
    tessera::writeFileAtomically(manifestFile, std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()));
    written.push_back({manifestFile.string(), tessera::fnv1a64(std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()))});
    // The image after the dump, and the dump moved into place last: a failure before leaves neither.
    written.insert(written.begin(), WrittenFile{o.out, tessera::writeSurface(image, o.out, o.exrType)});
    if (gDumpStaging) gDumpStaging->commit();
    return written;
}

// "hash     <16 hex digits>  <file>": FNV-1a 64 of each written file's bytes, in write order.
void printHashes(const std::vector<WrittenFile>& written) {
    for (const WrittenFile& w : written)
        std::printf("hash     %s  %s\n", tessera::hashHex(w.hash).c_str(),
                    (gDumpStaging ? gDumpStaging->finalPath(w.path) : w.path).c_str());
}

void printDrawStats(const tessera::DrawStats& s) {
    std::printf("triangles in %llu, clipped %llu, culled %llu, rasterized %llu; quads %llu; ps invocations %llu; samples passed %llu\n",
                (unsigned long long)s.setup.trianglesIn, (unsigned long long)s.setup.clipped,
                (unsigned long long)(s.setup.culledFacing + s.setup.culledDegenerate + s.setup.culledNonFinite),
                (unsigned long long)s.setup.trianglesOut, (unsigned long long)s.quads, (unsigned long long)s.psInvocations,
                (unsigned long long)s.samplesPassed);
    for (const auto& [path, draws] : s.paths) std::printf("path %-44s %llu draws\n", path.c_str(), (unsigned long long)draws);
    if (s.psPerSample > 0 || s.edgeTestedPixels > 0 || s.computeShadedSamples > 0) {
        // MSAA: what ran once per pixel and what ran once per sample.
        std::printf("msaa     pixel shader %llu per pixel, %llu per sample; compute shading %llu pixels, %llu samples\n",
                    (unsigned long long)(s.psInvocations - s.psPerSample), (unsigned long long)s.psPerSample,
                    (unsigned long long)s.computeShadedPixels, (unsigned long long)s.computeShadedSamples);
        if (s.edgeTestedPixels > 0)
            std::printf("edges    %llu of %llu pixels shaded per sample (%.2f%%)\n", (unsigned long long)s.edgePixels,
                        (unsigned long long)s.edgeTestedPixels, 100.0 * double(s.edgePixels) / double(s.edgeTestedPixels));
    }
    std::printf("simd     %llu blocks of 8x8 px through the %s kernels, %llu of them lean (SIMD depth test)\n",
                (unsigned long long)s.simdBlocks, tessera::quadBlockTarget(), (unsigned long long)s.leanBlocks);
}

// forward-plus-amd's ray-cast shadows (GPU Pro 4 §5.6.2): its "shadow.counters" as one line.
void printShadowStats(const tessera::BufferRegistry& registry) {
    const tessera::Surface* counters = registry.find("shadow.counters");
    if (!counters) return;
    std::uint32_t c[5];
    std::memcpy(c, counters->bytes().data(), sizeof(c));
    std::printf("shadows  %u rays (jobs), %u occluded; %u light slots masked behind the surface; %u pixels list more than "
                "128 lights (%u overlapping lights past slot 127)\n",
                c[0], c[1], c[2], c[3], c[4]);
}

// The frame rendered `warmup` times untimed, then `repeat` times timed, each run into a fresh
// registry (`registry` keeps the last run's buffers, which are written). `beforeRun` resets the
// counters a run accumulates, so the draw counters printed are one frame's.
struct FrameRuns {
    std::vector<std::vector<tessera::PassTiming>> passes;  // per timed run, in pass order
    std::vector<double> frameMs;                           // per timed run (with --dump-after, the last
                                                           // run's time includes writing those dumps)
    std::vector<WrittenFile> afterWritten;                 // --dump-after's files
    nlohmann::json after = nlohmann::json::object();       // --dump-after: pass -> its buffers
};

// --dump-after's pass names checked against the frame before it runs.
void checkDumpAfter(const tessera::Frame& frame, const RenderOptions& o) {
    for (const std::string& wanted : o.dumpAfter) {
        std::string names;
        bool found = false;
        for (const tessera::Pass& p : frame.passes()) {
            found = found || p.name == wanted;
            names += (names.empty() ? "" : ", ") + p.name;
        }
        if (!found) throw UsageError("--dump-after: this frame has no pass '" + wanted + "' (its passes: " + names + ")");
    }
}

template <class BeforeRun>
FrameRuns runFrames(const tessera::Frame& frame, tessera::BufferRegistry& registry, const RenderOptions& o,
                    tessera::cli::Progress& progress, const std::string& label, BeforeRun beforeRun,
                    tessera::PixelHistory* history = nullptr, tessera::PixelWatch* watch = nullptr,
                    tessera::Device* device = nullptr) {
    FrameRuns runs;
    const std::uint32_t total = o.warmup + o.repeat;
    for (std::uint32_t i = 0; i < total; ++i) {
        if (total > 1) progress.update(label, i, total);
        else progress.update(label, 0, 0);
        beforeRun();
        // --probe: the rasterizer reports the pixel during the last (recorded) run only.
        if (device && watch && i + 1 == total) device->setPixelWatch(watch);
        registry = tessera::BufferRegistry{};
        // The last run (the one written) also writes the buffers after the passes --dump-after names.
        // --probe records the pixel after every pass of the same run.
        tessera::Frame::AfterPass afterPass;
        if (i + 1 == total && (!o.dumpAfter.empty() || history))
            afterPass = [&](const tessera::Pass& pass, const tessera::BufferRegistry& now) {
                if (history) {
                    if (watch) history->addDrawEvents(pass.name, *watch);
                    history->record(pass.name, now);
                }
                if (std::find(o.dumpAfter.begin(), o.dumpAfter.end(), pass.name) == o.dumpAfter.end()) return;
                nlohmann::json buffers = nlohmann::json::array();
                dumpRegistry(now, fs::path(o.dumpDir) / ("after-" + pass.name), o, true, runs.afterWritten, buffers);
                runs.after[pass.name] = {{"folder", "after-" + pass.name}, {"buffers", buffers}};
            };
        const auto t = Clock::now();
        std::vector<tessera::PassTiming> timings = frame.run(registry, afterPass);
        const double ms = msSince(t);
        if (device) device->setPixelWatch(nullptr);
        if (i < o.warmup) continue;
        runs.passes.push_back(std::move(timings));
        runs.frameMs.push_back(ms);
    }
    return runs;
}

// --probe X,Y: the pixel's history for a frame of width x height (the pixel checked inside it).
std::optional<tessera::PixelHistory> probeHistory(const RenderOptions& o, std::uint32_t width, std::uint32_t height) {
    if (!o.probe) return std::nullopt;
    const auto [x, y] = *o.probe;
    if (x >= width || y >= height)
        throw UsageError("--probe: (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " + std::to_string(width) +
                         "x" + std::to_string(height) + " frame");
    return tessera::PixelHistory(x, y);
}

// The tile edge (px) of a technique's per-tile light lists: its "tileSize" option or the default
// (16, forward-plus-amd's fixed 8); 0 for techniques without tiles.
std::uint32_t lightGridTileSize(const tessera::SceneDescription& desc) {
    const tessera::TechniqueInfo* info = tessera::findTechnique(desc.technique);
    if (!info || info->tileSize == 0) return 0;
    if (!tessera::findOption(desc.technique, "tileSize")) return info->tileSize;
    const nlohmann::json& options = desc.techniqueOptions;
    if (options.is_object() && options.contains("tileSize") && options["tileSize"].is_number_unsigned())
        return options["tileSize"].get<std::uint32_t>();
    return info->tileSize;
}

std::string gCommandLine;  // "tessera render ...", for the manifest

// "deferred and deferred-killzone": the techniques that declare `feature` (TechniqueInfo::features).
std::string techniquesWith(std::uint32_t feature) {
    std::vector<std::string> ids;
    for (const tessera::TechniqueInfo& t : tessera::techniques())
        if (t.features & feature) ids.emplace_back(t.id);
    std::string text;
    for (std::size_t i = 0; i < ids.size(); ++i) text += (i == 0 ? "" : i + 1 == ids.size() ? " and " : ", ") + ids[i];
    return text;
}

// The manifest's common part: what was rendered and how, the passes with their declared buffers,
// and --dump-after's snapshots. No times (--stats has them): the same render gives the same file.
nlohmann::json manifestBase(const tessera::Frame& frame, const FrameRuns& runs, const RenderOptions& o) {
    nlohmann::json passes = nlohmann::json::array();
    for (const tessera::Pass& p : frame.passes()) passes.push_back({{"name", p.name}, {"reads", p.reads}, {"writes", p.writes}});
    return {{"tessera", TESSERA_VERSION}, {"command", gCommandLine}, {"passes", passes}, {"after", runs.after},
            {"exposure", o.exposure}};
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The process's peak resident set size (getrusage ru_maxrss, KiB on Linux) in MiB.
double peakRssMiB() {
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
    return double(usage.ru_maxrss) / 1024.0;
}

// "pass <name> <ms>" per pass and "frame <ms>": one run's times as they are, or with --repeat N > 1
// each pass's and the frame's median over the N runs with the range beside it.
void printTimings(const FrameRuns& runs, const RenderOptions& o, bool frameLine) {
    const std::size_t n = runs.frameMs.size();
    if (n == 1) {
        for (const auto& t : runs.passes[0]) std::printf("pass %-12s %9.3f ms\n", t.name.c_str(), t.milliseconds);
        if (frameLine) std::printf("frame    %9.3f ms\n", runs.frameMs[0]);
        return;
    }
    std::printf("repeat   %zu timed runs after %u warm-up runs; times below are medians (min..max)\n", n, o.warmup);
    for (std::size_t p = 0; p < runs.passes[0].size(); ++p) {
        std::vector<double> ms;
        for (const auto& run : runs.passes) ms.push_back(run[p].milliseconds);
        const auto [lo, hi] = std::minmax_element(ms.begin(), ms.end());
        std::printf("pass %-12s %9.3f ms  (%.3f..%.3f)\n", runs.passes[0][p].name.c_str(), median(ms), *lo, *hi);
    }
    if (frameLine) {
        const auto [lo, hi] = std::minmax_element(runs.frameMs.begin(), runs.frameMs.end());
        std::printf("frame    %9.3f ms  (%.3f..%.3f)\n", median(runs.frameMs), *lo, *hi);
    }
}

void printPeakMemory() { std::printf("peak memory  %.1f MiB\n", peakRssMiB()); }

// The frame a scene file describes: its camera, size, technique options and precision (render
// adds samples and statistics).
tessera::TechniqueContext frameContext(tessera::Device& device, const tessera::SceneResources& resources, const tessera::Camera& camera,
                                       const tessera::SceneDescription& desc, const fs::path& sceneFile) {
    tessera::TechniqueContext ctx;
    ctx.device = &device;
    ctx.resources = &resources;
    ctx.camera = camera;
    ctx.width = desc.width;
    ctx.height = desc.height;
    ctx.options = desc.techniqueOptions;
    ctx.precision = desc.precision;
    ctx.sceneFile = sceneFile.string();
    return ctx;
}

// ---- Memory: estimated and refused before allocating (frame/memory_limit.h) --------------------
std::uint64_t memoryLimitBytes(const RenderOptions& o) {
    return o.memoryLimitGiB ? std::uint64_t(*o.memoryLimitGiB * 1073741824.0) : tessera::defaultMemoryLimitBytes();
}

std::string memoryLimitText(const RenderOptions& o) {
    const std::string limit = tessera::formatBytes(double(memoryLimitBytes(o)));
    if (o.memoryLimitGiB) return limit + " (--memory-limit)";
    return limit + " (3/4 of the " + tessera::formatBytes(double(tessera::availableMemoryBytes())) +
           " this process may use; --memory-limit GIB sets it)";
}

// Throws MemoryLimitError when `bytes` pass the limit: "FILE: WHAT needs about X, past the
// memory limit of Y (...)".
void checkMemory(const RenderOptions& o, const std::string& file, const std::string& what, double bytes) {
    if (bytes > double(memoryLimitBytes(o)))
        throw tessera::MemoryLimitError(file + ": " + what + " needs about " + tessera::formatBytes(bytes) +
                                        ", past the memory limit of " + memoryLimitText(o) + "; nothing was allocated");
}

struct SceneBytes {
    double geometry = 0.0, images = 0.0;
};
SceneBytes sceneBytes(const tessera::Scene& scene) {
    SceneBytes b;
    for (const tessera::Mesh& m : scene.meshes)
        for (const tessera::MeshPrimitive& p : m.primitives)
            b.geometry += double(p.positionsObject.size()) * sizeof(tessera::SceneVertex) + double(p.indices.size()) * 4.0;
    for (const tessera::Image& img : scene.images) b.images += double(img.width) * img.height * 4.0;
    return b;
}

// A bound on the frame's buffers that needs no probe frames: 512 B per sample (the largest
// technique holds 84 B per pixel per sample), 16 B per light per 8 x 8 tile (two unbounded
// lists of 4 B indices, twice over) and 4 KiB per light. Far below the limit: no probes.
bool frameSurelyFits(const RenderOptions& o, std::uint32_t width, std::uint32_t height, std::size_t lights) {
    const double pixels = double(width) * height;
    const double bound = pixels * o.msaa * 512.0 + pixels / 64.0 * double(lights) * 16.0 + double(lights) * 4096.0;
    return bound < 0.5 * double(memoryLimitBytes(o));
}

int renderBuiltin(const RenderOptions& o) {
    tessera::BuiltinSceneOptions opt;
    opt.width = o.width ? o.width : opt.width;
    opt.height = o.height ? o.height : opt.height;
    opt.sampleCount = o.msaa;
    opt.precision = o.precision.value_or(tessera::Precision::Exact);
    tessera::Device device(o.device);
    tessera::DrawStats drawStats;
    if (!frameSurelyFits(o, opt.width, opt.height, 0)) {
        // Two probe frames (64 x 64 and 128 x 64 px): every builtin buffer grows with the pixels.
        const auto bytesAt = [&](std::uint32_t width) {
            tessera::BuiltinSceneOptions probe = opt;
            probe.width = width;
            probe.height = 64;
            tessera::DrawStats probeStats;
            tessera::BufferRegistry probeRegistry;
            tessera::buildBuiltinScene(device, probe, probeStats).run(probeRegistry);
            return double(probeRegistry.bytes());
        };
        const double small = bytesAt(64), large = bytesAt(128);
        const double perPixel = (large - small) / (64.0 * 64.0);
        checkMemory(o, "builtin", "rendering " + std::to_string(opt.width) + "x" + std::to_string(opt.height) + " at --msaa " +
                                      std::to_string(opt.sampleCount),
                    small + perPixel * (double(opt.width) * opt.height - 64.0 * 64.0));
    }
    tessera::BufferRegistry registry;
    registry.setByteLimit(memoryLimitBytes(o), memoryLimitText(o));
    const tessera::Frame frame = tessera::buildBuiltinScene(device, opt, drawStats);
    tessera::cli::Progress progress(o.progress);
    checkDumpAfter(frame, o);
    std::optional<tessera::PixelHistory> history = probeHistory(o, opt.width, opt.height);
    tessera::PixelWatch watch;
    if (o.probe) watch = {(*o.probe)[0], (*o.probe)[1], {}};
    const FrameRuns runs =
        runFrames(frame, registry, o, progress, "rendering builtin", [&] { drawStats = {}; }, history ? &*history : nullptr,
                  o.probe ? &watch : nullptr, &device);
    nlohmann::json manifest = manifestBase(frame, runs, o);
    manifest["scene"] = "builtin";
    manifest["technique"] = "builtin";
    manifest["precision"] = std::string(tessera::precisionName(opt.precision));
    manifest["width"] = opt.width;
    manifest["height"] = opt.height;
    manifest["msaa"] = opt.sampleCount;
    std::vector<WrittenFile> written = writeOutputs(registry, o, manifest);
    written.insert(written.begin(), runs.afterWritten.begin(), runs.afterWritten.end());
    progress.finish();
    if (o.stats) {
        printTimings(runs, o, o.repeat > 1);
        printDrawStats(drawStats);
        printPeakMemory();
        printHashes(written);
    }
    if (history) {
        if (o.probeJson)
            std::printf("%s\n", nlohmann::json{{"pixel", {(*o.probe)[0], (*o.probe)[1]}}, {"technique", "builtin"},
                                               {"events", history->events()}, {"final", history->last()}, {"tile", nullptr}}
                                   .dump()
                                   .c_str());
        else std::fputs(history->text().c_str(), stdout);
    }
    if (o.quiet || o.probeJson) {
        // nothing more: --json prints one JSON object
    } else if (o.noOutput) std::printf("rendered %ux%u, nothing written (--no-output)\n", opt.width, opt.height);
    else std::printf("wrote %s (%ux%u)\n", o.out.c_str(), opt.width, opt.height);
    return 0;
}

int render(const std::vector<std::string_view>& args) {
    bool help = false;
    RenderOptions o = parseRenderArgs(args, help);
    if (help) {
        std::fputs(kRenderUsage, stdout);
        return 0;
    }
    checkOutputPaths(o);
    DumpStaging staging(o);
    gDumpStaging = &staging;
    struct Forget {
        ~Forget() { gDumpStaging = nullptr; }
    } forget;
    if (o.scene == "builtin") return renderBuiltin(o);

    // Loading: bad input is exit 2 (InputError); everything else that fails is exit 1.
    tessera::cli::Progress progress(o.progress);
    const auto t0 = Clock::now();
    const fs::path sceneFile = resolveScene(o.scene);
    tessera::SceneDescription desc = describe(sceneFile);
    if (!o.technique.empty() && o.technique != desc.technique) {
        // A scene file's "options" belong to its own technique.
        if (desc.techniqueOptions.is_object() && !desc.techniqueOptions.empty())
            warn(sceneFile.string() + "'s options are " + desc.technique + "'s; --technique " + o.technique +
                 " renders without them");
        desc.techniqueOptions = nlohmann::json::object();
        desc.technique = o.technique;
    }
    // The scene file's technique (--technique was checked with the flags): unknown is exit 2 naming the file.
    (void)tessera::requireTechnique(desc.technique, sceneFile.string());
    applyOptionArgs(o, desc.technique, desc.techniqueOptions);
    if (const tessera::TechniqueInfo* info = tessera::findTechnique(desc.technique); info && info->build && o.msaa > 1 && !info->msaa) {
        std::string ready;
        for (const tessera::TechniqueInfo& t : tessera::techniques())
            if (t.msaa) ready += (ready.empty() ? "" : ", ") + std::string(t.id);
        throw UsageError("--msaa: technique " + desc.technique + " does not render with MSAA yet (MSAA: " + ready + ")");
    }
    o.viewTileSize = lightGridTileSize(desc);
    if (!o.dumpLights.empty() && !(tessera::findTechnique(desc.technique)->features & tessera::kPerLightSteps))
        throw UsageError("--dump-lights: " + desc.technique + " does not shade light by light (" +
                         techniquesWith(tessera::kPerLightSteps) + " do); --dump-after shows its passes");
    if (o.width) desc.width = o.width;
    if (o.height) desc.height = o.height;
    if (o.precision) desc.precision = *o.precision;
    if (o.lights) {
        if (desc.generators.empty())
            warn("--lights: " + sceneFile.string() + " has no light generators; the flag changes nothing");
        for (auto& g : desc.generators) g.count = *o.lights;
    }
    if (!tessera::findTechnique(desc.technique) || !tessera::findTechnique(desc.technique)->build) {
        tessera::TechniqueContext probe;  // reports unknown / unimplemented with the key path
        (void)tessera::buildTechnique(desc.technique, probe, sceneFile.string());
    }
    progress.update("loading " + sceneFile.filename().string(), 0, 0);
    tessera::Camera camera;
    tessera::Scene scene = tessera::loadScene(desc, true, &camera);
    if (o.keepBackFaceNormals) {
        const bool anyDoubleSided = std::any_of(scene.materials.begin(), scene.materials.end(),
                                                [](const tessera::Material& m) { return m.doubleSided; });
        if (!anyDoubleSided) warn("--double-sided-normals: " + sceneFile.string() + " has no double-sided material; the flag changes nothing");
        for (tessera::Material& m : scene.materials) m.reverseBackFaceNormals = false;
    }
    // A scene with no lights at all gets the default rig under a lighting technique (preview has
    // its own head light), announced, unless --no-default-lights.
    const std::uint32_t features = tessera::findTechnique(desc.technique)->features;
    if (scene.lights.empty() && !(features & tessera::kOwnHeadLight) && !o.noDefaultLights) {
        scene.lights = tessera::defaultLightRig(scene.bounds(), camera);
        if (!scene.lights.empty() && !o.quiet)
            std::fprintf(stderr, "tessera: note: %s has no lights; shading with the default rig (a key and a fill point "
                                 "light from the camera, README \"Scenes\"); --no-default-lights turns it off\n",
                         sceneFile.string().c_str());
    }
    if (const auto depth = tessera::depthPrecisionWarning(camera, scene.bounds())) warn(sceneFile.string() + ": " + *depth);
    // Capsule lights are the Cookbook's: every other technique skips them (viewLights disables them).
    if (!(features & tessera::kShadesCapsuleLights)) {
        const auto capsules = std::count_if(scene.lights.begin(), scene.lights.end(),
                                            [](const tessera::Light& l) { return l.type == tessera::LightType::Capsule; });
        if (capsules > 0)
            warn(sceneFile.string() + " has " + std::to_string(capsules) + " capsule light(s); " + desc.technique +
                 " does not shade capsule lights (" + techniquesWith(tessera::kShadesCapsuleLights) + " does), so they are skipped");
    }
    // Light groups are PR&C's stencil groups: deferred-classic and light-prepass honour them.
    if (!(features & tessera::kHonoursLightGroups)) {
        if (scene.usesLightGroups())
            warn(sceneFile.string() + " uses lightGroups; " + desc.technique +
                 " lights every surface with every light (" + techniquesWith(tessera::kHonoursLightGroups) + " honour the groups)");
    }
    // Ray-cast shadows and VPLs are GPU Pro 4's Forward+ extensions: forward-plus-amd alone.
    if (!(features & tessera::kShadowRaysAndVpls)) {
        const bool casters = std::any_of(scene.lights.begin(), scene.lights.end(), [](const tessera::Light& l) { return l.castsShadows; });
        const bool indirect = std::any_of(scene.lights.begin(), scene.lights.end(), [](const tessera::Light& l) { return l.indirect; });
        if (casters || indirect)
            warn(sceneFile.string() + " marks " + (casters ? "shadow-casting" : "") + (casters && indirect ? " and " : "") +
                 (indirect ? "indirect" : "") + " lights; " + desc.technique +
                 " has no ray-cast shadows or VPLs (" + techniquesWith(tessera::kShadowRaysAndVpls) + " does), so they light as plain lights");
    }  // forward-plus-amd notes what its "auto" options leave out (frame notes, printed after the render)
    const double loadMs = msSince(t0);
    // Textures are decoded next: refuse now if they (and the decode's float copies) cannot fit.
    const SceneBytes loaded = sceneBytes(scene);
    const tessera::TextureMemoryEstimate textures = tessera::SceneResources::estimateTextureMemory(
        scene, tessera::findTechnique(desc.technique)->textures, std::size_t(tbb::this_task_arena::max_concurrency()));
    checkMemory(o, sceneFile.string(), "decoding the scene's textures",
                loaded.geometry + loaded.images + textures.textureBytes + textures.transientBytes);
    const double residentBytes = loaded.geometry + loaded.images + textures.textureBytes;
    const auto t1 = Clock::now();
    const tessera::SceneResources resources(
        scene, [&](std::size_t done, std::size_t total) { progress.update("textures and mips", done, total); },
        tessera::findTechnique(desc.technique)->textures);
    const double texturesMs = msSince(t1);

    tessera::Device device(o.device);
    tessera::DrawStats drawStats;
    tessera::TechniqueContext ctx = frameContext(device, resources, camera, desc, sceneFile);
    ctx.sampleCount = o.msaa;
    ctx.stats = &drawStats;
    std::map<std::string, std::uint64_t> variantCounts;
    ctx.variantCounts = &variantCounts;
    tessera::FrameNotes notes;
    ctx.notes = &notes;
    // --dump-lights: the chosen lights' steps, written during the last (written) run only.
    for (const std::uint32_t light : o.dumpLights)
        if (light >= scene.lights.size())
            throw UsageError("--dump-lights: light " + std::to_string(light) + " does not exist (" + sceneFile.string() + " has " +
                             std::to_string(scene.lights.size()) + " lights, 0.." +
                             std::to_string(scene.lights.size() == 0 ? 0 : scene.lights.size() - 1) + ")");
    std::uint32_t runsStarted = 0;
    std::vector<WrittenFile> lightWritten;
    nlohmann::json lightSteps = nlohmann::json::object();
    std::optional<tessera::PixelHistory> history = probeHistory(o, desc.width, desc.height);
    tessera::PixelWatch watch;
    if (o.probe) watch = {(*o.probe)[0], (*o.probe)[1], {}};
    if (!o.dumpLights.empty() || history)
        ctx.afterLightStep = [&](std::size_t light, std::string_view step, const tessera::BufferRegistry& now) {
            if (runsStarted != o.warmup + o.repeat) return;
            if (history) {
                history->addDrawEvents("lights", watch, static_cast<long long>(light), step);
                history->record("lights", now, static_cast<long long>(light), step);
            }
            if (std::find(o.dumpLights.begin(), o.dumpLights.end(), light) == o.dumpLights.end()) return;
            const std::string folder = "light-" + std::to_string(light) + "-" + std::string(step);
            nlohmann::json buffers = nlohmann::json::array();
            dumpRegistry(now, fs::path(o.dumpDir) / folder, o, true, lightWritten, buffers);
            lightSteps[std::to_string(light)][std::string(step)] = {{"folder", folder}, {"buffers", buffers}};
        };
    if (!frameSurelyFits(o, desc.width, desc.height, scene.lights.size())) {
        progress.update("estimating memory", 0, 0);
        const tessera::FrameMemoryEstimate e = tessera::estimateFrameMemory(desc.technique, ctx, sceneFile.string());
        checkMemory(o, sceneFile.string(),
                    "rendering " + std::to_string(desc.width) + "x" + std::to_string(desc.height) + " with " + desc.technique +
                        (o.msaa > 1 ? " at --msaa " + std::to_string(o.msaa) : "") + " (frame buffers " +
                        tessera::formatBytes(e.bytes) + ", " + std::to_string(int(std::lround(e.bytesPerPixel))) +
                        " B per pixel; scene and textures " + tessera::formatBytes(residentBytes) + ")",
                    residentBytes + e.bytes);
    }
    const tessera::Frame frame = tessera::buildTechnique(desc.technique, ctx, sceneFile.string());
    checkDumpAfter(frame, o);

    try {
        tessera::BufferRegistry registry;
        registry.setByteLimit(std::uint64_t(std::max(0.0, double(memoryLimitBytes(o)) - residentBytes)), memoryLimitText(o));
        const FrameRuns runs = runFrames(frame, registry, o, progress, "rendering " + desc.technique, [&] {
            ++runsStarted;
            drawStats = {};
            variantCounts.clear();
            notes.clear();
        }, history ? &*history : nullptr, o.probe ? &watch : nullptr, &device);
        progress.update("writing " + o.out, 0, 0);
        nlohmann::json manifest = manifestBase(frame, runs, o);
        manifest["scene"] = sceneFile.string();
        manifest["technique"] = desc.technique;
        manifest["precision"] = std::string(tessera::precisionName(desc.precision));
        manifest["width"] = desc.width;
        manifest["height"] = desc.height;
        manifest["msaa"] = o.msaa;
        manifest["options"] = desc.techniqueOptions.is_null() ? nlohmann::json::object() : desc.techniqueOptions;
        manifest["lights"] = scene.lights.size();
        nlohmann::json noteList = nlohmann::json::array();
        for (const tessera::FrameNote& n : notes.list())
            noteList.push_back({{"kind", n.kind}, {"count", n.count}, {"what", n.what}, {"erratum", n.erratum},
                                {"remedy", n.remedy}, {"visible", n.visible}});
        manifest["notes"] = noteList;
        const glm::quat& q = camera.orientationWorld;
        manifest["camera"] = {{"positionWorld", {camera.positionWorld.x, camera.positionWorld.y, camera.positionWorld.z}},
                              {"orientationWorld", {q.x, q.y, q.z, q.w}},
                              {"projection", camera.projection == tessera::ProjectionKind::Perspective ? "perspective" : "orthographic"},
                              {"fovYDeg", camera.fovYDeg},
                              {"near", camera.nearZ},
                              {"far", camera.farZ}};
        if (!o.dumpLights.empty()) manifest["lightSteps"] = lightSteps;
        std::vector<WrittenFile> written = writeOutputs(registry, o, manifest);
        written.insert(written.begin(), runs.afterWritten.begin(), runs.afterWritten.end());
        written.insert(written.begin(), lightWritten.begin(), lightWritten.end());
        progress.finish();
        if (!o.quiet && !o.probeJson) printFrameNotes(desc.technique, notes, registry);  // --json: one JSON object
        if (o.stats) {
            std::printf("scene %s: %llu triangles, %zu draws, %zu lights, technique %s, precision %s, %ux%u\n",
                        sceneFile.string().c_str(), (unsigned long long)scene.triangleCount(), resources.drawItems().size(),
                        scene.lights.size(), desc.technique.c_str(), std::string(tessera::precisionName(desc.precision)).c_str(),
                        desc.width, desc.height);
            std::printf("load     %9.3f ms (glTF, images, lights)\n", loadMs);
            std::printf("textures %9.3f ms (%zu textures with mips, %.1f MiB)\n", texturesMs, resources.textureCount(),
                        double(resources.textureBytes()) / (1024.0 * 1024.0));
            printTimings(runs, o, true);
            printDrawStats(drawStats);
            printShadowStats(registry);
            printPeakMemory();
            for (const auto& [variant, draws] : variantCounts)
                std::printf("variant  %-40s %6llu draws\n", variant.c_str(), (unsigned long long)draws);
            printHashes(written);
        }
        if (history) {
            history->addTileInfo(registry, lightGridTileSize(desc), scene.lights.size());
            if (o.probeJson) {
                const nlohmann::json j{{"pixel", {(*o.probe)[0], (*o.probe)[1]}}, {"technique", desc.technique},
                                       {"events", history->events()}, {"final", history->last()}, {"tile", history->tile()}};
                std::printf("%s\n", j.dump().c_str());
            } else {
                std::fputs(history->text().c_str(), stdout);
            }
        }
        if (o.quiet || o.probeJson) {
            // nothing more: --json prints one JSON object
        } else if (o.noOutput)
            std::printf("rendered %ux%u with %s, nothing written (--no-output)\n", desc.width, desc.height, desc.technique.c_str());
        else
            std::printf("wrote %s (%ux%u, %s)\n", o.out.c_str(), desc.width, desc.height, desc.technique.c_str());
        return 0;
    } catch (const tessera::InputError&) {  // MemoryLimitError from a buffer past the limit: exit 2
        progress.finish();
        throw;
    } catch (const std::exception& e) {
        progress.finish();
        std::fprintf(stderr, "tessera render: %s\n", gDumpStaging ? gDumpStaging->named(e.what()).c_str() : e.what());
        return 1;
    }
}

std::string firstSentence(const std::string& text) {
    const std::size_t end = text.find(". ");
    return end == std::string::npos ? text : text.substr(0, end + 1);
}

int list(const std::vector<std::string_view>& args) {
    for (const std::string_view a : args) {
        if (a == "--help" || a == "-h") {
            std::fputs(kListUsage, stdout);
            return 0;
        }
        throw UsageError("list takes no arguments, got '" + std::string(a) + "'");
    }
    std::puts("techniques:");
    for (const tessera::TechniqueInfo& t : tessera::techniques())
        std::printf("  %-18s %-12s %s [%s]\n", std::string(t.id).c_str(), !t.build ? "planned" : t.msaa ? "ready, MSAA" : "ready",
                    std::string(t.summary).c_str(), std::string(t.source).c_str());
    const fs::path dir = bundledScenesDir();
    std::printf("bundled scenes (%s):\n", dir.string().c_str());
    std::printf("  %-22s %s\n", "builtin", "generated cubes and a blended pane (no files, no lights)");
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().extension() == ".json" && e.path().filename() != "scene.schema.json") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files) {
        std::string description;
        try {
            std::ifstream in(f, std::ios::binary);
            const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            tessera::checkJsonDepth(text, f.string());
            const nlohmann::json j = nlohmann::json::parse(text);
            if (j.contains("description") && j["description"].is_string()) description = firstSentence(j["description"].get<std::string>());
        } catch (const std::exception&) {
            description = "(not valid JSON)";
        }
        std::printf("  %-22s %s\n", f.stem().string().c_str(), description.c_str());
    }
    return 0;
}

// `tessera options [TECHNIQUE]`: the option catalogue (techniques/option_catalog.h) as text.
int options(const std::vector<std::string_view>& args) {
    std::string only;
    for (const std::string_view a : args) {
        if (a == "--help" || a == "-h") {
            std::fputs(kOptionsUsage, stdout);
            return 0;
        }
        if (!a.empty() && a[0] == '-') throw UsageError("unknown option '" + std::string(a) + "' (see tessera options --help)");
        if (!only.empty()) throw UsageError("options takes one TECHNIQUE at most");
        only = std::string(a);
        if (!tessera::findTechnique(only)) {
            std::string ids;
            for (const tessera::TechniqueInfo& t : tessera::techniques()) ids += (ids.empty() ? "" : ", ") + std::string(t.id);
            throw UsageError("options: unknown technique '" + only + "' (one of " + ids + ")");
        }
    }
    bool first = true;
    for (const tessera::TechniqueInfo& t : tessera::techniques()) {
        if (!only.empty() && t.id != only) continue;
        if (!first) std::puts("");
        first = false;
        const auto list = tessera::techniqueOptions(t.id);
        std::printf("%s%s\n", std::string(t.id).c_str(),
                    !t.build ? " (planned)" : list.empty() ? ": no options" : "");
        for (const OptionInfo& option : list) {
            std::printf("  %-17s %s\n", std::string(option.key).c_str(), tessera::optionValuesText(option).c_str());
            std::printf("  %-17s default %s", "", std::string(option.faithful).c_str());
            if (!option.corrected.empty()) std::printf("; correction %s", std::string(option.corrected).c_str());
            if (option.erratum != 0) std::printf("; ERRATA.md #%d", option.erratum);
            std::printf("\n  %-17s %s\n", "", std::string(option.meaning).c_str());
        }
    }
    return 0;
}

// `tessera info builtin`: the generated scene's facts without a file.
int infoBuiltin() {
    const tessera::BuiltinSceneOptions opt;
    std::printf("scene       builtin (generated, no files)\n");
    std::printf("technique   its own Lambert-shaded draws (no scene-file technique), %ux%u by default, precision exact "
                "unless --precision; --msaa 1, 2, 4 or 8\n",
                opt.width, opt.height);
    std::printf("contents    generated cubes and a blended pane; no textures, no technique options\n");
    return 0;
}

int info(const std::vector<std::string_view>& args) {
    std::string sceneArg;
    for (const std::string_view a : args) {
        if (a == "--help" || a == "-h") {
            std::fputs(kInfoUsage, stdout);
            return 0;
        }
        if (!a.empty() && a[0] == '-') throw UsageError("unknown option '" + std::string(a) + "' (see tessera info --help)");
        if (!sceneArg.empty()) throw UsageError("one scene only");
        sceneArg = std::string(a);
    }
    if (sceneArg.empty()) throw UsageError("info needs a SCENE");
    if (sceneArg == "builtin") return infoBuiltin();
    const fs::path file = resolveScene(sceneArg);
    const tessera::SceneDescription desc = describe(file);
    tessera::Camera camera;
    const tessera::Scene scene = tessera::loadScene(desc, false, &camera);
    std::size_t primitives = 0;
    for (const tessera::Mesh& m : scene.meshes) primitives += m.primitives.size();
    const SceneBytes loaded = sceneBytes(scene);  // images: from their headers (not decoded here)
    const tessera::TechniqueInfo& technique = tessera::requireTechnique(desc.technique, file.string());
    const tessera::TextureMemoryEstimate textures = tessera::SceneResources::estimateTextureMemory(
        scene, technique.textures, std::size_t(tbb::this_task_arena::max_concurrency()));
    std::size_t lightsByType[3] = {0, 0, 0};
    for (const tessera::Light& l : scene.lights) ++lightsByType[int(l.type)];
    const tessera::Bounds b = scene.bounds();
    std::printf("scene       %s\n", file.string().c_str());
    std::printf("technique   %s (precision %s), %ux%u\n", desc.technique.c_str(), std::string(tessera::precisionName(desc.precision)).c_str(),
                desc.width, desc.height);
    std::printf("triangles   %llu (in %zu instances of %zu meshes, %zu primitives)\n", (unsigned long long)scene.triangleCount(),
                scene.instances.size(), scene.meshes.size(), primitives);
    std::printf("materials   %zu; textures %zu; images %zu\n", scene.materials.size(), scene.textures.size(), scene.images.size());
    std::printf("cameras     %zu in the glTF files; render camera at (%g, %g, %g), fovY %g deg, near %g, far %g\n",
                scene.cameras.size(), camera.positionWorld.x, camera.positionWorld.y, camera.positionWorld.z, camera.fovYDeg,
                camera.nearZ, camera.farZ);
    std::printf("lights      %zu (point %zu, spot %zu, directional %zu)\n", scene.lights.size(), lightsByType[0], lightsByType[1],
                lightsByType[2]);
    if (b.empty()) std::printf("bounds      empty\n");
    else
        std::printf("bounds      (%g, %g, %g) .. (%g, %g, %g)\n", b.minWorld.x, b.minWorld.y, b.minWorld.z, b.maxWorld.x,
                    b.maxWorld.y, b.maxWorld.z);
    // Frame buffers: the technique's probe frames (estimateFrameMemory), untextured (no images here).
    double frameBytes = 0.0, perPixel = 0.0;
    if (technique.build) {
        const tessera::SceneResources resources(scene, {}, technique.textures);
        tessera::Device device(tessera::DeviceConfig{});
        const tessera::TechniqueContext ctx = frameContext(device, resources, camera, desc, file);
        const tessera::FrameMemoryEstimate e = tessera::estimateFrameMemory(desc.technique, ctx, file.string());
        frameBytes = e.bytes;
        perPixel = e.bytesPerPixel;
    }
    const double resident = loaded.geometry + loaded.images + textures.textureBytes + frameBytes;
    std::printf("memory      about %s besides the program, peak %s while textures decode: geometry %s, decoded images %s, "
                "textures with mips %s (+ %s of float copies while decoding), frame buffers %s (%.0f B per pixel, 1 sample)\n",
                tessera::formatBytes(resident).c_str(),
                tessera::formatBytes(loaded.geometry + loaded.images + textures.textureBytes + textures.transientBytes).c_str(),
                tessera::formatBytes(loaded.geometry).c_str(), tessera::formatBytes(loaded.images).c_str(),
                tessera::formatBytes(textures.textureBytes).c_str(), tessera::formatBytes(textures.transientBytes).c_str(),
                tessera::formatBytes(frameBytes).c_str(), perPixel);
    std::printf("limit       renders are refused past %s (3/4 of the %s this process may use; tessera render --memory-limit)\n",
                tessera::formatBytes(double(tessera::defaultMemoryLimitBytes())).c_str(),
                tessera::formatBytes(double(tessera::availableMemoryBytes())).c_str());
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    std::vector<std::string_view> args(argv + 1, argv + argc);
    gCommandLine = "tessera";
    for (const std::string_view a : args) {
        gCommandLine += ' ';
        gCommandLine.append(a);
    }
    try {
        if (args.empty() || args[0] == "--help" || args[0] == "-h" || (args[0] == "help" && args.size() == 1)) {
            std::fputs(kUsage, args.empty() ? stderr : stdout);
            return args.empty() ? 2 : 0;
        }
        if (args[0] == "--version" || args[0] == "version") {
            std::printf("tessera %s\n", TESSERA_VERSION);
            return 0;
        }
        if (args[0] == "help") {  // help COMMAND = COMMAND --help
            if (args.size() > 2) throw UsageError("help takes one COMMAND");
            args = {args[1], "--help"};
        }
        const std::vector<std::string_view> rest(args.begin() + 1, args.end());
        if (args[0] == "render") return render(rest);
        if (args[0] == "list") return list(rest);
        if (args[0] == "options") return options(rest);
        if (args[0] == "probe") {  // probe SCENE X Y [flags] = render SCENE --probe X,Y [--no-output] [flags]
            if (rest.size() == 1 && (rest[0] == "--help" || rest[0] == "-h")) {
                std::fputs(kProbeUsage, stdout);
                return 0;
            }
            if (rest.size() < 3) throw UsageError("probe needs SCENE X Y (window pixels)");
            const std::string xy = std::string(rest[1]) + "," + std::string(rest[2]);
            std::vector<std::string_view> renderArgs{rest[0], "--probe", xy};
            bool writes = false;
            for (std::size_t i = 3; i < rest.size(); ++i) {
                writes = writes || rest[i] == "--out" || rest[i] == "--dump";
                renderArgs.push_back(rest[i]);
            }
            if (!writes) renderArgs.push_back("--no-output");
            return render(renderArgs);
        }
        if (args[0] == "info") return info(rest);
        if (args[0] == "report") return tessera::cli::reportCommand(rest);
        if (args[0] == "diff") return tessera::cli::diffCommand(rest);
        std::fprintf(stderr, "tessera: unknown command '%s'\n%s", std::string(args[0]).c_str(), kUsage);
        return 2;
    } catch (const UsageError& e) {
        // The command's own help names its options; the top-level usage would bury the message.
        const bool known = !args.empty() && (args[0] == "render" || args[0] == "list" || args[0] == "options" || args[0] == "probe" || args[0] == "report" ||
                                             args[0] == "info" || args[0] == "diff");
        if (known) std::fprintf(stderr, "tessera: %s\n(see `tessera help %s`)\n", e.what(), std::string(args[0]).c_str());
        else std::fprintf(stderr, "tessera: %s\n%s", e.what(), kUsage);
        return 2;
    } catch (const tessera::InputError& e) {
        std::fprintf(stderr, "tessera: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "tessera: %s\n", e.what());
        return 1;
    }
}

