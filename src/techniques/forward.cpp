// The `forward` technique (3dgep article §1.1 "Definitions"; the demo's g_ForwardTechnique in
// 3dgep demo's main.cpp): clear -> opaque pass -> transparent pass, one draw per (instance, primitive) in scene
// order, every enabled light per pixel through the specialized Phong pixel shader.
#include <tessera/techniques/forward.h>

#include <cmath>
#include <memory>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <tessera/errors/input_error.h>
#include <tessera/math/projection_terms.h>
#include <tessera/raster/draw_batch.h>
#include <tessera/shading/phong_material_shader.h>
#include <tessera/techniques/technique_options.h>

namespace tessera {
namespace {

// The demo's transparent blend (3dgep demo's main.cpp alphaBlending: BlendMode(true, false, SrcAlpha,
// OneMinusSrcAlpha) with the BlendMode defaults for alpha: One, Zero, Add).
constexpr RenderTargetBlendDesc kDemoAlphaBlend{true,        Blend::SrcAlpha, Blend::InvSrcAlpha, BlendOp::Add,
                                                Blend::One,  Blend::Zero,     BlendOp::Add,        WriteAll};

template <class T, int kTargets>
void drawItem(DrawBatch& batch, const DrawState& state, const RenderTargets& targets, const PrimitiveBuffer& prim,
              const PhongVS& vs, const PhongMaterial& material, const ForwardPassSetup& setup,
              std::map<std::string, std::uint64_t>* variantCounts, const TileLightList* tileLights) {
    std::span<const ViewLight<T>> lights;
    if constexpr (std::is_same_v<T, float>) lights = setup.lightsExact;
    else lights = setup.lightsReference;
    PhongShaderData<T> shaderData = makePhongShaderData<T>(material, *setup.textures, lights);
    shaderData.tileLights = tileLights;
    if constexpr (std::is_same_v<T, float>) shaderData.fastLights = setup.fastLights.get();
    const PhongShaderData<T>& data = batch.keep(std::move(shaderData));  // read when the batch runs
    const PhongVariant variant = selectPhongVariant<T>(phongFeatures(material, setup.alphaTest));
    PhongShadeFn<T> shade;
    const bool fast = setup.precision == Precision::Fast;
    if constexpr (std::is_same_v<T, float>) shade = fast ? variant.fast : variant.exact;
    else shade = variant.reference;
    if (variantCounts) ++(*variantCounts)[fast ? variant.fastName : variant.name];
    const std::span<const SceneVertex> vertices(prim.vertices);
    if (variant.mayDiscard) batch.draw(state, targets, vertices, prim.indices, vs, PhongPS<T, true, kTargets>{shade, &data});
    else batch.draw(state, targets, vertices, prim.indices, vs, PhongPS<T, false, kTargets>{shade, &data});
}

} // namespace

glm::mat4 projection3dgep(const Camera& camera, float aspect, ProjectionConvention convention) {
    const float a = camera.aspect > 0.0f ? camera.aspect : aspect;
    const float n = camera.nearZ, f = camera.farZ;
    // The demo never had an orthographic camera, so DemoGl has nothing faithful to keep here, and
    // the GL form (orthoRH_NO, z_ndc in [-1, 1]) under D3D11 clipping (0 <= z <= w) would discard
    // the nearer half of the depth range: both conventions take the D3D form.
    if (camera.projection == ProjectionKind::Orthographic)
        return glm::orthoRH_ZO(-camera.xMag, camera.xMag, -camera.yMag, camera.yMag, n, f);
    const float tanHalfFovy = detTan(hlsl::radians(camera.fovYDeg) / 2.0f);
    glm::mat4 p(0.0f);
    p[0][0] = 1.0f / (a * tanHalfFovy);
    p[1][1] = 1.0f / tanHalfFovy;
    p[2][3] = -1.0f;
    const bool infinite = !std::isfinite(f);
    if (convention == ProjectionConvention::DemoGl) {
        // glm 0.9.6.3 perspective: -(f + n) / (f - n), -(2 f n) / (f - n); limits -1, -2n.
        p[2][2] = infinite ? -1.0f : -(f + n) / (f - n);
        p[3][2] = infinite ? -2.0f * n : nearFarTerm(f, n, 2.0f);  // -(2 f n) / (f - n), finite at any world scale
    } else {
        // perspectiveRH_ZO: f / (n - f), -(f n) / (f - n); limits -1, -n.
        p[2][2] = infinite ? -1.0f : f / (n - f);
        p[3][2] = infinite ? -n : nearFarTerm(f, n, 1.0f);  // -(f n) / (f - n), finite at any world scale
    }
    return p;
}

std::shared_ptr<ForwardPassSetup> makeForwardPassSetup(const TechniqueContext& ctx, ProjectionConvention projection,
                                                       PhongSamplerChoice sampler, bool alphaTest) {
    auto setup = std::make_shared<ForwardPassSetup>();
    setup->width = ctx.width;
    setup->height = ctx.height;
    setup->sampleCount = ctx.sampleCount;
    setup->alphaTest = alphaTest;
    setup->notes = ctx.notes;
    setup->precision = ctx.precision;
    setup->viewFromWorld = ctx.camera.viewFromWorld();
    setup->clipFromView = projection3dgep(ctx.camera, float(ctx.width) / float(ctx.height), projection);
    const SceneResources& res = *ctx.resources;
    setup->textures = std::make_unique<PhongTextureSet>(res, sampler);
    // Lights in the scene's order, to view space once per frame (the demo's UpdateLights).
    // Float lights always (the techniques' culling reads them), double ones for reference shading.
    setup->lightsExact = viewLights<float>(ctx.lights(), setup->viewFromWorld);
    if (ctx.precision == Precision::Reference) setup->lightsReference = viewLights<double>(ctx.lights(), setup->viewFromWorld);
    if (ctx.precision == Precision::Fast) setup->fastLights = std::make_shared<const FastLightSet>(FastLightSet::build(setup->lightsExact));
    return setup;
}

void noteAlphaTestOff(const ForwardPassSetup& setup, const PhongMaterial& material) {
    if (!setup.notes || setup.alphaTest || !(phongFeatures(material, true) & kPhongAlphaTest)) return;
    setup.notes->add({"alpha-test-off", "draws of alpha-masked materials shaded without the alpha test (cut-out texels drawn solid)",
                      1, 2, "--option alphaTest=true", true});
}

void drawForwardPass(const ForwardPassSetup& setup, Device& device, const SceneResources& res, const RenderTargets& rt,
                     bool transparentPass, DrawStats* stats, std::map<std::string, std::uint64_t>* variantCounts,
                     const ForwardPassOverrides& overrides) {
    const bool reference = setup.precision == Precision::Reference;
    // The pass's draws binned together (raster/draw_batch.h): they read the scene's textures and
    // the light lists, never the targets they write.
    DrawBatch batch(device);
    for (const DrawItem& item : res.drawItems()) {
        const PhongMaterial material = phongFromGltf(res.material(item.material));
        if (material.isTransparent() != transparentPass) continue;  // the demo's Opaque/TransparentPass
        DrawState st;
        st.viewport = Viewport{0.0f, 0.0f, float(setup.width), float(setup.height), 0.0f, 1.0f};
        st.rasterizer.frontCounterClockwise = item.frontCounterClockwise;
        st.depthStencil.depthFunc = overrides.depthFunc;
        st.precision = setup.precision;
        if (transparentPass) {
            // g_pTransparentPipeline: alpha blending, depth test LESS with writes off, cull none.
            st.rasterizer.cullMode = CullMode::None;
            st.depthStencil.depthWriteEnable = false;
            st.blend.renderTarget[0] = kDemoAlphaBlend;
        } else {
            // g_pOpaquePipeline: D3D11 defaults (depth LESS, writes on, cull back);
            // glTF doubleSided materials are drawn with cull none.
            st.rasterizer.cullMode = material.doubleSided ? CullMode::None : CullMode::Back;
        }
        const glm::mat4 viewFromObject = setup.viewFromWorld * item.worldFromObject;
        const PhongVS vs{setup.clipFromView * viewFromObject, viewFromObject};
        const PrimitiveBuffer& prim = res.primitives()[item.primitive];
        noteAlphaTestOff(setup, material);
        if (reference)
            drawItem<double, 2>(batch, st, rt, prim, vs, material, setup, variantCounts, overrides.tileLights);
        else
            drawItem<float, 1>(batch, st, rt, prim, vs, material, setup, variantCounts, overrides.tileLights);
    }
    batch.runInto(stats);
}

Frame buildForward(const TechniqueContext& ctx) {
    const std::string file = ctx.errorFile();
    const OptionReader options(ctx.options, kForwardOptions, file);
    const std::string projection = options.word("projection");
    const std::string sampler = options.word("sampler");
    const bool alphaTest = options.flag("alphaTest");
    std::shared_ptr<ForwardPassSetup> setup =
        makeForwardPassSetup(ctx, projection == "d3d" ? ProjectionConvention::D3d : ProjectionConvention::DemoGl,
                             sampler == "gltf" ? PhongSamplerChoice::Gltf : PhongSamplerChoice::Demo, alphaTest);

    const bool reference = ctx.precision == Precision::Reference;
    const std::uint32_t samples = ctx.sampleCount;
    Frame frame;
    // With MSAA every target has `samples` samples and the last pass resolves the image.
    const std::string back = backBufferTarget(samples), backReference = referenceBufferTarget(samples);
    const std::vector<std::string> colorBuffers =
        withBackBufferTargets(withReferenceBuffer({std::string(kBackBufferName)}, ctx.precision), samples);
    std::vector<std::string> allBuffers = colorBuffers;
    allBuffers.emplace_back("depth");

    frame.add({"clear", {}, allBuffers, [setup, reference, back, backReference, samples](BufferRegistry& reg) {
                   const std::uint32_t w = setup->width, h = setup->height;
                   reg.create(back, {w, h, Format::R8G8B8A8_UNORM, samples}).clearColor(kDemoClearColor);
                   if (reference) reg.create(backReference, {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(kDemoClearColor);
                   reg.create("depth", {w, h, Format::D24_UNORM_S8_UINT, samples}).clearDepthStencil(true, 1.0f, true, 0);
               }});

    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;
    std::map<std::string, std::uint64_t>* variantCounts = ctx.variantCounts;
    const SceneResources* res = ctx.resources;
    const auto drawPass = [setup, device, stats, variantCounts, res](bool transparentPass) {
        return [setup, device, stats, variantCounts, res, transparentPass](BufferRegistry& reg) {
            drawForwardPass(*setup, *device, *res, forwardPassTargets(*setup, reg), transparentPass, stats, variantCounts);
        };
    };
    std::vector<std::string> drawReads = allBuffers;
    frame.add({"opaque", drawReads, allBuffers, drawPass(false)});
    frame.add({"transparent", drawReads, colorBuffers, drawPass(true)});
    if (samples > 1) frame.add(resolveBackBufferPass(samples, ctx.precision));
    return frame;
}

RenderTargets forwardPassTargets(const ForwardPassSetup& setup, BufferRegistry& registry) {
    RenderTargets rt;
    rt.colors[0] = &registry.get(backBufferTarget(setup.sampleCount));
    if (setup.precision == Precision::Reference) rt.colors[1] = &registry.get(referenceBufferTarget(setup.sampleCount));
    rt.depthStencil = &registry.get("depth");
    return rt;
}

TileLightList bindTileLightList(BufferRegistry& registry, bool transparentPass, std::uint32_t indexCount,
                                std::uint32_t tileSizePx) {
    const std::string which = transparentPass ? "transparent" : "opaque";
    const Surface& grid = registry.get("lightgrid." + which);
    const Surface& list = registry.get("lightindex." + which);
    TileLightList bound;
    bound.grid = grid.bytes().data();
    bound.gridWidth = grid.width();
    bound.gridHeight = grid.height();
    bound.indices = list.bytes().data();
    bound.indexCount = indexCount;
    bound.tileSizePx = tileSizePx;
    return bound;
}

} // namespace tessera
