// The `deferred-classic` technique (techniques/deferred_classic.h; PR&C D3D11 ch. 11 §11.2, §11.4.2):
// clear -> G-buffer (Listing 11.1) -> lights (Listing 11.3 over quads, scissored quads or volumes,
// additive) -> [present] -> forward's transparent pass.
#include <tessera/techniques/deferred_classic.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <tessera/buffers/conversion.h>
#include <tessera/buffers/target_reader.h>
#include <tessera/errors/input_error.h>
#include <tessera/math/det_math.h>
#include <tessera/gbuffer/prc_gbuffer.h>
#include <tessera/shading/prc_lighting.h>
#include <tessera/techniques/light_volumes.h>
#include <tessera/techniques/technique_options.h>

#include "gbuffer_pass.h"
#include "msaa_deferred.h"

namespace tessera {
namespace {

enum class Geometry : std::uint8_t { Quads, Scissor, Volumes };

struct ClassicOptions {
    Geometry geometry = Geometry::Quads;
    bool normalizeV = false;
    bool roundOut = false;
    bool stencil = false;
    bool optimized = false;     // gbuffer optimized (deferred-classic only)
    bool safeNormals = false;   // normalEncoding safe
    PhongSamplerChoice sampler = PhongSamplerChoice::Demo;
    bool alphaTest = false;
    EdgeDetector edges = EdgeDetector::Coverage;  // MSAA: Listing 11.17's coverage flag
    bool finalPerSample = false;  // light-prepass MSAA final pass: per sample at edges (corrects Listing 11.19)
};

ClassicOptions parseOptions(const TechniqueContext& ctx, bool lightPrePass, const std::string& file) {
    const OptionReader r(ctx.options,
                         lightPrePass ? std::span<const OptionInfo>(kLightPrePassOptions)
                                      : std::span<const OptionInfo>(kDeferredClassicOptions),
                         file);
    ClassicOptions o;
    o.geometry = r.is("lightGeometry", "scissor")   ? Geometry::Scissor
                 : r.is("lightGeometry", "volumes") ? Geometry::Volumes
                                                    : Geometry::Quads;
    o.normalizeV = r.is("viewVector", "normalized");
    o.roundOut = r.is("scissorRound", "out");
    o.stencil = r.flag("stencil");
    o.optimized = !lightPrePass && r.is("gbuffer", "optimized");
    o.safeNormals = !lightPrePass && r.is("normalEncoding", "safe");
    o.sampler = r.is("sampler", "gltf") ? PhongSamplerChoice::Gltf : PhongSamplerChoice::Demo;
    o.alphaTest = r.flag("alphaTest");
    o.edges = gbuffer_detail::parseEdgeDetector(r);
    o.finalPerSample = lightPrePass && r.is("msaaFinal", "perSample");
    return o;
}

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

template <bool D> using ClassicGBufferPS = gbuffer_detail::GBufferShader<ClassicEncoder, D>;
template <bool D> using ClassicGBufferMsaaPS = gbuffer_detail::GBufferShader<ClassicEncoder, D, true>;
template <bool D> using OptimizedGBufferPS = gbuffer_detail::GBufferShader<OptimizedEncoder, D>;
template <bool D> using OptimizedGBufferMsaaPS = gbuffer_detail::GBufferShader<OptimizedEncoder, D, true>;
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

struct ClassicShared {
    bool lightPrePass = false;  // light-prepass: Listing 11.5 into the light buffer
    bool optimized = false;     // the optimized layout: decode RT0, position from depth
    bool safeNormals = false;   // normalEncoding safe: the decode clamps 1 - |e|^2 at 0
    const Surface* depth = nullptr;
    PrcProjectionAB ab;
    float proj00 = 1.0f, proj11 = 1.0f;
    glm::vec2 screenPx{1.0f};
    glm::mat4 worldFromViewLh{1.0f};
    TargetReader normal, diffuse, specular, position, lightBuffer;
    glm::vec3 cameraWorld{0.0f};
    bool normalizeV = false;
};

struct LocalVertex {
    glm::vec3 pos;
};
struct ClassicVS {
    using Varyings = NoVaryings;
    glm::mat4 clipFromLocal{1.0f};
    VertexOutput<NoVaryings> operator()(const LocalVertex& v) const { return {clipFromLocal * glm::vec4(v.pos, 1.0f), {}}; }
};

// Listing 11.3's PS: Load the four targets at int(SV_Position), CalcLighting, float4(lighting, 1).
template <class T>
struct ClassicLightPS {
    using Varyings = NoVaryings;
    static constexpr int kTargetCount = 1;
    const ClassicShared* shared = nullptr;
    const PrcLight<T>* light = nullptr;
    std::uint32_t lightIndex = 0;
    void operator()(const PixelInput<NoVaryings>& in, PixelOutput<1>& out) const {
        const ClassicShared& g = *shared;
        // Texture2DMS.Load(int2(screenPos.xy), i) (§11.5): the shader's sample, 0 when it runs per
        // pixel; SV_Position is the sample's position when it runs per sample.
        const auto x = std::uint32_t(in.posWindow.x), y = std::uint32_t(in.posWindow.y);
        const std::uint32_t i = in.sampleIndex;
        const glm::vec4 normalStored = g.normal.load(x, y, i);
        Vec3<T> normal{glm::vec3(normalStored)};
        Vec3<T> position;
        if (g.optimized) {
            // SpheremapDecode, then the left-handed view normal to world; the position from the
            // hardware depth (Listing 11.12: ProjectionB / (depth - ProjectionA) along the pixel's
            // view ray (x_ndc / P00, y_ndc / P11, 1)).
            const glm::vec2 e(normalStored);
            normal = Vec3<T>(glm::mat3(g.worldFromViewLh) * (g.safeNormals ? prcSpheremapDecodeSafe(e) : prcSpheremapDecode(e)));
            const float linearDepth = prcLinearDepth(g.depth->loadDepth(x, y, i), g.ab);
            const glm::vec2 ndc(in.posWindow.x / g.screenPx.x * 2.0f - 1.0f, 1.0f - in.posWindow.y / g.screenPx.y * 2.0f);
            const glm::vec3 viewRay(ndc.x / g.proj00, ndc.y / g.proj11, 1.0f);
            position = Vec3<T>(glm::vec3(g.worldFromViewLh * glm::vec4(viewRay * linearDepth, 1.0f)));
        } else {
            position = Vec3<T>(glm::vec3(g.position.load(x, y, i)));
        }
        Vec3<T> lighting;
        if (g.lightPrePass) {  // Listing 11.5: float4(diffuse light, monochrome specular)
            const Vec4<T> texel = prcLightBufferTexel<T>(*light, normal, T(normalStored.w), position, Vec3<T>(g.cameraWorld), g.normalizeV);
            lighting = Vec3<T>(texel);
            out.target[0] = glm::vec4(texel);
        } else {
            const Vec3<T> diffuse(glm::vec3(g.diffuse.load(x, y, i)));
            const glm::vec4 spec = g.specular.load(x, y, i);
            const T power = g.optimized ? T(spec.w * 255.0f) : T(spec.w);
            lighting = prcClassicLighting<T>(*light, normal, position, diffuse, Vec3<T>(glm::vec3(spec)), power, Vec3<T>(g.cameraWorld),
                                             g.normalizeV);
            out.target[0] = glm::vec4(glm::vec3(lighting), 1.0f);
        }
        if (std::vector<LightTerm>* trace = watchedLightTerms()) [[unlikely]] {
            LightTerm term;
            term.light = lightIndex;
            term.combined = true;
            const PrcIncidence<T> inc = prcIncidence(*light, position);
            term.falloff = float(inc.attenuation);
            term.nDotL = float(hlsl::dot(normal, inc.toLight));
            if (light->type != LightType::Directional) {
                term.distance = float(glm::length(glm::dvec3(light->position - position)));
                term.range = float(light->range);
            }
            term.diffuse = glm::vec4(glm::vec3(lighting), 0.0f);
            trace->push_back(term);
        }
    }
};

// One light's draw: its PrcLight (float and double), mesh, matrix and states.
struct ClassicDraw {
    std::uint32_t index = 0;
    PrcLight<float> lightExact;
    PrcLight<double> lightReference;
    std::vector<LocalVertex> vertices;
    std::vector<std::uint32_t> indices;
    glm::mat4 clipFromLocal{1.0f};
    PassState pass;
    bool scissor = false;
    ScissorRect rect;
};

struct ClassicSetup {
    ClassicOptions options;
    std::shared_ptr<ForwardPassSetup> forward;
    ClassicShared shared;
    glm::mat4 worldFromView{1.0f};
    std::vector<ClassicDraw> draws;
    std::function<void(std::size_t, std::string_view, const BufferRegistry&)> afterLightStep;
};

// Additive light pass states: no depth test for the quads (stencil EQUAL 1 with the mask; with
// light groups the light's groups against the geometry's, §11.4.2).
PassState lightPassState(const ClassicOptions& o, bool lightGroups, std::uint8_t groups) {
    PassState p;
    p.rasterizer.cullMode = CullMode::Back;
    p.depthStencil.depthEnable = false;
    p.depthStencil.depthWriteEnable = false;
    if (lightGroups) gbuffer_detail::stencilLightGroups(p, groups);
    else if (o.stencil) gbuffer_detail::stencilEqualOne(p);
    p.blend.renderTarget[0] = kAdditiveBlend;
    return p;
}

template <class T>
PrcLight<T> prcLightFrom(const Light& l) {
    PrcLight<T> p;
    p.type = l.type;
    p.position = Vec3<T>(l.positionWorld);
    p.color = Vec3<T>(l.color * l.intensity);
    p.direction = Vec3<T>(l.directionWorld);
    p.range = T(l.range);
    // SpotlightAngles as cosines: x the inner (full intensity) cone, y the outer.
    p.cosInner = T(detCos(double(hlsl::radians(l.spotInnerHalfAngleDeg))));
    p.cosOuter = T(detCos(double(hlsl::radians(l.spotHalfAngleDeg))));
    return p;
}

void setQuad(ClassicDraw& d) {
    d.vertices.clear();
    for (const glm::vec3& p : gbuffer_detail::kQuadClip) d.vertices.push_back({p});
    d.indices.assign(gbuffer_detail::kQuadIndices.begin(), gbuffer_detail::kQuadIndices.end());
    d.clipFromLocal = glm::mat4(1.0f);
}

std::vector<ClassicDraw> planDraws(const std::vector<Light>& lights, const ClassicOptions& o, const ForwardPassSetup& fwd,
                                   const Camera& camera, bool lightGroups) {
    const LightVolumes volumes;
    const LightVolumeOptions fit{VolumeFit::Circumscribed, VolumeRotation::Robust};
    std::vector<ClassicDraw> draws;
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const Light& l = lights[i];
        if (!l.enabled || l.type == LightType::Capsule) continue;  // the chapter's lights: point, spot, directional
        ClassicDraw d;
        d.index = std::uint32_t(i);
        d.lightExact = prcLightFrom<float>(l);
        d.lightReference = prcLightFrom<double>(l);
        d.pass = lightPassState(o, lightGroups, l.lightGroups);
        setQuad(d);
        const bool local = l.type != LightType::Directional && std::isfinite(l.range);
        if (local && o.geometry == Geometry::Scissor) {
            // Listing 11.14 in the left-handed view space the listing assumes (tessera's view is
            // right-handed: z flipped); the sphere bounds a spot's cone too.
            const glm::vec3 cRh = glm::vec3(fwd.viewFromWorld * glm::vec4(l.positionWorld, 1.0f));
            const PrcScissorRect r = prcPointLightScissor({cRh.x, cRh.y, -cRh.z}, l.range, fwd.clipFromView[0][0],
                                                          fwd.clipFromView[1][1], camera.nearZ, camera.farZ, fwd.width, fwd.height,
                                                          o.roundOut);
            d.scissor = true;
            d.rect = ScissorRect{r.left, r.top, r.right, r.bottom};
        } else if (local && o.geometry == Geometry::Volumes) {
            // The volume's bounding sphere (its range; a spot's cone lies inside it) against the
            // clip planes, in the right-handed view (z < 0 in front of the eye).
            const float zView = -glm::vec3(fwd.viewFromWorld * glm::vec4(l.positionWorld, 1.0f)).z;  // distance along the view axis
            const bool crossesNear = zView - l.range < camera.nearZ;
            const bool crossesFar = zView + l.range > camera.farZ;
            if (!(crossesNear && crossesFar)) {
                const VolumeMesh& mesh = volumes.meshFor(l.type);
                d.vertices.clear();
                for (const glm::vec3& p : mesh.positions) d.vertices.push_back({p});
                d.indices = mesh.indices;
                const glm::mat4 clipFromWorld = fwd.clipFromView * fwd.viewFromWorld;
                d.clipFromLocal = clipFromWorld * volumes.worldFromObject(l, fit, &clipFromWorld);
                d.pass.rasterizer.frontCounterClockwise = true;  // the 3dgep meshes: counter-clockwise outside
                d.pass.depthStencil.depthEnable = true;
                if (crossesFar) {  // front faces, LESS_EQUAL: occluded light rejected
                    d.pass.rasterizer.cullMode = CullMode::Back;
                    d.pass.depthStencil.depthFunc = ComparisonFunc::LessEqual;
                } else {  // back faces, GREATER_EQUAL: light "floating in air" rejected; the eye may be inside
                    d.pass.rasterizer.cullMode = CullMode::Front;
                    d.pass.depthStencil.depthFunc = ComparisonFunc::GreaterEqual;
                }
            }
        }
        draws.push_back(std::move(d));
    }
    return draws;
}

template <class T>
void runLights(const ClassicSetup& setup, Device& device, BufferRegistry& reg, Surface& target, DrawStats* stats,
               std::map<std::string, std::uint64_t>* variantCounts) {
    const ForwardPassSetup& fwd = *setup.forward;
    const Viewport viewport{0.0f, 0.0f, float(fwd.width), float(fwd.height), 0.0f, 1.0f};
    Surface& depth = reg.get("depth");
    const bool msaa = fwd.sampleCount > 1;
    for (const ClassicDraw& d : setup.draws) {
        RenderTargets rt;
        rt.colors[0] = &target;
        rt.depthStencil = &depth;
        ClassicLightPS<T> ps;
        ps.shared = &setup.shared;
        if constexpr (std::is_same_v<T, double>) ps.light = &d.lightReference;
        else ps.light = &d.lightExact;
        ps.lightIndex = d.index;
        const auto drawWith = [&](const PassState& pass, const auto& shader) {
            DrawState st = makeDrawState(pass, viewport);
            st.precision = fwd.precision;
            if (d.scissor) {
                st.rasterizer.scissorEnable = true;
                st.scissor = d.rect;
            }
            DrawStats s = device.draw(st, rt, std::span<const LocalVertex>(d.vertices), d.indices, ClassicVS{d.clipFromLocal}, shader);
            if (stats) *stats += s;
        };
        // §11.5: one sample where the samples agree, every sample at edge pixels.
        gbuffer_detail::drawPerPixelThenEdgeSamples(msaa, d.pass, ps, drawWith);
        if (variantCounts) ++(*variantCounts)["classic-light"];
        if (setup.afterLightStep) setup.afterLightStep(d.index, "shade", reg);
    }
}

// Classic (§11.2) or light pre-pass (§11.3): the same options, light planning and light draws.
Frame buildFrame(const TechniqueContext& ctx, bool lightPrePass) {
    const std::string file = ctx.errorFile();
    auto setup = std::make_shared<ClassicSetup>();
    setup->options = parseOptions(ctx, lightPrePass, file);
    const ClassicOptions& opt = setup->options;
    setup->afterLightStep = ctx.afterLightStep;
    setup->forward = makeForwardPassSetup(ctx, ProjectionConvention::D3d, opt.sampler, opt.alphaTest);
    setup->worldFromView = glm::inverse(setup->forward->viewFromWorld);
    setup->shared.cameraWorld = glm::vec3(setup->worldFromView[3]);
    setup->shared.normalizeV = opt.normalizeV;
    setup->shared.lightPrePass = lightPrePass;
    const bool optimized = opt.optimized && !lightPrePass;
    setup->shared.optimized = optimized;
    setup->shared.safeNormals = opt.safeNormals;
    {
        const glm::mat4 flipZ = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 1.0f, -1.0f));
        setup->shared.worldFromViewLh = glm::inverse(flipZ * setup->forward->viewFromWorld);
        setup->shared.ab = prcProjectionAB(ctx.camera.nearZ, ctx.camera.farZ);
        setup->shared.proj00 = setup->forward->clipFromView[0][0];
        setup->shared.proj11 = setup->forward->clipFromView[1][1];
        setup->shared.screenPx = glm::vec2(float(ctx.width), float(ctx.height));
    }
    // Light groups (§11.4.2) take all eight stencil bits; MSAA's edge pass needs one of them.
    const bool lightGroups = ctx.resources->scene().usesLightGroups();
    if (lightGroups && ctx.sampleCount > 1)
        throw inputError(file, "/lights", "the scene uses lightGroups, which take all eight stencil bits, and MSAA's edge pass "
                                          "needs one of them: render it without --msaa, or without lightGroups");
    setup->draws = planDraws(ctx.lights(), opt, *setup->forward, ctx.camera, lightGroups);

    const bool reference = ctx.precision == Precision::Reference;
    const std::uint32_t samples = ctx.sampleCount;
    const bool msaa = samples > 1;
    // With MSAA every buffer has `samples` samples, the image is drawn into "backbuffer.msaa" and
    // the last pass resolves it (technique.h).
    const std::string back = backBufferTarget(samples), backReference = referenceBufferTarget(samples);
    // Classic: Listing 11.1's four targets; light pre-pass: Listing 11.4's two (normal + power, position).
    const std::vector<std::string> targets =
        lightPrePass ? std::vector<std::string>{"gbuffer.normal", "gbuffer.position"}
        : optimized  ? std::vector<std::string>{"gbuffer.normal", "gbuffer.diffuse", "gbuffer.specular"}
                     : std::vector<std::string>{"gbuffer.normal", "gbuffer.diffuse", "gbuffer.specular", "gbuffer.position"};
    std::vector<std::string> gbuffer = targets;
    gbuffer.emplace_back("depth");
    std::vector<std::string> gbufferWrites = gbuffer;
    if (msaa) {
        gbufferWrites.emplace_back(gbuffer_detail::kEdgeSurfaceTarget);
        gbufferWrites.emplace_back(gbuffer_detail::kEdgeCoverageTarget);
    }
    std::vector<std::string> created = gbufferWrites;
    if (msaa) created.emplace_back(gbuffer_detail::kEdgesBuffer);
    created.push_back(back);
    if (lightPrePass) created.emplace_back("lightbuffer");
    const bool accumulation = reference && !lightPrePass;
    if (accumulation) created.emplace_back("accumulation");
    if (reference) created.push_back(backReference);
    Frame frame;
    frame.add({"clear", {}, created,
               [setup, targets, reference, accumulation, lightPrePass, optimized, samples, back, backReference](BufferRegistry& reg) {
                   const std::uint32_t w = setup->forward->width, h = setup->forward->height;
                   const glm::vec4 black(0.0f, 0.0f, 0.0f, 1.0f);  // the lights' sum starts from nothing
                   reg.create(back, {w, h, Format::R8G8B8A8_UNORM, samples}).clearColor(black);
                   const Format optimizedFormats[] = {Format::R16G16_SNORM, Format::R10G10B10A2_UNORM, Format::R8G8B8A8_UNORM};
                   for (std::size_t k = 0; k < targets.size(); ++k)
                       reg.create(targets[k], {w, h, optimized ? optimizedFormats[k] : Format::R32G32B32A32_FLOAT, samples})
                           .clearColor(glm::vec4(0.0f));
                   reg.create("depth", {w, h, Format::D24_UNORM_S8_UINT, samples}).clearDepthStencil(true, 1.0f, true, 0);
                   if (samples > 1) gbuffer_detail::createEdgeTargets(reg, w, h, samples);
                   if (lightPrePass) reg.create("lightbuffer", {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(glm::vec4(0.0f));
                   if (accumulation) reg.create("accumulation", {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(black);
                   if (reference) reg.create(backReference, {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(black);
               }});
    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;
    std::map<std::string, std::uint64_t>* variantCounts = ctx.variantCounts;
    const SceneResources* res = ctx.resources;
    frame.add({"gbuffer", gbuffer, gbufferWrites,
               [setup, device, stats, variantCounts, res, lightPrePass, optimized, samples, lightGroups](BufferRegistry& reg) {
                   RenderTargets rt;
                   rt.colors[0] = &reg.get("gbuffer.normal");
                   if (lightPrePass) {
                       rt.colors[1] = &reg.get("gbuffer.position");
                   } else {
                       rt.colors[1] = &reg.get("gbuffer.diffuse");
                       rt.colors[2] = &reg.get("gbuffer.specular");
                       if (!optimized) rt.colors[3] = &reg.get("gbuffer.position");
                   }
                   rt.depthStencil = &reg.get("depth");
                   PassState pass;
                   pass.depthStencil.depthFunc = ComparisonFunc::Less;
                   // The lit-geometry mask, or each item's light groups as the reference (§11.4.2).
                   if (setup->options.stencil || lightGroups) gbuffer_detail::stencilReplaceOne(pass);
                   const ForwardPassSetup& f = *setup->forward;
                   const auto configure = [&](auto& ps) {
                       ps.sampleCount = samples;
                       if constexpr (requires { ps.worldFromView; }) ps.worldFromView = setup->worldFromView;
                       if constexpr (requires { ps.safeNormals; }) ps.safeNormals = setup->options.safeNormals;
                   };
                   // With MSAA the layout's targets are followed by the edge detectors' two.
                   const auto draw = [&]<template <bool> class PS, template <bool> class MsaaPS>(int layoutTargets, const char* name) {
                       if (samples == 1) {
                           gbuffer_detail::drawOpaqueGBuffer<PS>(f, *device, *res, rt, pass, name, configure, stats, variantCounts,
                                                                 lightGroups);
                       } else {
                           gbuffer_detail::bindEdgeTargets(rt, reg, layoutTargets);
                           gbuffer_detail::drawOpaqueGBuffer<MsaaPS>(f, *device, *res, rt, pass, name, configure, stats, variantCounts);
                       }
                   };
                   if (lightPrePass) draw.template operator()<LppGBufferPS, LppGBufferMsaaPS>(2, "lpp-gbuffer");
                   else if (optimized)
                       draw.template operator()<OptimizedGBufferPS, OptimizedGBufferMsaaPS>(3, "classic-gbuffer-optimized");
                   else draw.template operator()<ClassicGBufferPS, ClassicGBufferMsaaPS>(4, "classic-gbuffer");
               }});
    if (msaa) frame.add(gbuffer_detail::edgePass(device, stats, opt.edges));
    const std::string lightTarget = lightPrePass ? "lightbuffer" : accumulation ? "accumulation" : back;
    std::vector<std::string> lightReads = gbuffer;
    lightReads.push_back(lightTarget);
    frame.add({"lights", lightReads, {lightTarget}, [setup, device, stats, variantCounts, lightTarget, lightPrePass](BufferRegistry& reg) {
                   ClassicShared& shared = setup->shared;
                   shared.normal = TargetReader(reg.get("gbuffer.normal"));
                   if (shared.optimized) shared.depth = &reg.get("depth");
                   else shared.position = TargetReader(reg.get("gbuffer.position"));
                   if (!lightPrePass) {
                       shared.diffuse = TargetReader(reg.get("gbuffer.diffuse"));
                       shared.specular = TargetReader(reg.get("gbuffer.specular"));
                   }
                   Surface& target = reg.get(lightTarget);
                   if (setup->forward->precision == Precision::Reference)
                       runLights<double>(*setup, *device, reg, target, stats, variantCounts);
                   else runLights<float>(*setup, *device, reg, target, stats, variantCounts);
               }});
    if (lightPrePass) {
        // The second geometry pass (§11.3): the opaque geometry again, LESS_EQUAL against its own
        // depth without writes, each pixel reading the light buffer.
        std::vector<std::string> finalTargets = withReferenceBuffer({back}, ctx.precision);
        if (reference) finalTargets[1] = backReference;
        std::vector<std::string> finalReads = finalTargets;
        finalReads.emplace_back("lightbuffer");
        finalReads.emplace_back("depth");
        frame.add({"final", finalReads, finalTargets,
                   [setup, device, stats, variantCounts, res, reference, back, backReference, samples](BufferRegistry& reg) {
                       RenderTargets rt;
                       rt.colors[0] = &reg.get(back);
                       if (reference) rt.colors[1] = &reg.get(backReference);
                       rt.depthStencil = &reg.get("depth");
                       PassState pass;
                       pass.depthStencil.depthFunc = ComparisonFunc::LessEqual;
                       pass.depthStencil.depthWriteEnable = false;
                       const TargetReader lightBuffer(reg.get("lightbuffer"));
                       const bool perSample = samples > 1 && setup->options.finalPerSample;
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
                           // msaaFinal perSample: the geometry twice (§11.5), once per pixel where the
                           // edge bit is clear, once per sample where it is set.
                           gbuffer_detail::drawOpaqueGBuffer<PS>(f, *device, *res, rt, gbuffer_detail::withEdgeTest(pass, false),
                                                                 "lpp-final", configure, stats, variantCounts);
                           gbuffer_detail::drawOpaqueGBuffer<PerSamplePS>(f, *device, *res, rt, gbuffer_detail::withEdgeTest(pass, true),
                                                                          "lpp-final-sample", configure, stats, variantCounts);
                       };
                       if (reference) draw.template operator()<LppFinalReferencePS, LppFinalReferencePerSamplePS>();
                       else draw.template operator()<LppFinalExactPS, LppFinalExactPerSamplePS>();
                   }});
    } else if (reference) {
        frame.add(gbuffer_detail::presentAccumulationPass(ctx.precision, samples));
    }
    frame.add(gbuffer_detail::forwardTransparentPass(setup->forward, ctx));
    if (msaa) frame.add(resolveBackBufferPass(samples, ctx.precision));
    return frame;
}

} // namespace

Frame buildDeferredClassic(const TechniqueContext& ctx) { return buildFrame(ctx, false); }

Frame buildLightPrePass(const TechniqueContext& ctx) { return buildFrame(ctx, true); }

} // namespace tessera
