// The GPU Pro 4 light-culling kernel (§5.3.1, §5.6.1) as a compute::dispatch kernel: one group of
// 8x8 threads per tile, group-shared depth bounds, 2.5D mask and light list, then the write-back
// into one global pool with the offsets InterlockedAdd hands out in row-major group order, so
// Parallel and Serial give the same bytes. The binned light loop (tessera) hands each group its
// tile's candidate lights instead of all.
#include <tessera/techniques/amd_light_culling.h>

#include <tessera/compute/interlocked.h>
#include <tessera/culling/depth_mask.h>
#include <tessera/gbuffer/screen_to_view.h>

#include <algorithm>
#include <array>
#include <bit>
#include <optional>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "tile_binning.h"

namespace tessera {

namespace {

constexpr std::uint32_t kThreadsPerTile = kAmdTileSizePx * kAmdTileSizePx;  // 64

// groupshared variables of the kernel.
struct AmdCullShared {
    std::uint32_t zMinBits;                                 // ldsZMin
    std::uint32_t zMaxBits;                                 // ldsZMax
    std::uint32_t depthMask;                                // the 2.5D occupancy mask
    std::uint32_t lightIdxCounter;                          // ldsLightIdxCounter
    std::uint32_t lightIdxStart;                            // ldsLightIdxStart
    std::array<std::uint32_t, kAmdLightCapacity> lightIdx; // ldsLightIdx[LIGHT_CAPACITY]
    // Half-Z list B (TiledLighting11's second per-tile list).
    std::uint32_t lightIdxCounterFar;
    std::uint32_t lightIdxStartFar;
    std::array<std::uint32_t, kAmdLightCapacity> lightIdxFar;
};

// The binned light loop (AmdLightLoop::Binned): each tile's candidate lights, ascending.
struct AmdLightBins {
    std::vector<std::uint32_t> tileStart;   // CSR over tiles (row-major): tileLights[tileStart[t], tileStart[t + 1])
    std::vector<std::uint32_t> tileLights;
};

// The kernel's side planes per column (right eqn[1], left eqn[3]) and per row (top eqn[0],
// bottom eqn[2]), taken from the tiles of row 0 and column 0 (tile_binning.h: the same plane for
// every tile of a column or row, up to rounding far below the padding).
struct AmdAxisPlanes {
    std::vector<glm::dvec3> right, left, top, bottom;
};

AmdAxisPlanes amdAxisPlanes(glm::uvec2 tiles, glm::uvec2 windowPx, const glm::mat4& inverseProjection, AmdTileCorners corners) {
    AmdAxisPlanes p;
    for (std::uint32_t gx = 0; gx < tiles.x; ++gx) {
        const auto eqn = tileSidePlanesAmd({gx, 0u}, kAmdTileSizePx, windowPx, inverseProjection, corners);
        p.right.emplace_back(eqn[1]);
        p.left.emplace_back(eqn[3]);
    }
    for (std::uint32_t gy = 0; gy < tiles.y; ++gy) {
        const auto eqn = tileSidePlanesAmd({0u, gy}, kAmdTileSizePx, windowPx, inverseProjection, corners);
        p.top.emplace_back(eqn[0]);
        p.bottom.emplace_back(eqn[2]);
    }
    return p;
}

// Whether the projection has the orientation the binary searches assume: LH view space, NDC x
// right = view +x, NDC y up = view +y, the NDC centre in front (+z). Otherwise every light's
// columns and rows are scanned, which assumes nothing.
bool standardOrientation(const glm::mat4& inverseProjection) {
    const auto at = [&](float x, float y) { return glm::vec3(clipToView(glm::vec4(x, y, 1.0f, 1.0f), inverseProjection)); };
    const glm::vec3 centre = at(0.0f, 0.0f);
    return centre.z > 0.0f && at(0.5f, 0.0f).x > centre.x && at(-0.5f, 0.0f).x < centre.x && at(0.0f, 0.5f).y > centre.y &&
           at(0.0f, -0.5f).y < centre.y;
}

// The columns and rows a light can pass sphereOverlapsTileAmd's side tests on. The kernel keeps a
// side when dot(eqn, c) < r (binary32); the binning drops a column only when dot >= r + pad in
// double on the column's plane, so a dropped column fails the kernel on every tile of it. NaN
// never drops.
binning::TileRuns amdLightRuns(const glm::vec4& light, const AmdAxisPlanes& planes, glm::uvec2 tiles, bool searchable) {
    const glm::dvec3 c(light.x, light.y, light.z);
    const double r = double(light.w);
    const double limit = r + binning::padFor(c, r);
    const auto kept = [&](const glm::dvec3& n) { return !(glm::dot(n, c) >= limit); };
    binning::TileRuns runs;
    if (!searchable || !(c.z - limit > 0.0)) {  // not wholly in front of the eye (or NaN): scan
        binning::scanRuns(tiles.x, [&](std::uint32_t gx) { return kept(planes.right[gx]) && kept(planes.left[gx]); }, runs.x0,
                          runs.x1, runs.x2, runs.x3);
        binning::scanRuns(tiles.y, [&](std::uint32_t gy) { return kept(planes.top[gy]) && kept(planes.bottom[gy]); }, runs.y0,
                          runs.y1, runs.y2, runs.y3);
        return runs.empty() ? binning::TileRuns{} : runs;
    }
    // Wholly in front: the right plane keeps the columns from the light's on (a suffix), the left
    // plane those up to it (a prefix); rows run top to bottom: the bottom plane keeps a suffix,
    // the top plane a prefix.
    const bool columns = binning::searchRun(
        tiles.x, [&](std::uint32_t gx) { return kept(planes.right[gx]); }, [&](std::uint32_t gx) { return kept(planes.left[gx]); },
        runs.x0, runs.x1);
    const bool rows = binning::searchRun(
        tiles.y, [&](std::uint32_t gy) { return kept(planes.bottom[gy]); }, [&](std::uint32_t gy) { return kept(planes.top[gy]); },
        runs.y0, runs.y1);
    return columns && rows ? runs : binning::TileRuns{};
}

AmdLightBins binLightsAmd(std::span<const glm::vec4> lights, glm::uvec2 tiles, glm::uvec2 windowPx,
                          const glm::mat4& inverseProjection, AmdTileCorners corners) {
    const AmdAxisPlanes planes = amdAxisPlanes(tiles, windowPx, inverseProjection, corners);
    const bool searchable = standardOrientation(inverseProjection);
    std::vector<binning::TileRuns> runs(lights.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lights.size(), 256), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) runs[i] = amdLightRuns(lights[i], planes, tiles, searchable);
    });
    // Counting sort of (tile, light) by tile, lights visited in ascending index.
    const auto forTiles = [&](const binning::TileRuns& run, auto&& f) {
        if (run.empty()) return;
        const auto row = [&](std::uint32_t gy) {
            for (std::uint32_t gx = run.x0; gx <= run.x1; ++gx) f(gx + gy * tiles.x);
            for (std::uint32_t gx = run.x2; gx <= run.x3; ++gx) f(gx + gy * tiles.x);
        };
        for (std::uint32_t gy = run.y0; gy <= run.y1; ++gy) row(gy);
        for (std::uint32_t gy = run.y2; gy <= run.y3; ++gy) row(gy);
    };
    AmdLightBins bins;
    const std::size_t tileCount = std::size_t{tiles.x} * tiles.y;
    bins.tileStart.assign(tileCount + 1, 0u);
    for (const binning::TileRuns& run : runs) forTiles(run, [&](std::uint32_t t) { ++bins.tileStart[t + 1]; });
    for (std::size_t t = 0; t < tileCount; ++t) bins.tileStart[t + 1] += bins.tileStart[t];
    std::vector<std::uint32_t> cursor(bins.tileStart.begin(), bins.tileStart.end() - 1);
    bins.tileLights.resize(bins.tileStart.back());
    for (std::size_t i = 0; i < runs.size(); ++i)
        forTiles(runs[i], [&](std::uint32_t t) { bins.tileLights[cursor[t]++] = static_cast<std::uint32_t>(i); });
    return bins;
}

struct AmdCullKernel {
    static constexpr glm::uvec3 groupSize{kAmdTileSizePx, kAmdTileSizePx, 1u};
    using Shared = AmdCullShared;

    std::span<const DepthImageView> depth;  // one image per MSAA sample (ForwardPlus11: every sample joins)
    std::span<const glm::vec4> lights;
    glm::mat4 inverseProjection{1.0f};
    AmdCullingOptions options;
    AmdTileLightLists* out = nullptr;
    const AmdLightBins* bins = nullptr;  // the binned loop's candidates; null: every light
    // The write-back: each group copies its lists to its own staging slice (from stageStart[tile],
    // room for min(candidates, 256) entries per list) and cullTilesAmd makes the pool
    // reservations after the dispatch, in row-major group order: the offsets the kernel's
    // InterlockedAdd(gLightIdxCounter) gives under compute/dispatch.h order rule 3, without any
    // group waiting for its predecessors' reservations.
    std::uint32_t* staging = nullptr;
    const std::size_t* stageStart = nullptr;

    // The pixel's view z and whether it takes part (not the cleared value).
    bool viewZ(float d, float& z) const {
        if (options.depthConvention == AmdDepthConvention::GpuPro4) {
            z = clipToView(glm::vec4(0.0f, 0.0f, d, 1.0f), inverseProjection).z;
            return options.range == AmdDepthRange::NearToMax || d != 1.0f;  // NearToMax: cleared = far plane
        }
        z = 1.0f / (d * inverseProjection[2][3] + inverseProjection[3][3]);
        return d != 0.0f;
    }

    void operator()(compute::GroupContext<Shared>& g) const {
        Shared& s = g.shared();
        const glm::uvec2 groupId(g.groupId());
        const std::uint32_t tileIndex = groupId.x + groupId.y * out->tileCount.x;
        const glm::uvec2 windowPx(depth[0].width, depth[0].height);
        // Every thread builds the same frustum in the shader; group-uniform here.
        const std::array<glm::vec3, 4> eqn =
            tileSidePlanesAmd(groupId, kAmdTileSizePx, windowPx, inverseProjection, options.corners);
        // The pixel's samples' view z and which of them take part (bit per sample).
        compute::PerThread<std::array<float, 8>, kThreadsPerTile> pixelZ;
        compute::PerThread<std::uint32_t, kThreadsPerTile> pixelValid;

        g.forOneThread(0, [&](const compute::ThreadIds&) {
            s.zMinBits = options.depthConvention == AmdDepthConvention::GpuPro4 ? 0xFFFFFFFFu : 0x7F7FFFFFu;
            s.zMaxBits = 0u;
            s.depthMask = 0u;
            s.lightIdxCounter = 0u;
            s.lightIdxCounterFar = 0u;
        });
        g.forEachThread([&](const compute::ThreadIds& t) {
            pixelValid[t] = 0u;
            for (std::size_t i = 0; i < depth.size(); ++i) {
                const float d = depth[i].load(t.dispatchThreadId.x, t.dispatchThreadId.y);
                float z = 0.0f;
                const bool valid = viewZ(d, z);
                pixelZ[t][i] = z;
                if (!valid) continue;
                pixelValid[t] |= 1u << i;
                compute::interlockedMax(s.zMaxBits, std::bit_cast<std::uint32_t>(z));
                compute::interlockedMin(s.zMinBits, std::bit_cast<std::uint32_t>(z));
            }
        });
        if (options.range == AmdDepthRange::NearToMax)  // the near plane's view z (depth 0)
            s.zMinBits = std::bit_cast<std::uint32_t>(clipToView(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f), inverseProjection).z);
        const float maxZ = std::bit_cast<float>(s.zMaxBits);
        const float minZ = std::bit_cast<float>(s.zMinBits);
        const bool mask25D = options.depthCulling == AmdDepthCulling::DepthMask25D && options.range == AmdDepthRange::Opaque;
        const bool halfZ = options.halfZ && options.range == AmdDepthRange::Opaque;
        const float pitch = depthMaskPitch(minZ, maxZ);
        if (mask25D) {
            g.forEachThread([&](const compute::ThreadIds& t) {
                for (std::size_t i = 0; i < depth.size(); ++i)
                    if (pixelValid[t] & (1u << i)) compute::interlockedOr(s.depthMask, depthMaskBit(pixelZ[t][i], minZ, pitch));
            });
        }
        // for (i = lIdx; i < numLights; i += 64) over every light, or over the tile's binned
        // candidates (ascending light index either way, so the same appends in the same order).
        const std::uint32_t* candidates = bins ? bins->tileLights.data() + bins->tileStart[tileIndex] : nullptr;
        const std::uint32_t loopCount =
            static_cast<std::uint32_t>(bins ? bins->tileStart[tileIndex + 1] - bins->tileStart[tileIndex] : lights.size());
        g.forEachStrided(loopCount, [&](const compute::ThreadIds&, std::uint32_t k) {
            const std::uint32_t i = candidates ? candidates[k] : k;
            const glm::vec3 center(lights[i]);
            const float radius = lights[i].w;
            if (!sphereOverlapsTileAmd(center, radius, eqn, minZ, maxZ)) return;
            if (mask25D && !depthMasksOverlap(lightDepthMask(center.z, radius, minZ, pitch), s.depthMask)) return;
            bool nearList = true;
            if (halfZ) {  // DoLightCulling: list A over [minZ, halfZ], list B over [halfZ, maxZ]
                const HalfZOverlap halves = sphereOverlapsHalfZAmd(center.z, radius, minZ, maxZ);
                nearList = halves.nearHalf;
                if (halves.farHalf) {
                    const std::uint32_t dstFar = compute::interlockedAdd(s.lightIdxCounterFar, 1u);
                    if (dstFar < kAmdLightCapacity) s.lightIdxFar[dstFar] = i;
                }
            }
            if (!nearList) return;
            const std::uint32_t dstIdx = compute::interlockedAdd(s.lightIdxCounter, 1u);
            if (dstIdx < kAmdLightCapacity) s.lightIdx[dstIdx] = i;
        });
        g.forOneThread(0, [&](const compute::ThreadIds&) {
            const std::uint32_t count = std::min(s.lightIdxCounter, kAmdLightCapacity);
            const std::uint32_t countFar = std::min(s.lightIdxCounterFar, kAmdLightCapacity);
            // The reservation (if count != 0: InterlockedAdd(gLightIdxCounter, count, start);
            // ptLowerBound[t] = start) is made after the dispatch (cullTilesAmd).
            s.lightIdxStart = static_cast<std::uint32_t>(stageStart[tileIndex]);
            s.lightIdxStartFar = s.lightIdxStart + count;
            out->tileLightCount[tileIndex] = count;
            out->tileFoundCount[tileIndex] = s.lightIdxCounter;
            if (halfZ) {
                out->tileLightCountFar[tileIndex] = countFar;
                out->tileFoundCountFar[tileIndex] = s.lightIdxCounterFar;
            }
            out->tileMinZBits[tileIndex] = s.zMinBits;
            out->tileMaxZBits[tileIndex] = s.zMaxBits;
            out->tileDepthMask[tileIndex] = s.depthMask;
        });
        const std::uint32_t count = std::min(s.lightIdxCounter, kAmdLightCapacity);
        const std::uint32_t countFar = std::min(s.lightIdxCounterFar, kAmdLightCapacity);
        g.forEachThread([&](const compute::ThreadIds& t) {
            for (std::uint32_t i = t.groupIndex; i < count; i += kThreadsPerTile) staging[s.lightIdxStart + i] = s.lightIdx[i];
            for (std::uint32_t i = t.groupIndex; i < countFar; i += kThreadsPerTile) staging[s.lightIdxStartFar + i] = s.lightIdxFar[i];
        });
    }
};

// One culling pass; bins: the candidates of the binned loop (null: all lights).
AmdTileLightLists cullPass(std::span<const DepthImageView> depth, std::span<const glm::vec4> lightsViewLh, const glm::mat4& inverseProjection,
                           const AmdCullingOptions& options, const AmdLightBins* bins) {
    AmdTileLightLists out;
    out.tileCount = tileCount(glm::uvec2(depth[0].width, depth[0].height), kAmdTileSizePx);
    const std::size_t tiles = std::size_t{out.tileCount.x} * out.tileCount.y;
    out.tileOffset.assign(tiles, 0u);
    out.tileLightCount.assign(tiles, 0u);
    out.tileFoundCount.assign(tiles, 0u);
    out.tileMinZBits.assign(tiles, 0u);
    out.tileMaxZBits.assign(tiles, 0u);
    out.tileDepthMask.assign(tiles, 0u);
    const bool halfZ = options.halfZ && options.range == AmdDepthRange::Opaque;
    if (halfZ) {
        out.tileOffsetFar.assign(tiles, 0u);
        out.tileLightCountFar.assign(tiles, 0u);
        out.tileFoundCountFar.assign(tiles, 0u);
    }
    // Each tile's staging slice: room for its lists (both with half-Z) full, or holding all of
    // its candidates.
    std::vector<std::size_t> stageStart(tiles + 1, 0);
    for (std::size_t t = 0; t < tiles; ++t) {
        const std::size_t found = bins ? bins->tileStart[t + 1] - bins->tileStart[t] : lightsViewLh.size();
        stageStart[t + 1] = stageStart[t] + (halfZ ? 2u : 1u) * std::min<std::size_t>(kAmdLightCapacity, found);
    }
    if (stageStart.back() > 0xFFFFFFFFu) throw std::length_error("cullTilesAmd: more than 2^32 light-list entries");
    std::vector<std::uint32_t> staging(stageStart.back());

    AmdCullKernel kernel;
    kernel.depth = depth;
    kernel.lights = lightsViewLh;
    kernel.inverseProjection = inverseProjection;
    kernel.options = options;
    kernel.out = &out;
    kernel.bins = bins;
    kernel.staging = staging.data();
    kernel.stageStart = stageStart.data();
    compute::DispatchDesc desc;
    desc.order = options.order;
    compute::dispatch(kernel, glm::uvec3(out.tileCount, 1u), desc);

    // gLightIdxCounter's reservations in row-major group order: count + countFar entries for a
    // tile with lights (A, then B; uint32 arithmetic, as InterlockedAdd), offset 0 for an empty list.
    std::uint32_t next = 0;
    for (std::size_t t = 0; t < tiles; ++t) {
        const std::uint32_t count = out.tileLightCount[t], countFar = halfZ ? out.tileLightCountFar[t] : 0u;
        std::uint32_t start = 0;
        if (count + countFar != 0) {
            start = next;
            next += count + countFar;
        }
        if (halfZ) out.tileOffsetFar[t] = countFar != 0 ? start + count : 0u;
        out.tileOffset[t] = count == 0 ? 0u : start;
    }
    out.lightIndices.resize(next);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tiles, 64), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t t = r.begin(); t < r.end(); ++t) {
            const std::uint32_t* slice = staging.data() + stageStart[t];
            const std::uint32_t count = out.tileLightCount[t];
            std::copy(slice, slice + count, out.lightIndices.begin() + out.tileOffset[t]);
            if (halfZ && out.tileLightCountFar[t] != 0)
                std::copy(slice + count, slice + count + out.tileLightCountFar[t], out.lightIndices.begin() + out.tileOffsetFar[t]);
        }
    });
    for (std::size_t t = 0; t < tiles; ++t) {
        if (out.tileFoundCount[t] > kAmdLightCapacity) {
            ++out.overflowTiles;
            out.droppedLights += out.tileFoundCount[t] - kAmdLightCapacity;
        }
        if (halfZ && out.tileFoundCountFar[t] > kAmdLightCapacity) {
            ++out.overflowTilesFar;
            out.droppedLightsFar += out.tileFoundCountFar[t] - kAmdLightCapacity;
        }
    }
    return out;
}

}  // namespace

std::vector<AmdTileLightLists> cullTilesAmd(std::span<const DepthImageView> depth, std::span<const glm::vec4> lightsViewLh,
                                            const glm::mat4& inverseProjection, std::span<const AmdCullingOptions> passes) {
    if (depth.empty() || depth.size() > 8) throw std::invalid_argument("cullTilesAmd: 1 to 8 depth samples per pixel");
    for (const DepthImageView& d : depth)
        if (d.width == 0 || d.height == 0 || d.depth.size() < std::size_t{d.width} * d.height || d.width != depth[0].width ||
            d.height != depth[0].height)
            throw std::invalid_argument("cullTilesAmd: a depth sample image is empty, smaller than width x height or of another size");
    const glm::uvec2 windowPx(depth[0].width, depth[0].height);
    // The binning depends on the lights, the projection and the tile corners only: one per
    // corner convention, shared by the passes that use it.
    std::array<std::optional<AmdLightBins>, 2> binsByCorners;
    std::vector<AmdTileLightLists> out;
    for (const AmdCullingOptions& options : passes) {
        const AmdLightBins* bins = nullptr;
        if (options.lightLoop == AmdLightLoop::Binned) {
            std::optional<AmdLightBins>& slot = binsByCorners[options.corners == AmdTileCorners::Screen ? 0 : 1];
            if (!slot)
                slot = binLightsAmd(lightsViewLh, tileCount(windowPx, kAmdTileSizePx), windowPx, inverseProjection, options.corners);
            bins = &*slot;
        }
        out.push_back(cullPass(depth, lightsViewLh, inverseProjection, options, bins));
    }
    return out;
}

std::vector<AmdTileLightLists> cullTilesAmd(const DepthImageView& depth, std::span<const glm::vec4> lightsViewLh,
                                            const glm::mat4& inverseProjection, std::span<const AmdCullingOptions> passes) {
    return cullTilesAmd(std::span<const DepthImageView>(&depth, 1), lightsViewLh, inverseProjection, passes);
}

AmdTileLightLists cullTilesAmd(const DepthImageView& depth, std::span<const glm::vec4> lightsViewLh,
                               const glm::mat4& inverseProjection, const AmdCullingOptions& options) {
    return std::move(cullTilesAmd(depth, lightsViewLh, inverseProjection, std::span<const AmdCullingOptions>(&options, 1)).front());
}

}  // namespace tessera
