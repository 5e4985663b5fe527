// The `forward-plus-amd` technique (GPU Pro 4 ch. 5; ForwardPlus11, TiledLighting11): clear -> depth
// pre-pass (forward-plus's) -> light culling (cullTilesAmd: opaque lists with 2.5D / half-Z, then
// the transparent [near, maxZ] lists) -> opaque pass -> transparent pass, shaded with AMD's
// lighting or, with "shading": "3dgep", forward's Phong passes reading the AMD lists.
#include <tessera/techniques/forward_plus_amd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include <tessera/io/input_error.h>
#include <tessera/math/depth_mask.h>
#include <tessera/math/det_math.h>
#include <tessera/math/screen_to_view.h>
#include <tessera/math/tile_frustum.h>
#include <tessera/shading/phong_surface.h>
#include <tessera/shading/amd_lighting.h>
#include <tessera/shading/phong_material_shader.h>
#include <tessera/shading/tile_heat_colors.h>
#include <tessera/techniques/amd_light_culling.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/forward_plus.h>
#include <tessera/techniques/technique_options.h>

namespace tessera {
namespace {

constexpr std::uint32_t kMaxSurfaceEdge = 16384;  // D3D11_REQ_TEXTURE2D_U_OR_V_DIMENSION, texels
constexpr float kSphereRoundUp = 1.0f + 1.0f / 1048576.0f;  // 1 + 2^-20: see spotBoundingSphere
constexpr std::uint32_t kCounterRows = 3;  // "lightlist.counters": opaque (A), transparent, opaque far (B)

// The demo's alpha blend (forward.cpp kDemoAlphaBlend): SrcAlpha / InvSrcAlpha, alpha One / Zero.
constexpr RenderTargetBlendDesc kAlphaBlend{true,       Blend::SrcAlpha, Blend::InvSrcAlpha, BlendOp::Add,
                                            Blend::One, Blend::Zero,     BlendOp::Add,        WriteAll};

struct AmdOptions {
    bool shadingAmd = true;
    bool depthMask = true;
    bool halfZ = false;
    ProjectionConvention projection = ProjectionConvention::D3d;
    PhongSamplerChoice sampler = PhongSamplerChoice::Demo;
    bool alphaTest = false;
    AmdLightLoop lightLoop = AmdLightLoop::Binned;
};

AmdOptions parseOptions(const TechniqueContext& ctx, const std::string& file) {
    AmdOptions o;
    o.shadingAmd = optionEnum(ctx.options, "shading", {"amd", "3dgep"}, "amd", file) == "amd";
    o.depthMask = optionEnum(ctx.options, "culling", {"depth-mask", "min-max"}, "depth-mask", file) == "depth-mask";
    o.halfZ = optionBool(ctx.options, "halfZ", false, file);
    if (o.halfZ && !o.shadingAmd)
        throw inputError(file, "/options/halfZ",
                         "halfZ needs \"shading\": \"amd\" (the 3dgep pixel shader reads one list per tile)");
    o.projection = optionEnum(ctx.options, "projection", {"demo-gl", "d3d"}, o.shadingAmd ? "d3d" : "demo-gl", file) == "d3d"
                       ? ProjectionConvention::D3d
                       : ProjectionConvention::DemoGl;
    o.sampler = optionEnum(ctx.options, "sampler", {"demo", "gltf"}, "demo", file) == "gltf" ? PhongSamplerChoice::Gltf
                                                                                               : PhongSamplerChoice::Demo;
    o.alphaTest = optionBool(ctx.options, "alphaTest", false, file);
    o.lightLoop = optionEnum(ctx.options, "lightLoop", {"binned", "all-lights"}, "binned", file) == "binned" ? AmdLightLoop::Binned
                                                                                                     : AmdLightLoop::AllLights;
    return o;
}

// AMD's world-space light properties, indexed by scene light index (g_PointLightBuffer* /
// g_SpotLightBuffer* of ForwardPlus11; GPU Pro 4 §5.3.1). kind: what the light is to the AMD shader.
enum class AmdKind : std::uint8_t { None, Point, Spot };

struct AmdLightTable {
    std::vector<AmdKind> kind;
    std::vector<AmdPointLight<float>> points;  // valid where kind == Point
    std::vector<AmdSpotLight<float>> spots;    // valid where kind == Spot
};

// What the culling pass hands the shading passes.
struct AmdState {
    AmdOptions options;
    std::shared_ptr<ForwardPassSetup> setup;
    glm::mat4 inverseProjectionLh{1.0f};  // inverse(P_rh * diag(1, 1, -1, 1))
    std::vector<glm::vec4> spheresViewLh;  // culling spheres (centre LH view, radius)
    AmdLightTable table;
    glm::vec3 cameraPosWorld{0.0f};
    AmdTileLightLists opaque, transparent;
    TileLightList opaqueList, transparentList;  // 3dgep shading: bound by the passes
};

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

// Culling spheres in AMD's LH view space and the AMD shading table, from the scene's lights.
// Disabled lights get radius -inf (no `x < r` test passes); directional lights radius +inf.
void convertLights(AmdState& st, std::span<const Light> sceneLights) {
    const std::vector<ViewLight<float>>& view = st.setup->lightsExact;
    const std::size_t n = view.size();
    st.spheresViewLh.resize(n);
    st.table.kind.assign(n, AmdKind::None);
    st.table.points.resize(n);
    st.table.spots.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const ViewLight<float>& l = view[i];
        const Light& w = sceneLights[i];
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
}

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
}

// ----- AMD shading (ForwardPlus11 RenderScenePS, amd_lighting.h) --------------------------------

struct AmdShadeData {
    const AmdState* state = nullptr;
    const AmdTileLightLists* lists = nullptr;
    bool halfZ = false;
};

// RenderScenePS. Varyings from PhongVS with viewFromObject = worldFromObject: posView holds the
// WORLD position and normalView the world normal (AMD shades in world space). T = float: exact
// and fast (one target); T = double: reference, the same operations in double from the float
// inputs (varyings, texels, the light table after its format conversions), written to the back
// buffer and, clamped as the UNORM target clamps, to the float copy (kTargets = 2).
template <bool kDiscard, class T = float, int kTargets = 1>
struct AmdScenePS {
    using Varyings = PhongVaryings;
    static constexpr int kTargetCount = kTargets;
    static constexpr bool kMayDiscard = kDiscard;
    const PhongShaderData<float>* material = nullptr;
    AmdShadeData shade;
    bool alphaTest = false;
    bool blended = false;

    void operator()(const PixelInput<PhongVaryings>& in, PixelOutput<kTargets>& out) const {
        glm::vec4 diffuseTex = material->diffuseColor;
        if (material->diffuseTexture.bound()) diffuseTex = phong_detail::textureRule(diffuseTex, material->diffuseTexture.sample(in));
        const float alpha = material->ignoreDiffuseAlpha ? 1.0f : diffuseTex.w;
        T specMask = T(diffuseTex.w);  // fSpecMask = DiffuseTex.a
        if constexpr (kDiscard) {
            if (alphaTest) {  // USE_ALPHA_TEST: discard below the threshold, fSpecMask = 0
                if (alpha * material->opacity < material->alphaThreshold) {
                    out.discard();
                    return;
                }
                specMask = T(0);
            }
        }
        const Vec3<T> posWorld(in.varyings.posView);
        const Vec3<T> normalWorld = hlsl::normalize(Vec3<T>(in.varyings.normalView));
        const Vec3<T> viewDir = amdViewDir(Vec3<T>(shade.state->cameraPosWorld), posWorld);

        // GetTileIndex: floor(x / 8) + floor(y / 8) * numTilesX.
        const AmdTileLightLists& lists = *shade.lists;
        const auto tileX = std::uint32_t(std::floor(in.posWindow.x / float(kAmdTileSizePx)));
        const auto tileY = std::uint32_t(std::floor(in.posWindow.y / float(kAmdTileSizePx)));
        AmdLightingResult<T> accum;
        if (tileX < lists.tileCount.x && tileY < lists.tileCount.y) {
            const std::uint32_t tile = tileX + tileY * lists.tileCount.x;
            std::span<const std::uint32_t> list = lists.tileLights(tile);
            if (shade.halfZ) {
                const float minZ = std::bit_cast<float>(lists.tileMinZBits[tile]);
                const float maxZ = std::bit_cast<float>(lists.tileMaxZBits[tile]);
                const float viewZ = clipToView(glm::vec4(0.0f, 0.0f, in.posWindow.z, 1.0f), shade.state->inverseProjectionLh).z;
                if (!pixelUsesNearHalfAmd(viewZ, halfZAmd(minZ, maxZ))) list = lists.tileLightsFar(tile);
            }
            const AmdLightTable& table = shade.state->table;
            std::vector<LightTerm>* const trace = watchedLightTerms();
            for (std::uint32_t index : list) {  // the point-light loop
                if (table.kind[index] != AmdKind::Point) continue;
                const AmdPointLight<float>& p = table.points[index];
                const AmdPointLight<T> light{Vec3<T>(p.centerWorld), T(p.radius), Vec3<T>(p.color)};
                const AmdLightingResult<T> r = amdPointLight(light, posWorld, normalWorld, viewDir);
                accum.diffuse += r.diffuse;
                accum.specular += r.specular;
                if (trace) [[unlikely]] trace->push_back(amdDescribePoint(index, light, posWorld, normalWorld, r));
            }
            for (std::uint32_t index : list) {  // the spot-light loop
                if (table.kind[index] != AmdKind::Spot) continue;
                const AmdSpotLight<float>& sp = table.spots[index];
                const AmdSpotLight<T> light{Vec3<T>(sp.boundingCenterWorld), T(sp.boundingRadius), Vec3<T>(sp.color),
                                            Vec4<T>(sp.spotParams)};
                const AmdLightingResult<T> r = amdSpotLight(light, posWorld, normalWorld, viewDir);
                accum.diffuse += r.diffuse;
                accum.specular += r.specular;
                if (trace) [[unlikely]] trace->push_back(amdDescribeSpot(index, light, posWorld, normalWorld, r));
            }
        }
        const Vec3<T> rgb = amdComposePixel(accum, normalWorld, Vec3<T>(glm::vec3(diffuseTex)), specMask,
                                            Vec3<T>(kAmdAmbientUp), Vec3<T>(kAmdAmbientDown));
        out.target[0] = glm::vec4(glm::vec3(rgb), blended ? alpha * material->opacity : 1.0f);
        if constexpr (kTargets == 2) out.target[1] = convert::clampUnorm(out.target[0]);
    }
};

void drawAmdPass(const AmdState& st, Device& device, const SceneResources& res, const RenderTargets& rt, bool transparentPass,
                 DrawStats* stats) {
    const ForwardPassSetup& setup = *st.setup;
    AmdShadeData shade{&st, transparentPass ? &st.transparent : &st.opaque, st.options.halfZ && !transparentPass};
    for (const DrawItem& item : res.drawItems()) {
        const PhongMaterial material = phongFromGltf(res.material(item.material));
        if (material.isTransparent() != transparentPass) continue;
        DrawState ds;
        ds.viewport = Viewport{0.0f, 0.0f, float(setup.width), float(setup.height), 0.0f, 1.0f};
        ds.rasterizer.frontCounterClockwise = item.frontCounterClockwise;
        ds.depthStencil.depthFunc = ComparisonFunc::LessEqual;  // after the pre-pass, as forward-plus
        if (transparentPass) {
            ds.rasterizer.cullMode = CullMode::None;
            ds.depthStencil.depthWriteEnable = false;
            ds.blend.renderTarget[0] = kAlphaBlend;
        } else {
            ds.rasterizer.cullMode = material.doubleSided ? CullMode::None : CullMode::Back;
        }
        ds.precision = setup.precision;  // the pre-pass's depth path (LESS_EQUAL)
        // The clip matrix exactly as the pre-pass forms it (same depth values: LESS_EQUAL passes).
        const glm::mat4 viewFromObject = setup.viewFromWorld * item.worldFromObject;
        const PhongVS vs{setup.clipFromView * viewFromObject, item.worldFromObject};
        const PrimitiveBuffer& prim = res.primitives()[item.primitive];
        const PhongShaderData<float> data = makePhongShaderData<float>(material, *setup.textures, {});
        const std::span<const SceneVertex> vertices(prim.vertices);
        DrawStats s;
        if (setup.precision == Precision::Reference)
            s = setup.alphaTest ? device.draw(ds, rt, vertices, prim.indices, vs,
                                              AmdScenePS<true, double, 2>{&data, shade, true, transparentPass})
                                : device.draw(ds, rt, vertices, prim.indices, vs,
                                              AmdScenePS<false, double, 2>{&data, shade, false, transparentPass});
        else
            s = setup.alphaTest ? device.draw(ds, rt, vertices, prim.indices, vs, AmdScenePS<true>{&data, shade, true, transparentPass})
                                : device.draw(ds, rt, vertices, prim.indices, vs, AmdScenePS<false>{&data, shade, false, transparentPass});
        if (stats) *stats += s;
    }
}

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

Frame buildForwardPlusAmd(const TechniqueContext& ctx) {
    const std::string file = ctx.errorFile();
    auto st = std::make_shared<AmdState>();
    st->options = parseOptions(ctx, file);
    st->setup = makeForwardPassSetup(ctx, st->options.projection, st->options.sampler, st->options.alphaTest);
    // AMD's view space is left-handed: the same camera with z negated. P_lh = P_rh * diag(1,1,-1,1)
    // maps (x, y, -z_rh) to the same clip coordinates, so its inverse takes depth to LH view z.
    const glm::mat4 flipZ(glm::vec4(1, 0, 0, 0), glm::vec4(0, 1, 0, 0), glm::vec4(0, 0, -1, 0), glm::vec4(0, 0, 0, 1));
    st->inverseProjectionLh = glm::inverse(st->setup->clipFromView * flipZ);
    st->cameraPosWorld = ctx.camera.positionWorld;
    convertLights(*st, ctx.resources->scene().lights);

    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;
    std::map<std::string, std::uint64_t>* variantCounts = ctx.variantCounts;
    const SceneResources* res = ctx.resources;
    const std::string back(kBackBufferName);

    Frame frame;
    addForwardPlusClearAndPrepass(frame, st->setup, device, res, stats);
    std::vector<std::string> cullWrites{"lightgrid.opaque",  "lightindex.opaque", "lightgrid.transparent",
                                        "lightindex.transparent", "tiles.depthRange", "tiles.depthMask",
                                        "heatmap.radar",     "lightlist.counters"};
    if (st->options.halfZ) cullWrites.emplace_back("lightgrid.opaque.far");
    frame.add({"light-culling", {"depth"}, cullWrites, [st, device](BufferRegistry& reg) { cullAll(*st, *device, reg); }});
    const auto drawPass = [st, device, stats, variantCounts, res](bool transparentPass) {
        return [st, device, stats, variantCounts, res, transparentPass](BufferRegistry& reg) {
            RenderTargets rt;
            rt.colors[0] = &reg.get(backBufferTarget(st->setup->sampleCount));
            if (st->setup->precision == Precision::Reference) rt.colors[1] = &reg.get(referenceBufferTarget(st->setup->sampleCount));
            rt.depthStencil = &reg.get("depth");
            if (st->options.shadingAmd) {
                drawAmdPass(*st, *device, *res, rt, transparentPass, stats);
                return;
            }
            const std::string which = transparentPass ? "transparent" : "opaque";
            const Surface& grid = reg.get("lightgrid." + which);
            const Surface& list = reg.get("lightindex." + which);
            const AmdTileLightLists& lists = transparentPass ? st->transparent : st->opaque;
            TileLightList& bound = transparentPass ? st->transparentList : st->opaqueList;
            bound.grid = grid.bytes().data();
            bound.gridWidth = grid.width();
            bound.gridHeight = grid.height();
            bound.indices = list.bytes().data();
            bound.indexCount = std::uint32_t(lists.lightIndices.size());
            bound.tileSizePx = kAmdTileSizePx;
            ForwardPassOverrides overrides;
            overrides.depthFunc = ComparisonFunc::LessEqual;
            overrides.tileLights = &bound;
            drawForwardPass(*st->setup, *device, *res, rt, transparentPass, stats, variantCounts, overrides);
        };
    };
    const auto withColors = [&ctx](std::vector<std::string> names) {
        return withBackBufferTargets(withReferenceBuffer(std::move(names), ctx.precision), ctx.sampleCount);
    };
    const std::vector<std::string> colors = withColors({back});
    frame.add({"opaque", withColors({back, "depth", "lightgrid.opaque", "lightindex.opaque"}), withColors({back, "depth"}),
               drawPass(false)});
    frame.add({"transparent", withColors({back, "depth", "lightgrid.transparent", "lightindex.transparent"}), colors,
               drawPass(true)});
    if (ctx.sampleCount > 1) frame.add(resolveBackBufferPass(ctx.sampleCount, ctx.precision));
    return frame;
}

} // namespace tessera
