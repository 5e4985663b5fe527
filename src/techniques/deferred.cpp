// The `deferred` and `deferred-killzone` techniques (3dgep article §3; the demo's g_DeferredTechnique in
// 3dgep demo's main.cpp, DeferredRendering.hlsl PS_Geometry / PS_DeferredLighting, DeferredLightingPass.cpp):
// clear -> G-buffer -> depth copy -> per-light volumes -> (compose / present) -> transparent.
// Options and buffers are documented in include/tessera/techniques/deferred.h.
#include <tessera/techniques/deferred.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/ext/matrix_clip_space.hpp>

#include <tessera/buffers/target_reader.h>
#include <tessera/errors/input_error.h>
#include <tessera/gbuffer/screen_to_view.h>
#include <tessera/gbuffer/specular_power_packing.h>
#include <tessera/shading/phong_surface.h>
#include <tessera/techniques/deferred_states.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/light_volumes.h>
#include <tessera/techniques/technique_options.h>

#include "gbuffer_pass.h"
#include "msaa_deferred.h"

namespace tessera {
namespace {

// "killzone.samples" row length, texels (kMaxSurfaceDimension).
constexpr std::uint32_t kSamplesRow = 16384;

enum class Method { Dgep, Killzone };

struct DeferredOptions {
    ProjectionConvention projection = ProjectionConvention::DemoGl;
    PixelSamplePoint samplePoint = PixelSamplePoint::Corner;
    LightVolumeOptions volumes;
    bool floatTargets = false;         // gbuffer float
    bool positionFromGBuffer = false;  // position gbuffer
    bool accumulateLighting = false;   // accumulate lighting
    PhongSamplerChoice sampler = PhongSamplerChoice::Demo;
    bool alphaTest = false;            // transparent pass only
    std::uint64_t threshold = kKillzoneDefaultThreshold;
    EdgeDetector edges = EdgeDetector::DepthNormal;  // MSAA: the demo has none; Intel's test
};

// ---------------------------------------------------------------------------------------------
// G-buffer pixel shader (PS_Geometry): the forward PS's material gathering (shadePhong in
// src/shading/phong_material_shader.cpp, the same operations in the same order, so that a float
// G-buffer holds exactly the values forward shades with), the demo's discard, no lighting.

// PS_Geometry's outputs: SV_Target0 light accumulation, 1 diffuse, 2 specular, 3 view normal,
// (4 view position with position gbuffer).
template <int kLayoutTargets>
struct DeferredEncoder {
    static constexpr int kTargetCount = kLayoutTargets;
    bool floatTargets = false;     // spec power unpacked in RT2.a
    bool forwardAlpha = false;     // accumulate lighting: RT0.a = alpha * Opacity (forward's output alpha)
    float opacity = 1.0f;          // the material's Opacity
    template <class Out>
    void encode(const PhongSurface<float>& s, const PixelInput<PhongVaryings>& in, Out& out) const {
        const glm::vec4 ambientEmissive = s.ambient + s.emissive;
        out.target[0] = forwardAlpha ? glm::vec4(ambientEmissive.x, ambientEmissive.y, ambientEmissive.z, s.alpha * opacity)
                                     : ambientEmissive;
        out.target[1] = s.diffuse;
        // OUT.Specular = float4(specular.rgb, log2(specularPower) / 10.5f)
        out.target[2] = glm::vec4(s.specular.x, s.specular.y, s.specular.z,
                                  floatTargets ? s.specularPower : packSpecularPower(s.specularPower));
        out.target[3] = s.normalView;
        if constexpr (kLayoutTargets == 5) out.target[4] = glm::vec4(in.varyings.posView, 1.0f);
    }
};
template <bool D> using GBufferPS4 = gbuffer_detail::GBufferShader<DeferredEncoder<4>, D>;
template <bool D> using GBufferPS5 = gbuffer_detail::GBufferShader<DeferredEncoder<5>, D>;
template <bool D> using GBufferMsaaPS4 = gbuffer_detail::GBufferShader<DeferredEncoder<4>, D, true>;
template <bool D> using GBufferMsaaPS5 = gbuffer_detail::GBufferShader<DeferredEncoder<5>, D, true>;

// ---------------------------------------------------------------------------------------------
// Light volumes and the full-screen quad: VS_main with position only (no varyings used).

struct VolumeVertex {
    glm::vec3 posObject;
};

struct VolumeVS {
    using Varyings = NoVaryings;
    glm::mat4 clipFromObject{1.0f};  // ModelViewProjection
    VertexOutput<NoVaryings> operator()(const VolumeVertex& v) const {
        return {clipFromObject * glm::vec4(v.posObject, 1.0f), {}};
    }
};

// CreateScreenQuad(-1, 1, -1, 1, -1): the quad at z = -1, counter-clockwise seen from +z (a
// front face under the demo's FrontCounterClockwise rasterizer), drawn with
// glm::ortho(-1, 1, -1, 1, 0, 1) (OpenGL form: z_clip = -2 z - 1 = 1, the far plane).
const std::array<VolumeVertex, 4> kScreenQuad{{{{-1.0f, -1.0f, -1.0f}}, {{1.0f, -1.0f, -1.0f}}, {{1.0f, 1.0f, -1.0f}},
                                               {{-1.0f, 1.0f, -1.0f}}}};
const std::array<std::uint32_t, 6> kScreenQuadIndices{0, 1, 2, 0, 2, 3};

// ---------------------------------------------------------------------------------------------
// What PS_DeferredLighting (and the compose pass) read: the G-buffer, the depth copy and
// ScreenToViewParams.
struct LightingInputs {
    TargetReader diffuse, specular, normal, position, accumulation, lightDiffuse, lightSpecular;
    const Surface* depth = nullptr;   // "depth.copy"
    glm::mat4 inverseProjection{1.0f};
    glm::vec2 screenDimensions{1.0f};
    PixelSamplePoint samplePoint = PixelSamplePoint::Corner;
    bool floatTargets = false, positionFromGBuffer = false;

    // The reconstructed view position of the shader's pixel or sample: the demo's corner, or the
    // centre: SV_Position, which is the sample's position when the shader runs per sample.
    glm::vec4 positionView(const PixelInput<NoVaryings>& pin, std::uint32_t x, std::uint32_t y) const {
        const float d = depth->loadDepth(x, y, pin.sampleIndex);
        if (samplePoint == PixelSamplePoint::Centre)
            return screenToView(glm::vec4(pin.posWindow.x, pin.posWindow.y, d, 1.0f), screenDimensions, inverseProjection);
        return reconstructPositionView(x, y, d, screenDimensions, inverseProjection, samplePoint);
    }

    // Exp2(specular.a * 10.5) of the demo, or the unpacked float.
    float specularPower(const glm::vec4& specularStored) const {
        return floatTargets ? specularStored.w : unpackSpecularPower(specularStored.w);
    }
};

// PS_DeferredLighting for one light. kTargets = 1: the demo's
// `(diffuse * lit.Diffuse) + (specular * lit.Specular)`; kTargets = 2 (accumulate lighting):
// lit.Diffuse and lit.Specular. No Enabled and no range check: the volume selects the pixels.
// T = float: exact, or fast with fastmath (phong_lighting.h); T = double: reference, the
// G-buffer's float values shaded in double and rounded once to float by the output.
template <int kTargets, class T = float>
struct DeferredLightingPS {
    using Varyings = NoVaryings;
    static constexpr int kTargetCount = kTargets;
    const LightingInputs* in = nullptr;
    const ViewLight<T>* light = nullptr;
    bool fast = false;
    std::uint32_t lightIndex = 0;  // scene index of `light`, for a pixel watch's LightTerm
    void operator()(const PixelInput<NoVaryings>& pin, PixelOutput<kTargets>& out) const {
        // int2 texCoord = IN.position.xy (truncation: the pixel's integer corner). With MSAA the
        // shader's sample (0 per pixel): Texture2DMS.Load(texCoord, SV_SampleIndex).
        const glm::ivec2 px = pixelFromSvPosition(glm::vec2(pin.posWindow));
        const std::uint32_t x = std::uint32_t(px.x), y = std::uint32_t(px.y), i = pin.sampleIndex;
        const Vec4<T> posView(in->positionFromGBuffer ? in->position.load(x, y, i) : in->positionView(pin, x, y));
        const Vec4<T> eyeView{T(0), T(0), T(0), T(1)};
        const Vec4<T> viewDirView = hlsl::normalize(eyeView - posView);
        const Vec4<T> diffuse(in->diffuse.load(x, y, i));
        const glm::vec4 specularStored = in->specular.load(x, y, i);
        const Vec4<T> specular(specularStored);
        const Vec4<T> normalView(in->normal.load(x, y, i));
        const T specularPower = T(in->specularPower(specularStored));
        LightingResult<T> lit;
        const auto shade = [&]<bool kFast>() {
            switch (light->type) {
            case LightType::Directional: lit = doDirectionalLight<T, kFast>(*light, specularPower, viewDirView, normalView); break;
            case LightType::Point: lit = doPointLight<T, kFast>(*light, specularPower, viewDirView, posView, normalView); break;
            case LightType::Spot: lit = doSpotLight<T, kFast>(*light, specularPower, viewDirView, posView, normalView); break;
            case LightType::Capsule: break;  // runLights draws no capsule
            }
        };
        if constexpr (std::is_same_v<T, float>) {
            if (fast) shade.template operator()<true>();
            else shade.template operator()<false>();
        } else {
            shade.template operator()<false>();
        }
        if (std::vector<LightTerm>* trace = watchedLightTerms()) [[unlikely]]
            trace->push_back(fast ? describeLight<T, true>(lightIndex, *light, posView, normalView, lit)
                                  : describeLight<T, false>(lightIndex, *light, posView, normalView, lit));
        if constexpr (kTargets == 1) {
            out.target[0] = glm::vec4(diffuse * lit.diffuse + specular * lit.specular);
        } else {
            out.target[0] = glm::vec4(lit.diffuse);
            out.target[1] = glm::vec4(lit.specular);
        }
    }
};

// accumulate lighting: forward's final expression from the G-buffer and the light sums
// (ForwardRendering.hlsl PS_main after DoLighting): diffuse *= float4(D.rgb, 1); specular only
// when SpecularPower > 1; ((ambient + emissive) + diffuse) + specular; alpha from RT0.
struct ComposePS {
    using Varyings = NoVaryings;
    static constexpr int kTargetCount = 1;
    const LightingInputs* in = nullptr;
    void operator()(const PixelInput<NoVaryings>& pin, PixelOutput<1>& out) const {
        const glm::ivec2 px = pixelFromSvPosition(glm::vec2(pin.posWindow));
        const std::uint32_t x = std::uint32_t(px.x), y = std::uint32_t(px.y), i = pin.sampleIndex;
        const glm::vec4 ambientEmissive = in->accumulation.load(x, y, i);
        const glm::vec4 litDiffuse = in->lightDiffuse.load(x, y, i);
        const glm::vec4 specularStored = in->specular.load(x, y, i);
        glm::vec4 diffuse = in->diffuse.load(x, y, i);
        diffuse *= glm::vec4(litDiffuse.x, litDiffuse.y, litDiffuse.z, 1.0f);
        glm::vec4 specular(0.0f);
        if (in->specularPower(specularStored) > 1.0f)
            specular = glm::vec4(specularStored.x, specularStored.y, specularStored.z, 0.0f) * in->lightSpecular.load(x, y, i);
        const glm::vec4 sum = (ambientEmissive + diffuse) + specular;
        out.target[0] = glm::vec4(sum.x, sum.y, sum.z, ambientEmissive.w);
    }
};

// ---------------------------------------------------------------------------------------------

struct DeferredSetup {
    Method method = Method::Dgep;
    DeferredOptions options;
    std::shared_ptr<ForwardPassSetup> forward;
    std::vector<Light> lightsWorld;  // the scene's lights, scene order
    LightVolumes volumes;
    std::vector<VolumeVertex> sphereVertices, coneVertices;
    LightingInputs inputs;           // bound after the G-buffer pass
    std::string accumulationName;    // RT0
    bool separateAccumulation = false;
    std::function<void(std::size_t, std::string_view, const BufferRegistry&)> afterLightStep;  // TechniqueContext's
};

DeferredOptions parseOptions(const TechniqueContext& ctx, Method method, const std::string& file) {
    DeferredOptions o;
    const OptionReader r(ctx.options, method == Method::Killzone ? std::span<const OptionInfo>(kKillzoneOptions)
                                                                 : std::span<const OptionInfo>(kDeferredOptions),
                         file);
    o.projection = r.is("projection", "d3d") ? ProjectionConvention::D3d : ProjectionConvention::DemoGl;
    o.samplePoint = r.is("reconstruct", "centre") ? PixelSamplePoint::Centre : PixelSamplePoint::Corner;
    o.volumes.fit = r.is("lightVolumes", "circumscribed") ? VolumeFit::Circumscribed : VolumeFit::Inscribed;
    o.volumes.rotation = r.is("volumeRotation", "robust") ? VolumeRotation::Robust : VolumeRotation::Glm096;
    o.floatTargets = r.is("gbuffer", "float");
    // Precision reference keeps the G-buffer unquantized: float targets, power unpacked.
    if (ctx.precision == Precision::Reference) o.floatTargets = true;
    o.positionFromGBuffer = r.is("position", "gbuffer");
    o.accumulateLighting = r.is("accumulate", "lighting");
    o.sampler = r.is("sampler", "gltf") ? PhongSamplerChoice::Gltf : PhongSamplerChoice::Demo;
    o.alphaTest = r.flag("alphaTest");
    o.edges = gbuffer_detail::parseEdgeDetector(r);
    if (method == Method::Killzone) o.threshold = std::uint64_t(r.integer("threshold"));
    return o;
}

// A point or spot light whose range is not finite has no finite volume (glTF
// KHR_lights_punctual without range): it is drawn like a directional light, as the far-plane
// quad, so every pixel in front of the far plane is shaded (a tessera choice; the demo's ranges
// are finite).
bool drawnAsQuad(const Light& light) { return light.type == LightType::Directional || !std::isfinite(light.range); }

// One draw of a volume (or the quad) with pass state `pass`; `ps` null = depth/stencil only.
// Recorded in `batch` when given (no query then): its stats come from the batch's run().
template <class PS>
DrawStats drawLightGeometry(const DeferredSetup& setup, Device& device, const PassState& pass, const RenderTargets& targets,
                            const Light& light, const PS* ps, OcclusionQuery* query, DrawStats* stats, DrawBatch* batch = nullptr) {
    const ForwardPassSetup& fwd = *setup.forward;
    const Viewport viewport{0.0f, 0.0f, float(fwd.width), float(fwd.height), 0.0f, 1.0f};
    DrawState st = makeDrawState(pass, viewport);
    st.precision = fwd.precision;
    VolumeVS vs;
    std::span<const VolumeVertex> vertices;
    std::span<const std::uint32_t> indices;
    if (drawnAsQuad(light)) {
        // DeferredLightingPass::Visit: ModelView = identity, ModelViewProjection = ortho.
        vs.clipFromObject = glm::orthoRH_NO(-1.0f, 1.0f, -1.0f, 1.0f, 0.0f, 1.0f);
        vertices = kScreenQuad;
        indices = kScreenQuadIndices;
    } else {
        // ModelView = View * T * R * S; ModelViewProjection = Projection * ModelView.
        const glm::mat4 clipFromWorld = fwd.clipFromView * fwd.viewFromWorld;
        const glm::mat4 viewFromObject = fwd.viewFromWorld * setup.volumes.worldFromObject(light, setup.options.volumes, &clipFromWorld);
        vs.clipFromObject = fwd.clipFromView * viewFromObject;
        const bool sphere = light.type == LightType::Point;
        vertices = sphere ? std::span<const VolumeVertex>(setup.sphereVertices) : std::span<const VolumeVertex>(setup.coneVertices);
        indices = setup.volumes.meshFor(light.type).indices;
    }
    if (batch) {
        if (ps) batch->draw(st, targets, vertices, indices, vs, *ps);
        else batch->draw(st, targets, vertices, indices, vs, NoPixelShader{});
        return {};
    }
    DrawStats s = ps ? device.draw(st, targets, vertices, indices, vs, *ps, query)
                     : device.draw(st, targets, vertices, indices, vs, NoPixelShader{}, query);
    if (stats) *stats += s;
    return s;
}

// DeferredLightingPass::Render clears the whole stencil before every light. Only pixels that the
// draws since the last clear touched (SetupStats::touched) can hold anything but the clear value,
// so clearing their bounding rectangle leaves the same bytes at a fraction of the cost (a whole
// D24S8 buffer per light at 1280x720 is 3.7 MB of writes). With a DrawBatch the clear is recorded
// between the light's draws and runs tile by tile, only on tiles drawn since the last clear.
// With MSAA the clears keep the edge bit (gbuffer_detail::kEdgeStencilBit): `writeMask` 0x7F.
class StencilClears {
public:
    StencilClears(Surface& depth, std::uint8_t writeMask, DrawBatch* batch) : mDepth(depth), mWriteMask(writeMask), mBatch(batch) {}
    void clear(std::uint8_t value) {
        const bool onlyDrawn = mKnown && value == mValue;
        if (mBatch) {
            mBatch->clearDepthStencil(mDepth, false, 0.0f, true, value, mWriteMask, onlyDrawn);
        } else if (!onlyDrawn) {
            mDepth.clearDepthStencil(false, 0.0f, true, value, mWriteMask);
        } else if (!mDirty.empty()) {
            mDepth.clearDepthStencilRect(std::uint32_t(mDirty.minX), std::uint32_t(mDirty.minY), std::uint32_t(mDirty.maxX),
                                         std::uint32_t(mDirty.maxY), false, 0.0f, true, value, mWriteMask);
        }
        mKnown = true;
        mValue = value;
        mDirty = PixelRect{};
    }
    void drew(const DrawStats& s) { mDirty = unite(mDirty, s.setup.touched); }

private:
    Surface& mDepth;
    std::uint8_t mWriteMask = 0xFF;
    DrawBatch* mBatch = nullptr;
    bool mKnown = false;  // the first clear is whole: the G-buffer pass's stencil is not tracked
    std::uint8_t mValue = 0;
    PixelRect mDirty;
};

// Whether the eye (the view-space origin) lies inside the light's sphere (point) or cone (spot):
// the case in which Killzone 2's marking clips the volume's front faces and lights nothing (ERRATA #6).
bool eyeInsideLightVolume(const ViewLight<float>& light) {
    const glm::vec3 toEye = -glm::vec3(light.positionView);
    const float distance = glm::length(toEye);
    if (!(distance < light.range)) return false;
    if (light.type != LightType::Spot || distance == 0.0f) return true;
    const float cosAngle = glm::dot(toEye / distance, glm::normalize(glm::vec3(light.directionView)));
    return cosAngle >= std::cos(glm::radians(light.spotlightAngleDeg));
}

// The lighting pass: per enabled light in scene order, the 3dgep (unmark, shade) or Killzone 2
// (mark, count, shade-if-above-threshold) sequence; directional lights as the far-plane quad.
template <int kTargets, class T>
void runLights(DeferredSetup& setup, Device& device, BufferRegistry& reg, DrawStats* stats,
               std::map<std::string, std::uint64_t>* variantCounts) {
    using PS = DeferredLightingPS<kTargets, T>;
    const ForwardPassSetup& fwd = *setup.forward;
    Surface& depth = reg.get("depth");
    RenderTargets depthOnly;
    depthOnly.depthStencil = &depth;
    RenderTargets shadeTargets;
    shadeTargets.depthStencil = &depth;
    if constexpr (kTargets == 1) {
        shadeTargets.colors[0] = &reg.get(setup.accumulationName);
    } else {
        shadeTargets.colors[0] = &reg.get("light.diffuse");
        shadeTargets.colors[1] = &reg.get("light.specular");
    }
    Surface* samples = setup.method == Method::Killzone ? &reg.get("killzone.samples") : nullptr;
    const auto count = [variantCounts](const char* what, const Light& light) {
        if (!variantCounts) return;
        std::string name(what);
        name += light.type == LightType::Point ? "point" : light.type == LightType::Spot ? "spot" : "directional";
        ++(*variantCounts)[name];
    };
    // MSAA: the edge bit stays set under the light steps (their stencil reads and writes use the
    // low bits), and every shading draw runs twice: per pixel where it is clear, per sample where set.
    const bool msaa = fwd.sampleCount > 1;
    // 3dgep's steps binned together (raster/draw_batch.h): a light's unmark, shade and the next
    // light's stencil clear are ordered commands of each tile's list. Killzone 2's count is an
    // occlusion query read before its shade: its draws run one at a time.
    std::optional<DrawBatch> batch;
    if (setup.method == Method::Dgep) batch.emplace(device);
    DrawBatch* const binned = batch ? &*batch : nullptr;
    const auto runBatch = [&] {
        if (binned) binned->runInto(stats);
    };
    StencilClears stencil(depth, msaa ? std::uint8_t(~gbuffer_detail::kEdgeStencilBit) : std::uint8_t(0xFF), binned);
    const auto lowBits = [msaa](PassState p) {
        if (msaa) {
            p.depthStencil.stencilReadMask &= std::uint8_t(~gbuffer_detail::kEdgeStencilBit);
            p.depthStencil.stencilWriteMask &= std::uint8_t(~gbuffer_detail::kEdgeStencilBit);
        }
        return p;
    };
    const auto shade = [&](const PassState& pass, const Light& light, const PS& ps) {
        gbuffer_detail::drawPerPixelThenEdgeSamples(msaa, pass, ps, [&](const PassState& state, const auto& shader) {
            stencil.drew(drawLightGeometry(setup, device, state, shadeTargets, light, &shader, nullptr, stats, binned));
        });
    };
    const auto stepDone = [&](std::size_t light, std::string_view step) {
        if (!setup.afterLightStep) return;
        runBatch();  // the step's buffers as they stand after it
        setup.afterLightStep(light, step, reg);
    };
    for (std::size_t i = 0; i < setup.lightsWorld.size(); ++i) {
        const Light& light = setup.lightsWorld[i];
        if (!light.enabled) continue;  // the demo draws no volume for a disabled light
        if (light.type == LightType::Capsule) continue;  // not a 3dgep light (deferred-cookbook shades capsules)
        const ViewLight<T>* viewLight;
        if constexpr (std::is_same_v<T, float>) viewLight = &fwd.lightsExact[i];
        else viewLight = &fwd.lightsReference[i];
        const PS ps{&setup.inputs, viewLight, fwd.precision == Precision::Fast, std::uint32_t(i)};
        if (drawnAsQuad(light)) {
            // DeferredLightingPass::Render clears the stencil for every enabled light; the
            // directional pipeline does not use it.
            stencil.clear(setup.method == Method::Killzone ? kKillzoneStencilClear : kDeferredStencilClear);
            shade(kDeferredDirectionalPass, light, ps);
            count("light:", light);
            stepDone(i, "shade");
            continue;
        }
        if (setup.method == Method::Dgep) {
            stencil.clear(kDeferredStencilClear);
            stencil.drew(drawLightGeometry<PS>(setup, device, lowBits(kDeferredUnmarkPass), depthOnly, light, nullptr, nullptr, stats, binned));
            stepDone(i, "unmark");
            shade(kDeferredShadePass, light, ps);
            count("light:", light);
            stepDone(i, "shade");
        } else {
            stencil.clear(kKillzoneStencilClear);
            stencil.drew(drawLightGeometry<PS>(setup, device, lowBits(kKillzoneMarkPass), depthOnly, light, nullptr, nullptr, stats));
            stepDone(i, "mark");
            OcclusionQuery query;
            query.begin();
            stencil.drew(drawLightGeometry<PS>(setup, device, lowBits(kKillzoneCountPass), depthOnly, light, nullptr, &query, stats));
            query.end();
            const std::uint64_t passed = query.samplesPassed();
            const std::uint32_t stored = std::uint32_t(std::min<std::uint64_t>(passed, kKillzoneNotCounted - 1u));
            encodeTexelUint(Format::R32_UINT, glm::uvec4(stored, 0u, 0u, 1u),
                            samples->texel(std::uint32_t(i % kSamplesRow), std::uint32_t(i / kSamplesRow)));
            stepDone(i, "count");
            if (killzoneShouldShade(passed, setup.options.threshold)) {
                shade(kKillzoneShadePass, light, ps);
                count("light:", light);
                stepDone(i, "shade");
            } else {
                count("killzone-skipped:", light);
                if (fwd.notes && eyeInsideLightVolume(fwd.lightsExact[i]))
                    fwd.notes->add({"eye-inside-volume", "lights skipped: the eye is inside their volume, whose clipped front faces mark nothing",
                                    1, 6, "--technique deferred", true});
                else if (fwd.notes && passed > 0)  // marked samples the threshold (an option) left unshaded
                    fwd.notes->add({"below-query-threshold",
                                    "lights skipped: their occlusion query passed samples, but not more than \"threshold\"", 1, 0,
                                    "--option threshold=0", true});
            }
        }
    }
    runBatch();
}

// The "lights" pass: each light's volume steps (unmark, shade; Killzone: mark, count, shade) over the
// G-buffer and the depth copy, into `lightTargets`.
Pass lightsPass(const std::shared_ptr<DeferredSetup>& setup, const TechniqueContext& ctx, const std::vector<std::string>& gbufferTargets,
                const std::vector<std::string>& lightTargets) {
    const DeferredOptions& opt = setup->options;
    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;
    std::map<std::string, std::uint64_t>* variantCounts = ctx.variantCounts;
    std::vector<std::string> lightReads = gbufferTargets;
    lightReads.emplace_back("depth");
    lightReads.emplace_back("depth.copy");
    std::vector<std::string> lightWrites = lightTargets;
    lightWrites.emplace_back("depth");
    std::vector<std::string> inspection;  // Killzone 2's per-light sample counts: no later pass reads them
    if (setup->method == Method::Killzone) {
        lightWrites.emplace_back("killzone.samples");
        inspection.emplace_back("killzone.samples");
    }
    if (opt.accumulateLighting) lightReads.insert(lightReads.end(), lightTargets.begin(), lightTargets.end());
    return {"lights", lightReads, lightWrites, [setup, device, stats, variantCounts](BufferRegistry& reg) {
                   LightingInputs& in = setup->inputs;
                   in.diffuse = TargetReader(reg.get("gbuffer.diffuse"));
                   in.specular = TargetReader(reg.get("gbuffer.specular"));
                   in.normal = TargetReader(reg.get("gbuffer.normal"));
                   if (setup->options.positionFromGBuffer) in.position = TargetReader(reg.get("gbuffer.position"));
                   in.depth = &reg.get("depth.copy");
                   const bool reference = setup->forward->precision == Precision::Reference;
                   if (setup->options.accumulateLighting) {
                       if (reference) runLights<2, double>(*setup, *device, reg, stats, variantCounts);
                       else runLights<2, float>(*setup, *device, reg, stats, variantCounts);
                   } else {
                       if (reference) runLights<1, double>(*setup, *device, reg, stats, variantCounts);
                       else runLights<1, float>(*setup, *device, reg, stats, variantCounts);
                   }
               },
            inspection};
}

// The "compose" pass (accumulate lighting): forward's final expression on every pixel in front of
// the far plane (the directional quad's pixels), written to the back buffer without blending; with
// MSAA per pixel where the edge bit is clear and per sample where it is set.
Pass composePass(const std::shared_ptr<DeferredSetup>& setup, const TechniqueContext& ctx) {
    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;
    const bool reference = ctx.precision == Precision::Reference;
    const bool msaa = ctx.sampleCount > 1;
    const std::string back = backBufferTarget(ctx.sampleCount), backReference = referenceBufferTarget(ctx.sampleCount);
    std::vector<std::string> composeReads{"accumulation", "gbuffer.diffuse", "gbuffer.specular", "light.diffuse",
                                          "light.specular", "depth", back};
    std::vector<std::string> composed{back};
    if (reference) {
        composeReads.push_back(backReference);
        composed.push_back(backReference);
    }
    // Precision reference composes into the float buffer and quantizes it afterwards.
    return {"compose", composeReads, composed, [setup, device, stats, reference, back, backReference, msaa](BufferRegistry& reg) {
                   LightingInputs& in = setup->inputs;
                   in.accumulation = TargetReader(reg.get("accumulation"));
                   in.lightDiffuse = TargetReader(reg.get("light.diffuse"));
                   in.lightSpecular = TargetReader(reg.get("light.specular"));
                   RenderTargets rt;
                   rt.colors[0] = &reg.get(reference ? backReference : back);
                   rt.depthStencil = &reg.get("depth");
                   PassState pass = kDeferredDirectionalPass;
                   pass.blend = BlendState{};
                   Light quad;
                   quad.type = LightType::Directional;
                   const ComposePS ps{&setup->inputs};
                   gbuffer_detail::drawPerPixelThenEdgeSamples(msaa, pass, ps, [&](const PassState& state, const auto& shader) {
                       drawLightGeometry(*setup, *device, state, rt, quad, &shader, nullptr, stats);
                   });
                   if (reference) {
                       Surface& composedRef = reg.get(backReference);
                       storeAsUnorm(composedRef, composedRef);
                       storeAsUnorm(composedRef, reg.get(back));
                   }
               }};
}

Frame buildDeferredFrame(const TechniqueContext& ctx, Method method) {
    const std::string file = ctx.errorFile();
    auto setup = std::make_shared<DeferredSetup>();
    setup->method = method;
    setup->options = parseOptions(ctx, method, file);
    setup->afterLightStep = ctx.afterLightStep;
    const DeferredOptions& opt = setup->options;
    setup->forward = makeForwardPassSetup(ctx, opt.projection, opt.sampler, opt.alphaTest);
    setup->lightsWorld = ctx.lights();
    for (const glm::vec3& p : setup->volumes.sphere().positions) setup->sphereVertices.push_back({p});
    for (const glm::vec3& p : setup->volumes.cone().positions) setup->coneVertices.push_back({p});
    setup->separateAccumulation = opt.floatTargets || opt.accumulateLighting;
    // ScreenToViewParams: InverseProjection = glm::inverse(projection), ScreenDimensions = viewport.
    setup->inputs.inverseProjection = glm::inverse(setup->forward->clipFromView);
    setup->inputs.screenDimensions = glm::vec2(float(ctx.width), float(ctx.height));
    setup->inputs.samplePoint = opt.samplePoint;
    setup->inputs.floatTargets = opt.floatTargets;
    setup->inputs.positionFromGBuffer = opt.positionFromGBuffer;

    const Format colorFormat = opt.floatTargets ? Format::R32G32B32A32_FLOAT : Format::R8G8B8A8_UNORM;
    const Format depthFormat = opt.floatTargets ? Format::D32_FLOAT_S8X24_UINT : Format::D24_UNORM_S8_UINT;
    // With MSAA every buffer has `samples` samples and the image is resolved last (technique.h).
    const std::uint32_t samples = ctx.sampleCount;
    const bool msaa = samples > 1;
    const std::string back = backBufferTarget(samples), backReference = referenceBufferTarget(samples);
    setup->accumulationName = setup->separateAccumulation ? "accumulation" : back;
    std::vector<std::string> gbufferTargets{setup->accumulationName, "gbuffer.diffuse", "gbuffer.specular", "gbuffer.normal"};
    if (opt.positionFromGBuffer) gbufferTargets.emplace_back("gbuffer.position");
    std::vector<std::string> lightTargets;
    if (opt.accumulateLighting) lightTargets = {"light.diffuse", "light.specular"};
    else lightTargets = {setup->accumulationName};
    std::vector<std::string> created = gbufferTargets;
    if (setup->separateAccumulation) created.push_back(back);
    if (ctx.precision == Precision::Reference) created.push_back(backReference);
    if (opt.accumulateLighting) created.insert(created.end(), lightTargets.begin(), lightTargets.end());
    created.emplace_back("depth");
    if (method == Method::Killzone) created.emplace_back("killzone.samples");
    if (msaa) {
        created.emplace_back(gbuffer_detail::kEdgeSurfaceTarget);
        created.emplace_back(gbuffer_detail::kEdgeCoverageTarget);
        created.emplace_back(gbuffer_detail::kEdgesBuffer);
    }

    Frame frame;
    frame.add({"clear", {}, created, [setup, colorFormat, depthFormat, samples, back, backReference](BufferRegistry& reg) {
                   const DeferredOptions& o = setup->options;
                   const std::uint32_t w = setup->forward->width, h = setup->forward->height;
                   reg.create(back, {w, h, Format::R8G8B8A8_UNORM, samples}).clearColor(kDemoClearColor);
                   if (setup->forward->precision == Precision::Reference)
                       reg.create(backReference, {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(kDemoClearColor);
                   if (setup->separateAccumulation)
                       reg.create("accumulation", {w, h, colorFormat, samples}).clearColor(kDemoClearColor);
                   reg.create("gbuffer.diffuse", {w, h, colorFormat, samples}).clearColor(kDemoClearColor);
                   reg.create("gbuffer.specular", {w, h, colorFormat, samples}).clearColor(kDemoClearColor);
                   reg.create("gbuffer.normal", {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(kDemoClearColor);
                   if (o.positionFromGBuffer)
                       reg.create("gbuffer.position", {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(kDemoClearColor);
                   if (o.accumulateLighting) {
                       reg.create("light.diffuse", {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(glm::vec4(0.0f));
                       reg.create("light.specular", {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(glm::vec4(0.0f));
                   }
                   reg.create("depth", {w, h, depthFormat, samples}).clearDepthStencil(true, 1.0f, true, 0);
                   if (samples > 1) gbuffer_detail::createEdgeTargets(reg, w, h, samples);
                   if (setup->method == Method::Killzone) {
                       const std::uint32_t n = std::uint32_t(std::max<std::size_t>(setup->lightsWorld.size(), 1));
                       reg.create("killzone.samples", {std::min(n, kSamplesRow), (n + kSamplesRow - 1) / kSamplesRow,
                                                       Format::R32_UINT, 1})
                           .clearUint(glm::uvec4(kKillzoneNotCounted));
                   }
               }});

    frame.add(gbuffer_detail::deferredGBufferPass(setup->forward, ctx, gbufferTargets, opt.floatTargets, opt.accumulateLighting));
    if (msaa) frame.add(gbuffer_detail::edgePass(ctx.device, ctx.stats, opt.edges));

    // CopyTexturePass(depthStencilBuffer, depthStencilTexture): the lighting PS's DepthTextureVS.
    frame.add({"copy depth", {"depth"}, {"depth.copy"}, [](BufferRegistry& reg) {
                   const Surface& depth = reg.get("depth");
                   Surface& copy = reg.create("depth.copy", depth.desc());
                   std::copy(depth.bytes().begin(), depth.bytes().end(), copy.bytes().begin());
               }});

    frame.add(lightsPass(setup, ctx, gbufferTargets, lightTargets));

    const bool reference = ctx.precision == Precision::Reference;
    if (setup->separateAccumulation) {
        // The accumulation target to the back buffer as the output merger converts a PS value
        // to R8G8B8A8_UNORM (storeAsUnorm); precision reference also keeps the clamped float values.
        std::vector<std::string> presented = withReferenceBuffer({back}, ctx.precision);
        if (reference) presented[1] = backReference;
        frame.add({"present", {"accumulation"}, presented, [reference, back, backReference](BufferRegistry& reg) {
                       const Surface& accumulation = reg.get("accumulation");
                       storeAsUnorm(accumulation, reg.get(back));
                       if (reference) storeAsUnorm(accumulation, reg.get(backReference));
                   }});
    }
    if (opt.accumulateLighting) frame.add(composePass(setup, ctx));

    // The demo's TransparentPass with g_pTransparentPipeline, as forward's (3dgep article §3.4:
    // "identical to the forward rendering technique"), over the back buffer and the G-buffer's depth.
    frame.add(gbuffer_detail::forwardTransparentPass(setup->forward, ctx));
    if (msaa) frame.add(resolveBackBufferPass(samples, ctx.precision));
    return frame;
}

} // namespace

namespace gbuffer_detail {

Pass deferredGBufferPass(std::shared_ptr<const ForwardPassSetup> forward, const TechniqueContext& ctx,
                         std::vector<std::string> targets, bool floatTargets, bool forwardAlpha) {
    const bool msaa = ctx.sampleCount > 1;
    const bool position = targets.size() > 4;
    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;
    std::map<std::string, std::uint64_t>* variantCounts = ctx.variantCounts;
    const SceneResources* res = ctx.resources;
    std::vector<std::string> writes = targets;
    writes.emplace_back("depth");
    std::vector<std::string> out = writes;
    if (msaa) {
        out.emplace_back(kEdgeSurfaceTarget);
        out.emplace_back(kEdgeCoverageTarget);
    }
    return {"gbuffer", writes, out,
            [forward, device, stats, variantCounts, res, targets, floatTargets, forwardAlpha, position, msaa](BufferRegistry& reg) {
                RenderTargets rt;
                for (std::size_t i = 0; i < targets.size(); ++i) rt.colors[i] = &reg.get(targets[i]);
                if (msaa) bindEdgeTargets(rt, reg, int(targets.size()));
                rt.depthStencil = &reg.get("depth");
                drawDeferredGBuffer(*forward, *device, *res, rt, floatTargets, forwardAlpha, position, stats, variantCounts);
            }};
}

} // namespace gbuffer_detail

void drawDeferredGBuffer(const ForwardPassSetup& fwd, Device& device, const SceneResources& res, const RenderTargets& rt,
                         bool floatTargets, bool forwardAlpha, bool positionTarget, DrawStats* stats,
                         std::map<std::string, std::uint64_t>* variantCounts) {
    // g_pGeometryPipeline: depth LESS with writes, cull back (as forward's opaque pass, with its
    // glTF additions: doubleSided culls none, mirrored transforms).
    const std::uint32_t samples = rt.colors[0]->sampleCount();
    const auto configure = [&](auto& ps) {
        ps.floatTargets = floatTargets;
        ps.forwardAlpha = forwardAlpha;
        ps.opacity = ps.data->opacity;
        ps.sampleCount = samples;
    };
    const auto draw = [&]<template <bool> class PS>() {
        gbuffer_detail::drawOpaqueGBuffer<PS>(fwd, device, res, rt, kDeferredGBufferPass, "gbuffer", configure, stats, variantCounts);
    };
    if (samples > 1 && positionTarget) draw.template operator()<GBufferMsaaPS5>();
    else if (samples > 1) draw.template operator()<GBufferMsaaPS4>();
    else if (positionTarget) draw.template operator()<GBufferPS5>();  // RT4 holds the view position
    else draw.template operator()<GBufferPS4>();
}

Frame buildDeferred(const TechniqueContext& context) { return buildDeferredFrame(context, Method::Dgep); }

Frame buildDeferredKillzone(const TechniqueContext& context) { return buildDeferredFrame(context, Method::Killzone); }

} // namespace tessera
