// Running a frame for `tessera render`: the warm-up and timed runs (--warmup, --repeat) into a
// fresh registry each, --dump-after's and --probe's recordings during the last run, and what
// --stats prints of them (pass and frame times, draw counters, shadow counters, peak memory).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <tessera/frame/frame.h>
#include <tessera/inspect/pixel_history.h>
#include <tessera/raster/device.h>
#include <tessera/scene/scene_file.h>

#include "progress.h"
#include "render_args.h"
#include "render_output.h"

namespace tessera::cli {

using Clock = std::chrono::steady_clock;
inline double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// Whether a render looks at its intermediate buffers (--dump, with --dump-after, or --probe): without,
// the frame skips the passes that only write buffers to be looked at (Pass::inspectionOnly).
inline bool inspects(const RenderOptions& o) { return !o.dumpDir.empty() || o.probe.has_value(); }

// What runFrames measured and wrote.
struct FrameRuns {
    std::vector<std::vector<tessera::PassTiming>> passes;  // per timed run, in pass order
    std::vector<double> frameMs;                           // per timed run (with --dump-after, the last
                                                           // run's time includes writing those dumps)
    std::vector<WrittenFile> afterWritten;                 // --dump-after's files
    nlohmann::json after = nlohmann::json::object();       // --dump-after: pass -> its buffers
};

// --dump-after's pass names checked against the frame before it runs (UsageError naming the passes);
// `--dump-after all` becomes every pass's name.
void checkDumpAfter(const Frame& frame, RenderOptions& o);

// The frame rendered `warmup` times untimed, then `repeat` times timed, each run into a fresh
// registry (`registry` keeps the last run's buffers, which are written). `beforeRun` resets the
// counters a run accumulates, so the draw counters printed are one frame's. With `history` and
// `watch` (--probe), the watched pixel is recorded through the last run on `device`.
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
        registry.clear();  // every run starts from no buffers, under the caller's byte limit
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
                dumpRegistry(now, std::filesystem::path(o.dumpDir) / ("after-" + pass.name), o, true, runs.afterWritten, buffers);
                runs.after[pass.name] = {{"folder", "after-" + pass.name}, {"buffers", buffers}};
            };
        const auto t = Clock::now();
        std::vector<tessera::PassTiming> timings = frame.run(registry, afterPass, inspects(o));
        const double ms = msSince(t);
        if (device) device->setPixelWatch(nullptr);
        if (i < o.warmup) continue;
        runs.passes.push_back(std::move(timings));
        runs.frameMs.push_back(ms);
    }
    return runs;
}

// --probe X,Y: the pixel's history for a frame of width x height (the pixel checked inside it).
std::optional<PixelHistory> probeHistory(const RenderOptions& o, std::uint32_t width, std::uint32_t height);

// The tile edge (px) of a technique's per-tile light lists: its "tileSize" option or the default
// (16, forward-plus-amd's fixed 8); 0 for techniques without tiles.
std::uint32_t lightGridTileSize(const SceneDescription& desc);

// The manifest's common part: what was rendered and how, the passes with their declared buffers,
// and --dump-after's snapshots. No times (--stats has them): the same render gives the same file.
nlohmann::json manifestBase(const Frame& frame, const FrameRuns& runs, const RenderOptions& o);

// "pass <name> <ms>" per pass and "frame <ms>": one run's times as they are, or with --repeat N > 1
// each pass's and the frame's median over the N runs with the range beside it.
void printTimings(const FrameRuns& runs, const RenderOptions& o, bool frameLine);
// "triangles in ..., quads, ps invocations ...", the draw paths, MSAA and SIMD block counts.
void printDrawStats(const DrawStats& s);
// forward-plus-amd's ray-cast shadows (GPU Pro 4 §5.6.2): its "shadow.counters" as one line.
void printShadowStats(const BufferRegistry& registry);
// "buffers  N, X MiB: ..." : the frame's buffers by why they exist (frame/frame.h auditBuffers):
// read by a later pass, the image, written for inspection, and any that nothing reads.
void printBufferStats(const Frame& frame, const BufferRegistry& registry, bool inspection);
// "peak memory  N MiB": the process's peak resident set size (getrusage ru_maxrss).
void printPeakMemory();

} // namespace tessera::cli
