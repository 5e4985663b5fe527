// Private to the forward-plus sources (src/techniques/forward_plus*.cpp): the options, the state
// the passes of one frame share, the light binning's records, the light lists' global side, the
// culling's records and scratch, and the functions one file defines for another.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/buffers/surface.h>
#include <tessera/compute/ordered_counter.h>
#include <tessera/culling/frustum.h>
#include <tessera/culling/plane.h>
#include <tessera/culling/tile_depth_range.h>
#include <tessera/frame/buffer_registry.h>
#include <tessera/raster/device.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/forward_plus.h>
#include <tessera/techniques/technique.h>

#include "tile_binning.h"

namespace tessera::forward_plus_detail {

struct ForwardPlusOptions {
    ProjectionConvention projection = ProjectionConvention::DemoGl;
    PhongSamplerChoice sampler = PhongSamplerChoice::Demo;
    bool alphaTest = false;
    bool unbounded = false;      // "lightLists": "unbounded"
    bool coneCorrected = false;  // "coneTest": "corrected"
    bool brute = false;          // "culling": "brute"
    std::uint32_t tileSizePx = 16;
};

// The "options" object (forward_plus.h), checked (forward_plus_options.cpp).
ForwardPlusOptions parseOptions(const TechniqueContext& ctx, const std::string& file);

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

inline void storeUint32(std::byte* base, std::size_t element, std::uint32_t value) {
    std::memcpy(base + element * sizeof(std::uint32_t), &value, sizeof(value));
}

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

// forward_plus_binning.cpp: the bound of a spot light's cone, and a light's tile columns and rows.
BoundingSphere coneBoundingSphere(const Cone& cone);
LightTileRect lightTileRect(const ViewLight<float>& light, const BoundingSphere& s, const std::vector<Frustum>& frustums,
                            glm::uvec2 tiles, float nearClipVS);

// ----- The light lists' global side (CS_main's outputs; both culling paths write them) ----------

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
// coneInsideFrustum itself) and tests/techniques/forward_plus_test.cpp check the bytes.
struct SpotCullTerms {
    bool nearCulls = false;          // ConeInsidePlane(cone, nearPlane): culled on every tile
    float dotTFar = 0.0f, dotQFar = 0.0f;  // dot((0, 0, 1), T), dot((0, 0, 1), Q)
    float dotTMin = 0.0f, dotQMin = 0.0f;  // dot((0, 0, -1), T), dot((0, 0, -1), Q)
    glm::vec3 boundCentre{0.0f};
    float boundReach = std::numeric_limits<float>::quiet_NaN();  // radius + pad; NaN: always exact
};

// The per-light terms (forward_plus_row_culling.cpp).
SpotCullTerms spotCullTerms(const Cone& cone, const BoundingSphere& bound, bool corrected, float nearClipVS);

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

// ----- The culling pass and its two paths (instantiated for kBlock 8, 16 and 32) -----------------

// The "light-culling" pass (forward_plus_light_culling.cpp).
template <std::uint32_t kBlock>
void cullLights(ForwardPlusState& st, Device& device, BufferRegistry& reg);

// "culling": "brute": CS_main's loop over every light as a thread-group dispatch
// (forward_plus_cull_kernel.cpp).
template <std::uint32_t kBlock>
void cullLightsBrute(const ForwardPlusState& st, Device& device, const CullScratch& sc, const Surface& depthSurface,
                     std::uint32_t localCapacity, const GlobalList& opaque, const GlobalList& transparent);

// "culling": "binned": the row-parallel culling (forward_plus_row_culling.cpp).
template <std::uint32_t kBlock>
void cullLightsBinned(const ForwardPlusState& st, Device& device, CullScratch& sc, const Surface& depthSurface,
                      float nearClipVS, std::uint32_t localCapacity, std::uint64_t capacity, const GlobalList& opaque,
                      const GlobalList& transparent);

// The "heatmap" pass (forward_plus_heat_map.cpp).
void writeHeatMap(Device& device, const Surface& grid, std::uint32_t block, Surface& heatmap);

} // namespace tessera::forward_plus_detail
