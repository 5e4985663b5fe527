// The `light-prepass` technique (techniques/light_prepass.h; PR&C D3D11 ch. 11 §11.3): clear ->
// G-buffer (Listing 11.4) -> lights into the light buffer (Listing 11.5; prc_light_pass.h) -> the
// opaque geometry again (Listing 11.6, "final") -> forward's transparent pass.
#include <tessera/techniques/light_prepass.h>

#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include <tessera/buffers/conversion.h>
#include <tessera/techniques/technique_options.h>

#include "gbuffer_pass.h"
#include "msaa_deferred.h"
#include "prc_light_pass.h"

namespace tessera {
namespace {

// Listing 11.4's PS (light pre-pass): (normalize(NormalWS), SpecularPower), (PositionWS, 1).
struct LppEncoder {
    static constexpr int kTargetCount = 2;
    glm::mat4 worldFromView{1.0f};
    template <class Out>
    void encode(const PhongSurface<float>& s, const PixelInput<PhongVaryings>& in, Out& out) const {
        out.target[0] = glm::vec4(hlsl::normalize(glm::mat3(worldFromView) * glm::vec3(s.normalView)), s.specularPower);
        out.target[1] = glm::vec4(glm::vec3(worldFromView * glm::vec4(in.varyings.posView, 1.0f)), 1.0f);
    }
};

template <bool D> using LppGBufferPS = gbuffer_detail::GBufferShader<LppEncoder, D>;
template <bool D> using LppGBufferMsaaPS = gbuffer_detail::GBufferShader<LppEncoder, D, true>;

// Listing 11.6's PS, the second geometry pass: the light buffer at the pixel times the material's
// diffuse texel, plus its monochrome specular times SpecularAlbedo. T = double: the reference
// mode's arithmetic, written to the back buffer and (clamped) to its float copy.
template <bool kDiscard, class T>
struct LppFinalPS {
    using Varyings = PhongVaryings;
    static constexpr int kTargetCount = std::is_same_v<T, double> ? 2 : 1;
    static constexpr bool kMayDiscard = kDiscard;
    PhongGatherFn gather = nullptr;
    const PhongShaderData<float>* data = nullptr;
    const TargetReader* lightBuffer = nullptr;
    std::uint32_t sampleCount = 1;
    bool coverageLoop = true;  // MSAA: Listing 11.19 (faithful); false: one sample per invocation
    void operator()(const PixelInput<PhongVaryings>& in, PixelOutput<kTargetCount>& out) const {
        PhongSurface<float> s;
        if (!gather(*data, in, s)) {
            out.discard();
            return;
        }
        const auto x = std::uint32_t(in.posWindow.x), y = std::uint32_t(in.posWindow.y);
        Vec3<T> color;
        if (sampleCount == 1 || !coverageLoop) {  // one sample: the shader's (0 when it runs per pixel)
            const glm::vec4 lighting = lightBuffer->load(x, y, in.sampleIndex);
            color = prcLightPrePassFinal(Vec4<T>(lighting), Vec3<T>(glm::vec3(s.diffuse)), Vec3<T>(glm::vec3(s.specular)));
        } else {
            // MSAA (§11.5, Listing 11.19's loop): the light buffer's covered samples summed, the
            // albedos applied to the sums (Listing 11.6's combination; 11.19's own 1/pi and 0.7 are
            // that listing's stand-ins for material values), divided by the samples applied.
            Vec4<T> sum(T(0));
            T applied = T(0);
            for (std::uint32_t i = 0; i < sampleCount; ++i)
                if (in.coverage & (1u << i)) {
                    sum += Vec4<T>(lightBuffer->load(x, y, i));
                    applied += T(1);
                }
            color = prcLightPrePassFinal(sum, Vec3<T>(glm::vec3(s.diffuse)), Vec3<T>(glm::vec3(s.specular))) / applied;
        }
        out.target[0] = glm::vec4(glm::vec3(color), 1.0f);
        if constexpr (kTargetCount == 2) out.target[1] = convert::clampUnorm(out.target[0]);
    }
};
template <bool kDiscard>
using LppFinalExactPS = LppFinalPS<kDiscard, float>;
template <bool kDiscard>
using LppFinalReferencePS = LppFinalPS<kDiscard, double>;
template <bool kDiscard>
using LppFinalExactPerSamplePS = gbuffer_detail::PerSample<LppFinalPS<kDiscard, float>>;
template <bool kDiscard>
using LppFinalReferencePerSamplePS = gbuffer_detail::PerSample<LppFinalPS<kDiscard, double>>;

// The second geometry pass (§11.3): the opaque geometry again, LESS_EQUAL against its own depth
// without writes, each pixel reading the light buffer; with MSAA, Listing 11.19's coverage loop or
// (msaaFinal perSample) per sample at edge pixels.
Pass finalPass(const std::shared_ptr<prc_light_pass::Setup>& setup, const TechniqueContext& ctx, bool finalPerSample) {
    const bool reference = ctx.precision == Precision::Reference;
    const std::uint32_t samples = ctx.sampleCount;
    const std::string back = backBufferTarget(samples), backReference = referenceBufferTarget(samples);
    std::vector<std::string> finalTargets = withReferenceBuffer({back}, ctx.precision);
    if (reference) finalTargets[1] = backReference;
    std::vector<std::string> finalReads = finalTargets;
    finalReads.emplace_back("lightbuffer");
    finalReads.emplace_back("depth");
    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;
    std::map<std::string, std::uint64_t>* variantCounts = ctx.variantCounts;
    const SceneResources* res = ctx.resources;
    return {"final", finalReads, finalTargets,
            [setup, device, stats, variantCounts, res, reference, back, backReference, samples, finalPerSample](BufferRegistry& reg) {
                RenderTargets rt;
                rt.colors[0] = &reg.get(back);
                if (reference) rt.colors[1] = &reg.get(backReference);
                rt.depthStencil = &reg.get("depth");
                PassState pass;
                pass.depthStencil.depthFunc = ComparisonFunc::LessEqual;
                pass.depthStencil.depthWriteEnable = false;
                const TargetReader lightBuffer(reg.get("lightbuffer"));
                const bool perSample = samples > 1 && finalPerSample;
                const auto configure = [&](auto& ps) {
                    ps.lightBuffer = &lightBuffer;
                    ps.sampleCount = samples;
                    ps.coverageLoop = !perSample;
                };
                const ForwardPassSetup& f = *setup->forward;
                const auto draw = [&]<template <bool> class PS, template <bool> class PerSamplePS>() {
                    if (!perSample) {
                        gbuffer_detail::drawOpaqueGBuffer<PS>(f, *device, *res, rt, pass, "lpp-final", configure, stats, variantCounts);
                        return;
                    }
                    // msaaFinal perSample: the geometry twice (§11.5), once per pixel where the edge
                    // bit is clear, once per sample where it is set.
                    gbuffer_detail::drawOpaqueGBuffer<PS>(f, *device, *res, rt, gbuffer_detail::withEdgeTest(pass, false), "lpp-final",
                                                          configure, stats, variantCounts);
                    gbuffer_detail::drawOpaqueGBuffer<PerSamplePS>(f, *device, *res, rt, gbuffer_detail::withEdgeTest(pass, true),
                                                                   "lpp-final-sample", configure, stats, variantCounts);
                };
                if (reference) draw.template operator()<LppFinalReferencePS, LppFinalReferencePerSamplePS>();
                else draw.template operator()<LppFinalExactPS, LppFinalExactPerSamplePS>();
            }};
}

} // namespace

Frame buildLightPrePass(const TechniqueContext& ctx) {
    const std::string file = ctx.errorFile();
    const OptionReader options(ctx.options, kLightPrePassOptions, file);
    const bool finalPerSample = options.is("msaaFinal", "perSample");
    const prc_light_pass::Options opt = prc_light_pass::readOptions(options);
    const std::shared_ptr<prc_light_pass::Setup> setup =
        prc_light_pass::makeSetup(ctx, opt, /*lightPrePass=*/true, /*optimized=*/false, /*safeNormals=*/false, file);

    const bool reference = ctx.precision == Precision::Reference;
    const std::uint32_t samples = ctx.sampleCount;
    const bool msaa = samples > 1;
    const std::string back = backBufferTarget(samples), backReference = referenceBufferTarget(samples);
    // Listing 11.4's two targets: (world normal, specular power), (world position, 1).
    const std::vector<std::string> targets{"gbuffer.normal", "gbuffer.position"};
    const prc_light_pass::GBufferNames names = prc_light_pass::gbufferNames(targets, samples);
    const std::vector<std::string>& gbuffer = names.gbuffer;
    const std::vector<std::string>& gbufferWrites = names.writes;
    std::vector<std::string> created = names.created;
    created.emplace_back("lightbuffer");
    if (reference) created.push_back(backReference);
    Frame frame;
    frame.add({"clear", {}, created, [setup, targets, reference, samples, back, backReference](BufferRegistry& reg) {
                   const std::uint32_t w = setup->forward->width, h = setup->forward->height;
                   const glm::vec4 black(0.0f, 0.0f, 0.0f, 1.0f);
                   reg.create(back, {w, h, Format::R8G8B8A8_UNORM, samples}).clearColor(black);
                   for (const std::string& target : targets)
                       reg.create(target, {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(glm::vec4(0.0f));
                   reg.create("depth", {w, h, Format::D24_UNORM_S8_UINT, samples}).clearDepthStencil(true, 1.0f, true, 0);
                   if (samples > 1) gbuffer_detail::createEdgeTargets(reg, w, h, samples);
                   reg.create("lightbuffer", {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(glm::vec4(0.0f));
                   if (reference) reg.create(backReference, {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(black);
               }});
    const glm::mat4 worldFromView = setup->worldFromView;
    frame.add(prc_light_pass::gbufferPass<LppGBufferPS, LppGBufferMsaaPS>(
        setup, ctx, targets, gbufferWrites, "lpp-gbuffer", [worldFromView](auto& ps) { ps.worldFromView = worldFromView; }));
    if (msaa) frame.add(gbuffer_detail::edgePass(ctx.device, ctx.stats, opt.edges));
    frame.add(prc_light_pass::lightsPass(setup, ctx, gbuffer, "lightbuffer"));
    frame.add(finalPass(setup, ctx, finalPerSample));
    frame.add(gbuffer_detail::forwardTransparentPass(setup->forward, ctx));
    if (msaa) frame.add(resolveBackBufferPass(samples, ctx.precision));
    return frame;
}

} // namespace tessera
