// Ray-cast shadow jobs (GPU Pro 4 ch. 5 §5.6.2): job creation walks each pixel's tile list and
// packs (pixel, slot) jobs; ray casting answers each job with one Embree occlusion ray and ORs
// the result into the pixel's 128-bit mask. Both are deterministic at any thread count.
#include <tessera/techniques/amd_shadow_rays.h>

#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <tessera/raytrace/shadow_ray_scene.h>

namespace tessera {
namespace {

constexpr std::size_t kJobGrain = 4096;  // jobs per TBB task in the ray-casting loop

std::uint32_t tileOf(const ShadowPixels& pixels, const AmdTileLightLists& lists, std::uint32_t pixelIndex) {
    const std::uint32_t x = pixelIndex % pixels.width, y = pixelIndex / pixels.width;
    return x / kAmdTileSizePx + (y / kAmdTileSizePx) * lists.tileCount.x;
}

// Whether the light can light the point at all (the AMD shader's own bounds).
bool overlaps(const ShadowCaster& light, const glm::vec3& posWorld) {
    const glm::vec3 toLight = light.positionWorld - posWorld;
    const float distance = std::sqrt(glm::dot(toLight, toLight));
    if (!(distance < light.range)) return false;
    if (light.cosCone < -1.0f) return true;
    return glm::dot(-toLight / distance, light.directionWorld) > light.cosCone;
}

} // namespace

glm::vec3 shadowSurfacePoint(const ShadowPixels& pixels, std::uint32_t pixelIndex) {
    const std::uint32_t x = pixelIndex % pixels.width, y = pixelIndex / pixels.width;
    const glm::dvec4 posClip(2.0 * (double(x) + 0.5) / double(pixels.width) - 1.0,
                             1.0 - 2.0 * (double(y) + 0.5) / double(pixels.height), double(pixels.depthWindow[pixelIndex]), 1.0);
    const glm::dvec4 posWorld = pixels.worldFromClip * posClip;
    return glm::vec3(glm::dvec3(posWorld) / posWorld.w);
}

glm::vec3 shadowRayOrigin(const ShadowPixels& pixels, std::uint32_t pixelIndex, float normalOffset) {
    return shadowSurfacePoint(pixels, pixelIndex) + glm::vec3(pixels.normalWorld[pixelIndex]) * normalOffset;
}

ShadowJobs createShadowJobs(const ShadowPixels& pixels, const AmdTileLightLists& lists, std::span<const ShadowCaster> lights,
                            const ShadowRayOptions& options) {
    const std::uint64_t pixelCount = std::uint64_t{pixels.width} * pixels.height;
    if (pixelCount > kShadowMaxPixels)
        throw std::runtime_error("ray-cast shadows: " + std::to_string(pixels.width) + " x " + std::to_string(pixels.height) +
                                 " pixels exceed the job format's 2^25 pixel indices");
    ShadowJobs out;
    out.mask.assign(pixelCount * kShadowMaskWords, 0u);
    std::vector<std::vector<std::uint32_t>> rowJobs(pixels.height);
    std::vector<ShadowJobStats> rowStats(pixels.height);
    tbb::parallel_for(std::uint32_t(0), pixels.height, [&](std::uint32_t y) {
        std::vector<std::uint32_t>& jobs = rowJobs[y];
        ShadowJobStats& stats = rowStats[y];
        for (std::uint32_t x = 0; x < pixels.width; ++x) {
            const std::uint32_t pixel = y * pixels.width + x;
            if (!(pixels.depthWindow[pixel] < 1.0f)) continue;  // cleared: no surface
            const std::span<const std::uint32_t> list = lists.tileLights(tileOf(pixels, lists, pixel));
            if (list.size() > kShadowMaxSlots) ++stats.overflowPixels;
            const glm::vec3 posWorld = shadowSurfacePoint(pixels, pixel);
            const glm::vec3 normal(pixels.normalWorld[pixel]);
            for (std::uint32_t slot = 0; slot < list.size(); ++slot) {
                const ShadowCaster& light = lights[list[slot]];
                if (!light.castsShadows || !overlaps(light, posWorld)) continue;
                if (slot >= kShadowMaxSlots) {
                    ++stats.overflowLights;
                    continue;
                }
                if (options.backfaces != ShadowBackfaces::Cast && !(glm::dot(normal, light.positionWorld - posWorld) > 0.0f)) {
                    if (options.backfaces == ShadowBackfaces::Mask) {
                        out.mask[std::size_t{pixel} * kShadowMaskWords + shadowMaskWord(slot)] |= shadowMaskFlag(slot);
                        ++stats.backfaceMasked;
                    }
                    continue;
                }
                jobs.push_back(packShadowJob(pixel, slot));
            }
        }
    });
    std::size_t total = 0;
    for (const std::vector<std::uint32_t>& r : rowJobs) total += r.size();
    out.jobs.reserve(total);
    for (std::uint32_t y = 0; y < pixels.height; ++y) {
        out.jobs.insert(out.jobs.end(), rowJobs[y].begin(), rowJobs[y].end());
        out.stats.backfaceMasked += rowStats[y].backfaceMasked;
        out.stats.overflowPixels += rowStats[y].overflowPixels;
        out.stats.overflowLights += rowStats[y].overflowLights;
    }
    out.stats.jobs = out.jobs.size();
    return out;
}

void castShadowJobs(const ShadowPixels& pixels, const AmdTileLightLists& lists, std::span<const ShadowCaster> lights,
                    const ShadowRayScene& occluders, const ShadowRayOptions& options, ShadowJobs& jobs) {
    std::atomic<std::uint64_t> occludedCount{0};
    // Each pixel's ray origin once (jobs of one pixel share it), then the jobs in blocks.
    std::vector<glm::vec3> originWorld(std::size_t{pixels.width} * pixels.height);
    tbb::parallel_for(std::uint32_t(0), pixels.height, [&](std::uint32_t y) {
        for (std::uint32_t x = 0; x < pixels.width; ++x) {
            const std::uint32_t p = y * pixels.width + x;
            if (pixels.depthWindow[p] < 1.0f) originWorld[p] = shadowRayOrigin(pixels, p, options.normalOffset);
        }
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, jobs.jobs.size(), kJobGrain), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<ShadowRayScene::Segment> segments(r.size());
        std::vector<std::uint8_t> hit(r.size());
        for (std::size_t j = r.begin(); j < r.end(); ++j) {
            const std::uint32_t job = jobs.jobs[j];
            const std::uint32_t pixel = shadowJobPixel(job), slot = shadowJobSlot(job);
            const ShadowCaster& light = lights[lists.tileLights(tileOf(pixels, lists, pixel))[slot]];
            const glm::vec3& origin = originWorld[pixel];
            segments[j - r.begin()] = {origin, light.positionWorld - origin, 1.0f - kShadowRayEndFraction};
        }
        occluders.occluded(segments, hit);
        std::uint64_t hits = 0;
        for (std::size_t j = r.begin(); j < r.end(); ++j) {
            if (!hit[j - r.begin()]) continue;
            ++hits;
            const std::uint32_t job = jobs.jobs[j];
            const std::uint32_t pixel = shadowJobPixel(job), slot = shadowJobSlot(job);
            // The chapter's InterlockedOr: jobs of one pixel may run on different threads.
            std::atomic_ref<std::uint32_t> word(jobs.mask[std::size_t{pixel} * kShadowMaskWords + shadowMaskWord(slot)]);
            word.fetch_or(shadowMaskFlag(slot), std::memory_order_relaxed);
        }
        occludedCount.fetch_add(hits, std::memory_order_relaxed);
    });
    jobs.stats.occluded = occludedCount.load();
}

} // namespace tessera
