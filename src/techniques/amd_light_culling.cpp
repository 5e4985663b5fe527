// The GPU Pro 4 light-culling kernel (seed 002 §2, §6) as a compute::dispatch kernel: one group of
// 8x8 threads per tile, group-shared depth bounds, 2.5D mask and light list, then the write-back
// into one global pool through an OrderedCounter, so Parallel and Serial give the same bytes.
#include <tessera/techniques/amd_light_culling.h>

#include <tessera/compute/interlocked.h>
#include <tessera/compute/ordered_counter.h>
#include <tessera/math/depth_mask.h>
#include <tessera/math/screen_to_view.h>

#include <algorithm>
#include <array>
#include <bit>
#include <stdexcept>

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

struct AmdCullKernel {
    static constexpr glm::uvec3 groupSize{kAmdTileSizePx, kAmdTileSizePx, 1u};
    using Shared = AmdCullShared;

    const DepthImageView* depth = nullptr;
    std::span<const glm::vec4> lights;
    glm::mat4 inverseProjection{1.0f};
    AmdCullingOptions options;
    AmdTileLightLists* out = nullptr;
    compute::OrderedCounter* poolCounter = nullptr;

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
        const glm::uvec2 windowPx(depth->width, depth->height);
        // Every thread builds the same frustum in the shader; group-uniform here.
        const std::array<glm::vec3, 4> eqn =
            tileSidePlanesAmd(groupId, kAmdTileSizePx, windowPx, inverseProjection, options.corners);
        compute::PerThread<float, kThreadsPerTile> pixelZ;
        compute::PerThread<bool, kThreadsPerTile> pixelValid;

        g.forOneThread(0, [&](const compute::ThreadIds&) {
            s.zMinBits = options.depthConvention == AmdDepthConvention::GpuPro4 ? 0xFFFFFFFFu : 0x7F7FFFFFu;
            s.zMaxBits = 0u;
            s.depthMask = 0u;
            s.lightIdxCounter = 0u;
            s.lightIdxCounterFar = 0u;
        });
        g.forEachThread([&](const compute::ThreadIds& t) {
            const float d = depth->load(t.dispatchThreadId.x, t.dispatchThreadId.y);
            float z = 0.0f;
            pixelValid[t] = viewZ(d, z);
            pixelZ[t] = z;
            if (pixelValid[t]) {
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
                if (pixelValid[t]) compute::interlockedOr(s.depthMask, depthMaskBit(pixelZ[t], minZ, pitch));
            });
        }
        g.forEachStrided(static_cast<std::uint32_t>(lights.size()), [&](const compute::ThreadIds&, std::uint32_t i) {
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
            std::uint32_t startOffset = 0;
            if (count + countFar != 0) startOffset = poolCounter->reserve(g, count + countFar);
            s.lightIdxStart = startOffset;
            s.lightIdxStartFar = countFar != 0 ? startOffset + count : 0u;
            if (halfZ) {
                out->tileOffsetFar[tileIndex] = s.lightIdxStartFar;
                out->tileLightCountFar[tileIndex] = countFar;
                out->tileFoundCountFar[tileIndex] = s.lightIdxCounterFar;
            }
            if (count == 0) startOffset = 0;  // a list with no lights keeps offset 0
            out->tileOffset[tileIndex] = startOffset;  // ptLowerBound[tileIdx]
            out->tileLightCount[tileIndex] = count;
            out->tileFoundCount[tileIndex] = s.lightIdxCounter;
            out->tileMinZBits[tileIndex] = s.zMinBits;
            out->tileMaxZBits[tileIndex] = s.zMaxBits;
            out->tileDepthMask[tileIndex] = s.depthMask;
        });
        const std::uint32_t count = std::min(s.lightIdxCounter, kAmdLightCapacity);
        const std::uint32_t countFar = std::min(s.lightIdxCounterFar, kAmdLightCapacity);
        g.forEachThread([&](const compute::ThreadIds& t) {
            for (std::uint32_t i = t.groupIndex; i < count; i += kThreadsPerTile)
                out->lightIndices[s.lightIdxStart + i] = s.lightIdx[i];
            for (std::uint32_t i = t.groupIndex; i < countFar; i += kThreadsPerTile)
                out->lightIndices[s.lightIdxStartFar + i] = s.lightIdxFar[i];
        });
    }
};

}  // namespace

AmdTileLightLists cullTilesAmd(const DepthImageView& depth, std::span<const glm::vec4> lightsViewLh,
                               const glm::mat4& inverseProjection, const AmdCullingOptions& options) {
    if (depth.width == 0 || depth.height == 0 || depth.depth.size() < std::size_t{depth.width} * depth.height)
        throw std::invalid_argument("cullTilesAmd: the depth buffer is empty or smaller than width x height");
    AmdTileLightLists out;
    out.tileCount = tileCount(glm::uvec2(depth.width, depth.height), kAmdTileSizePx);
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
    // Worst case: every tile (both lists) full. Trimmed to the counter after the dispatch.
    out.lightIndices.assign(tiles * (halfZ ? 2u : 1u) * std::min<std::size_t>(kAmdLightCapacity, lightsViewLh.size()), 0u);

    compute::OrderedCounter poolCounter(0);  // gLightIdxCounter
    compute::OrderedCounter* counters[] = {&poolCounter};
    AmdCullKernel kernel;
    kernel.depth = &depth;
    kernel.lights = lightsViewLh;
    kernel.inverseProjection = inverseProjection;
    kernel.options = options;
    kernel.out = &out;
    kernel.poolCounter = &poolCounter;
    compute::DispatchDesc desc;
    desc.order = options.order;
    desc.orderedCounters = counters;
    compute::dispatch(kernel, glm::uvec3(out.tileCount, 1u), desc);

    out.lightIndices.resize(poolCounter.value());
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

}  // namespace tessera
