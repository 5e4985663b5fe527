// forward-plus's "light-culling" pass (3dgep article §4.3–§4.5): in_Frustums read back, each
// light's tile rectangle and culling record, the light grids and index lists sized and created,
// then the brute kernel or the row-parallel culling, and "lightlist.counters" with its notes.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <tessera/compute/ordered_counter.h>
#include <tessera/culling/frustum.h>
#include <tessera/culling/tile_frustum.h>
#include <tessera/frame/frame_notes.h>
#include <tessera/math/det_math.h>

#include "forward_plus_detail.h"

namespace tessera::forward_plus_detail {
namespace {

constexpr std::uint32_t kMaxSurfaceEdge = 16384;  // D3D11_REQ_TEXTURE2D_U_OR_V_DIMENSION, texels

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

} // namespace

// Runs the culling for one tile size: binning and the row-parallel culling, or (brute) the
// kernel; then the counters.
template <std::uint32_t kBlock>
void cullLights(ForwardPlusState& st, Device& device, BufferRegistry& reg) {
    const glm::uvec2 tiles = st.tiles;
    const std::size_t tileCount = std::size_t{tiles.x} * tiles.y;
    const std::span<const ViewLight<float>> lights = st.setup->lightsExact;
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
        cullLightsBrute<kBlock>(st, device, sc, depthSurface, localCapacity, opaque, transparent);
    } else {
        cullLightsBinned<kBlock>(st, device, sc, depthSurface, nearClipVS, localCapacity, capacity, opaque, transparent);
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

template void cullLights<8>(ForwardPlusState&, Device&, BufferRegistry&);
template void cullLights<16>(ForwardPlusState&, Device&, BufferRegistry&);
template void cullLights<32>(ForwardPlusState&, Device&, BufferRegistry&);

} // namespace tessera::forward_plus_detail
