// forward-plus-amd's light culling (GPU Pro 4 ch. 5 §5.3; ForwardPlus11's TiledLightCullCS as
// cullTilesAmd runs it): AMD's light table and culling spheres from the scene's lights, the
// "light-culling" pass that stores the lists, tile depth ranges, 2.5D masks, radar heat map and
// counters, and the spot light's bounding sphere.
#include "forward_plus_amd_detail.h"

#include <tbb/parallel_for.h>

namespace tessera {

namespace {
constexpr float kSphereRoundUp = 1.0f + 1.0f / 1048576.0f;  // 1 + 2^-20: see spotBoundingSphere
} // namespace

SpotBoundingSphere spotBoundingSphere(float range, float halfAngleDeg) {
    SpotBoundingSphere b;
    if (!(halfAngleDeg < 90.0f)) {
        b.radius = range * kSphereRoundUp;
        return b;
    }
    const float theta = hlsl::radians(halfAngleDeg);
    if (halfAngleDeg <= 45.0f) {
        b.centerOffset = range / (2.0f * detCos(theta));
        b.radius = b.centerOffset * kSphereRoundUp;
    } else {
        b.centerOffset = range * detCos(theta);
        b.radius = range * detSin(theta) * kSphereRoundUp;
    }
    return b;
}

namespace forward_plus_amd_detail {

SurfaceDesc indexListDesc(std::uint64_t entries) {
    const std::uint64_t n = std::max<std::uint64_t>(entries, 1);
    const std::uint64_t width = std::min<std::uint64_t>(n, kMaxSurfaceEdge);
    const std::uint64_t height = (n + width - 1) / width;
    if (height > kMaxSurfaceEdge)
        throw std::runtime_error("forward-plus-amd: a light index pool of " + std::to_string(entries) +
                                 " entries exceeds a 16384 x 16384 R32_UINT buffer");
    return {static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height), Format::R32_UINT, 1};
}

void storeUint32(std::byte* base, std::size_t element, std::uint32_t value) {
    std::memcpy(base + element * sizeof(std::uint32_t), &value, sizeof(value));
}

// One light's culling sphere and AMD shading record (entry i of the tables).
void convertLight(AmdState& st, std::size_t i, const ViewLight<float>& l, const Light& w) {
    const glm::vec3 posLh = viewLhFromViewRh(glm::vec3(l.positionView));
    const glm::vec3 color = w.color * w.intensity;  // tessera: float colour, no RGBA8 quantization
    if (!l.enabled) {
        st.spheresViewLh[i] = glm::vec4(posLh, -std::numeric_limits<float>::infinity());
    } else if (l.type == LightType::Directional) {
        st.spheresViewLh[i] = glm::vec4(0.0f, 0.0f, 0.0f, std::numeric_limits<float>::infinity());
    } else if (l.type == LightType::Point) {
        st.spheresViewLh[i] = glm::vec4(posLh, l.range);
        st.table.kind[i] = AmdKind::Point;
        st.table.points[i] = AmdPointLight<float>{w.positionWorld, w.range, color};
    } else {
        const SpotBoundingSphere b = spotBoundingSphere(l.range, l.spotlightAngleDeg);
        const glm::vec3 dirLh = viewLhFromViewRh(glm::vec3(l.directionView));
        st.spheresViewLh[i] = glm::vec4(posLh + dirLh * b.centerOffset, b.radius);
        // The shader rebuilds the apex as centre - boundingRadius * dir (amdSpotPosition), so the
        // shading record holds the centre at `centerOffset` with boundingRadius = centerOffset:
        // the culling sphere itself for theta <= 45 deg (radius == offset), the apex either way.
        const float cosCone = detCos(hlsl::radians(w.spotHalfAngleDeg));
        AmdSpotLight<float> s;
        s.boundingCenterWorld = w.positionWorld + w.directionWorld * b.centerOffset;
        s.boundingRadius = b.centerOffset;
        s.color = color;
        s.spotParams = glm::vec4(w.directionWorld.x, w.directionWorld.y,
                                 w.directionWorld.z > 0.0f ? cosCone : -cosCone, w.range);
        st.table.kind[i] = AmdKind::Spot;
        st.table.spots[i] = s;
    }
}

// Culling spheres in AMD's LH view space and the AMD shading table, from the scene's lights.
// Disabled lights get radius -inf (no `x < r` test passes); directional lights radius +inf.
void convertLights(AmdState& st, std::span<const Light> sceneLights) {
    const std::vector<ViewLight<float>>& view = st.setup->lightsExact;
    const std::size_t n = view.size();
    st.spheresViewLh.resize(n);
    st.table.kind.assign(n, AmdKind::None);
    st.table.points.resize(n);
    st.table.spots.resize(n);
    for (std::size_t i = 0; i < n; ++i) convertLight(st, i, view[i], sceneLights[i]);
}

namespace {

constexpr std::uint32_t kCounterRows = 3;  // "lightlist.counters": opaque (A), transparent, opaque far (B)

// Writes one culling result's grid(s) and pool into the registry.
void storeLists(BufferRegistry& reg, const AmdTileLightLists& lists, const std::string& which, bool halfZ) {
    const glm::uvec2 tiles = lists.tileCount;
    Surface& grid = reg.create("lightgrid." + which, {tiles.x, tiles.y, Format::R32G32_UINT, 1});
    Surface& pool = reg.create("lightindex." + which, indexListDesc(lists.lightIndices.size()));
    const std::size_t tileCount = std::size_t{tiles.x} * tiles.y;
    for (std::size_t t = 0; t < tileCount; ++t) {
        storeUint32(grid.bytes().data(), 2 * t, lists.tileOffset[t]);
        storeUint32(grid.bytes().data(), 2 * t + 1, lists.tileLightCount[t]);
    }
    for (std::size_t e = 0; e < lists.lightIndices.size(); ++e) storeUint32(pool.bytes().data(), e, lists.lightIndices[e]);
    if (halfZ) {
        Surface& far = reg.create("lightgrid." + which + ".far", {tiles.x, tiles.y, Format::R32G32_UINT, 1});
        for (std::size_t t = 0; t < tileCount; ++t) {
            storeUint32(far.bytes().data(), 2 * t, lists.tileOffsetFar[t]);
            storeUint32(far.bytes().data(), 2 * t + 1, lists.tileLightCountFar[t]);
        }
    }
}

LightListCounters countersOf(const std::vector<std::uint32_t>& counts, const std::vector<std::uint32_t>& found,
                             std::uint32_t poolEntries) {
    LightListCounters c;
    c.requested = poolEntries;
    c.capacity = poolEntries;
    for (std::size_t t = 0; t < found.size(); ++t) {
        if (found[t] > kAmdLightCapacity) {
            ++c.tilesOverLocal;
            c.droppedLocal += found[t] - kAmdLightCapacity;
        }
        c.maxTileCount = std::max(c.maxTileCount, found[t]);
        c.nonEmptyTiles += counts[t] > 0 ? 1u : 0u;
    }
    return c;
}

} // namespace

void cullAll(AmdState& st, Device& device, BufferRegistry& reg) {
    const std::uint32_t width = st.setup->width, height = st.setup->height;
    const Surface& depthSurface = reg.get("depth");
    // One image per MSAA sample: ForwardPlus11's culling takes every sample of each pixel.
    const std::uint32_t samples = depthSurface.sampleCount();
    std::vector<std::vector<float>> depth(samples, std::vector<float>(std::size_t{width} * height));
    device.execute([&] {
        tbb::parallel_for(std::uint32_t(0), height, [&](std::uint32_t y) {
            for (std::uint32_t i = 0; i < samples; ++i)
                for (std::uint32_t x = 0; x < width; ++x) depth[i][std::size_t{y} * width + x] = depthSurface.loadDepth(x, y, i);
        });
    });
    if (st.shadowsActive) st.depthWindow = depth[0];  // job creation's depth (1 sample: shadows refuse MSAA)
    std::vector<DepthImageView> depthViews;
    for (const std::vector<float>& d : depth) depthViews.push_back(DepthImageView{d, width, height});
    const std::span<const DepthImageView> depthView(depthViews);
    AmdCullingOptions opaqueOptions;
    opaqueOptions.depthCulling = st.options.depthMask ? AmdDepthCulling::DepthMask25D : AmdDepthCulling::MinMax;
    opaqueOptions.halfZ = st.options.halfZ;
    opaqueOptions.lightLoop = st.options.lightLoop;
    AmdCullingOptions transparentOptions;
    transparentOptions.range = AmdDepthRange::NearToMax;
    transparentOptions.lightLoop = st.options.lightLoop;
    device.execute([&] {
        const std::array<AmdCullingOptions, 2> passes{opaqueOptions, transparentOptions};
        std::vector<AmdTileLightLists> lists = cullTilesAmd(depthView, st.spheresViewLh, st.inverseProjectionLh, passes);
        st.opaque = std::move(lists[0]);
        st.transparent = std::move(lists[1]);
    });

    storeLists(reg, st.opaque, "opaque", st.options.halfZ);
    storeLists(reg, st.transparent, "transparent", false);
    const glm::uvec2 tiles = st.opaque.tileCount;
    const std::size_t tileCount = std::size_t{tiles.x} * tiles.y;
    Surface& range = reg.create("tiles.depthRange", {tiles.x, tiles.y, Format::R32G32_UINT, 1});
    Surface& mask = reg.create("tiles.depthMask", {tiles.x, tiles.y, Format::R32_UINT, 1});
    for (std::size_t t = 0; t < tileCount; ++t) {
        storeUint32(range.bytes().data(), 2 * t, st.opaque.tileMinZBits[t]);
        storeUint32(range.bytes().data(), 2 * t + 1, st.opaque.tileMaxZBits[t]);
        storeUint32(mask.bytes().data(), t, st.opaque.tileDepthMask[t]);
    }
    // ForwardPlus11DebugDraw: every pixel of a tile gets the radar colour of the tile's count.
    Surface& radar = reg.create("heatmap.radar", {width, height, Format::R8G8B8A8_UNORM, 1});
    std::vector<std::uint32_t> tileColor(tileCount);
    for (std::size_t t = 0; t < tileCount; ++t) {
        std::uint32_t count = st.opaque.tileFoundCount[t];
        if (st.options.halfZ) count = std::max(count, st.opaque.tileFoundCountFar[t]);
        tileColor[t] = amdRadarColorRgba8(count, kAmdLightCapacity);
    }
    for (std::uint32_t y = 0; y < height; ++y)
        for (std::uint32_t x = 0; x < width; ++x)
            std::memcpy(radar.texel(x, y), &tileColor[(y / kAmdTileSizePx) * std::size_t{tiles.x} + x / kAmdTileSizePx],
                        sizeof(std::uint32_t));

    Surface& counters = reg.create("lightlist.counters", {kLightListCounterFields, kCounterRows, Format::R32_UINT, 1});
    std::array<LightListCounters, kCounterRows> rows{
        countersOf(st.opaque.tileLightCount, st.opaque.tileFoundCount, std::uint32_t(st.opaque.lightIndices.size())),
        countersOf(st.transparent.tileLightCount, st.transparent.tileFoundCount,
                   std::uint32_t(st.transparent.lightIndices.size())),
        LightListCounters{}};
    if (st.options.halfZ) {
        // Row 2 describes list B alone; the pool (row 0's requested / capacity) holds A and B.
        rows[2] = countersOf(st.opaque.tileLightCountFar, st.opaque.tileFoundCountFar, 0);
        std::uint32_t entriesFar = 0;
        for (std::uint32_t c : st.opaque.tileLightCountFar) entriesFar += c;
        rows[2].requested = entriesFar;
        rows[2].capacity = entriesFar;
    }
    static_assert(sizeof(LightListCounters) == kLightListCounterFields * sizeof(std::uint32_t));
    for (std::uint32_t row = 0; row < kCounterRows; ++row) std::memcpy(counters.texel(0, row), &rows[row], sizeof(LightListCounters));
    if (FrameNotes* notes = st.setup->notes) {
        for (const FrameNote& n : st.configurationNotes) notes->add(n);
    }
    if (FrameNotes* notes = st.setup->notes)
        for (const LightListCounters& c : rows)
            notes->add({"light-list-clamp", "tile light-list entries past LIGHT_CAPACITY 256 dropped", c.droppedLocal, 20, "", true});
}

} // namespace forward_plus_amd_detail
} // namespace tessera
