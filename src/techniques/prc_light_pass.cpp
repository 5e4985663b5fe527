// What deferred-classic and light-prepass share (prc_light_pass.h): the light-pass options, each
// light's draw and the "lights" pass with Listing 11.3's / 11.5's light shader (PR&C D3D11 ch. 11).
// The light shader's rasterizer instantiations live here once, for both techniques.
#include "prc_light_pass.h"

#include <cmath>
#include <map>
#include <span>
#include <utility>

#include <tessera/errors/input_error.h>
#include <tessera/math/det_math.h>
#include <tessera/raster/draw_batch.h>
#include <tessera/techniques/light_volumes.h>

#include "gbuffer_pass.h"
#include "msaa_deferred.h"

namespace tessera::prc_light_pass {
namespace {

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
    const Inputs* shared = nullptr;
    const PrcLight<T>* light = nullptr;
    std::uint32_t lightIndex = 0;
    void operator()(const PixelInput<NoVaryings>& in, PixelOutput<1>& out) const {
        const Inputs& g = *shared;
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

// Additive light pass states: no depth test for the quads (stencil EQUAL 1 with the mask; with
// light groups the light's groups against the geometry's, §11.4.2).
PassState lightPassState(const Options& o, bool lightGroups, std::uint8_t groups) {
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

void setQuad(LightDraw& d) {
    d.vertices.clear();
    for (const glm::vec3& p : gbuffer_detail::kQuadClip) d.vertices.push_back({p});
    d.indices.assign(gbuffer_detail::kQuadIndices.begin(), gbuffer_detail::kQuadIndices.end());
    d.clipFromLocal = glm::mat4(1.0f);
}

std::vector<LightDraw> planDraws(const std::vector<Light>& lights, const Options& o, const ForwardPassSetup& fwd,
                                   const Camera& camera, bool lightGroups) {
    const LightVolumes volumes;
    const LightVolumeOptions fit{VolumeFit::Circumscribed, VolumeRotation::Robust};
    std::vector<LightDraw> draws;
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const Light& l = lights[i];
        if (!l.enabled || l.type == LightType::Capsule) continue;  // the chapter's lights: point, spot, directional
        LightDraw d;
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
void runLights(const Setup& setup, Device& device, BufferRegistry& reg, Surface& target, DrawStats* stats,
               std::map<std::string, std::uint64_t>* variantCounts) {
    const ForwardPassSetup& fwd = *setup.forward;
    const Viewport viewport{0.0f, 0.0f, float(fwd.width), float(fwd.height), 0.0f, 1.0f};
    Surface& depth = reg.get("depth");
    const bool msaa = fwd.sampleCount > 1;
    // Every light binned together (raster/draw_batch.h): additive draws that read the G-buffer and
    // the stencil and write only `target`, in light order in each tile's list.
    DrawBatch batch(device);
    const auto runBatch = [&] { batch.runInto(stats); };
    for (const LightDraw& d : setup.draws) {
        RenderTargets rt;
        rt.colors[0] = &target;
        rt.depthStencil = &depth;
        ClassicLightPS<T> ps;
        ps.shared = &setup.inputs;
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
            batch.draw(st, rt, std::span<const LocalVertex>(d.vertices), d.indices, ClassicVS{d.clipFromLocal}, shader);
        };
        // §11.5: one sample where the samples agree, every sample at edge pixels.
        gbuffer_detail::drawPerPixelThenEdgeSamples(msaa, d.pass, ps, drawWith);
        if (variantCounts) ++(*variantCounts)["classic-light"];
        if (setup.afterLightStep) {
            runBatch();  // the step's buffers as they stand after it
            setup.afterLightStep(d.index, "shade", reg);
        }
    }
    runBatch();
}

} // namespace

Options readOptions(const OptionReader& r) {
    Options o;
    o.geometry = r.is("lightGeometry", "scissor")   ? Geometry::Scissor
                 : r.is("lightGeometry", "volumes") ? Geometry::Volumes
                                                    : Geometry::Quads;
    o.normalizeV = r.is("viewVector", "normalized");
    o.roundOut = r.is("scissorRound", "out");
    o.stencil = r.flag("stencil");
    o.sampler = r.is("sampler", "gltf") ? PhongSamplerChoice::Gltf : PhongSamplerChoice::Demo;
    o.alphaTest = r.flag("alphaTest");
    o.edges = gbuffer_detail::parseEdgeDetector(r);
    return o;
}

std::shared_ptr<Setup> makeSetup(const TechniqueContext& ctx, const Options& options, bool lightPrePass, bool optimized,
                                 bool safeNormals, const std::string& file) {
    auto setup = std::make_shared<Setup>();
    setup->options = options;
    setup->afterLightStep = ctx.afterLightStep;
    setup->forward = makeForwardPassSetup(ctx, ProjectionConvention::D3d, options.sampler, options.alphaTest);
    setup->worldFromView = glm::inverse(setup->forward->viewFromWorld);
    Inputs& in = setup->inputs;
    in.cameraWorld = glm::vec3(setup->worldFromView[3]);
    in.normalizeV = options.normalizeV;
    in.lightPrePass = lightPrePass;
    in.optimized = optimized;
    in.safeNormals = safeNormals;
    const glm::mat4 flipZ = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 1.0f, -1.0f));
    in.worldFromViewLh = glm::inverse(flipZ * setup->forward->viewFromWorld);
    in.ab = prcProjectionAB(ctx.camera.nearZ, ctx.camera.farZ);
    in.proj00 = setup->forward->clipFromView[0][0];
    in.proj11 = setup->forward->clipFromView[1][1];
    in.screenPx = glm::vec2(float(ctx.width), float(ctx.height));
    // Light groups (§11.4.2) take all eight stencil bits; MSAA's edge pass needs one of them.
    setup->lightGroups = ctx.resources->scene().usesLightGroups();
    if (setup->lightGroups && ctx.sampleCount > 1)
        throw inputError(file, "/lights", "the scene uses lightGroups, which take all eight stencil bits, and MSAA's edge pass "
                                          "needs one of them: render it without --msaa, or without lightGroups");
    setup->draws = planDraws(ctx.lights(), options, *setup->forward, ctx.camera, setup->lightGroups);
    return setup;
}

GBufferNames gbufferNames(const std::vector<std::string>& targets, std::uint32_t samples) {
    GBufferNames n;
    n.gbuffer = targets;
    n.gbuffer.emplace_back("depth");
    n.writes = n.gbuffer;
    if (samples > 1) {
        n.writes.emplace_back(gbuffer_detail::kEdgeSurfaceTarget);
        n.writes.emplace_back(gbuffer_detail::kEdgeCoverageTarget);
    }
    n.created = n.writes;
    if (samples > 1) n.created.emplace_back(gbuffer_detail::kEdgesBuffer);
    n.created.push_back(backBufferTarget(samples));
    return n;
}

PassState gbufferPassState(const Setup& setup) {
    PassState pass;
    pass.depthStencil.depthFunc = ComparisonFunc::Less;
    // The lit-geometry mask, or each item's light groups as the reference (§11.4.2).
    if (setup.options.stencil || setup.lightGroups) gbuffer_detail::stencilReplaceOne(pass);
    return pass;
}

Pass lightsPass(const std::shared_ptr<Setup>& setup, const TechniqueContext& ctx, std::vector<std::string> gbuffer,
                const std::string& lightTarget) {
    gbuffer.push_back(lightTarget);
    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;
    std::map<std::string, std::uint64_t>* variantCounts = ctx.variantCounts;
    return {"lights", gbuffer, {lightTarget}, [setup, device, stats, variantCounts, lightTarget](BufferRegistry& reg) {
                Inputs& in = setup->inputs;
                in.normal = TargetReader(reg.get("gbuffer.normal"));
                if (in.optimized) in.depth = &reg.get("depth");
                else in.position = TargetReader(reg.get("gbuffer.position"));
                if (!in.lightPrePass) {
                    in.diffuse = TargetReader(reg.get("gbuffer.diffuse"));
                    in.specular = TargetReader(reg.get("gbuffer.specular"));
                }
                Surface& target = reg.get(lightTarget);
                if (setup->forward->precision == Precision::Reference)
                    runLights<double>(*setup, *device, reg, target, stats, variantCounts);
                else runLights<float>(*setup, *device, reg, target, stats, variantCounts);
            }};
}

} // namespace tessera::prc_light_pass
