// Pieces the G-buffer techniques share (deferred-cookbook, deferred-classic, light-prepass): the
// opaque geometry pass through a G-buffer pixel shader fed by the Phong material gather, the
// full-screen quad of the light passes, and forward's transparent pass over the lit image.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <tessera/raster/draw_batch.h>
#include <tessera/shading/phong_surface.h>
#include <tessera/techniques/deferred_states.h>
#include <tessera/techniques/forward.h>

namespace tessera::gbuffer_detail {

// Every opaque draw item (transparent materials are left to the forward pass) drawn with `pass`
// (the item's winding and double-sidedness applied, as forward's opaque pass), through
// PS<mayDiscard> whose `gather` and `data` this sets; `configure(ps)` sets the rest.
// stencilRefFromLightGroups: the stencil reference is each item's light groups (PR&C D3D11
// §11.4.2: "geometry writes ref = the OR of its groups").
template <template <bool> class PS, class Configure>
void drawOpaqueGBuffer(const ForwardPassSetup& f, Device& device, const SceneResources& res, const RenderTargets& rt,
                       const PassState& pass, std::string_view variantPrefix, Configure&& configure, DrawStats* stats,
                       std::map<std::string, std::uint64_t>* variantCounts, bool stencilRefFromLightGroups = false) {
    DrawBatch batch(device);  // every opaque item binned together (raster/draw_batch.h)
    for (const DrawItem& item : res.drawItems()) {
        const PhongMaterial material = phongFromGltf(res.material(item.material));
        if (material.isTransparent()) continue;
        DrawState st = makeDrawState(pass, Viewport{0.0f, 0.0f, float(f.width), float(f.height), 0.0f, 1.0f});
        if (stencilRefFromLightGroups) st.stencilRef = item.lightGroups;
        st.precision = f.precision;
        st.rasterizer.frontCounterClockwise = item.frontCounterClockwise;
        st.rasterizer.cullMode = material.doubleSided ? CullMode::None : CullMode::Back;
        const glm::mat4 viewFromObject = f.viewFromWorld * item.worldFromObject;
        const PhongVS vs{f.clipFromView * viewFromObject, viewFromObject};
        const PrimitiveBuffer& prim = res.primitives()[item.primitive];
        const PhongShaderData<float>& data =
            batch.keep(makePhongShaderData<float>(material, *f.textures, std::span<const ViewLight<float>>()));
        const PhongGatherVariant variant = selectPhongGather(phongFeatures(material, true), variantPrefix);
        if (variantCounts) ++(*variantCounts)[variant.name];
        const auto run = [&](auto ps) {
            ps.gather = variant.fn;
            ps.data = &data;
            configure(ps);
            batch.draw(st, rt, std::span<const SceneVertex>(prim.vertices), prim.indices, vs, ps);
        };
        if (variant.mayDiscard) run(PS<true>{});
        else run(PS<false>{});
    }
    batch.runInto(stats);
}

// A full-screen quad in clip space at z = 0, w = 1, as the triangle strip (-1, 1), (1, 1),
// (-1, -1), (1, -1): two triangles, clockwise on screen (D3D11's default front face).
inline constexpr std::array<glm::vec3, 4> kQuadClip{{{-1.0f, 1.0f, 0.0f}, {1.0f, 1.0f, 0.0f}, {-1.0f, -1.0f, 0.0f}, {1.0f, -1.0f, 0.0f}}};
inline constexpr std::array<std::uint32_t, 6> kQuadIndices{0, 1, 2, 1, 3, 2};  // the strip's second triangle is (v1, v3, v2)

// A stencil test that writes nothing: both faces `func` with KEEP, ReadMask `readMask`, reference `ref`.
inline void stencilTestOnly(PassState& p, ComparisonFunc func, std::uint8_t readMask, std::uint8_t ref) {
    p.depthStencil.stencilEnable = true;
    const StencilFaceDesc face{StencilOp::Keep, StencilOp::Keep, StencilOp::Keep, func};
    p.depthStencil.frontFace = face;
    p.depthStencil.backFace = face;
    p.depthStencil.stencilReadMask = readMask;
    p.depthStencil.stencilWriteMask = 0;
    p.stencilRef = ref;
}
// The stencil mask of lit geometry (PR&C D3D11 §11.4.2; the Cookbook's companion code): the
// G-buffer pass writes 1 under geometry (ALWAYS / REPLACE, ref 1), the light passes test EQUAL 1.
inline void stencilReplaceOne(PassState& p) {
    p.depthStencil.stencilEnable = true;
    const StencilFaceDesc replace{StencilOp::Keep, StencilOp::Keep, StencilOp::Replace, ComparisonFunc::Always};
    p.depthStencil.frontFace = replace;
    p.depthStencil.backFace = replace;
    p.stencilRef = 1;
}
inline void stencilEqualOne(PassState& p) { stencilTestOnly(p, ComparisonFunc::Equal, 0xFF, 1); }
// Light groups (PR&C D3D11 §11.4.2): a light passes where (stored & its groups) != 0, i.e.
// ref 0 LESS (stored & ReadMask) with ReadMask = the light's groups; nothing written.
inline void stencilLightGroups(PassState& p, std::uint8_t lightGroups) {
    stencilTestOnly(p, ComparisonFunc::Less, lightGroups, 0);
}

// The 3dgep G-buffer pass of deferred and tiled-deferred (drawDeferredGBuffer, techniques/deferred.h):
// writes `targets`, RT0 first, then "gbuffer.diffuse", "gbuffer.specular", "gbuffer.normal" and
// optionally "gbuffer.position" (a fifth name binds the position target), and "depth"; with MSAA
// also the edge detectors' two targets (msaa_deferred.h). Defined in deferred.cpp.
Pass deferredGBufferPass(std::shared_ptr<const ForwardPassSetup> forward, const TechniqueContext& ctx,
                         std::vector<std::string> targets, bool floatTargets, bool forwardAlpha);

// Precision reference: the float "accumulation" to the back buffer as an UNORM target stores a PS
// value, and clamped to the reference buffer (every sample; with MSAA the ".msaa" targets).
inline Pass presentAccumulationPass(Precision precision, std::uint32_t sampleCount = 1) {
    const std::string back = backBufferTarget(sampleCount), backReference = referenceBufferTarget(sampleCount);
    return {"present", {"accumulation"}, withBackBufferTargets(withReferenceBuffer({std::string(kBackBufferName)}, precision), sampleCount),
            [back, backReference](BufferRegistry& reg) {
                const Surface& accumulation = reg.get("accumulation");
                storeAsUnorm(accumulation, reg.get(back));
                storeAsUnorm(accumulation, reg.get(backReference));
            }};
}

// Forward's transparent pass over the back buffer (and the reference copy) with the technique's
// depth; with MSAA over their multisampled targets.
inline Pass forwardTransparentPass(std::shared_ptr<const ForwardPassSetup> setup, const TechniqueContext& ctx) {
    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;
    std::map<std::string, std::uint64_t>* variantCounts = ctx.variantCounts;
    const SceneResources* res = ctx.resources;
    const std::vector<std::string> colors = withBackBufferTargets(withReferenceBuffer({std::string(kBackBufferName)}, ctx.precision), ctx.sampleCount);
    std::vector<std::string> reads = colors;
    reads.emplace_back("depth");
    return {"transparent", reads, colors, [setup, device, stats, variantCounts, res](BufferRegistry& reg) {
                drawForwardPass(*setup, *device, *res, forwardPassTargets(*setup, reg), true, stats, variantCounts);
            }};
}

} // namespace tessera::gbuffer_detail
