// The `forward-plus-amd` technique (GPU Pro 4 ch. 5; ForwardPlus11, TiledLighting11): clear -> depth
// pre-pass (forward-plus's) -> light culling -> [shadow jobs -> shadow rays] -> opaque -> [indirect]
// -> transparent, shaded with AMD's lighting or forward's Phong passes reading the AMD lists. This file
// reads the options and builds the frame; the passes are in forward_plus_amd_*.cpp.
#include <tessera/techniques/forward_plus_amd.h>

#include "forward_plus_amd_detail.h"

namespace tessera {

using namespace forward_plus_amd_detail;

namespace {

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

} // namespace

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
                   [st, device, res, stats](BufferRegistry& reg) { drawRsm(*st, *device, *res, reg, stats); },
                   {"rsm.depth"}});  // the RSM draw's own depth target
        frame.add({"vpl", {"rsm.position", "rsm.normal", "rsm.color"}, {"vpl.position", "vpl.direction", "vpl.color"},
                   [st](BufferRegistry& reg) { makeVpls(*st, reg); }});
    }
    addForwardPlusClearAndPrepass(frame, st->setup, device, res, stats, st->shadowsActive);
    std::vector<std::string> cullWrites{"lightgrid.opaque",  "lightindex.opaque", "lightgrid.transparent",
                                        "lightindex.transparent", "tiles.depthRange", "tiles.depthMask",
                                        "heatmap.radar",     "lightlist.counters"};
    if (st->options.halfZ) cullWrites.emplace_back("lightgrid.opaque.far");
    // The culling's per-tile results that no later pass reads: depth bounds, 2.5D masks, the radar
    // heat map and the list counters.
    // The VPLs join the light arrays that the culling takes (the vpl.* buffers hold the same lights).
    std::vector<std::string> cullReads{"depth"};
    if (st->indirectActive) cullReads.insert(cullReads.end(), {"vpl.position", "vpl.direction", "vpl.color"});
    frame.add({"light-culling", cullReads, cullWrites, [st, device](BufferRegistry& reg) { cullAll(*st, *device, reg); },
               {"tiles.depthRange", "tiles.depthMask", "heatmap.radar", "lightlist.counters"}});
    if (st->shadowsActive) {
        frame.add({"shadow-jobs", {"depth", "gbuffer.normal", "lightgrid.opaque", "lightindex.opaque"}, {"shadow.jobs"},
                   [st, device](BufferRegistry& reg) { createJobsPass(*st, *device, reg); }});
        frame.add({"shadow-rays", {"shadow.jobs", "depth", "gbuffer.normal", "lightgrid.opaque", "lightindex.opaque"},
                   {"shadow.mask", "shadow.counters"},
                   [st, device, res](BufferRegistry& reg) { castRaysPass(*st, *device, *res, reg); },
                   {"shadow.counters"}});  // --stats prints them
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
    if (st->options.halfZ) opaqueReads.emplace_back("lightgrid.opaque.far");  // Half-Z shades from both lists
    frame.add({"opaque", opaqueReads, withColors({back, "depth"}), drawPass(false)});
    // The VPLs' contribution alone, DiffuseTex * their diffuse light (float), drawn again beside the
    // image (which holds it summed with the direct light) to be looked at: an inspection pass.
    if (st->indirectActive)
        frame.add({"indirect", {"depth", "lightgrid.opaque", "lightindex.opaque"}, {"indirect"},
                   [st, device, stats, res](BufferRegistry& reg) {
                       RenderTargets rt;
                       rt.colors[0] = &reg.create("indirect", {st->setup->width, st->setup->height, Format::R32G32B32A32_FLOAT,
                                                               st->setup->sampleCount});
                       rt.colors[0]->clearColor(glm::vec4(0.0f));
                       rt.depthStencil = &reg.get("depth");
                       drawAmdPass(*st, *device, *res, rt, false, stats, true);
                   },
                   {"indirect"}});
    frame.add({"transparent", withColors({back, "depth", "lightgrid.transparent", "lightindex.transparent"}), colors,
               drawPass(true)});
    if (ctx.sampleCount > 1) frame.add(resolveBackBufferPass(ctx.sampleCount, ctx.precision));
    return frame;
}

} // namespace tessera
