// The `forward-plus` technique of the 3dgep article (tiled forward shading, §4; the demo's
// ForwardPlusRendering.hlsl and g_ForwardPlusTechnique): clear, depth pre-pass, grid frustums,
// the light-culling dispatch (per-tile depth range, opaque and transparent light lists, light
// grids), the heat map, then forward's opaque and transparent passes reading the tile's list.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string_view>

#include <glm/glm.hpp>

#include <tessera/frame/buffer_registry.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/technique.h>

namespace tessera {

// Its options (techniques/option_catalog.h): keys, values, the faithful default, the correction and its
// ERRATA.md row; read through OptionReader, listed by `tessera options`.
namespace option_values {
inline constexpr std::array<std::string_view, 2> kLightLists{"demo", "unbounded"};
inline constexpr std::array<std::string_view, 2> kConeTest{"demo", "corrected"};
inline constexpr std::array<std::string_view, 2> kCulling{"binned", "brute"};
} // namespace option_values

inline constexpr std::array<OptionInfo, 7> kForwardPlusOptions{
    kProjectionOption,
    kSamplerOption,
    kAlphaTestOption,
    OptionInfo{"lightLists", OptionInfo::Kind::Word, option_values::kLightLists, -1, "demo", "unbounded", 15,
               "the demo's fixed light lists (1024 per tile, 200 per tile globally) that overflow silently, or lists "
               "that never drop a light"},
    OptionInfo{"coneTest", OptionInfo::Kind::Word, option_values::kConeTest, -1, "demo", "corrected", 10,
               "the article's ConeInsidePlane (m not normalised: not conservative), or the corrected test"},
    kTileSizeOption,
    OptionInfo{"culling", OptionInfo::Kind::Word, option_values::kCulling, -1, "binned", "", 0,
               "how the culling dispatch finds each tile's lights: binned by tile rows, or every light in every tile "
               "(the same lists)"}};

// Options (scene file "options"; unknown keys or values are InputErrors naming /options/KEY).
// Defaults are faithful to the demo; the other values are named corrections (ERRATA.md).
//   "projection": "demo-gl" | "d3d"   as forward (forward.h). The culling uses the same matrix:
//       nearClipVS = ScreenToView(0, 0, 0, 1).z is -2fn/(f+n) under demo-gl.
//   "sampler": "demo" | "gltf"        as forward.
//   "alphaTest": false | true         as forward; with true the depth pre-pass runs the same
//       alpha test (otherwise cut-out texels would write depth and hide what lies behind).
//   "lightLists": "demo" (default) | "unbounded"
//       demo: the demo's sizes. Per tile the group-shared lists o_LightList[1024] and
//       t_LightList[1024]: an append past 1024 still increments the count but stores nothing;
//       the grid keeps the full count, and the copy to the global list reads the missing
//       entries as 0 (an out-of-bounds group-shared read, undefined in D3D11.3; tessera reads 0,
//       as every other out-of-bounds read does), so light 0 takes their place. Global lists of
//       numTiles * 200 entries (3dgep demo's main.cpp; "an average of 200 lights per tile", 3dgep article §4.3.2):
//       the counter keeps growing past the end, writes past it are discarded (D3D11.3 UAV
//       out-of-bounds write) and the pixel shader reads 0 there (out-of-bounds StructuredBuffer
//       load), so an overflowing tile is shaded `count` times with light 0, or, where light 0
//       does not reach, with no light at all: the article's "many tiles simply appeared black"
//       with 512 large lights (ERRATA.md).
//       unbounded: local lists as long as the tile's candidate lights and global lists sized by
//       the sum over tiles of candidate lights: nothing is ever dropped.
//     Either way the overflow is counted in "lightlist.counters" (readForwardPlusCounters).
//   "coneTest": "demo" (default) | "corrected"   spot lights: the article's ConeInsidePlane
//       (m = cross(cross(N, d), d) not normalized, so it can cull a cone that reaches the tile)
//       or the corrected test (culling/plane.h coneInsidePlaneCorrected).
//   "tileSize": 16 (default, BLOCK_SIZE) | 8 | 32   tile edge in px (one thread group per tile).
//   "culling": "binned" (default) | "brute"   how the dispatch finds each tile's lights; the
//       lists are identical (tests/golden/forward_plus_scenes_test.cpp). brute: every tile
//       tests every light, the demo's `for (i = groupIndex; i < NUM_LIGHTS; i += 256)`.
//       binned (tessera): a pre-pass bounds each light's tiles by a padded, conservative test
//       against the tile-column and tile-row planes (a binary search; for a light reaching the
//       eye's plane every column and row, kept as up to two runs), and each tile tests only
//       those lights, in the same ascending order: per tile row in parallel, no thread groups
//       (forward_plus_row_culling.cpp "row-parallel culling"); the scratch is kept from frame to frame. A
//       spot light's cone tests take the near, far and min planes from per-light terms and
//       decide a side plane from the cone's bounding sphere where the sphere is clearly on one
//       side (forward_plus_detail.h SpotCullTerms): the same booleans, cheaper.
// Light order inside a tile list: ascending light index (the strided loop appends in lockstep,
// compute/dispatch.h order rule 2); tiles take their global offsets in row-major order
// (compute/ordered_counter.h), at any thread count.
// What each pass does (TechniqueInfo::passes; "clear", "transparent", "resolve" are shared).
inline constexpr std::array<PassCaption, 5> kForwardPlusPassCaptions{{
    {"depth-prepass", "Depth pre-pass: the opaque geometry's depth only, for the tiles' depth ranges (3dgep article §4 "
                      "Forward+)."},
    {"frustums", "One frustum per tile, built once from the inverse projection (3dgep article §4; demo "
                 "ForwardPlusRendering.hlsl)."},
    {"light-culling", "The culling compute shader: each tile's depth range, then sphere and cone tests against its "
                      "frustum, appending to the light grid and index list (3dgep article §4; ERRATA #10, #14, #15)."},
    {"heatmap", "Lights per tile as the demo's debug texture."},
    {"opaque", "Shading reads only the tile's light list (3dgep article §4)."},
}};

// Buffers (--dump writes them all):
//   "backbuffer"            R8G8B8A8_UNORM: the image
//   "depth"                 D24_UNORM_S8_UINT: the pre-pass depth (the opaque pass tests it with
//                           LESS_EQUAL and rewrites the same values)
//   "frustums"              R32G32B32A32_FLOAT, (4 * tilesX) x tilesY: texel (4 tx + i, ty) is
//                           plane i (left, right, top, bottom) of tile (tx, ty) as (N.xyz, d)
//   "lightgrid.opaque", "lightgrid.transparent"   R32G32_UINT, tilesX x tilesY: (offset, count)
//   "lightindex.opaque", "lightindex.transparent" R32_UINT: the global light index lists,
//                           element e at texel (e % W, e / W), W = min(capacity, 16384)
//   "heatmap"               R32G32B32A32_FLOAT, the screen size: the demo's DebugTexture (tile
//                           grid lines, then LightCountHeatMap(o_LightCount / 50)). The demo's
//                           culling CS writes it; tessera writes the same texels in a pass of
//                           its own ("heatmap", after "light-culling") from the opaque grid's
//                           counts, so that the culling pass's time is the culling's.
//   "lightlist.counters"    R32_UINT, 8 x 2: row 0 opaque, row 1 transparent, the fields of
//                           LightListCounters in order
// Every precision mode runs (README "Precision modes"). With MSAA the back buffer and depth hold
// TechniqueContext::sampleCount samples, the tile bounds take every sample, and the image is
// resolved last (README "MSAA").
Frame buildForwardPlus(const TechniqueContext& context);

// The demo's list sizes (3dgep article §4.3.2, §4.5; ForwardPlusRendering.hlsl, 3dgep demo's main.cpp).
inline constexpr std::uint32_t kForwardPlusLocalListCapacity = 1024;   // o_LightList[1024], entries
inline constexpr std::uint32_t kForwardPlusAverageLightsPerTile = 200; // global list: numTiles * 200 entries

// One light list's bookkeeping for the frame (a row of "lightlist.counters").
struct LightListCounters {
    std::uint32_t requested = 0;        // the global counter after the dispatch: sum of tile counts
    std::uint32_t capacity = 0;         // entries the global list holds
    std::uint32_t tilesOverLocal = 0;   // tiles whose count exceeded the local list
    std::uint32_t droppedLocal = 0;     // appends past the local list, summed over tiles
    std::uint32_t tilesOverGlobal = 0;  // tiles with entries past the global list's end
    std::uint32_t droppedGlobal = 0;    // entries written past the global list's end (discarded)
    std::uint32_t maxTileCount = 0;     // largest tile count
    std::uint32_t nonEmptyTiles = 0;    // tiles with count > 0
};
inline constexpr std::uint32_t kLightListCounterFields = 8;

struct ForwardPlusCounters {
    LightListCounters opaque, transparent;
};

// Reads "lightlist.counters"; throws std::out_of_range when the registry has none.
ForwardPlusCounters readForwardPlusCounters(const BufferRegistry& registry);

// The heat-map colour of a tile with `lightCount` opaque lights (> 0):
// LightCountHeatMap.SampleLevel(LinearClampSampler, float2(lightCount / 50.0f, 0), 0). The demo's
// gradient (LightCountHeatMap.psd) is not public (Git LFS); tessera's stand-in is a 5-texel
// texture blue, cyan, green, yellow, red, filtered as a linear clamp sampler (texel centres at
// (i + 0.5) / 5, weights in float): 1-10 lights blue, 20-30 green (the article's caption),
// 50 and more red.
glm::vec4 forwardPlusHeatMapColor(std::uint32_t lightCount);

// The first two passes of forward-plus, shared with forward-plus-amd: "clear" (creates the
// R8G8B8A8_UNORM back buffer cleared to the demo's colour and the D24_UNORM_S8_UINT "depth"
// cleared to 1, 0) and "depth-prepass", the demo's g_pDepthPrepassPipeline: the opaque draw
// items, VS only (with `setup.alphaTest` the alpha-test PS, nothing written), depth LESS with
// writes, cull back (glTF doubleSided: none). writeNormals (GPU Pro 4 §5.6.2, the pre-pass as a
// G-pass): the pass also writes "gbuffer.normal" (R32G32B32A32_FLOAT, cleared to 0): the unit
// WORLD normal, normalize(upper3x3(worldFromObject) * n), as AMD's shading forms it, w = 1.
void addForwardPlusClearAndPrepass(Frame& frame, std::shared_ptr<const ForwardPassSetup> setup, Device* device,
                                   const SceneResources* resources, DrawStats* stats, bool writeNormals = false);

} // namespace tessera
