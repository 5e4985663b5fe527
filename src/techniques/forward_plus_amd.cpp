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

#include <tessera/errors/input_error.h>
#include <tessera/culling/depth_mask.h>
#include <tessera/math/det_math.h>
#include <tessera/gbuffer/screen_to_view.h>
#include <tessera/culling/tile_frustum.h>
#include <tessera/shading/phong_surface.h>
#include <tessera/shading/amd_lighting.h>
#include <tessera/shading/phong_material_shader.h>
#include <tessera/raytrace/shadow_ray_scene.h>
#include <tessera/shading/tile_heat_colors.h>
#include <tessera/techniques/amd_light_culling.h>
#include <tessera/techniques/amd_shadow_rays.h>
#include <tessera/techniques/amd_vpl.h>
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
    std::string shadows = "auto";   // "auto" | "on" | "off"
    ShadowRayOptions shadowRays;
    std::string indirect = "auto";  // "auto" | "on" | "off"
    VplOptions vpl;
};

AmdOptions parseOptions(const TechniqueContext& ctx, const std::string& file) {
    const OptionReader r(ctx.options, kForwardPlusAmdOptions, file);
    AmdOptions o;
    o.shadingAmd = r.is("shading", "amd");
    o.depthMask = r.is("culling", "depth-mask");
    o.halfZ = r.flag("halfZ");
    if (o.halfZ && !o.shadingAmd)
        throw inputError(file, "/options/halfZ",
                         "halfZ needs \"shading\": \"amd\" (the 3dgep pixel shader reads one list per tile)");
    // projection's default follows the shading: d3d (AMD's sample), demo-gl (the 3dgep demo's).
    const bool d3d = r.given("projection") ? r.is("projection", "d3d") : o.shadingAmd;
    o.projection = d3d ? ProjectionConvention::D3d : ProjectionConvention::DemoGl;
    o.sampler = r.is("sampler", "gltf") ? PhongSamplerChoice::Gltf : PhongSamplerChoice::Demo;
    o.alphaTest = r.flag("alphaTest");
    o.lightLoop = r.is("lightLoop", "binned") ? AmdLightLoop::Binned : AmdLightLoop::AllLights;
    o.shadows = r.word("shadows");
    o.shadowRays.normalOffset = float(r.number("shadowNormalOffset"));
    o.shadowRays.backfaces = r.is("shadowBackfaces", "mask")  ? ShadowBackfaces::Mask
                             : r.is("shadowBackfaces", "lit") ? ShadowBackfaces::Lit
                                                              : ShadowBackfaces::Cast;
    o.shadowRays.overflow = r.is("shadowOverflow", "lit") ? ShadowOverflow::Lit : ShadowOverflow::Unlit;
    o.indirect = r.word("indirect");
    o.vpl.rsmSize = std::uint32_t(r.integer("rsmSize"));
    // vplGrid's default: 16, or the RSM's size when that is smaller.
    o.vpl.grid = r.given("vplGrid") ? std::uint32_t(r.integer("vplGrid")) : std::min<std::uint32_t>(16, o.vpl.rsmSize);
    o.vpl.coneDeg = float(r.number("vplConeDeg"));
    o.vpl.range = float(r.number("vplRange"));
    o.vpl.intensity = float(r.number("vplIntensity"));
    o.vpl.direction = r.is("vplDirection", "reflect") ? VplDirection::Reflect : VplDirection::Normal;
    o.vpl.normalOffset = float(r.number("vplOffset"));
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
    // GPU Pro 4 §5.6.2 (shadowsActive): the lights as job creation sees them (scene lights, then
    // VPLs that never cast), the pixels it reads, and the jobs and mask it makes.
    bool shadowsActive = false;
    std::vector<ShadowCaster> casters;
    std::vector<float> depthWindow;
    std::vector<glm::vec4> normalWorld;
    glm::dmat4 worldFromClip{1.0};
    ShadowJobs shadowJobs;
    // §5.5 (indirectActive): the indirect light, its RSM view; lights [sceneLightCount, ...) are VPLs.
    bool indirectActive = false;
    Light indirectLight;
    RsmView rsm;
    std::uint32_t sceneLightCount = 0;
    // What "auto" turned off in this configuration, noted every frame (the cull pass adds them).
    std::vector<FrameNote> configurationNotes;
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

// ----- AMD shading (ForwardPlus11 RenderScenePS, amd_lighting.h) --------------------------------

struct AmdShadeData {
    const AmdState* state = nullptr;
    const AmdTileLightLists* lists = nullptr;
    bool halfZ = false;
    // GPU Pro 4 §5.6.2: the pixel's int4 mask (kShadowMaskWords per pixel, row-major, maskWidth
    // pixels a row); a set bit masks the light of that slot. Null: no shadows (transparent pass).
    const std::uint32_t* shadowMask = nullptr;
    std::uint32_t maskWidth = 0;
    bool overflowUnlit = false;  // slots >= 128 masked (ShadowOverflow::Unlit)
    // §5.5: lights from firstIndirect on are VPLs (isIndirectLight); indirectOnly: the pass that
    // writes the indirect contribution alone.
    std::uint32_t firstIndirect = std::numeric_limits<std::uint32_t>::max();
    bool indirectOnly = false;
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
        // glTF 2.0 §3.9.5: a double-sided material's back face is lit with the reversed normal.
        const glm::vec3 normalWorldFacing = facingVaryings(in.varyings, in.isFrontFace, material->reverseBackFaceNormals).normalView;
        const Vec3<T> normalWorld = hlsl::normalize(Vec3<T>(normalWorldFacing));
        const Vec3<T> viewDir = amdViewDir(Vec3<T>(shade.state->cameraPosWorld), posWorld);

        // GetTileIndex: floor(x / 8) + floor(y / 8) * numTilesX.
        const AmdTileLightLists& lists = *shade.lists;
        const auto tileX = std::uint32_t(std::floor(in.posWindow.x / float(kAmdTileSizePx)));
        const auto tileY = std::uint32_t(std::floor(in.posWindow.y / float(kAmdTileSizePx)));
        AmdLightingResult<T> accum;
        Vec3<T> indirect(T(0));  // the VPLs' diffuse light
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
            const std::uint32_t* mask = nullptr;
            if (shade.shadowMask)
                mask = shade.shadowMask + (std::size_t(in.posWindow.y) * shade.maskWidth + std::size_t(in.posWindow.x)) * kShadowMaskWords;
            const auto shadowed = [&](std::uint32_t slot) {
                if (!mask) return false;
                if (slot >= kShadowMaxSlots) return shade.overflowUnlit;
                return shadowMaskBit(std::span<const std::uint32_t, kShadowMaskWords>(mask, kShadowMaskWords), slot);
            };
            for (std::uint32_t slot = 0; slot < list.size(); ++slot) {  // the point-light loop
                const std::uint32_t index = list[slot];
                if (table.kind[index] != AmdKind::Point || shade.indirectOnly || shadowed(slot)) continue;
                const AmdPointLight<float>& p = table.points[index];
                const AmdPointLight<T> light{Vec3<T>(p.centerWorld), T(p.radius), Vec3<T>(p.color)};
                const AmdLightingResult<T> r = amdPointLight(light, posWorld, normalWorld, viewDir);
                accum.diffuse += r.diffuse;
                accum.specular += r.specular;
                if (trace) [[unlikely]] trace->push_back(amdDescribePoint(index, light, posWorld, normalWorld, r));
            }
            for (std::uint32_t slot = 0; slot < list.size(); ++slot) {  // the spot-light loop
                const std::uint32_t index = list[slot];
                if (table.kind[index] != AmdKind::Spot) continue;
                const bool indirectLight = index >= shade.firstIndirect;  // isIndirectLight
                if (shade.indirectOnly && !indirectLight) continue;
                if (!indirectLight && shadowed(slot)) continue;
                const AmdSpotLight<float>& sp = table.spots[index];
                const AmdSpotLight<T> light{Vec3<T>(sp.boundingCenterWorld), T(sp.boundingRadius), Vec3<T>(sp.color),
                                            Vec4<T>(sp.spotParams)};
                const AmdLightingResult<T> r = amdSpotLight(light, posWorld, normalWorld, viewDir);
                if (indirectLight) {  // FetchIndirectLight: diffuse only (a VPL stands for a diffuse reflector)
                    indirect += r.diffuse;
                    continue;
                }
                accum.diffuse += r.diffuse;
                accum.specular += r.specular;
                if (trace) [[unlikely]] trace->push_back(amdDescribeSpot(index, light, posWorld, normalWorld, r));
            }
        }
        const Vec3<T> albedo{glm::vec3(diffuseTex)};
        if (shade.indirectOnly) {
            out.target[0] = glm::vec4(glm::vec3(albedo * indirect), 1.0f);
            return;
        }
        Vec3<T> rgb = amdComposePixel(accum, normalWorld, albedo, specMask, Vec3<T>(kAmdAmbientUp), Vec3<T>(kAmdAmbientDown));
        // One-bounce light: DiffuseTex * the VPLs' diffuse, added after AMD's composition (without
        // VPLs nothing is added: the image keeps forward-plus-amd's bits).
        if (shade.firstIndirect < shade.state->table.kind.size()) rgb = rgb + albedo * indirect;
        out.target[0] = glm::vec4(glm::vec3(rgb), blended ? alpha * material->opacity : 1.0f);
        if constexpr (kTargets == 2) out.target[1] = convert::clampUnorm(out.target[0]);
    }
};

// The opaque or transparent pass, or (indirectOnly) the opaque geometry again writing only the
// VPLs' contribution (float at every precision, into the one target of `rt`).
void drawAmdPass(const AmdState& st, Device& device, const SceneResources& res, const RenderTargets& rt, bool transparentPass,
                 DrawStats* stats, bool indirectOnly = false) {
    const ForwardPassSetup& setup = *st.setup;
    AmdShadeData shade{&st, transparentPass ? &st.transparent : &st.opaque, st.options.halfZ && !transparentPass};
    if (st.shadowsActive && !transparentPass) {
        shade.shadowMask = st.shadowJobs.mask.data();
        shade.maskWidth = setup.width;
        shade.overflowUnlit = st.options.shadowRays.overflow == ShadowOverflow::Unlit;
    }
    if (st.indirectActive) shade.firstIndirect = st.sceneLightCount;
    shade.indirectOnly = indirectOnly;
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
            ds.depthStencil.depthWriteEnable = !indirectOnly;
        }
        ds.precision = setup.precision;  // the pre-pass's depth path (LESS_EQUAL)
        // The clip matrix exactly as the pre-pass forms it (same depth values: LESS_EQUAL passes).
        const glm::mat4 viewFromObject = setup.viewFromWorld * item.worldFromObject;
        const PhongVS vs{setup.clipFromView * viewFromObject, item.worldFromObject};
        const PrimitiveBuffer& prim = res.primitives()[item.primitive];
        const PhongShaderData<float> data = makePhongShaderData<float>(material, *setup.textures, {});
        const std::span<const SceneVertex> vertices(prim.vertices);
        if (!indirectOnly) noteAlphaTestOff(setup, material);
        DrawStats s;
        if (indirectOnly)
            s = setup.alphaTest ? device.draw(ds, rt, vertices, prim.indices, vs, AmdScenePS<true>{&data, shade, true, false})
                                : device.draw(ds, rt, vertices, prim.indices, vs, AmdScenePS<false>{&data, shade, false, false});
        else if (setup.precision == Precision::Reference)
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

// ----- GPU Pro 4 §5.5: the reflective shadow map and its VPLs ---------------------------------

// The RSM's three targets (Dachsbacher and Stamminger 2005): world position (w = 1), unit world
// normal (w = 1), reflected flux = DiffuseTex.rgb x the light's colour x intensity (w = 1).
// PhongVS with worldFromObject as its "view": posView / normalView are world space.
struct RsmPS {
    using Varyings = PhongVaryings;
    static constexpr int kTargetCount = 3;
    const PhongShaderData<float>* material = nullptr;
    glm::vec3 lightColor{1.0f};
    void operator()(const PixelInput<PhongVaryings>& in, PixelOutput<3>& out) const {
        glm::vec4 diffuseTex = material->diffuseColor;
        if (material->diffuseTexture.bound()) diffuseTex = phong_detail::textureRule(diffuseTex, material->diffuseTexture.sample(in));
        out.target[0] = glm::vec4(in.varyings.posView, 1.0f);
        // glTF 2.0 §3.9.5: a double-sided back face seen by the light reflects along its reversed normal.
        out.target[1] = glm::vec4(hlsl::normalize(facingVaryings(in.varyings, in.isFrontFace, material->reverseBackFaceNormals).normalView), 1.0f);
        out.target[2] = glm::vec4(glm::vec3(diffuseTex) * lightColor, 1.0f);
    }
};

// The "rsm" pass: the opaque draw items from the indirect light (rsmView), depth LESS with
// writes into "rsm.depth" (D32_FLOAT), each material's culling, precision exact.
void drawRsm(const AmdState& st, Device& device, const SceneResources& res, BufferRegistry& reg, DrawStats* stats) {
    const std::uint32_t size = st.options.vpl.rsmSize;
    RenderTargets rt;
    rt.colors[0] = &reg.create("rsm.position", {size, size, Format::R32G32B32A32_FLOAT, 1});
    rt.colors[1] = &reg.create("rsm.normal", {size, size, Format::R32G32B32A32_FLOAT, 1});
    rt.colors[2] = &reg.create("rsm.color", {size, size, Format::R32G32B32A32_FLOAT, 1});
    for (int i = 0; i < 3; ++i) rt.colors[i]->clearColor(glm::vec4(0.0f));
    rt.depthStencil = &reg.create("rsm.depth", {size, size, Format::D32_FLOAT, 1});
    rt.depthStencil->clearDepthStencil(true, 1.0f, false, 0);
    const glm::vec3 lightColor = st.indirectLight.color * st.indirectLight.intensity;
    for (const DrawItem& item : res.drawItems()) {
        const PhongMaterial material = phongFromGltf(res.material(item.material));
        if (material.isTransparent()) continue;
        DrawState ds;
        ds.viewport = Viewport{0.0f, 0.0f, float(size), float(size), 0.0f, 1.0f};
        ds.rasterizer.frontCounterClockwise = item.frontCounterClockwise;
        ds.rasterizer.cullMode = material.doubleSided ? CullMode::None : CullMode::Back;
        const PhongVS vs{st.rsm.clipFromWorld * item.worldFromObject, item.worldFromObject};
        const PrimitiveBuffer& prim = res.primitives()[item.primitive];
        const PhongShaderData<float> data = makePhongShaderData<float>(material, *st.setup->textures, {});
        const DrawStats s = device.draw(ds, rt, std::span<const SceneVertex>(prim.vertices), prim.indices, vs, RsmPS{&data, lightColor});
        if (stats) *stats += s;
    }
}

// The "vpl" pass (§5.1 step 2): N x N VPLs from the RSM, appended after the scene's lights to the
// culling spheres, the shading table and the casters (they cast no shadows); "vpl.position"
// (w = 1 valid, 0 empty texel), "vpl.direction" (w = cos of the cone), "vpl.color" (w = range).
void makeVpls(AmdState& st, BufferRegistry& reg) {
    const VplOptions& o = st.options.vpl;
    const std::vector<Vpl> vpls = vplsFromRsm(reg.get("rsm.position"), reg.get("rsm.normal"), reg.get("rsm.color"), st.rsm, o);
    std::vector<Light> lights;
    lights.reserve(vpls.size());
    for (const Vpl& v : vpls) lights.push_back(vplLight(v, o));
    const std::vector<ViewLight<float>> view = viewLights<float>(lights, st.setup->viewFromWorld);
    const std::size_t first = st.sceneLightCount, n = first + vpls.size();
    st.spheresViewLh.resize(n);
    st.table.kind.resize(first);  // a frame that runs again starts from the scene's lights
    st.table.kind.resize(n, AmdKind::None);
    st.table.points.resize(n);
    st.table.spots.resize(n);
    st.casters.resize(first);
    st.casters.resize(n);
    for (std::size_t i = 0; i < vpls.size(); ++i) convertLight(st, first + i, view[i], lights[i]);
    const std::uint32_t grid = o.grid;
    Surface& position = reg.create("vpl.position", {grid, grid, Format::R32G32B32A32_FLOAT, 1});
    Surface& direction = reg.create("vpl.direction", {grid, grid, Format::R32G32B32A32_FLOAT, 1});
    Surface& color = reg.create("vpl.color", {grid, grid, Format::R32G32B32A32_FLOAT, 1});
    const float cosCone = detCos(hlsl::radians(o.coneDeg));
    for (std::uint32_t j = 0; j < grid; ++j)
        for (std::uint32_t i = 0; i < grid; ++i) {
            const Vpl& v = vpls[std::size_t{j} * grid + i];
            const glm::vec4 values[3] = {glm::vec4(v.positionWorld, v.valid ? 1.0f : 0.0f), glm::vec4(v.directionWorld, cosCone),
                                         glm::vec4(v.color, o.range)};
            std::memcpy(position.texel(i, j), &values[0], sizeof(glm::vec4));
            std::memcpy(direction.texel(i, j), &values[1], sizeof(glm::vec4));
            std::memcpy(color.texel(i, j), &values[2], sizeof(glm::vec4));
        }
}

// ----- GPU Pro 4 §5.6.2: ray-cast shadows --------------------------------------------------------

ShadowPixels shadowPixelsOf(const AmdState& st) {
    return ShadowPixels{st.setup->width, st.setup->height, st.depthWindow, st.normalWorld, st.worldFromClip};
}

// "shadow-jobs": reads the G-pass (the depth as the culling pass decoded it into st.depthWindow,
// the normal) and the opaque lists, writes "shadow.jobs" (R32_UINT, the job buffer laid out as
// the light index pool).
void createJobsPass(AmdState& st, Device& device, BufferRegistry& reg) {
    const Surface& normal = reg.get("gbuffer.normal");
    st.normalWorld.resize(std::size_t{st.setup->width} * st.setup->height);
    device.execute([&] {
        std::memcpy(st.normalWorld.data(), normal.bytes().data(), st.normalWorld.size() * sizeof(glm::vec4));
        st.shadowJobs = createShadowJobs(shadowPixelsOf(st), st.opaque, st.casters, st.options.shadowRays);
    });
    Surface& jobs = reg.create("shadow.jobs", indexListDesc(st.shadowJobs.jobs.size()));
    if (!st.shadowJobs.jobs.empty())
        std::memcpy(jobs.bytes().data(), st.shadowJobs.jobs.data(), st.shadowJobs.jobs.size() * sizeof(std::uint32_t));
}

// "shadow-rays": one Embree occlusion ray per job into "shadow.mask" (R32G32B32A32_UINT per
// pixel) and "shadow.counters" (R32_UINT x 5: jobs, occluded, backface-masked, overflow pixels,
// overflow lights).
void castRaysPass(AmdState& st, Device& device, const SceneResources& res, BufferRegistry& reg) {
    const ShadowRayScene& occluders = shadowRaySceneOf(res);
    device.execute([&] { castShadowJobs(shadowPixelsOf(st), st.opaque, st.casters, occluders, st.options.shadowRays, st.shadowJobs); });
    Surface& mask = reg.create("shadow.mask", {st.setup->width, st.setup->height, Format::R32G32B32A32_UINT, 1});
    std::memcpy(mask.bytes().data(), st.shadowJobs.mask.data(), st.shadowJobs.mask.size() * sizeof(std::uint32_t));
    const ShadowJobStats& c = st.shadowJobs.stats;
    const std::array<std::uint64_t, 5> values{c.jobs, c.occluded, c.backfaceMasked, c.overflowPixels, c.overflowLights};
    Surface& counters = reg.create("shadow.counters", {5, 1, Format::R32_UINT, 1});
    for (std::size_t i = 0; i < values.size(); ++i)
        storeUint32(counters.bytes().data(), i, std::uint32_t(std::min<std::uint64_t>(values[i], 0xFFFFFFFFu)));
    if (FrameNotes* notes = st.setup->notes) {
        const bool lit = st.options.shadowRays.overflow == ShadowOverflow::Lit;
        notes->add({"shadow-mask-overflow",
                    std::string("pixel-light pairs past the 128-slot shadow mask, which has no bit for them: ") +
                        (lit ? "lit without a shadow test" : "dropped (unlit)"),
                    c.overflowLights, 31, lit ? "--option shadowOverflow=unlit" : "--option shadowOverflow=lit", true});
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
    const std::vector<Light>& sceneLights = ctx.lights();
    convertLights(*st, sceneLights);
    st->sceneLightCount = std::uint32_t(sceneLights.size());

    // GPU Pro 4 §5.6.2 / §5.5: only what the scene asks for (a scene without shadow-casting or
    // indirect lights runs the plain passes).
    st->casters.resize(sceneLights.size());
    bool anyCaster = false;
    for (std::size_t i = 0; i < sceneLights.size(); ++i) {
        const Light& l = sceneLights[i];
        ShadowCaster& c = st->casters[i];
        c.positionWorld = l.positionWorld;
        c.directionWorld = l.directionWorld;
        c.range = l.range;
        if (l.type == LightType::Spot) c.cosCone = detCos(hlsl::radians(l.spotHalfAngleDeg));
        c.castsShadows = l.castsShadows && l.enabled && (l.type == LightType::Point || l.type == LightType::Spot);
        anyCaster = anyCaster || c.castsShadows;
    }
    // "auto": what the scene asks for, where this configuration can do it; "on": the same, but a
    // scene or configuration that cannot is an InputError naming the reason.
    const Light* indirectLight = nullptr;
    for (const Light& l : sceneLights)
        if (l.indirect && l.enabled && !indirectLight) indirectLight = &l;
    const bool shadowsOn = st->options.shadows == "on", indirectOn = st->options.indirect == "on";
    std::string shadowBlocker, indirectBlocker;  // why not, in this configuration
    if (!anyCaster) shadowBlocker = "the scene marks no shadow-casting point or spot light (\"shadowCasters\")";
    else if (!st->options.shadingAmd) shadowBlocker = "ray-cast shadows are shaded by \"shading\": \"amd\"";
    else if (st->options.halfZ) shadowBlocker = "ray-cast shadows index the single opaque list per tile: halfZ must be false";
    else if (ctx.sampleCount > 1)
        shadowBlocker = "ray-cast shadows need 1 sample per pixel (the G-pass normal and the shadow mask are per pixel)";
    if (!indirectLight) indirectBlocker = "the scene has no light with \"indirect\": true";
    else if (!st->options.shadingAmd) indirectBlocker = "VPLs are shaded by \"shading\": \"amd\"";
    if (shadowsOn && !shadowBlocker.empty()) throw inputError(file, "/options/shadows", "\"on\", but " + shadowBlocker);
    if (indirectOn && !indirectBlocker.empty()) throw inputError(file, "/options/indirect", "\"on\", but " + indirectBlocker);
    if (st->options.shadows == "auto" && anyCaster && !shadowBlocker.empty()) {
        const auto casters = std::count_if(sceneLights.begin(), sceneLights.end(), [](const Light& l) {
            return l.castsShadows && l.enabled && (l.type == LightType::Point || l.type == LightType::Spot);
        });
        st->configurationNotes.push_back({"shadows-auto-off", "shadow-casting lights lit without ray-cast shadows (\"shadows\": \"auto\"): " + shadowBlocker,
                                          std::uint64_t(casters), 0, "", true});
    }
    if (st->options.indirect == "auto" && indirectLight && !indirectBlocker.empty())
        st->configurationNotes.push_back({"indirect-auto-off", "indirect lights without VPLs (\"indirect\": \"auto\"): " + indirectBlocker, 1, 0, "", true});
    st->shadowsActive = st->options.shadows != "off" && shadowBlocker.empty();
    st->indirectActive = st->options.indirect != "off" && indirectBlocker.empty();
    if (st->indirectActive) st->indirectLight = *indirectLight;
    if (st->shadowsActive) {
        if (std::uint64_t{ctx.width} * ctx.height > kShadowMaxPixels)
            throw inputError(file, "/options/shadows",
                             std::to_string(ctx.width) + " x " + std::to_string(ctx.height) +
                                 " pixels exceed the shadow job's 25-bit pixel index (2^25 = 33,554,432 pixels)");
        st->worldFromClip = glm::inverse(glm::dmat4(st->setup->clipFromView) * glm::dmat4(st->setup->viewFromWorld));
        (void)shadowRaySceneOf(*ctx.resources);  // the BVH: built once per scene, here rather than inside a timed pass
    }
    if (st->indirectActive && st->options.vpl.grid > st->options.vpl.rsmSize)
        throw inputError(file, "/options/vplGrid",
                         std::to_string(st->options.vpl.grid) + " VPLs per side need an RSM of at least as many texels (rsmSize " +
                             std::to_string(st->options.vpl.rsmSize) + ")");
    if (st->indirectActive) st->rsm = rsmView(st->indirectLight, ctx.resources->scene().bounds());

    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;
    std::map<std::string, std::uint64_t>* variantCounts = ctx.variantCounts;
    const SceneResources* res = ctx.resources;
    const std::string back(kBackBufferName);

    Frame frame;
    if (st->indirectActive) {
        frame.add({"rsm", {}, {"rsm.position", "rsm.normal", "rsm.color", "rsm.depth"},
                   [st, device, res, stats](BufferRegistry& reg) { drawRsm(*st, *device, *res, reg, stats); }});
        frame.add({"vpl", {"rsm.position", "rsm.normal", "rsm.color"}, {"vpl.position", "vpl.direction", "vpl.color"},
                   [st](BufferRegistry& reg) { makeVpls(*st, reg); }});
    }
    addForwardPlusClearAndPrepass(frame, st->setup, device, res, stats, st->shadowsActive);
    std::vector<std::string> cullWrites{"lightgrid.opaque",  "lightindex.opaque", "lightgrid.transparent",
                                        "lightindex.transparent", "tiles.depthRange", "tiles.depthMask",
                                        "heatmap.radar",     "lightlist.counters"};
    if (st->options.halfZ) cullWrites.emplace_back("lightgrid.opaque.far");
    frame.add({"light-culling", {"depth"}, cullWrites, [st, device](BufferRegistry& reg) { cullAll(*st, *device, reg); }});
    if (st->shadowsActive) {
        frame.add({"shadow-jobs", {"depth", "gbuffer.normal", "lightgrid.opaque", "lightindex.opaque"}, {"shadow.jobs"},
                   [st, device](BufferRegistry& reg) { createJobsPass(*st, *device, reg); }});
        frame.add({"shadow-rays", {"shadow.jobs", "depth", "gbuffer.normal", "lightgrid.opaque", "lightindex.opaque"},
                   {"shadow.mask", "shadow.counters"},
                   [st, device, res](BufferRegistry& reg) { castRaysPass(*st, *device, *res, reg); }});
    }
    const auto drawPass = [st, device, stats, variantCounts, res](bool transparentPass) {
        return [st, device, stats, variantCounts, res, transparentPass](BufferRegistry& reg) {
            const RenderTargets rt = forwardPassTargets(*st->setup, reg);
            if (st->options.shadingAmd) {
                drawAmdPass(*st, *device, *res, rt, transparentPass, stats);
                return;
            }
            const AmdTileLightLists& lists = transparentPass ? st->transparent : st->opaque;
            TileLightList& bound = transparentPass ? st->transparentList : st->opaqueList;
            bound = bindTileLightList(reg, transparentPass, std::uint32_t(lists.lightIndices.size()), kAmdTileSizePx);
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
    std::vector<std::string> opaqueReads = withColors({back, "depth", "lightgrid.opaque", "lightindex.opaque"});
    if (st->shadowsActive) opaqueReads.emplace_back("shadow.mask");
    frame.add({"opaque", opaqueReads, withColors({back, "depth"}), drawPass(false)});
    if (st->indirectActive)  // the VPLs' contribution alone, DiffuseTex * their diffuse light (float)
        frame.add({"indirect", {"depth", "lightgrid.opaque", "lightindex.opaque"}, {"indirect"},
                   [st, device, stats, res](BufferRegistry& reg) {
                       RenderTargets rt;
                       rt.colors[0] = &reg.create("indirect", {st->setup->width, st->setup->height, Format::R32G32B32A32_FLOAT,
                                                               st->setup->sampleCount});
                       rt.colors[0]->clearColor(glm::vec4(0.0f));
                       rt.depthStencil = &reg.get("depth");
                       drawAmdPass(*st, *device, *res, rt, false, stats, true);
                   }});
    frame.add({"transparent", withColors({back, "depth", "lightgrid.transparent", "lightindex.transparent"}), colors,
               drawPass(true)});
    if (ctx.sampleCount > 1) frame.add(resolveBackBufferPass(ctx.sampleCount, ctx.precision));
    return frame;
}

} // namespace tessera
