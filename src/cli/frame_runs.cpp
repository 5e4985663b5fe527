// Running and timing a frame for `tessera render` (frame_runs.h).
#include "frame_runs.h"

#include <array>
#include <cstdio>
#include <cstring>

#include <sys/resource.h>

#include <tessera/raster/quad_block.h>
#include <tessera/techniques/option_catalog.h>
#include <tessera/techniques/technique.h>

#include "commands.h"

namespace tessera::cli {
namespace {

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

} // namespace

void checkDumpAfter(const tessera::Frame& frame, RenderOptions& o) {
    if (o.dumpAfterAll) {  // `--dump-after all`: every pass, in frame order
        o.dumpAfter.clear();
        for (const tessera::Pass& p : frame.passes()) o.dumpAfter.push_back(p.name);
        o.dumpAfterAll = false;
    }
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

std::optional<tessera::PixelHistory> probeHistory(const RenderOptions& o, std::uint32_t width, std::uint32_t height) {
    if (!o.probe) return std::nullopt;
    const auto [x, y] = *o.probe;
    if (x >= width || y >= height)
        throw UsageError("--probe: (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " + std::to_string(width) +
                         "x" + std::to_string(height) + " frame");
    return tessera::PixelHistory(x, y);
}

std::uint32_t lightGridTileSize(const tessera::SceneDescription& desc) {
    const tessera::TechniqueInfo* info = tessera::findTechnique(desc.technique);
    if (!info || info->tileSize == 0) return 0;
    if (!tessera::findOption(desc.technique, "tileSize")) return info->tileSize;
    const nlohmann::json& options = desc.techniqueOptions;
    if (options.is_object() && options.contains("tileSize") && options["tileSize"].is_number_unsigned())
        return options["tileSize"].get<std::uint32_t>();
    return info->tileSize;
}

nlohmann::json manifestBase(const tessera::Frame& frame, const FrameRuns& runs, const RenderOptions& o) {
    nlohmann::json passes = nlohmann::json::array();
    for (const tessera::Pass& p : frame.passes()) passes.push_back({{"name", p.name}, {"reads", p.reads}, {"writes", p.writes}});
    return {{"tessera", TESSERA_VERSION}, {"command", commandLine()}, {"passes", passes}, {"after", runs.after},
            {"exposure", o.exposure}};
}

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

void printBufferStats(const tessera::Frame& frame, const tessera::BufferRegistry& registry, bool inspection) {
    using Role = tessera::BufferUse::Role;
    const std::array<std::string_view, 2> images{tessera::kBackBufferName, tessera::kReferenceBufferName};
    const std::vector<tessera::BufferUse> uses = tessera::auditBuffers(frame, registry, images, inspection);
    std::array<std::uint64_t, 4> count{}, bytes{};
    std::array<std::string, 4> names;
    for (const tessera::BufferUse& u : uses) {
        const std::size_t r = std::size_t(u.role);
        ++count[r];
        bytes[r] += u.bytes;
        names[r] += (names[r].empty() ? "" : ", ") + u.name;
    }
    const auto mib = [](std::uint64_t b) { return double(b) / (1024.0 * 1024.0); };
    std::printf("buffers  %zu, %.1f MiB: %llu read by a later pass (%.1f MiB)", uses.size(), mib(registry.bytes()),
                (unsigned long long)count[std::size_t(Role::Read)], mib(bytes[std::size_t(Role::Read)]));
    if (count[std::size_t(Role::Image)] > 0)
        std::printf(", %llu image read by no pass (%.1f MiB)", (unsigned long long)count[std::size_t(Role::Image)],
                    mib(bytes[std::size_t(Role::Image)]));
    if (count[std::size_t(Role::Inspection)] > 0)
        std::printf(", %llu for inspection (%.1f MiB: %s)", (unsigned long long)count[std::size_t(Role::Inspection)],
                    mib(bytes[std::size_t(Role::Inspection)]), names[std::size_t(Role::Inspection)].c_str());
    if (count[std::size_t(Role::Unread)] > 0)
        std::printf(", %llu read by nothing (%.1f MiB: %s)", (unsigned long long)count[std::size_t(Role::Unread)],
                    mib(bytes[std::size_t(Role::Unread)]), names[std::size_t(Role::Unread)].c_str());
    // Passes skipped because nothing looks at what they write (without --dump or --probe).
    std::string skipped;
    if (!inspection)
        for (const tessera::Pass& p : frame.passes())
            if (p.inspectionOnly()) skipped += (skipped.empty() ? "" : ", ") + p.name;
    if (!skipped.empty()) std::printf("; skipped inspection-only passes: %s (--dump or --probe runs them)", skipped.c_str());
    std::printf("\n");
}

void printPeakMemory() { std::printf("peak memory  %.1f MiB\n", peakRssMiB()); }

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
    std::printf("simd     %llu blocks of 8x8 px through the %s kernels, %llu of them lean (SIMD depth test), "
                "%llu shaded by one block-shader call\n",
                (unsigned long long)s.simdBlocks, tessera::quadBlockTarget(), (unsigned long long)s.leanBlocks,
                (unsigned long long)s.blockShaderCalls);
    // Draws binned into shared tile lists (raster/draw_batch.h), in how many sweeps of the tiles,
    // and the tiles the batches' recorded clears cleared (the deferred light loop's stencil).
    std::printf("binned   %llu draws in %llu runs of shared tile lists", (unsigned long long)s.binnedDraws,
                (unsigned long long)s.binnedRuns);
    if (s.batchClearedTiles > 0) std::printf(", %llu tiles cleared between them", (unsigned long long)s.batchClearedTiles);
    std::printf("\n");
}

void printShadowStats(const tessera::BufferRegistry& registry) {
    const tessera::Surface* counters = registry.find("shadow.counters");
    if (!counters) return;
    std::uint32_t c[5];
    std::memcpy(c, counters->bytes().data(), sizeof(c));
    std::printf("shadows  %u rays (jobs), %u occluded; %u light slots masked behind the surface; %u pixels list more than "
                "128 lights (%u overlapping lights past slot 127)\n",
                c[0], c[1], c[2], c[3], c[4]);
}

} // namespace tessera::cli
