// The `forward-plus` technique (3dgep article §4; the demo's g_ForwardPlusTechnique in its main.cpp and
// ForwardPlusRendering.hlsl): clear -> depth pre-pass -> CS_ComputeFrustums -> CS_main (light
// culling: row-parallel, or with culling "brute" emulated with compute::dispatch) -> heat map
// (CS_main's DebugTexture) -> opaque pass -> transparent pass, the last two through forward's
// passes with the tile's light list (forward.h ForwardPassOverrides).
#include <tessera/techniques/forward_plus.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <tessera/buffers/conversion.h>
#include <tessera/compute/dispatch.h>
#include <tessera/compute/ordered_counter.h>
#include <tessera/errors/input_error.h>
#include <tessera/math/det_math.h>
#include <tessera/culling/frustum.h>
#include <tessera/culling/tile_depth_range.h>
#include <tessera/culling/tile_frustum.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/technique_options.h>

#include "tile_binning.h"

namespace tessera {
namespace {

constexpr std::uint32_t kMaxSurfaceEdge = 16384;  // D3D11_REQ_TEXTURE2D_U_OR_V_DIMENSION, texels
// LightCountHeatMap's u = o_LightCount / 50.0f (ForwardPlusRendering.hlsl CS_main).
constexpr float kHeatMapFullScale = 50.0f;  // lights at the gradient's end

struct ForwardPlusOptions {
    ProjectionConvention projection = ProjectionConvention::DemoGl;
    PhongSamplerChoice sampler = PhongSamplerChoice::Demo;
    bool alphaTest = false;
    bool unbounded = false;      // "lightLists": "unbounded"
    bool coneCorrected = false;  // "coneTest": "corrected"
    bool brute = false;          // "culling": "brute"
    std::uint32_t tileSizePx = 16;
};

ForwardPlusOptions parseOptions(const TechniqueContext& ctx, const std::string& file) {
    ForwardPlusOptions o;
    o.projection = optionEnum(ctx.options, "projection", {"demo-gl", "d3d"}, "demo-gl", file) == "d3d"
                       ? ProjectionConvention::D3d
                       : ProjectionConvention::DemoGl;
    o.sampler = optionEnum(ctx.options, "sampler", {"demo", "gltf"}, "demo", file) == "gltf" ? PhongSamplerChoice::Gltf
                                                                                               : PhongSamplerChoice::Demo;
    o.alphaTest = optionBool(ctx.options, "alphaTest", false, file);
    o.unbounded = optionEnum(ctx.options, "lightLists", {"demo", "unbounded"}, "demo", file) == "unbounded";
    o.coneCorrected = optionEnum(ctx.options, "coneTest", {"demo", "corrected"}, "demo", file) == "corrected";
    o.brute = optionEnum(ctx.options, "culling", {"binned", "brute"}, "binned", file) == "brute";
    if (ctx.options.is_object() && ctx.options.contains("tileSize")) {
        const nlohmann::json& v = ctx.options["tileSize"];
        if (!v.is_number_integer() || (v.get<std::int64_t>() != 8 && v.get<std::int64_t>() != 16 && v.get<std::int64_t>() != 32))
            throw inputError(file, "/options/tileSize", "expected 8, 16 or 32 (tile edge in px)");
        o.tileSizePx = static_cast<std::uint32_t>(v.get<std::int64_t>());
    }
    return o;
}

// ----- Light-list storage shared by the passes of one frame --------------------------------------

struct CullScratch;  // the culling's buffers (below)

// What the culling pass hands the shading passes (besides the named buffers themselves).
struct ForwardPlusState {
    ForwardPlusOptions options;
    std::shared_ptr<ForwardPassSetup> setup;
    glm::uvec2 tiles{0};               // tilesX, tilesY
    glm::mat4 inverseProjection{1.0f};  // ScreenToViewParams.InverseProjection = inverse(projection)
    glm::vec2 screenDimensions{0.0f};   // ScreenToViewParams.ScreenDimensions, px
    bool orthographic = false;          // the camera's projection (tile planes: gridFrustumOrthographic)
    TileLightList opaqueList, transparentList;  // bound by the opaque / transparent passes
    std::shared_ptr<CullScratch> scratch;        // the culling's buffers, kept from frame to frame
};

void storeUint32(std::byte* base, std::size_t element, std::uint32_t value) {
    std::memcpy(base + element * sizeof(std::uint32_t), &value, sizeof(value));
}

// A flat R32_UINT list of `capacity` entries as a surface: W = min(capacity, 16384) per row.
SurfaceDesc indexListDesc(std::uint64_t capacity) {
    const std::uint64_t entries = std::max<std::uint64_t>(capacity, 1);
    const std::uint64_t width = std::min<std::uint64_t>(entries, kMaxSurfaceEdge);
    const std::uint64_t height = (entries + width - 1) / width;
    if (height > kMaxSurfaceEdge)
        throw std::runtime_error("forward-plus: a light index list of " + std::to_string(capacity) +
                                 " entries exceeds a 16384 x 16384 R32_UINT buffer");
    return {static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height), Format::R32_UINT, 1};
}

// ----- CS_ComputeFrustums (3dgep article §4.2) ---------------------------------------------------
// One thread per tile, BLOCK_SIZE x BLOCK_SIZE threads per group, ceil(tiles / BLOCK_SIZE) groups;
// threads past numThreads (= tiles) write nothing.
template <std::uint32_t kBlock>
struct ComputeFrustumsKernel {
    static constexpr glm::uvec3 groupSize{kBlock, kBlock, 1};
    using Shared = compute::NoShared;
    glm::uvec2 numThreads{0};  // DispatchParams.numThreads: tiles per axis
    glm::vec2 screenDimensions{0.0f};
    glm::mat4 inverseProjection{1.0f};
    bool orthographic = false;  // planes through near and far corners (gridFrustumOrthographic)
    Frustum* outFrustums = nullptr;  // RWStructuredBuffer<Frustum> out_Frustums, x + y * numThreads.x
    void operator()(compute::GroupContext<Shared>& g) const {
        g.forEachThread([&](const compute::ThreadIds& t) {
            if (t.dispatchThreadId.x < numThreads.x && t.dispatchThreadId.y < numThreads.y) {
                const std::size_t index = t.dispatchThreadId.x + std::size_t{t.dispatchThreadId.y} * numThreads.x;
                outFrustums[index] =
                    orthographic ? gridFrustumOrthographic(glm::uvec2(t.dispatchThreadId), kBlock, screenDimensions, inverseProjection,
                                                           0.0f, 1.0f)
                                 : gridFrustum3dgep(glm::uvec2(t.dispatchThreadId), kBlock, screenDimensions, inverseProjection);
            }
        });
    }
};

// ----- Tessera's binning pre-pass (not in the demo) ---------------------------------------------
// For each light, the tile columns and rows outside which the kernel's test cannot pass
// (tile_binning.h): binary search with a padded sphere test against the column and row planes,
// or, for a sphere reaching the eye's plane, every column and row tested. Before that case was
// added, such lights could lose tiles the kernel keeps, in the transparent lists (16384 small
// Sponza lights: mean 106.86 instead of brute's 108.91). A spot light is bounded by
// coneBoundingSphere, which contains both points ConeInsidePlane tests. Non-finite values never
// exclude.
using LightTileRect = binning::TileRuns;

struct BinnedLight {
    std::uint32_t light;   // index in the scene's light list
    std::uint32_t x0, x1;  // tile columns, inclusive
};

struct BoundingSphere {
    glm::dvec3 c{0.0};
    double r = 0.0;
    double pad = 0.0;  // binning::padFor(c, r)
};

// The sphere around a cone's tip and base disc, in double: centre T + d h / 2, radius
// sqrt((h |d| / 2)^2 + (r |m|max)^2), where |m|max bounds the offset of ConeInsidePlane's Q from
// the base centre in units of r: |cross(cross(N, d), d)| <= |d|^2 for a unit N (the faithful
// test), 1 for the corrected one; 1e-6 more covers N's rounding. It holds T and both tests' Q.
BoundingSphere coneBoundingSphere(const Cone& cone) {
    const glm::dvec3 T(cone.T), d(cone.d);
    const double h = double(cone.h), dLength = glm::length(d);
    BoundingSphere s;
    s.c = T + d * (h * 0.5);
    const double mReach = double(std::abs(cone.r)) * std::max(1.0, dLength * dLength) * (1.0 + 1e-6);
    s.r = std::sqrt(0.25 * h * h * dLength * dLength + mReach * mReach);
    s.pad = binning::padFor(s.c, s.r);
    return s;
}

// The padded "sphere wholly in the negative half-space" (plane.h sphereInsidePlane), in double.
bool paddedInside(const BoundingSphere& s, const Plane& plane) {
    const double distance = (double(plane.N.x) * s.c.x + double(plane.N.y) * s.c.y) + double(plane.N.z) * s.c.z - double(plane.d);
    return distance < -(s.r + s.pad);
}

// The binning of a point light (bound: its sphere) or a spot light (bound: coneBoundingSphere).
LightTileRect lightTileRect(const ViewLight<float>& light, const BoundingSphere& s, const std::vector<Frustum>& frustums,
                            glm::uvec2 tiles, float nearClipVS) {
    LightTileRect rect;
    if (!light.enabled) return rect;
    if (light.type == LightType::Directional) return LightTileRect::all(tiles);
    if (s.c.z - s.r > double(nearClipVS) + s.pad) return rect;  // wholly behind the near clip plane
    const auto plane = [&](std::uint32_t tx, std::uint32_t ty, int i) -> const Plane& {
        return frustums[tx + std::size_t{ty} * tiles.x].planes[std::size_t(i)];
    };
    // Planes 0..3: left, right, top, bottom, normals into the tile.
    const auto keptColumn = [&](std::uint32_t tx) { return !paddedInside(s, plane(tx, 0, 0)) && !paddedInside(s, plane(tx, 0, 1)); };
    const auto keptRow = [&](std::uint32_t ty) { return !paddedInside(s, plane(0, ty, 2)) && !paddedInside(s, plane(0, ty, 3)); };
    if (s.c.z + s.r + s.pad >= 0.0) {  // reaches the eye's plane z = 0
        binning::scanRuns(tiles.x, keptColumn, rect.x0, rect.x1, rect.x2, rect.x3);
        binning::scanRuns(tiles.y, keptRow, rect.y0, rect.y1, rect.y2, rect.y3);
        return rect.empty() ? LightTileRect{} : rect;
    }
    // Wholly in front of the eye: inside(right plane of tx) holds for tx left of the sphere;
    // inside(left plane) for tx right of it. Rows: inside(bottom plane of ty) above the sphere,
    // inside(top) below it.
    const bool columns = binning::searchRun(
        tiles.x, [&](std::uint32_t tx) { return !paddedInside(s, plane(tx, 0, 1)); },
        [&](std::uint32_t tx) { return !paddedInside(s, plane(tx, 0, 0)); }, rect.x0, rect.x1);
    const bool rows = binning::searchRun(
        tiles.y, [&](std::uint32_t ty) { return !paddedInside(s, plane(0, ty, 3)); },
        [&](std::uint32_t ty) { return !paddedInside(s, plane(0, ty, 2)); }, rect.y0, rect.y1);
    return columns && rows ? rect : LightTileRect{};
}

// ----- CS_main: the light culling (3dgep article §4.3–§4.5; demo ForwardPlusRendering.hlsl) -------

struct CullShared {
    std::uint32_t uMinDepth, uMaxDepth;  // groupshared, asuint of the depth-buffer values
    Frustum groupFrustum;                // groupshared Frustum GroupFrustum
    std::uint32_t oLightCount, oLightIndexStartOffset;
    std::uint32_t tLightCount, tLightIndexStartOffset;
    float minDepthVS, maxDepthVS, nearClipVS;  // per-thread uniform values in the HLSL
};

struct OverflowTally {
    std::atomic<std::uint64_t> tilesOverLocal{0}, droppedLocal{0}, tilesOverGlobal{0}, droppedGlobal{0};
    std::atomic<std::uint32_t> maxTileCount{0}, nonEmptyTiles{0};

    void add(std::uint32_t count, std::uint32_t localCapacity, std::uint32_t offset, std::uint64_t globalCapacity) {
        if (count > localCapacity) {
            tilesOverLocal.fetch_add(1, std::memory_order_relaxed);
            droppedLocal.fetch_add(count - localCapacity, std::memory_order_relaxed);
        }
        const std::uint64_t end = std::uint64_t{offset} + count;
        if (count > 0 && end > globalCapacity) {
            tilesOverGlobal.fetch_add(1, std::memory_order_relaxed);
            droppedGlobal.fetch_add(std::min<std::uint64_t>(count, end - std::max<std::uint64_t>(globalCapacity, offset)),
                                    std::memory_order_relaxed);
        }
        std::uint32_t seen = maxTileCount.load(std::memory_order_relaxed);
        while (count > seen && !maxTileCount.compare_exchange_weak(seen, count, std::memory_order_relaxed)) {}
        if (count > 0) nonEmptyTiles.fetch_add(1, std::memory_order_relaxed);
    }
    LightListCounters counters(std::uint32_t requested, std::uint64_t capacity) const {
        const auto clamp32 = [](std::uint64_t v) { return static_cast<std::uint32_t>(std::min<std::uint64_t>(v, 0xFFFFFFFFu)); };
        return {requested,         clamp32(capacity),
                clamp32(tilesOverLocal.load()), clamp32(droppedLocal.load()),
                clamp32(tilesOverGlobal.load()), clamp32(droppedGlobal.load()),
                maxTileCount.load(), nonEmptyTiles.load()};
    }
};

// One light list's global side: RWStructuredBuffer<uint> o_LightIndexList, o_LightIndexCounter
// and RWTexture2D<uint2> o_LightGrid (and the t_ equivalents).
struct GlobalList {
    std::byte* indexList = nullptr;
    std::uint64_t capacity = 0;  // entries
    std::byte* grid = nullptr;   // tilesX x tilesY (offset, count)
    compute::OrderedCounter* counter = nullptr;
    OverflowTally* tally = nullptr;
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

// ----- Tessera's row-parallel culling ("culling": "binned") --------------------------------------
// The same tests in the same order as CullLightsKernel, so the same lists, grids and counters
// ("culling": "brute" runs the kernel over every light; tests/unit/forward_plus_test.cpp and
// tests/golden/forward_plus_scenes_test.cpp compare the two), organised for a CPU:
//  1. per tile, CS_main's depth range from the D24 codes: the min / max of asuint over the
//     decoded floats is the decode of the min / max code, because d24ToDepth is a correctly
//     rounded c / (2^24 - 1) (monotone) and non-negative floats order as their bits; an edge
//     tile's off-screen threads load 0.0f, the smallest value (culling/tile_depth_range.h);
//  2. per light, its tile rectangle (lightTileRect), and the lights bucketed by tile row in
//     ascending index;
//  3. per tile row, in parallel: each light of the row against each tile of its columns,
//     appended to the tile's slice of the row's list in ascending light index with an unclamped
//     count (the group-shared InterlockedAdd of the strided loop, dispatch.h order rule 2);
//  4. the global offsets the OrderedCounter hands out: the row-major exclusive prefix sum of
//     the counts in uint32 arithmetic (InterlockedAdd wraps), with the overflow tally;
//  5. per tile row, in parallel: the grid and the copy to the global list with the kernel's
//     rules (entries past the local capacity read 0, writes past the global list discarded).
// Nothing is allocated per tile; the scratch below lives with the technique and only grows.
// ----- Spot lights: the cone tests with per-light terms ---------------------------------------
// The same booleans as coneInsideFrustum[Corrected] + the opaque minPlane test, cheaper:
//  - the near plane {(0, 0, -1), -nearClipVS} is the same for every tile: tested once per light;
//  - the far plane {(0, 0, 1), maxDepthVS} and minPlane {(0, 0, -1), -minDepthVS} differ per
//    tile only in d, and ConeInsidePlane's Q depends only on N: dot(N, T) and dot(N, Q) are
//    computed once, then pointInsidePlane is `dot - d < 0` per tile, the same floats;
//  - a side plane is decided by the cone's bounding sphere (tip and base disc, the sphere
//    lightTileRect bins with) when the sphere lies clearly on one side: signed distance of the
//    centre beyond radius + pad puts T and Q (inside the sphere: |m| <= |d|^2 |N| in the faithful
//    test, |m / |m|| = 1 in the corrected one) on that side, and the pad (relative 2^-10 of
//    |c| + r + |d_plane|, as the binning's) is far above the rounding of the exact test's floats.
//    Otherwise the exact ConeInsidePlane runs.
// tests/golden/forward_plus_scenes_test.cpp (binned = brute, which runs the kernel with
// coneInsideFrustum itself) and tests/unit/forward_plus_test.cpp check the bytes.
struct SpotCullTerms {
    bool nearCulls = false;          // ConeInsidePlane(cone, nearPlane): culled on every tile
    float dotTFar = 0.0f, dotQFar = 0.0f;  // dot((0, 0, 1), T), dot((0, 0, 1), Q)
    float dotTMin = 0.0f, dotQMin = 0.0f;  // dot((0, 0, -1), T), dot((0, 0, -1), Q)
    glm::vec3 boundCentre{0.0f};
    float boundReach = std::numeric_limits<float>::quiet_NaN();  // radius + pad; NaN: always exact
};

SpotCullTerms spotCullTerms(const Cone& cone, const BoundingSphere& bound, bool corrected, float nearClipVS) {
    const auto testPoint = [&](const glm::vec3& N) {
        return corrected ? coneTestPointCorrected(cone, N) : coneTestPoint(cone, N);
    };
    SpotCullTerms t;
    const Plane nearPlane = nearPlane3dgep(nearClipVS);
    t.nearCulls = pointInsidePlane(cone.T, nearPlane) && pointInsidePlane(testPoint(nearPlane.N), nearPlane);
    const glm::vec3 farN(0.0f, 0.0f, 1.0f), minN(0.0f, 0.0f, -1.0f);  // farPlane3dgep / nearPlane3dgep normals
    t.dotTFar = cullmath::dot(farN, cone.T);
    t.dotQFar = cullmath::dot(farN, testPoint(farN));
    t.dotTMin = cullmath::dot(minN, cone.T);
    t.dotQMin = cullmath::dot(minN, testPoint(minN));
    const double reach = bound.r + bound.pad;
    if (std::isfinite(reach) && std::isfinite(bound.c.x) && std::isfinite(bound.c.y) && std::isfinite(bound.c.z) && reach < 1e30) {
        t.boundCentre = glm::vec3(bound.c);
        t.boundReach = static_cast<float>(reach);
    }
    return t;
}

// coneInsidePlane[Corrected](cone, plane) for a tile side plane, decided by the bounding sphere
// where it is clear (SpotCullTerms).
bool coneInsideSidePlane(const Cone& cone, const SpotCullTerms& t, const Plane& plane, bool corrected) {
    const float distance = signedDistance(plane, t.boundCentre);
    const float reach = t.boundReach + static_cast<float>(binning::kPadRelative) * std::abs(plane.d);
    if (distance > reach) return false;
    if (distance < -reach) return true;
    return corrected ? coneInsidePlaneCorrected(cone, plane) : coneInsidePlane(cone, plane);
}

struct CullLight {
    Sphere sphere;                        // Sphere{PositionVS, Range}; a cone's T and h
    glm::vec3 direction{0.0f};            // DirectionVS
    float coneRadius = 0.0f;              // tan(radians(SpotlightAngle)) * Range, as CS_main
    LightType type = LightType::Point;
    std::uint32_t x0 = 1, x1 = 0;         // tile columns, inclusive
    std::uint32_t x2 = 1, x3 = 0;         // a second run of columns (LightTileRect)
    SpotCullTerms spot;                   // spot lights only
};

struct TileCull {
    Frustum frustum;                   // in_Frustums[tile]
    Plane minPlane;                    // {(0, 0, -1), -minDepthVS}
    float maxDepthVS = 0.0f;           // ScreenToView(0, 0, asfloat(uMaxDepth), 1).z
};

struct CullScratch {
    std::vector<Frustum> frustums;
    std::vector<LightTileRect> rects;
    std::vector<CullLight> lights;
    std::vector<TileCull> tiles;
    std::vector<TileDepthBits> depthBits;  // per tile: asuint of uMinDepth, uMaxDepth
    std::vector<std::uint32_t> rowStart, rowCursor, rowLights;  // light indices by tile row (CSR)
    std::vector<std::uint32_t> tileSlice;  // (tilesX + 1) per row: start of each tile's slice
    std::vector<std::uint32_t> oCount, tCount, oOffset, tOffset;
    std::vector<std::vector<std::uint32_t>> rowO, rowT;  // per row: the tiles' o_ / t_LightList
};

// Reads in_Frustums from the "frustums" buffer.
void readFrustums(const Surface& surface, glm::uvec2 tiles, std::vector<Frustum>& out) {
    out.resize(std::size_t{tiles.x} * tiles.y);
    for (std::size_t t = 0; t < out.size(); ++t)
        for (std::size_t i = 0; i < 4; ++i) {
            float plane[4];
            std::memcpy(plane, surface.texel(std::uint32_t(t % tiles.x * 4 + i), std::uint32_t(t / tiles.x)), sizeof(plane));
            out[t].planes[i] = Plane{glm::vec3(plane[0], plane[1], plane[2]), plane[3]};
        }
}

// Step 1 for the tiles of row ty: asuint min / max of DepthTextureVS.Load over each tile.
void tileDepthRow(const Surface& depth, std::uint32_t block, std::uint32_t ty, glm::uvec2 tiles, TileDepthBits* out) {
    const std::uint32_t width = depth.width(), height = depth.height();
    const std::uint32_t y0 = ty * block, y1 = std::min(y0 + block, height);
    const bool rowPartial = y0 + block > height;
    const bool d24 = depth.format() == Format::D24_UNORM_S8_UINT;
    for (std::uint32_t tx = 0; tx < tiles.x; ++tx) {
        const std::uint32_t x0 = tx * block, x1 = std::min(x0 + block, width);
        std::uint32_t lo = 0xFFFFFFFFu, hi = 0;  // D24 codes, or float bits for other formats
        const std::uint32_t samples = depth.sampleCount();  // MSAA: every sample (a row's are contiguous)
        for (std::uint32_t y = y0; y < y1; ++y) {
            const std::byte* texel = depth.texel(x0, y);
            for (std::uint32_t x = x0; x < x1; ++x) {
                for (std::uint32_t i = 0; i < samples; ++i, texel += 4) {
                    std::uint32_t v;
                    if (d24) {
                        std::memcpy(&v, texel, sizeof(v));
                        v &= 0xFFFFFFu;
                    } else {
                        v = std::bit_cast<std::uint32_t>(depth.loadDepth(x, y, i));
                    }
                    lo = std::min(lo, v);
                    hi = std::max(hi, v);
                }
            }
        }
        TileDepthBits bits{d24 ? std::bit_cast<std::uint32_t>(convert::d24ToDepth(lo)) : lo,
                           d24 ? std::bit_cast<std::uint32_t>(convert::d24ToDepth(hi)) : hi};
        if (rowPartial || x0 + block > width) {  // off-screen threads load 0.0f (asuint 0)
            bits.minBits = 0;
        }
        out[tx] = bits;
    }
}

// Runs the culling for one tile size: binning and the row-parallel culling, or (brute) the
// kernel; then the counters.
template <std::uint32_t kBlock>
void cullLights(ForwardPlusState& st, Device& device, BufferRegistry& reg) {
    const glm::uvec2 tiles = st.tiles;
    const std::size_t tileCount = std::size_t{tiles.x} * tiles.y;
    const std::span<const ViewLight<float>> lights = st.setup->lightsExact;
    const std::uint32_t width = st.setup->width, height = st.setup->height;
    if (!st.scratch) st.scratch = std::make_shared<CullScratch>();
    CullScratch& sc = *st.scratch;
    readFrustums(reg.get("frustums"), tiles, sc.frustums);
    const std::vector<Frustum>& frustums = sc.frustums;
    const Surface& depthSurface = reg.get("depth");
    const float nearClipVS = screenToView(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f), st.screenDimensions, st.inverseProjection).z;

    // Per light: the tile rectangle (all tiles with culling brute) and the culling record.
    sc.rects.resize(lights.size());
    sc.lights.resize(lights.size());
    device.execute([&] {
        const LightTileRect all = LightTileRect::all(tiles);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lights.size(), 256), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                const ViewLight<float>& light = lights[i];
                CullLight& c = sc.lights[i];
                c.sphere = Sphere{glm::vec3(light.positionView), light.range};
                c.direction = glm::vec3(light.directionView);
                c.coneRadius = detTan(hlsl::radians(light.spotlightAngleDeg)) * light.range;
                c.type = light.type;
                LightTileRect rect = !light.enabled ? LightTileRect{} : all;
                if (light.enabled && !st.options.brute) {
                    const Cone cone{c.sphere.c, c.sphere.r, c.direction, c.coneRadius};
                    BoundingSphere bound{glm::dvec3(c.sphere.c), double(c.sphere.r), 0.0};
                    if (light.type == LightType::Spot) bound = coneBoundingSphere(cone);
                    else bound.pad = binning::padFor(bound.c, bound.r);
                    rect = lightTileRect(light, bound, frustums, tiles, nearClipVS);
                    if (light.type == LightType::Spot) c.spot = spotCullTerms(cone, bound, st.options.coneCorrected, nearClipVS);
                }
                sc.rects[i] = rect;
                c.x0 = rect.x0;
                c.x1 = rect.x1;
                c.x2 = rect.x2;
                c.x3 = rect.x3;
            }
        });
    });
    std::uint64_t candidatePairs = 0;
    const auto runLength = [](std::uint32_t a, std::uint32_t b) { return a <= b ? std::uint64_t{b - a + 1} : 0u; };
    for (const LightTileRect& r : sc.rects)
        candidatePairs += (runLength(r.x0, r.x1) + runLength(r.x2, r.x3)) * (runLength(r.y0, r.y1) + runLength(r.y2, r.y3));

    // Sizes: the demo's numTiles * 200 with a 1024-entry local list, or (unbounded) the sum over
    // tiles of their candidates, with a local list as long as the tile's candidates.
    std::uint32_t localCapacity = kForwardPlusLocalListCapacity;
    std::uint64_t capacity = std::uint64_t{tileCount} * kForwardPlusAverageLightsPerTile;
    if (st.options.unbounded) {
        localCapacity = static_cast<std::uint32_t>(std::min<std::size_t>(lights.size(), 0xFFFFFFFFu));
        capacity = candidatePairs;
    }

    Surface& gridOpaque = reg.create("lightgrid.opaque", {tiles.x, tiles.y, Format::R32G32_UINT, 1});
    Surface& gridTransparent = reg.create("lightgrid.transparent", {tiles.x, tiles.y, Format::R32G32_UINT, 1});
    Surface& listOpaque = reg.create("lightindex.opaque", indexListDesc(capacity));
    Surface& listTransparent = reg.create("lightindex.transparent", indexListDesc(capacity));
    // New surfaces hold zero bytes: the grids and lists start at 0.

    // o_LightIndexCounter / t_LightIndexCounter, reset to 0 every frame (the demo copies a 0).
    compute::OrderedCounter opaqueCounter(0), transparentCounter(0);
    OverflowTally opaqueTally, transparentTally;
    const GlobalList opaque{listOpaque.bytes().data(), capacity, gridOpaque.bytes().data(), &opaqueCounter, &opaqueTally};
    const GlobalList transparent{listTransparent.bytes().data(), capacity, gridTransparent.bytes().data(),
                                 &transparentCounter, &transparentTally};

    if (st.options.brute) {
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
    } else {
        // Step 2: the lights of each tile row, ascending (CSR).
        sc.rowStart.assign(std::size_t{tiles.y} + 1, 0);
        for (const LightTileRect& r : sc.rects)
            if (r.x0 <= r.x1) {
                for (std::uint32_t ty = r.y0; ty <= r.y1; ++ty) ++sc.rowStart[ty + 1];
                for (std::uint32_t ty = r.y2; ty <= r.y3; ++ty) ++sc.rowStart[ty + 1];
            }
        for (std::uint32_t ty = 0; ty < tiles.y; ++ty) sc.rowStart[ty + 1] += sc.rowStart[ty];
        sc.rowCursor.assign(sc.rowStart.begin(), sc.rowStart.end() - 1);
        sc.rowLights.resize(sc.rowStart.back());
        for (std::size_t i = 0; i < sc.rects.size(); ++i) {
            const LightTileRect& r = sc.rects[i];
            if (r.x0 <= r.x1) {
                for (std::uint32_t ty = r.y0; ty <= r.y1; ++ty) sc.rowLights[sc.rowCursor[ty]++] = std::uint32_t(i);
                for (std::uint32_t ty = r.y2; ty <= r.y3; ++ty) sc.rowLights[sc.rowCursor[ty]++] = std::uint32_t(i);
            }
        }
        sc.tiles.resize(tileCount);
        sc.depthBits.resize(tileCount);
        sc.tileSlice.resize((std::size_t{tiles.x} + 1) * tiles.y);
        sc.oCount.assign(tileCount, 0);
        sc.tCount.assign(tileCount, 0);
        sc.oOffset.resize(tileCount);
        sc.tOffset.resize(tileCount);
        sc.rowO.resize(tiles.y);
        sc.rowT.resize(tiles.y);
        const bool coneCorrected = st.options.coneCorrected;
        // Steps 1 and 3, one tile row per task.
        const auto cullRow = [&](std::uint32_t ty) {
            const std::size_t rowBase = std::size_t{ty} * tiles.x;
            tileDepthRow(depthSurface, kBlock, ty, tiles, sc.depthBits.data() + rowBase);
            for (std::uint32_t tx = 0; tx < tiles.x; ++tx) {
                TileCull& tc = sc.tiles[rowBase + tx];
                const TileDepthBits& bits = sc.depthBits[rowBase + tx];
                tc.frustum = frustums[rowBase + tx];
                const float minDepthVS =
                    screenToView(glm::vec4(0.0f, 0.0f, bits.minValue(), 1.0f), st.screenDimensions, st.inverseProjection).z;
                tc.maxDepthVS = screenToView(glm::vec4(0.0f, 0.0f, bits.maxValue(), 1.0f), st.screenDimensions, st.inverseProjection).z;
                tc.minPlane = nearPlane3dgep(minDepthVS);
            }
            // Each tile's slice: as many entries as the tile has candidates (a difference array
            // over the lights' column ranges, then an exclusive prefix sum).
            std::uint32_t* slice = sc.tileSlice.data() + (std::size_t{tiles.x} + 1) * ty;
            std::fill(slice, slice + tiles.x + 1, 0u);
            for (std::uint32_t k = sc.rowStart[ty]; k < sc.rowStart[ty + 1]; ++k) {
                const CullLight& c = sc.lights[sc.rowLights[k]];
                ++slice[c.x0];
                --slice[c.x1 + 1];  // uint32 wrap-around: the running sum below is exact
                if (c.x2 <= c.x3) {
                    ++slice[c.x2];
                    --slice[c.x3 + 1];
                }
            }
            std::uint32_t running = 0, start = 0;
            for (std::uint32_t tx = 0; tx <= tiles.x; ++tx) {
                running += slice[tx];
                slice[tx] = start;
                start += running;
            }
            std::vector<std::uint32_t>& oList = sc.rowO[ty];
            std::vector<std::uint32_t>& tList = sc.rowT[ty];
            if (oList.size() < start) oList.resize(start);
            if (tList.size() < start) tList.resize(start);
            std::uint32_t* oCount = sc.oCount.data() + rowBase;
            std::uint32_t* tCount = sc.tCount.data() + rowBase;
            for (std::uint32_t k = sc.rowStart[ty]; k < sc.rowStart[ty + 1]; ++k) {
                const std::uint32_t i = sc.rowLights[k];
                const CullLight& c = sc.lights[i];
                const auto cullTile = [&](std::uint32_t tx) {
                    const TileCull& tc = sc.tiles[rowBase + tx];
                    bool opaqueToo = false;
                    switch (c.type) {
                    case LightType::Point:
                        if (!sphereInsideFrustum(c.sphere, tc.frustum, nearClipVS, tc.maxDepthVS)) return;
                        opaqueToo = !sphereInsidePlane(c.sphere, tc.minPlane);
                        break;
                    case LightType::Spot: {  // coneInsideFrustum[Corrected], then the minPlane test
                        const SpotCullTerms& t = c.spot;
                        if (t.nearCulls) return;
                        if (t.dotTFar - tc.maxDepthVS < 0.0f && t.dotQFar - tc.maxDepthVS < 0.0f) return;  // far plane
                        const Cone cone{c.sphere.c, c.sphere.r, c.direction, c.coneRadius};
                        for (const Plane& plane : tc.frustum.planes)
                            if (coneInsideSidePlane(cone, t, plane, coneCorrected)) return;
                        opaqueToo = !(t.dotTMin - tc.minPlane.d < 0.0f && t.dotQMin - tc.minPlane.d < 0.0f);
                        break;
                    }
                    case LightType::Directional: opaqueToo = true; break;  // always added
                    case LightType::Capsule: return;  // not a 3dgep light: never listed
                    }
                    tList[slice[tx] + tCount[tx]++] = i;
                    if (opaqueToo) oList[slice[tx] + oCount[tx]++] = i;
                };
                // The two column runs are disjoint: each tile sees the light once.
                for (std::uint32_t tx = c.x0; tx <= c.x1; ++tx) cullTile(tx);
                for (std::uint32_t tx = c.x2; tx <= c.x3; ++tx) cullTile(tx);
            }
        };
        device.execute([&] { tbb::parallel_for(std::uint32_t(0), tiles.y, cullRow); });
        // Step 4: row-major offsets, as the OrderedCounter reserves them.
        std::uint32_t oNext = 0, tNext = 0;
        for (std::size_t tile = 0; tile < tileCount; ++tile) {
            sc.oOffset[tile] = oNext;
            sc.tOffset[tile] = tNext;
            oNext += sc.oCount[tile];
            tNext += sc.tCount[tile];
            opaqueTally.add(sc.oCount[tile], localCapacity, sc.oOffset[tile], capacity);
            transparentTally.add(sc.tCount[tile], localCapacity, sc.tOffset[tile], capacity);
        }
        opaqueCounter.reset(oNext);
        transparentCounter.reset(tNext);
        // Step 5: grids and global lists.
        const auto copy = [&](const GlobalList& global, std::uint32_t count, std::uint32_t offset, const std::uint32_t* list) {
            for (std::uint32_t i = 0; i < count; ++i) {
                const std::uint32_t at = offset + i;  // uint arithmetic, as in HLSL
                if (at < global.capacity) storeUint32(global.indexList, at, i < localCapacity ? list[i] : 0u);
            }
        };
        device.execute([&] {
            tbb::parallel_for(std::uint32_t(0), tiles.y, [&](std::uint32_t ty) {
                const std::uint32_t* slice = sc.tileSlice.data() + (std::size_t{tiles.x} + 1) * ty;
                for (std::uint32_t tx = 0; tx < tiles.x; ++tx) {
                    const std::size_t tile = std::size_t{ty} * tiles.x + tx;
                    storeUint32(opaque.grid, tile * 2, sc.oOffset[tile]);
                    storeUint32(opaque.grid, tile * 2 + 1, sc.oCount[tile]);
                    storeUint32(transparent.grid, tile * 2, sc.tOffset[tile]);
                    storeUint32(transparent.grid, tile * 2 + 1, sc.tCount[tile]);
                    copy(opaque, sc.oCount[tile], sc.oOffset[tile], sc.rowO[ty].data() + slice[tx]);
                    copy(transparent, sc.tCount[tile], sc.tOffset[tile], sc.rowT[ty].data() + slice[tx]);
                }
            });
        });
    }

    Surface& counterSurface = reg.create("lightlist.counters", {kLightListCounterFields, 2, Format::R32_UINT, 1});
    const std::array<LightListCounters, 2> rowsOut{opaqueTally.counters(opaqueCounter.value(), capacity),
                                                  transparentTally.counters(transparentCounter.value(), capacity)};
    for (std::uint32_t row = 0; row < 2; ++row) {
        static_assert(sizeof(LightListCounters) == kLightListCounterFields * sizeof(std::uint32_t));
        std::memcpy(counterSurface.texel(0, row), &rowsOut[row], sizeof(LightListCounters));
    }
    if (FrameNotes* notes = st.setup->notes)
        for (const LightListCounters& c : rowsOut)
            notes->add({"light-list-overflow", "tile light-list entries lost to the demo's fixed lists (1024 per tile, 200 per tile on average)",
                        std::uint64_t{c.droppedLocal} + c.droppedGlobal, 15, "--option lightLists=unbounded", true});
}

// The "heatmap" pass: the demo's DebugTexture as CS_main's last phase writes it, from the opaque
// grid's counts (o_LightCount): thread rows / columns 0 of a tile (0, 0, 0, 0.9), then rows /
// columns 1 (1, 1, 1, 0.5), else LightCountHeatMap(o_LightCount / 50) for o_LightCount > 0 and
// (0, 0, 0, 1) for 0. Off-screen threads write nothing (no texel there).
void writeHeatMap(Device& device, const Surface& grid, std::uint32_t block, Surface& heatmap) {
    const glm::vec4 edge(0.0f, 0.0f, 0.0f, 0.9f), inner(1.0f, 1.0f, 1.0f, 0.5f);
    const std::uint32_t width = heatmap.width(), height = heatmap.height(), tilesX = grid.width();
    device.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, height, block), [&](const tbb::blocked_range<std::uint32_t>& r) {
            for (std::uint32_t y = r.begin(); y < r.end(); ++y) {
                const std::uint32_t ty = y / block, gy = y % block;
                std::byte* out = heatmap.texel(0, y);
                for (std::uint32_t tx = 0; tx < tilesX; ++tx) {
                    std::uint32_t count;
                    std::memcpy(&count, grid.texel(tx, ty) + sizeof(std::uint32_t), sizeof(count));
                    const glm::vec4 heat = count > 0 ? forwardPlusHeatMapColor(count) : glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
                    const std::uint32_t x0 = tx * block, x1 = std::min(x0 + block, width);
                    for (std::uint32_t x = x0; x < x1; ++x, out += sizeof(glm::vec4)) {
                        const std::uint32_t gx = x - x0;
                        const glm::vec4& color = gx == 0 || gy == 0 ? edge : gx == 1 || gy == 1 ? inner : heat;
                        std::memcpy(out, &color, sizeof(color));
                    }
                }
            }
        });
    });
}

// The depth pre-pass pixel shaders: with kAlphaTest, PS_main's alpha and discard; with kNormal,
// GPU Pro 4 §5.6.2's G-pass output, the unit world normal (PhongVS given worldFromObject as its
// "view": normalView is the world normal, as AMD's shading reads it), w = 1. (Neither: no PS.)
template <bool kAlphaTest, bool kNormal>
struct PrepassPS {
    using Varyings = PhongVaryings;
    static constexpr int kTargetCount = kNormal ? 1 : 0;
    static constexpr bool kMayDiscard = kAlphaTest;
    PhongShadeFn<float> shade = nullptr;
    const PhongShaderData<float>* data = nullptr;
    bool reverseBackFaceNormals = false;  // glTF 2.0 §3.9.5 (facingVaryings)
    void operator()(const PixelInput<PhongVaryings>& in, PixelOutput<kTargetCount>& out) const {
        if constexpr (kAlphaTest) {
            Vec4<float> color;
            if (!shade(*data, in, color)) {
                out.discard();
                return;
            }
        }
        if constexpr (kNormal) {
            const glm::vec3 normalWorld = facingVaryings(in.varyings, in.isFrontFace, reverseBackFaceNormals).normalView;
            out.target[0] = glm::vec4(hlsl::normalize(normalWorld), 1.0f);
        }
    }
};

// The demo's depth pre-pass (g_pDepthPrepassPipeline): the opaque items, VS only, depth LESS with
// writes, the opaque pass's culling (cull back; glTF doubleSided: none). With normalWorld, also
// the G-pass normal (PrepassPS<., true>): the same clip positions, so the same depth.
void drawDepthPrepass(const ForwardPassSetup& setup, Device& device, const SceneResources& res, Surface& depthSurface,
                      DrawStats* stats, Surface* normalWorld = nullptr) {
    RenderTargets rt;
    rt.depthStencil = &depthSurface;
    rt.colors[0] = normalWorld;
    for (const DrawItem& item : res.drawItems()) {
        const PhongMaterial material = phongFromGltf(res.material(item.material));
        if (material.isTransparent()) continue;
        DrawState st;
        st.viewport = Viewport{0.0f, 0.0f, float(setup.width), float(setup.height), 0.0f, 1.0f};
        st.rasterizer.frontCounterClockwise = item.frontCounterClockwise;
        st.rasterizer.cullMode = material.doubleSided ? CullMode::None : CullMode::Back;
        st.precision = setup.precision;  // the opaque pass's LESS_EQUAL needs the same depth path
        const glm::mat4 viewFromObject = setup.viewFromWorld * item.worldFromObject;
        const PhongVS vs{setup.clipFromView * viewFromObject, normalWorld ? item.worldFromObject : viewFromObject};
        const PrimitiveBuffer& prim = res.primitives()[item.primitive];
        const std::span<const SceneVertex> vertices(prim.vertices);
        const PhongVariant variant = selectPhongVariant<float>(phongFeatures(material, setup.alphaTest));
        DrawStats s;
        if (normalWorld) {
            const PhongShaderData<float> data = makePhongShaderData<float>(material, *setup.textures, {});
            const bool reverse = material.reverseBackFaceNormals;
            s = variant.mayDiscard ? device.draw(st, rt, vertices, prim.indices, vs, PrepassPS<true, true>{variant.exact, &data, reverse})
                                   : device.draw(st, rt, vertices, prim.indices, vs, PrepassPS<false, true>{nullptr, nullptr, reverse});
        } else if (variant.mayDiscard) {
            const PhongShaderData<float> data = makePhongShaderData<float>(material, *setup.textures, {});
            s = device.draw(st, rt, vertices, prim.indices, vs, PrepassPS<true, false>{variant.exact, &data});
        } else {
            s = device.draw(st, rt, vertices, prim.indices, vs, NoPixelShader{});
        }
        if (stats) *stats += s;
    }
}

} // namespace

glm::vec4 forwardPlusHeatMapColor(std::uint32_t lightCount) {
    static constexpr std::array<glm::vec4, 5> kGradient{glm::vec4(0.0f, 0.0f, 1.0f, 1.0f), glm::vec4(0.0f, 1.0f, 1.0f, 1.0f),
                                                        glm::vec4(0.0f, 1.0f, 0.0f, 1.0f), glm::vec4(1.0f, 1.0f, 0.0f, 1.0f),
                                                        glm::vec4(1.0f, 0.0f, 0.0f, 1.0f)};
    const float u = float(lightCount) / kHeatMapFullScale;
    // Linear filtering, clamp addressing: texel space t = u * 5 - 0.5, clamped to the end texels.
    const float t = std::clamp(u * float(kGradient.size()) - 0.5f, 0.0f, float(kGradient.size() - 1));
    const float base = std::floor(t);
    const auto i0 = static_cast<std::size_t>(base);
    const std::size_t i1 = std::min(i0 + 1, kGradient.size() - 1);
    const float f = t - base;
    return kGradient[i0] + (kGradient[i1] - kGradient[i0]) * f;
}

ForwardPlusCounters readForwardPlusCounters(const BufferRegistry& registry) {
    const Surface* s = registry.find("lightlist.counters");
    if (!s) throw std::out_of_range("no buffer 'lightlist.counters' (not a forward-plus frame)");
    ForwardPlusCounters c;
    std::memcpy(&c.opaque, s->texel(0, 0), sizeof(LightListCounters));
    std::memcpy(&c.transparent, s->texel(0, 1), sizeof(LightListCounters));
    return c;
}

Frame buildForwardPlus(const TechniqueContext& ctx) {
    const std::string file = ctx.errorFile();
    auto st = std::make_shared<ForwardPlusState>();
    st->options = parseOptions(ctx, file);
    st->setup = makeForwardPassSetup(ctx, st->options.projection, st->options.sampler, st->options.alphaTest);
    const std::uint32_t block = st->options.tileSizePx;
    st->tiles = tileCount(glm::uvec2(ctx.width, ctx.height), block);
    // ScreenToViewParams (3dgep demo's main.cpp): InverseProjection = glm::inverse(projection), ScreenDimensions.
    st->inverseProjection = glm::inverse(st->setup->clipFromView);
    st->screenDimensions = glm::vec2(float(ctx.width), float(ctx.height));
    st->orthographic = ctx.camera.projection == ProjectionKind::Orthographic;

    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;
    std::map<std::string, std::uint64_t>* variantCounts = ctx.variantCounts;
    const SceneResources* res = ctx.resources;
    const std::string back(kBackBufferName);

    Frame frame;
    addForwardPlusClearAndPrepass(frame, st->setup, device, res, stats);
    frame.add({"frustums", {}, {"frustums"}, [st, device](BufferRegistry& reg) {
                   const glm::uvec2 tiles = st->tiles;
                   std::vector<Frustum> frustums(std::size_t{tiles.x} * tiles.y);
                   const auto run = [&]<std::uint32_t kBlock>() {
                       ComputeFrustumsKernel<kBlock> kernel;
                       kernel.numThreads = tiles;
                       kernel.screenDimensions = st->screenDimensions;
                       kernel.inverseProjection = st->inverseProjection;
                       kernel.orthographic = st->orthographic;
                       kernel.outFrustums = frustums.data();
                       const glm::uvec3 groups((tiles.x + kBlock - 1) / kBlock, (tiles.y + kBlock - 1) / kBlock, 1);
                       device->execute([&] { compute::dispatch(kernel, groups, {compute::GroupOrder::Parallel, {}}); });
                   };
                   if (st->options.tileSizePx == 8) run.template operator()<8>();
                   else if (st->options.tileSizePx == 32) run.template operator()<32>();
                   else run.template operator()<16>();
                   Surface& s = reg.create("frustums", {4 * tiles.x, tiles.y, Format::R32G32B32A32_FLOAT, 1});
                   for (std::size_t t = 0; t < frustums.size(); ++t)
                       for (std::size_t i = 0; i < 4; ++i) {
                           const Plane& p = frustums[t].planes[i];
                           const float plane[4] = {p.N.x, p.N.y, p.N.z, p.d};
                           std::memcpy(s.texel(std::uint32_t(t % tiles.x * 4 + i), std::uint32_t(t / tiles.x)), plane, sizeof(plane));
                       }
               }});
    const std::vector<std::string> cullWrites{"lightgrid.opaque", "lightgrid.transparent", "lightindex.opaque",
                                              "lightindex.transparent", "lightlist.counters"};
    frame.add({"light-culling", {"depth", "frustums"}, cullWrites, [st, device](BufferRegistry& reg) {
                   if (st->options.tileSizePx == 8) cullLights<8>(*st, *device, reg);
                   else if (st->options.tileSizePx == 32) cullLights<32>(*st, *device, reg);
                   else cullLights<16>(*st, *device, reg);
               }});
    // The demo's culling CS writes the DebugTexture in its last phase; tessera writes the same
    // texels in a pass of their own, from the opaque grid (writeHeatMap), so that the culling's
    // time is the culling's.
    frame.add({"heatmap", {"lightgrid.opaque"}, {"heatmap"}, [st, device](BufferRegistry& reg) {
                   const Surface& grid = reg.get("lightgrid.opaque");
                   Surface& heatmap =
                       reg.create("heatmap", {st->setup->width, st->setup->height, Format::R32G32B32A32_FLOAT, 1});
                   writeHeatMap(*device, grid, st->options.tileSizePx, heatmap);
               }});
    const auto drawPass = [st, device, stats, variantCounts, res](bool transparentPass) {
        return [st, device, stats, variantCounts, res, transparentPass](BufferRegistry& reg) {
            const ForwardPlusCounters counters = readForwardPlusCounters(reg);
            TileLightList& bound = transparentPass ? st->transparentList : st->opaqueList;
            bound = bindTileLightList(reg, transparentPass, (transparentPass ? counters.transparent : counters.opaque).capacity,
                                      st->options.tileSizePx);
            const RenderTargets rt = forwardPassTargets(*st->setup, reg);
            // Both Forward+ pipelines test LESS_EQUAL: the opaque pass against its own pre-pass
            // depth, the transparent pass without writes (3dgep demo's main.cpp).
            ForwardPassOverrides overrides;
            overrides.depthFunc = ComparisonFunc::LessEqual;
            overrides.tileLights = &bound;
            drawForwardPass(*st->setup, *device, *res, rt, transparentPass, stats, variantCounts, overrides);
        };
    };
    // Precision reference: the listed lights shaded in double into the float copy as well. With
    // MSAA the multisampled targets, resolved last.
    const auto withColors = [&ctx](std::vector<std::string> names) {
        return withBackBufferTargets(withReferenceBuffer(std::move(names), ctx.precision), ctx.sampleCount);
    };
    const std::vector<std::string> colors = withColors({back});
    frame.add({"opaque", withColors({back, "depth", "lightgrid.opaque", "lightindex.opaque", "lightlist.counters"}),
               withColors({back, "depth"}), drawPass(false)});
    frame.add({"transparent",
               withColors({back, "depth", "lightgrid.transparent", "lightindex.transparent", "lightlist.counters"}),
               colors,
               drawPass(true)});
    if (ctx.sampleCount > 1) frame.add(resolveBackBufferPass(ctx.sampleCount, ctx.precision));
    return frame;
}

void addForwardPlusClearAndPrepass(Frame& frame, std::shared_ptr<const ForwardPassSetup> setup, Device* device,
                                   const SceneResources* resources, DrawStats* stats, bool writeNormals) {
    const std::uint32_t samples = setup->sampleCount;
    const std::string back = backBufferTarget(samples), backReference = referenceBufferTarget(samples);
    std::vector<std::string> cleared{back, "depth"};
    if (setup->precision == Precision::Reference) cleared.push_back(backReference);
    if (writeNormals) cleared.emplace_back("gbuffer.normal");
    frame.add({"clear", {}, cleared, [setup, samples, back, backReference, writeNormals](BufferRegistry& reg) {
                   const std::uint32_t w = setup->width, h = setup->height;
                   reg.create(back, {w, h, Format::R8G8B8A8_UNORM, samples}).clearColor(kDemoClearColor);
                   if (setup->precision == Precision::Reference)
                       reg.create(backReference, {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(kDemoClearColor);
                   reg.create("depth", {w, h, Format::D24_UNORM_S8_UINT, samples}).clearDepthStencil(true, 1.0f, true, 0);
                   if (writeNormals)
                       reg.create("gbuffer.normal", {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(glm::vec4(0.0f));
               }});
    std::vector<std::string> prepassIo{"depth"};
    if (writeNormals) prepassIo.emplace_back("gbuffer.normal");
    frame.add({"depth-prepass", prepassIo, prepassIo, [setup, device, resources, stats, writeNormals](BufferRegistry& reg) {
                   drawDepthPrepass(*setup, *device, *resources, reg.get("depth"), stats,
                                    writeNormals ? &reg.get("gbuffer.normal") : nullptr);
               }});
}

} // namespace tessera
