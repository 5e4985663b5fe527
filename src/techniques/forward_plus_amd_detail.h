// Private to the forward-plus-amd sources (src/techniques/forward_plus_amd*.cpp): the options, the
// state the passes of one frame share (AMD's light table, the lists, the shadow and VPL records),
// and the pass functions one file defines for the frame builder in forward_plus_amd.cpp.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>
#include <span>

#include <tessera/techniques/forward_plus_amd.h>
#include <tessera/errors/input_error.h>
#include <tessera/culling/depth_mask.h>
#include <tessera/math/det_math.h>
#include <tessera/gbuffer/screen_to_view.h>
#include <tessera/culling/tile_frustum.h>
#include <tessera/shading/phong_surface.h>
#include <tessera/shading/amd_lighting.h>
#include <tessera/shading/phong_material_shader.h>
#include <tessera/raytrace/shadow_ray_scene.h>
#include <tessera/shading/tile_heat_colors.h>
#include <tessera/techniques/amd_light_culling.h>
#include <tessera/techniques/amd_shadow_rays.h>
#include <tessera/techniques/amd_vpl.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/forward_plus.h>
#include <tessera/techniques/technique_options.h>
#include <tessera/frame/buffer_registry.h>
#include <tessera/raster/device.h>

namespace tessera::forward_plus_amd_detail {

constexpr std::uint32_t kMaxSurfaceEdge = 16384;  // D3D11_REQ_TEXTURE2D_U_OR_V_DIMENSION, texels

struct AmdOptions {
    bool shadingAmd = true;
    bool depthMask = true;
    bool halfZ = false;
    ProjectionConvention projection = ProjectionConvention::D3d;
    PhongSamplerChoice sampler = PhongSamplerChoice::Demo;
    bool alphaTest = false;
    AmdLightLoop lightLoop = AmdLightLoop::Binned;
    std::string shadows = "auto";   // "auto" | "on" | "off"
    ShadowRayOptions shadowRays;
    std::string indirect = "auto";  // "auto" | "on" | "off"
    VplOptions vpl;
};

// AMD's world-space light properties, indexed by scene light index (g_PointLightBuffer* /
// g_SpotLightBuffer* of ForwardPlus11; GPU Pro 4 §5.3.1). kind: what the light is to the AMD shader.
enum class AmdKind : std::uint8_t { None, Point, Spot };

struct AmdLightTable {
    std::vector<AmdKind> kind;
    std::vector<AmdPointLight<float>> points;  // valid where kind == Point
    std::vector<AmdSpotLight<float>> spots;    // valid where kind == Spot
};

// What the culling pass hands the shading passes.
struct AmdState {
    AmdOptions options;
    std::shared_ptr<ForwardPassSetup> setup;
    glm::mat4 inverseProjectionLh{1.0f};  // inverse(P_rh * diag(1, 1, -1, 1))
    std::vector<glm::vec4> spheresViewLh;  // culling spheres (centre LH view, radius)
    AmdLightTable table;
    glm::vec3 cameraPosWorld{0.0f};
    AmdTileLightLists opaque, transparent;
    TileLightList opaqueList, transparentList;  // 3dgep shading: bound by the passes
    // GPU Pro 4 §5.6.2 (shadowsActive): the lights as job creation sees them (scene lights, then
    // VPLs that never cast), the pixels it reads, and the jobs and mask it makes.
    bool shadowsActive = false;
    std::vector<ShadowCaster> casters;
    std::vector<float> depthWindow;
    std::vector<glm::vec4> normalWorld;
    glm::dmat4 worldFromClip{1.0};
    ShadowJobs shadowJobs;
    // §5.5 (indirectActive): the indirect light, its RSM view; lights [sceneLightCount, ...) are VPLs.
    bool indirectActive = false;
    Light indirectLight;
    RsmView rsm;
    std::uint32_t sceneLightCount = 0;
    // What "auto" turned off in this configuration, noted every frame (the cull pass adds them).
    std::vector<FrameNote> configurationNotes;
};

// ----- forward_plus_amd_culling.cpp: the light table and the "light-culling" pass ------------------

// A 1-sample R32_UINT surface of at least `entries` elements, rows of up to 16384 (a light index
// pool or the shadow job buffer); throws past 16384 x 16384.
SurfaceDesc indexListDesc(std::uint64_t entries);
void storeUint32(std::byte* base, std::size_t element, std::uint32_t value);
// One light's culling sphere and AMD shading record (entry i of the tables).
void convertLight(AmdState& st, std::size_t i, const ViewLight<float>& l, const Light& w);
// Culling spheres in AMD's LH view space and the AMD shading table, from the scene's lights.
void convertLights(AmdState& st, std::span<const Light> sceneLights);
// "light-culling": the opaque and transparent lists from "depth", their grids and pools, the
// tiles' depth range and 2.5D mask, the radar heat map and the list counters.
void cullAll(AmdState& st, Device& device, BufferRegistry& reg);

// ----- forward_plus_amd_shading.cpp: ForwardPlus11's RenderScenePS --------------------------------

// The opaque or transparent pass, or (indirectOnly) the opaque geometry again writing only the
// VPLs' contribution (float at every precision, into the one target of `rt`).
void drawAmdPass(const AmdState& st, Device& device, const SceneResources& res, const RenderTargets& rt, bool transparentPass,
                 DrawStats* stats, bool indirectOnly = false);

// ----- forward_plus_amd_indirect.cpp: GPU Pro 4 §5.5, the reflective shadow map and its VPLs -------

// "rsm": the opaque draw items from the indirect light into "rsm.position/normal/color/depth".
void drawRsm(const AmdState& st, Device& device, const SceneResources& res, BufferRegistry& reg, DrawStats* stats);
// "vpl": N x N VPLs from the RSM, appended after the scene's lights to st's tables.
void makeVpls(AmdState& st, BufferRegistry& reg);

// ----- forward_plus_amd_shadows.cpp: GPU Pro 4 §5.6.2, ray-cast shadows -----------------------------

// "shadow-jobs": one job per (pixel, shadow-casting light of its tile list) into "shadow.jobs".
void createJobsPass(AmdState& st, Device& device, BufferRegistry& reg);
// "shadow-rays": one Embree occlusion ray per job into "shadow.mask" and "shadow.counters".
void castRaysPass(AmdState& st, Device& device, const SceneResources& res, BufferRegistry& reg);

} // namespace tessera::forward_plus_amd_detail
