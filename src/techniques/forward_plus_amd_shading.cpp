// forward-plus-amd's opaque, transparent and indirect passes shaded as ForwardPlus11's RenderScenePS
// (GPU Pro 4 ch. 5 §5.3.2; the lighting itself in shading/amd_lighting.h): each pixel walks its
// tile's point-light then spot-light loop, skips the lights its shadow mask bits mask (§5.6.2) and
// adds the VPLs' diffuse light (§5.5).
#include <tessera/raster/draw_batch.h>

#include "forward_plus_amd_detail.h"

namespace tessera::forward_plus_amd_detail {
namespace {

// The demo's alpha blend (forward.cpp kDemoAlphaBlend): SrcAlpha / InvSrcAlpha, alpha One / Zero.
constexpr RenderTargetBlendDesc kAlphaBlend{true,       Blend::SrcAlpha, Blend::InvSrcAlpha, BlendOp::Add,
                                            Blend::One, Blend::Zero,     BlendOp::Add,        WriteAll};

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

} // namespace

void drawAmdPass(const AmdState& st, Device& device, const SceneResources& res, const RenderTargets& rt, bool transparentPass,
                 DrawStats* stats, bool indirectOnly) {
    const ForwardPassSetup& setup = *st.setup;
    AmdShadeData shade{&st, transparentPass ? &st.transparent : &st.opaque, st.options.halfZ && !transparentPass};
    if (st.shadowsActive && !transparentPass) {
        shade.shadowMask = st.shadowJobs.mask.data();
        shade.maskWidth = setup.width;
        shade.overflowUnlit = st.options.shadowRays.overflow == ShadowOverflow::Unlit;
    }
    if (st.indirectActive) shade.firstIndirect = st.sceneLightCount;
    shade.indirectOnly = indirectOnly;
    DrawBatch batch(device);  // the pass's draws binned together (raster/draw_batch.h)
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
        const PhongShaderData<float>& data = batch.keep(makePhongShaderData<float>(material, *setup.textures, {}));
        const std::span<const SceneVertex> vertices(prim.vertices);
        if (!indirectOnly) noteAlphaTestOff(setup, material);
        const auto draw = [&](const auto& ps) { batch.draw(ds, rt, vertices, prim.indices, vs, ps); };
        if (indirectOnly) {
            if (setup.alphaTest) draw(AmdScenePS<true>{&data, shade, true, false});
            else draw(AmdScenePS<false>{&data, shade, false, false});
        } else if (setup.precision == Precision::Reference) {
            if (setup.alphaTest) draw(AmdScenePS<true, double, 2>{&data, shade, true, transparentPass});
            else draw(AmdScenePS<false, double, 2>{&data, shade, false, transparentPass});
        } else {
            if (setup.alphaTest) draw(AmdScenePS<true>{&data, shade, true, transparentPass});
            else draw(AmdScenePS<false>{&data, shade, false, transparentPass});
        }
    }
    batch.runInto(stats);
}

} // namespace tessera::forward_plus_amd_detail
