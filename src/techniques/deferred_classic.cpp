// The `deferred-classic` technique (techniques/deferred_classic.h; PR&C D3D11 ch. 11 §11.2, §11.4.2):
// clear -> G-buffer (Listing 11.1, or §11.4.1's optimized layout) -> lights (Listing 11.3 over quads,
// scissored quads or volumes, additive; prc_light_pass.h) -> [present] -> forward's transparent pass.
#include <tessera/techniques/deferred_classic.h>

#include <memory>
#include <string>
#include <vector>

#include <tessera/gbuffer/prc_gbuffer.h>
#include <tessera/techniques/technique_options.h>

#include "gbuffer_pass.h"
#include "msaa_deferred.h"
#include "prc_light_pass.h"

namespace tessera {
namespace {

// Listing 11.1's PS: (normalize(NormalWS), 1), (albedo, 1), (SpecularAlbedo, SpecularPower),
// (PositionWS, 1), from the Phong gather (world = the rigid view's inverse of view space).
struct ClassicEncoder {
    static constexpr int kTargetCount = 4;
    glm::mat4 worldFromView{1.0f};
    template <class Out>
    void encode(const PhongSurface<float>& s, const PixelInput<PhongVaryings>& in, Out& out) const {
        const glm::vec3 normalWorld = hlsl::normalize(glm::mat3(worldFromView) * glm::vec3(s.normalView));
        out.target[0] = glm::vec4(normalWorld, 1.0f);
        out.target[1] = glm::vec4(glm::vec3(s.diffuse), 1.0f);
        out.target[2] = glm::vec4(glm::vec3(s.specular), s.specularPower);
        out.target[3] = glm::vec4(glm::vec3(worldFromView * glm::vec4(in.varyings.posView, 1.0f)), 1.0f);
    }
};

// The optimized layout (§11.4.1, the chapter's companion code): RT0 R16G16_SNORM the view-space
// normal (left-handed) through Listing 11.8's sphere map, RT1 R10G10B10A2_UNORM the diffuse albedo,
// RT2 R8G8B8A8_UNORM the specular albedo with the power / 255 in alpha; the position comes from
// the depth buffer. 16 B/px with depth.
struct OptimizedEncoder {
    static constexpr int kTargetCount = 3;
    bool safeNormals = false;
    template <class Out>
    void encode(const PhongSurface<float>& s, const PixelInput<PhongVaryings>&, Out& out) const {
        const glm::vec3 nRh = hlsl::normalize(glm::vec3(s.normalView));
        const glm::vec3 nLh(nRh.x, nRh.y, -nRh.z);
        const glm::vec2 e = safeNormals ? prcSpheremapEncodeSafe(nLh) : prcSpheremapEncode(nLh);
        out.target[0] = glm::vec4(e, 0.0f, 0.0f);
        out.target[1] = glm::vec4(glm::vec3(s.diffuse), 1.0f);
        out.target[2] = glm::vec4(glm::vec3(s.specular), s.specularPower / 255.0f);
    }
};

template <bool D> using ClassicGBufferPS = gbuffer_detail::GBufferShader<ClassicEncoder, D>;
template <bool D> using ClassicGBufferMsaaPS = gbuffer_detail::GBufferShader<ClassicEncoder, D, true>;
template <bool D> using OptimizedGBufferPS = gbuffer_detail::GBufferShader<OptimizedEncoder, D>;
template <bool D> using OptimizedGBufferMsaaPS = gbuffer_detail::GBufferShader<OptimizedEncoder, D, true>;

} // namespace

Frame buildDeferredClassic(const TechniqueContext& ctx) {
    const std::string file = ctx.errorFile();
    const OptionReader options(ctx.options, kDeferredClassicOptions, file);
    const bool optimized = options.is("gbuffer", "optimized");
    const bool safeNormals = options.is("normalEncoding", "safe");
    const prc_light_pass::Options opt = prc_light_pass::readOptions(options);
    const std::shared_ptr<prc_light_pass::Setup> setup =
        prc_light_pass::makeSetup(ctx, opt, /*lightPrePass=*/false, optimized, safeNormals, file);

    const bool reference = ctx.precision == Precision::Reference;
    const std::uint32_t samples = ctx.sampleCount;
    const bool msaa = samples > 1;
    // With MSAA every buffer has `samples` samples, the image is drawn into "backbuffer.msaa" and
    // the last pass resolves it (technique.h).
    const std::string back = backBufferTarget(samples), backReference = referenceBufferTarget(samples);
    // Listing 11.1's four targets, or §11.4.1's three (the position from depth).
    const std::vector<std::string> targets =
        optimized ? std::vector<std::string>{"gbuffer.normal", "gbuffer.diffuse", "gbuffer.specular"}
                  : std::vector<std::string>{"gbuffer.normal", "gbuffer.diffuse", "gbuffer.specular", "gbuffer.position"};
    const prc_light_pass::GBufferNames names = prc_light_pass::gbufferNames(targets, samples);
    const std::vector<std::string>& gbuffer = names.gbuffer;
    const std::vector<std::string>& gbufferWrites = names.writes;
    std::vector<std::string> created = names.created;
    if (reference) {
        created.emplace_back("accumulation");
        created.push_back(backReference);
    }
    Frame frame;
    frame.add({"clear", {}, created, [setup, targets, reference, optimized, samples, back, backReference](BufferRegistry& reg) {
                   const std::uint32_t w = setup->forward->width, h = setup->forward->height;
                   const glm::vec4 black(0.0f, 0.0f, 0.0f, 1.0f);  // the lights' sum starts from nothing
                   reg.create(back, {w, h, Format::R8G8B8A8_UNORM, samples}).clearColor(black);
                   const Format optimizedFormats[] = {Format::R16G16_SNORM, Format::R10G10B10A2_UNORM, Format::R8G8B8A8_UNORM};
                   for (std::size_t k = 0; k < targets.size(); ++k)
                       reg.create(targets[k], {w, h, optimized ? optimizedFormats[k] : Format::R32G32B32A32_FLOAT, samples})
                           .clearColor(glm::vec4(0.0f));
                   reg.create("depth", {w, h, Format::D24_UNORM_S8_UINT, samples}).clearDepthStencil(true, 1.0f, true, 0);
                   if (samples > 1) gbuffer_detail::createEdgeTargets(reg, w, h, samples);
                   if (reference) {
                       reg.create("accumulation", {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(black);
                       reg.create(backReference, {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(black);
                   }
               }});
    const glm::mat4 worldFromView = setup->worldFromView;
    if (optimized)
        frame.add(prc_light_pass::gbufferPass<OptimizedGBufferPS, OptimizedGBufferMsaaPS>(
            setup, ctx, targets, gbufferWrites, "classic-gbuffer-optimized", [safeNormals](auto& ps) { ps.safeNormals = safeNormals; }));
    else
        frame.add(prc_light_pass::gbufferPass<ClassicGBufferPS, ClassicGBufferMsaaPS>(
            setup, ctx, targets, gbufferWrites, "classic-gbuffer", [worldFromView](auto& ps) { ps.worldFromView = worldFromView; }));
    if (msaa) frame.add(gbuffer_detail::edgePass(ctx.device, ctx.stats, opt.edges));
    frame.add(prc_light_pass::lightsPass(setup, ctx, gbuffer, reference ? "accumulation" : back));
    if (reference) frame.add(gbuffer_detail::presentAccumulationPass(ctx.precision, samples));
    frame.add(gbuffer_detail::forwardTransparentPass(setup->forward, ctx));
    if (msaa) frame.add(resolveBackBufferPass(samples, ctx.precision));
    return frame;
}

} // namespace tessera
