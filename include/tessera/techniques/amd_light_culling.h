// AMD Forward+ light culling on the CPU: GPU Pro 4's gather kernel (ch. 5 §5.3.1) over 8x8 tiles,
// one thread group per tile, with the two-level light list (a group-shared list of
// LIGHT_CAPACITY = 256, then one global index pool with per-tile offsets), optional 2.5D culling
// (GPU Pro 4 §5.6.1, culling/depth_mask.h), run through compute/dispatch.h. Input: a depth buffer and the
// lights' bounding spheres in AMD's left-handed view space; output: the pool and per-tile ranges
// the forward-plus-amd shading pass reads. Caller: the forward-plus-amd technique and its tests.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/compute/dispatch.h>
#include <tessera/culling/tile_depth_range.h>
#include <tessera/culling/tile_frustum.h>

namespace tessera {

inline constexpr std::uint32_t kAmdTileSizePx = 8;       // GPU Pro 4 §5.3.1: 8x8 px tiles, 64 threads a group
inline constexpr std::uint32_t kAmdLightCapacity = 256;  // GPU Pro 4 §5.3.1: LIGHT_CAPACITY, group-shared list entries

// How the tile's depth range is read from the depth buffer (culling/tile_depth_range.h).
enum class AmdDepthConvention : std::uint8_t {
    GpuPro4,        // GPU Pro 4 §5.3.1: depth cleared to 1.0 (skipped), z = projToView(depth).z; edge
                    // threads load 0 and add the near plane to the minimum (tileViewZBitsAmdGpuPro4)
    ForwardPlus11,  // ForwardPlus11: reversed depth cleared to 0 (skipped), z = 1 / (d _34 + _44)
                    // (tileViewZBitsAmdForwardPlus11)
};

enum class AmdDepthCulling : std::uint8_t {
    MinMax,       // GPU Pro 4 §5.3.1: side planes + the tile's [minZ, maxZ] slab
    DepthMask25D, // + GPU Pro 4 §5.6.1: the light's depth mask must share a cell with the tile's
};

// Which depth slab a tile's lights must reach.
enum class AmdDepthRange : std::uint8_t {
    Opaque,     // [minZ, maxZ] of the tile's non-cleared pixels (GPU Pro 4 §5.3.1)
    NearToMax,  // [near plane, maxZ] with cleared pixels entering the maximum as the far plane:
                // the list for blended geometry, which lies anywhere in front of the opaque depth
                // (tessera; TiledLighting11 takes the minimum from a blended-depth pre-pass instead).
                // GpuPro4 convention only; no 2.5D, no half-Z.
};

// Which lights each tile's strided loop visits. Both give the same bytes: the binned loop skips
// only lights whose side-plane test fails on that tile (tests/techniques/amd_light_culling_test.cpp
// "binned and all-lights loops give the same bytes").
enum class AmdLightLoop : std::uint8_t {
    AllLights,  // GPU Pro 4 §5.3.1 as written: every tile tests every light (14,400 tiles x N at 720p)
    Binned,     // tessera: per light, the tile columns and rows its padded bounding sphere can reach
                // (src/techniques/tile_binning.h); each tile visits its row's candidates in
                // ascending light index
};

struct AmdCullingOptions {
    AmdDepthConvention depthConvention = AmdDepthConvention::GpuPro4;
    AmdDepthCulling depthCulling = AmdDepthCulling::MinMax;
    AmdDepthRange range = AmdDepthRange::Opaque;
    // TiledLighting11's half-Z split (culling/depth_mask.h sphereOverlapsHalfZAmd): two lists per
    // tile, A over [minZ, halfZ] (tileOffset / tileLightCount) and B over [halfZ, maxZ]
    // (tileOffsetFar / tileLightCountFar), each its own group-shared list of LIGHT_CAPACITY; the
    // tile reserves countA + countB pool entries, A first. With 2.5D the mask test applies too.
    bool halfZ = false;
    AmdTileCorners corners = AmdTileCorners::Screen;  // projToView(pixel x, y) over the screen (GPU Pro 4's reading)
    compute::GroupOrder order = compute::GroupOrder::Parallel;  // same bytes as Serial (offsets in row-major order)
    AmdLightLoop lightLoop = AmdLightLoop::Binned;              // same bytes as AllLights
};

// The kernel's outputs. Tile t = gx + gy * tileCount.x (GPU Pro 4 §5.3.1 leaves tileIdx undefined).
// Pool layout: tiles in row-major order, each tile's lights in ascending light index (the
// deterministic order tessera fixes for the GPU's atomics, compute/dispatch.h); a tile with no
// lights reserves nothing and keeps offset 0, as the document's write-back does.
struct AmdTileLightLists {
    glm::uvec2 tileCount{0u};                    // tiles per axis: ceil(screen / 8)
    std::vector<std::uint32_t> lightIndices;     // gLightIdx, gLightIdxCounter entries
    std::vector<std::uint32_t> tileOffset;       // ptLowerBound[t]: first entry of tile t in the pool
    std::vector<std::uint32_t> tileLightCount;   // entries of tile t: min(found, 256). The document
                                                 // stores only the lower bound (GPU Pro 4 §5.3.1);
                                                 // GetTileOffsets needs this end.
    std::vector<std::uint32_t> tileFoundCount;   // ldsLightIdxCounter: lights that passed, unclamped
    std::vector<std::uint32_t> tileMinZBits;     // ldsZMin, ldsZMax (asuint of LH view z)
    std::vector<std::uint32_t> tileMaxZBits;
    std::vector<std::uint32_t> tileDepthMask;    // the 2.5D mask (0 when MinMax)
    // Half-Z only (empty otherwise): list B of each tile, as the three vectors above.
    std::vector<std::uint32_t> tileOffsetFar, tileLightCountFar, tileFoundCountFar;
    std::uint32_t overflowTiles = 0;             // tiles that found more than 256 lights (per list)
    std::uint64_t droppedLights = 0;             // lights lost to the 256 cap, summed over tiles
    std::uint32_t overflowTilesFar = 0;          // half-Z list B: the same counts
    std::uint64_t droppedLightsFar = 0;

    std::span<const std::uint32_t> tileLights(std::uint32_t tileIndex) const {
        return std::span<const std::uint32_t>(lightIndices).subspan(tileOffset[tileIndex], tileLightCount[tileIndex]);
    }
    std::span<const std::uint32_t> tileLightsFar(std::uint32_t tileIndex) const {
        return std::span<const std::uint32_t>(lightIndices).subspan(tileOffsetFar[tileIndex], tileLightCountFar[tileIndex]);
    }
};

// Runs the culling dispatch (tileCount.x x tileCount.y groups of 8x8 threads):
//   1. thread 0 initialises ldsZMin = 0xffffffff (GpuPro4) / 0x7f7fffff (ForwardPlus11),
//      ldsZMax = 0, the mask and the counter; barrier
//   2. every thread loads its pixel, and unless it is the cleared value does InterlockedMin /
//      InterlockedMax(asuint(view z)); barrier
//   3. (2.5D) every such thread ORs 1 << cell(z) into the tile mask; barrier
//   4. lights strided over the 64 threads (every light, or with AmdLightLoop::Binned the tile's
//      candidates; ascending light index either way): side planes
//      and slab (sphereOverlapsTileAmd), (2.5D) the mask AND; appendLightToList: InterlockedAdd
//      on the shared counter, store if the slot is < 256; barrier
//   5. thread 0: count = min(counter, 256) (the clamp GPU Pro 4 §5.3.1 needs: the printed
//      write-back copies `counter` entries and reads past the shared list above 256); if
//      count != 0 reserve `count` entries of the global pool (InterlockedAdd, taken in row-major
//      group order: compute/dispatch.h order rule 3); ptLowerBound[t] = start; barrier
//   6. the 64 threads copy the shared list into the pool (for i = lIdx; i < count; i += 64).
//   tessera runs steps 5-6 as: each group copies its lists into a staging slice of its own, and
//   the reservations are made after the dispatch in row-major order, so groups never wait for
//   each other: the same offsets and pool at any thread count.
// lightsViewLh: per light (centre x, y, z in AMD's left-handed view space, radius) — the kernel's
// `mul(float4(center.xyz, 1), g_mView)` done once by the caller. inverseProjection: glm matrix of
// the D3D projection's inverse (clipToView). Throws std::invalid_argument for an empty screen.
AmdTileLightLists cullTilesAmd(const DepthImageView& depth, std::span<const glm::vec4> lightsViewLh,
                               const glm::mat4& inverseProjection, const AmdCullingOptions& options = {});

// Several passes over the same depth buffer and lights (forward-plus-amd: the opaque lists, then
// the [near, maxZ] lists for blended geometry), one result per pass, each equal to its own
// cullTilesAmd call. The light binning depends only on the lights, the projection and the tile
// corners, so binned passes with the same corners share one.
std::vector<AmdTileLightLists> cullTilesAmd(const DepthImageView& depth, std::span<const glm::vec4> lightsViewLh,
                                            const glm::mat4& inverseProjection, std::span<const AmdCullingOptions> passes);
// MSAA: one depth image per sample (1 to 8, one size); every sample's view z joins the tile's
// bounds and (2.5D) its mask, as ForwardPlus11's MSAA loop over the samples of each pixel.
std::vector<AmdTileLightLists> cullTilesAmd(std::span<const DepthImageView> depthSamples, std::span<const glm::vec4> lightsViewLh,
                                            const glm::mat4& inverseProjection, std::span<const AmdCullingOptions> passes);

}  // namespace tessera
