// forward-plus's CS_main as the demo writes it (ForwardPlusRendering.hlsl): one thread group per
// tile, group-shared depth range and light lists, InterlockedAdd offsets; run by "culling":
// "brute" over every light through compute::dispatch, the reference the row-parallel path matches.
#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <tbb/parallel_for.h>

#include <tessera/compute/dispatch.h>
#include <tessera/culling/frustum.h>
#include <tessera/culling/tile_depth_range.h>

#include "forward_plus_detail.h"

namespace tessera::forward_plus_detail {
namespace {

// ----- CS_main: the light culling (3dgep article §4.3–§4.5; demo ForwardPlusRendering.hlsl) -------

struct CullShared {
    std::uint32_t uMinDepth, uMaxDepth;  // groupshared, asuint of the depth-buffer values
    Frustum groupFrustum;                // groupshared Frustum GroupFrustum
    std::uint32_t oLightCount, oLightIndexStartOffset;
    std::uint32_t tLightCount, tLightIndexStartOffset;
    float minDepthVS, maxDepthVS, nearClipVS;  // per-thread uniform values in the HLSL
};

template <std::uint32_t kBlock>
struct CullLightsKernel {
    static constexpr glm::uvec3 groupSize{kBlock, kBlock, 1};
    static constexpr std::uint32_t kThreads = kBlock * kBlock;
    using Shared = CullShared;

    std::span<const DepthImageView> depth;  // DepthTextureVS (the pre-pass depth, D24 decoded), per MSAA sample
    const Frustum* frustums = nullptr;    // in_Frustums
    std::span<const ViewLight<float>> lights;  // Lights
    const float* coneRadius = nullptr;         // per light: tan(radians(SpotlightAngle)) * Range, as CS_main computes it
    const std::vector<std::vector<BinnedLight>>* rows = nullptr;  // candidate lights per tile row
    glm::vec2 screenDimensions{0.0f};
    glm::mat4 inverseProjection{1.0f};
    bool coneCorrected = false;
    std::uint32_t localCapacity = kForwardPlusLocalListCapacity;  // entries of o_ / t_LightList
    GlobalList opaque, transparent;
    // RWTexture2D<float4> DebugTexture: written by the "heatmap" pass from the opaque grid
    // (writeHeatMap), the same texels this kernel's last phase writes in the demo.

    bool sphereIn(const Sphere& sphere, const CullShared& s, bool& opaqueToo) const {
        if (!sphereInsideFrustum(sphere, s.groupFrustum, s.nearClipVS, s.maxDepthVS)) return false;
        opaqueToo = !sphereInsidePlane(sphere, nearPlane3dgep(s.minDepthVS));  // minPlane
        return true;
    }
    bool coneIn(const Cone& cone, const CullShared& s, bool& opaqueToo) const {
        const Plane minPlane = nearPlane3dgep(s.minDepthVS);
        if (coneCorrected) {
            if (!coneInsideFrustumCorrected(cone, s.groupFrustum, s.nearClipVS, s.maxDepthVS)) return false;
            opaqueToo = !coneInsidePlaneCorrected(cone, minPlane);
        } else {
            if (!coneInsideFrustum(cone, s.groupFrustum, s.nearClipVS, s.maxDepthVS)) return false;
            opaqueToo = !coneInsidePlane(cone, minPlane);
        }
        return true;
    }

    void operator()(compute::GroupContext<Shared>& g) const {
        CullShared& s = g.shared();
        const glm::uvec2 groupId(g.groupId());
        const std::uint32_t tilesX = g.groupCount().x;
        const std::vector<BinnedLight>& candidates = (*rows)[groupId.y];
        // groupshared o_LightList / t_LightList: the demo's 1024 entries, or (unbounded) room for
        // every candidate of the tile. Per worker thread; a group runs to its end on one thread.
        static thread_local std::vector<std::uint32_t> oLightList, tLightList;
        const std::size_t listSize = std::min<std::size_t>(localCapacity, candidates.size());
        if (oLightList.size() < listSize) oLightList.resize(listSize);
        if (tLightList.size() < listSize) tLightList.resize(listSize);

        g.forOneThread(0, [&](const compute::ThreadIds&) {
            s.uMinDepth = 0xFFFFFFFFu;
            s.uMaxDepth = 0;
            s.oLightCount = 0;
            s.tLightCount = 0;
            s.groupFrustum = frustums[groupId.x + std::size_t{groupId.y} * tilesX];
        });
        // Every thread: uDepth = asuint(DepthTextureVS.Load(texCoord)); InterlockedMin/Max. Only
        // commutative min/max reach the shared values, so tileDepthRange3dgep's loop over the
        // tile's pixels (out-of-screen loads 0) gives the same bits (culling/tile_depth_range.h).
        g.forOneThread(0, [&](const compute::ThreadIds&) {
            const TileDepthRange3dgep range = tileDepthRange3dgep(depth, groupId, kBlock, screenDimensions, inverseProjection);  // every sample
            s.uMinDepth = std::bit_cast<std::uint32_t>(range.minDepth);
            s.uMaxDepth = std::bit_cast<std::uint32_t>(range.maxDepth);
            s.minDepthVS = range.minDepthVS;
            s.maxDepthVS = range.maxDepthVS;
            s.nearClipVS = range.nearClipVS;
        });
        // for (i = groupIndex; i < NUM_LIGHTS; i += BLOCK_SIZE * BLOCK_SIZE) over the tile's
        // candidates (all enabled lights with culling brute), in ascending light index.
        const auto append = [&](std::uint32_t& count, std::vector<std::uint32_t>& list, std::uint32_t lightIndex) {
            const std::uint32_t index = count++;  // InterlockedAdd(o_LightCount, 1, index)
            if (index < localCapacity) list[index] = lightIndex;
        };
        g.forEachStrided(static_cast<std::uint32_t>(candidates.size()), [&](const compute::ThreadIds&, std::uint32_t k) {
            const BinnedLight& candidate = candidates[k];
            if (groupId.x < candidate.x0 || groupId.x > candidate.x1) return;  // fails the test below (binning)
            const std::uint32_t i = candidate.light;
            const ViewLight<float>& light = lights[i];
            if (!light.enabled) return;
            bool opaqueToo = false;
            switch (light.type) {
            case LightType::Point: {
                const Sphere sphere{glm::vec3(light.positionView), light.range};
                if (!sphereIn(sphere, s, opaqueToo)) return;
                break;
            }
            case LightType::Spot: {
                const Cone cone{glm::vec3(light.positionView), light.range, glm::vec3(light.directionView), coneRadius[i]};
                if (!coneIn(cone, s, opaqueToo)) return;
                break;
            }
            case LightType::Directional: opaqueToo = true; break;  // always added
            case LightType::Capsule: return;  // disabled by viewLights: never reaches here
            }
            append(s.tLightCount, tLightList, i);
            if (opaqueToo) append(s.oLightCount, oLightList, i);
        });
        // if (groupIndex == 0): InterlockedAdd(o_LightIndexCounter[0], o_LightCount, offset);
        // o_LightGrid[groupID.xy] = uint2(offset, o_LightCount); the same for t_.
        g.forOneThread(0, [&](const compute::ThreadIds&) {
            const std::size_t tile = groupId.x + std::size_t{groupId.y} * tilesX;
            s.oLightIndexStartOffset = opaque.counter->reserve(g, s.oLightCount);
            storeUint32(opaque.grid, tile * 2, s.oLightIndexStartOffset);
            storeUint32(opaque.grid, tile * 2 + 1, s.oLightCount);
            s.tLightIndexStartOffset = transparent.counter->reserve(g, s.tLightCount);
            storeUint32(transparent.grid, tile * 2, s.tLightIndexStartOffset);
            storeUint32(transparent.grid, tile * 2 + 1, s.tLightCount);
            opaque.tally->add(s.oLightCount, localCapacity, s.oLightIndexStartOffset, opaque.capacity);
            transparent.tally->add(s.tLightCount, localCapacity, s.tLightIndexStartOffset, transparent.capacity);
        });
        // for (i = groupIndex; i < o_LightCount; i += 256) o_LightIndexList[offset + i] = o_LightList[i]:
        // reads past the local list give 0, writes past the global list are discarded.
        const auto copy = [&](const GlobalList& global, std::uint32_t count, std::uint32_t offset,
                              const std::vector<std::uint32_t>& list) {
            g.forEachStrided(count, [&](const compute::ThreadIds&, std::uint32_t i) {
                const std::uint32_t at = offset + i;  // uint arithmetic, as in HLSL
                if (at < global.capacity) storeUint32(global.indexList, at, i < localCapacity ? list[i] : 0u);
            });
        };
        copy(opaque, s.oLightCount, s.oLightIndexStartOffset, oLightList);
        copy(transparent, s.tLightCount, s.tLightIndexStartOffset, tLightList);
    }
};

} // namespace

template <std::uint32_t kBlock>
void cullLightsBrute(const ForwardPlusState& st, Device& device, const CullScratch& sc, const Surface& depthSurface,
                     std::uint32_t localCapacity, const GlobalList& opaque, const GlobalList& transparent) {
    const glm::uvec2 tiles = st.tiles;
    const std::span<const ViewLight<float>> lights = st.setup->lightsExact;
    const std::uint32_t width = st.setup->width, height = st.setup->height;
    const std::vector<Frustum>& frustums = sc.frustums;
    compute::OrderedCounter& opaqueCounter = *opaque.counter;
    compute::OrderedCounter& transparentCounter = *transparent.counter;
    // The demo's loop as a thread-group dispatch (the reference the binned path is checked
    // against): DepthTextureVS as the SRV (R24_UNORM_X8) loads it, every light per row.
    const std::uint32_t samples = depthSurface.sampleCount();
    std::vector<std::vector<float>> depth(samples, std::vector<float>(std::size_t{width} * height));
    std::vector<DepthImageView> depthViews;
    for (const std::vector<float>& d : depth) depthViews.push_back(DepthImageView{d, width, height});
    std::vector<std::vector<BinnedLight>> rows(tiles.y);
    std::vector<float> coneRadius(lights.size());
    for (std::size_t i = 0; i < lights.size(); ++i) coneRadius[i] = sc.lights[i].coneRadius;
    device.execute([&] {
        tbb::parallel_for(std::uint32_t(0), height, [&](std::uint32_t y) {
            for (std::uint32_t i = 0; i < samples; ++i)
                for (std::uint32_t x = 0; x < width; ++x) depth[i][std::size_t{y} * width + x] = depthSurface.loadDepth(x, y, i);
        });
        tbb::parallel_for(std::uint32_t(0), tiles.y, [&](std::uint32_t ty) {
            for (std::size_t i = 0; i < lights.size(); ++i)
                if (sc.rects[i].x0 <= sc.rects[i].x1 && sc.rects[i].y0 <= ty && ty <= sc.rects[i].y1)
                    rows[ty].push_back({std::uint32_t(i), sc.rects[i].x0, sc.rects[i].x1});
        });
    });
    CullLightsKernel<kBlock> kernel;
    kernel.depth = depthViews;
    kernel.frustums = frustums.data();
    kernel.lights = lights;
    kernel.coneRadius = coneRadius.data();
    kernel.rows = &rows;
    kernel.screenDimensions = st.screenDimensions;
    kernel.inverseProjection = st.inverseProjection;
    kernel.coneCorrected = st.options.coneCorrected;
    kernel.localCapacity = localCapacity;
    kernel.opaque = opaque;
    kernel.transparent = transparent;
    const std::array<compute::OrderedCounter*, 2> counters{&opaqueCounter, &transparentCounter};
    device.execute([&] {
        compute::dispatch(kernel, glm::uvec3(tiles.x, tiles.y, 1), compute::DispatchDesc{compute::GroupOrder::Parallel, counters});
    });
}

template void cullLightsBrute<8>(const ForwardPlusState&, Device&, const CullScratch&, const Surface&, std::uint32_t,
                                 const GlobalList&, const GlobalList&);
template void cullLightsBrute<16>(const ForwardPlusState&, Device&, const CullScratch&, const Surface&, std::uint32_t,
                                  const GlobalList&, const GlobalList&);
template void cullLightsBrute<32>(const ForwardPlusState&, Device&, const CullScratch&, const Surface&, std::uint32_t,
                                  const GlobalList&, const GlobalList&);

} // namespace tessera::forward_plus_detail
