// What deferred-classic and light-prepass share (PR&C D3D11 ch. 11 §11.2-§11.4): the light-pass
// options, each light's draw (a full-screen quad, a scissored quad or the light's volume) and the
// "lights" pass that runs Listing 11.3's shading (classic) or Listing 11.5's (light pre-pass) over
// the G-buffer. Each technique keeps its own G-buffer layout, clear and final passes in its file.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <tessera/buffers/target_reader.h>
#include <tessera/gbuffer/msaa_edges.h>
#include <tessera/gbuffer/prc_gbuffer.h>
#include <tessera/shading/prc_lighting.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/technique_options.h>

#include "gbuffer_pass.h"
#include "msaa_deferred.h"

namespace tessera::prc_light_pass {

enum class Geometry : std::uint8_t { Quads, Scissor, Volumes };

// The options both techniques read (kClassicGeometryOption ... kEdgesPrcOption, deferred_classic.h).
struct Options {
    Geometry geometry = Geometry::Quads;
    bool normalizeV = false;  // viewVector normalized (ERRATA #27)
    bool roundOut = false;    // scissorRound out (ERRATA #28)
    bool stencil = false;     // §11.4.2's stencil mask of lit geometry
    PhongSamplerChoice sampler = PhongSamplerChoice::Demo;
    bool alphaTest = false;
    EdgeDetector edges = EdgeDetector::Coverage;  // MSAA: Listing 11.17's coverage flag
};
Options readOptions(const OptionReader& options);

// What the light shader reads besides its light: the G-buffer (bound by the lights pass), the
// camera and, for the optimized layout, what rebuilds the position from depth.
struct Inputs {
    bool lightPrePass = false;  // light-prepass: Listing 11.5 into the light buffer
    bool optimized = false;     // the optimized layout: decode RT0, position from depth
    bool safeNormals = false;   // normalEncoding safe: the decode clamps 1 - |e|^2 at 0
    const Surface* depth = nullptr;
    PrcProjectionAB ab;
    float proj00 = 1.0f, proj11 = 1.0f;
    glm::vec2 screenPx{1.0f};
    glm::mat4 worldFromViewLh{1.0f};
    TargetReader normal, diffuse, specular, position;
    glm::vec3 cameraWorld{0.0f};
    bool normalizeV = false;
};

struct LocalVertex {
    glm::vec3 pos;
};

// One light's draw: its PrcLight (float and double), mesh, matrix and states.
struct LightDraw {
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

struct Setup {
    Options options;
    std::shared_ptr<ForwardPassSetup> forward;
    Inputs inputs;
    glm::mat4 worldFromView{1.0f};
    bool lightGroups = false;  // the scene's light groups take the stencil (§11.4.2)
    std::vector<LightDraw> draws;
    std::function<void(std::size_t, std::string_view, const BufferRegistry&)> afterLightStep;
};

// The forward pass set-up (D3D projection), the shader inputs and every light's draw; refuses light
// groups under MSAA (both need the stencil), naming `file`.
std::shared_ptr<Setup> makeSetup(const TechniqueContext& ctx, const Options& options, bool lightPrePass, bool optimized,
                                 bool safeNormals, const std::string& file);

// The buffer names of a G-buffer layout: `gbuffer` its targets and "depth" (what the light pass
// reads), `writes` those and, with MSAA, the edge detectors' inputs (what the G-buffer pass
// writes), `created` those, the edges buffer with MSAA and the back buffer (what "clear" creates).
struct GBufferNames {
    std::vector<std::string> gbuffer, writes, created;
};
GBufferNames gbufferNames(const std::vector<std::string>& targets, std::uint32_t samples);

// The G-buffer pass's depth-stencil state: LESS, and the lit-geometry mask or each item's light
// groups as the stencil reference (§11.4.2).
PassState gbufferPassState(const Setup& setup);

// The "gbuffer" pass: the opaque geometry through PS<discard> into the layout's `targets` (the first
// is "gbuffer.normal") and "depth"; with MSAA through MsaaPS, the edge detectors' two targets after
// the layout's. `configure(ps)` sets each shader's own fields; `variant` names the draws' shader.
template <template <bool> class PS, template <bool> class MsaaPS, class Configure>
Pass gbufferPass(const std::shared_ptr<Setup>& setup, const TechniqueContext& ctx, const std::vector<std::string>& targets,
                 const std::vector<std::string>& writes, const char* variant, Configure configure) {
    std::vector<std::string> reads = targets;
    reads.emplace_back("depth");
    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;
    std::map<std::string, std::uint64_t>* variantCounts = ctx.variantCounts;
    const SceneResources* res = ctx.resources;
    const std::uint32_t samples = ctx.sampleCount;
    return {"gbuffer", reads, writes, [=](BufferRegistry& reg) {
                RenderTargets rt;
                for (std::size_t k = 0; k < targets.size(); ++k) rt.colors[k] = &reg.get(targets[k]);
                rt.depthStencil = &reg.get("depth");
                const PassState pass = gbufferPassState(*setup);
                const auto configureAll = [&](auto& ps) {
                    ps.sampleCount = samples;
                    configure(ps);
                };
                if (samples == 1) {
                    gbuffer_detail::drawOpaqueGBuffer<PS>(*setup->forward, *device, *res, rt, pass, variant, configureAll, stats,
                                                          variantCounts, setup->lightGroups);
                } else {
                    gbuffer_detail::bindEdgeTargets(rt, reg, int(targets.size()));
                    gbuffer_detail::drawOpaqueGBuffer<MsaaPS>(*setup->forward, *device, *res, rt, pass, variant, configureAll, stats,
                                                              variantCounts);
                }
            }};
}

// The "lights" pass: reads `gbuffer` (the layout's targets and "depth") and adds each light's
// shading into `lightTarget` (step "shade" per light).
Pass lightsPass(const std::shared_ptr<Setup>& setup, const TechniqueContext& ctx, std::vector<std::string> gbuffer,
                const std::string& lightTarget);

} // namespace tessera::prc_light_pass
