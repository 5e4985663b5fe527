// forward-plus's first two passes, shared with forward-plus-amd (addForwardPlusClearAndPrepass):
// "clear" and the demo's depth pre-pass (g_pDepthPrepassPipeline), optionally also writing the
// G-pass world normal (GPU Pro 4 §5.6.2).
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <tessera/raster/draw_batch.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/forward_plus.h>

namespace tessera {
namespace {

// The depth pre-pass pixel shaders: with kAlphaTest, PS_main's alpha and discard; with kNormal,
// GPU Pro 4 §5.6.2's G-pass output, the unit world normal (PhongVS given worldFromObject as its
// "view": normalView is the world normal, as AMD's shading reads it), w = 1. (Neither: no PS.)
template <bool kAlphaTest, bool kNormal>
struct PrepassPS {
    using Varyings = PhongVaryings;
    static constexpr int kTargetCount = kNormal ? 1 : 0;
    static constexpr bool kMayDiscard = kAlphaTest;
    PhongShadeFn<float> shade = nullptr;
    const PhongShaderData<float>* data = nullptr;
    bool reverseBackFaceNormals = false;  // glTF 2.0 §3.9.5 (facingVaryings)
    void operator()(const PixelInput<PhongVaryings>& in, PixelOutput<kTargetCount>& out) const {
        if constexpr (kAlphaTest) {
            Vec4<float> color;
            if (!shade(*data, in, color)) {
                out.discard();
                return;
            }
        }
        if constexpr (kNormal) {
            const glm::vec3 normalWorld = facingVaryings(in.varyings, in.isFrontFace, reverseBackFaceNormals).normalView;
            out.target[0] = glm::vec4(hlsl::normalize(normalWorld), 1.0f);
        }
    }
};

// The demo's depth pre-pass (g_pDepthPrepassPipeline): the opaque items, VS only, depth LESS with
// writes, the opaque pass's culling (cull back; glTF doubleSided: none). With normalWorld, also
// the G-pass normal (PrepassPS<., true>): the same clip positions, so the same depth.
void drawDepthPrepass(const ForwardPassSetup& setup, Device& device, const SceneResources& res, Surface& depthSurface,
                      DrawStats* stats, Surface* normalWorld = nullptr) {
    RenderTargets rt;
    rt.depthStencil = &depthSurface;
    rt.colors[0] = normalWorld;
    DrawBatch batch(device);  // every opaque item binned together (raster/draw_batch.h)
    for (const DrawItem& item : res.drawItems()) {
        const PhongMaterial material = phongFromGltf(res.material(item.material));
        if (material.isTransparent()) continue;
        DrawState st;
        st.viewport = Viewport{0.0f, 0.0f, float(setup.width), float(setup.height), 0.0f, 1.0f};
        st.rasterizer.frontCounterClockwise = item.frontCounterClockwise;
        st.rasterizer.cullMode = material.doubleSided ? CullMode::None : CullMode::Back;
        st.precision = setup.precision;  // the opaque pass's LESS_EQUAL needs the same depth path
        const glm::mat4 viewFromObject = setup.viewFromWorld * item.worldFromObject;
        const PhongVS vs{setup.clipFromView * viewFromObject, normalWorld ? item.worldFromObject : viewFromObject};
        const PrimitiveBuffer& prim = res.primitives()[item.primitive];
        const std::span<const SceneVertex> vertices(prim.vertices);
        const PhongVariant variant = selectPhongVariant<float>(phongFeatures(material, setup.alphaTest));
        if (normalWorld) {
            const PhongShaderData<float>& data = batch.keep(makePhongShaderData<float>(material, *setup.textures, {}));
            const bool reverse = material.reverseBackFaceNormals;
            if (variant.mayDiscard) batch.draw(st, rt, vertices, prim.indices, vs, PrepassPS<true, true>{variant.exact, &data, reverse});
            else batch.draw(st, rt, vertices, prim.indices, vs, PrepassPS<false, true>{nullptr, nullptr, reverse});
        } else if (variant.mayDiscard) {
            const PhongShaderData<float>& data = batch.keep(makePhongShaderData<float>(material, *setup.textures, {}));
            batch.draw(st, rt, vertices, prim.indices, vs, PrepassPS<true, false>{variant.exact, &data});
        } else {
            batch.draw(st, rt, vertices, prim.indices, vs, NoPixelShader{});
        }
    }
    batch.runInto(stats);
}

} // namespace

void addForwardPlusClearAndPrepass(Frame& frame, std::shared_ptr<const ForwardPassSetup> setup, Device* device,
                                   const SceneResources* resources, DrawStats* stats, bool writeNormals) {
    const std::uint32_t samples = setup->sampleCount;
    const std::string back = backBufferTarget(samples), backReference = referenceBufferTarget(samples);
    std::vector<std::string> cleared{back, "depth"};
    if (setup->precision == Precision::Reference) cleared.push_back(backReference);
    if (writeNormals) cleared.emplace_back("gbuffer.normal");
    frame.add({"clear", {}, cleared, [setup, samples, back, backReference, writeNormals](BufferRegistry& reg) {
                   const std::uint32_t w = setup->width, h = setup->height;
                   reg.create(back, {w, h, Format::R8G8B8A8_UNORM, samples}).clearColor(kDemoClearColor);
                   if (setup->precision == Precision::Reference)
                       reg.create(backReference, {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(kDemoClearColor);
                   reg.create("depth", {w, h, Format::D24_UNORM_S8_UINT, samples}).clearDepthStencil(true, 1.0f, true, 0);
                   if (writeNormals)
                       reg.create("gbuffer.normal", {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(glm::vec4(0.0f));
               }});
    std::vector<std::string> prepassIo{"depth"};
    if (writeNormals) prepassIo.emplace_back("gbuffer.normal");
    frame.add({"depth-prepass", prepassIo, prepassIo, [setup, device, resources, stats, writeNormals](BufferRegistry& reg) {
                   drawDepthPrepass(*setup, *device, *resources, reg.get("depth"), stats,
                                    writeNormals ? &reg.get("gbuffer.normal") : nullptr);
               }});
}

} // namespace tessera
