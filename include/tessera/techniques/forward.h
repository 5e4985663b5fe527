// The `forward` technique of the 3dgep article (§2): clear, opaque pass, transparent pass with alpha
// blending, every light evaluated per pixel by the article's pixel shader
// (shading/phong_material_shader.h). Pass states follow the 3dgep demo's
// GraphicsTest/src/main.cpp; options select faithful or corrected behaviour.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/shading/phong_material_shader.h>
#include <tessera/state/comparison.h>
#include <tessera/techniques/technique.h>

namespace tessera {

// Its options (techniques/option_catalog.h): keys, values, the faithful default, the correction and its
// ERRATA.md row; read through OptionReader, listed by `tessera options`.
inline constexpr std::array<OptionInfo, 3> kForwardOptions{kProjectionOption, kSamplerOption, kAlphaTestOption};

// Options (scene file "options"; unknown keys or values are InputErrors naming /options/KEY):
//   "projection": "demo-gl" (default, faithful) | "d3d" (corrected).
//       demo-gl: the demo's glm::perspective in OpenGL form ([2][2] = -(f+n)/(f-n),
//       [3][2] = -2fn/(f-n)) used unchanged under D3D clipping 0 <= z <= w, so the effective
//       near plane is at view z = -2fn/(f+n) (-0.19998 for n = 0.1, f = 1000) and the depth
//       buffer holds GL NDC z (demo Camera.cpp; ERRATA #1).
//       d3d: perspectiveRH_ZO, near plane at -n, depth 0 at the near plane.
//   "sampler": "demo" (default: the demo's LinearRepeatSampler, trilinear + wrap, for every
//       slot) | "gltf" (each texture's glTF sampler).
//   "alphaTest": false (default: the demo's forward PS applies no AlphaThreshold, ERRATA #2)
//       | true (discard when alpha * Opacity < AlphaThreshold, as the demo's G-buffer PS does;
//       makes glTF MASK cut-outs work).
// What each pass does (TechniqueInfo::passes; "clear", "transparent", "resolve" are shared).
inline constexpr std::array<PassCaption, 1> kForwardPassCaptions{{
    {"opaque", "Every opaque draw shaded with every light in its pixel shader (3dgep article §2 Forward Rendering; demo "
               "ForwardRendering.hlsl)."},
}};

// Buffers: "backbuffer" R8G8B8A8_UNORM (the demo's gamma-space values, no sRGB encode),
// "depth" D24_UNORM_S8_UINT; with precision reference also "backbuffer.reference"
// R32G32B32A32_FLOAT (the double shading rounded once to float, not quantized to 8 bits).
// Precision fast: the fastmath lighting (phong_lighting.h) and the raster's fast path
// (DrawState::precision); the buffers are exact's.
Frame buildForward(const TechniqueContext& context);

enum class ProjectionConvention { DemoGl, D3d };

// The 3dgep demo's clear colour (its main.cpp g_ClearColor, cornflower blue), used by every technique
// that follows the demo so that their images compare; depth clears to 1, stencil to 0.
inline constexpr glm::vec4 kDemoClearColor{0.39f, 0.58f, 0.93f, 1.0f};

// The 3dgep projection of `camera` (vertical FOV, aspect = camera.aspect or `aspect`). The
// tangent comes from detTan (no libm); the element formulas are glm's (0.9.6.3 perspective for
// DemoGl, perspectiveRH_ZO for D3d). Infinite far: the limits f -> inf. Orthographic cameras:
// orthoRH_ZO under both conventions (the demo had none; the GL form would clip half the depth range).
glm::mat4 projection3dgep(const Camera& camera, float aspect, ProjectionConvention convention);

// What forward's passes share over a frame, also used by deferred's transparent pass ("identical
// to forward", 3dgep article §3.4): size, camera matrices, the Phong texture set and the view-space
// lights (float for exact, double for reference).
struct ForwardPassSetup {
    std::uint32_t width = 0, height = 0;   // px
    std::uint32_t sampleCount = 1;         // MSAA samples per pixel of every target
    glm::mat4 viewFromWorld{1.0f};
    glm::mat4 clipFromView{1.0f};
    bool alphaTest = false;
    Precision precision = Precision::Exact;
    std::unique_ptr<PhongTextureSet> textures;
    std::vector<ViewLight<float>> lightsExact;
    std::vector<ViewLight<double>> lightsReference;
    std::shared_ptr<const FastLightSet> fastLights;  // precision fast: lightsExact as arrays
    FrameNotes* notes = nullptr;           // the context's: draws of cut-out materials without the alpha test
};

// Notes (frame/frame_notes.h) a draw of `material` through the forward PS without the alpha test
// when the material would discard with it (glTF MASK, ERRATA #2): kind "alpha-test-off".
void noteAlphaTestOff(const ForwardPassSetup& setup, const PhongMaterial& material);

// The setup of `context` (its camera, size, precision and scene lights in scene order).
std::shared_ptr<ForwardPassSetup> makeForwardPassSetup(const TechniqueContext& context, ProjectionConvention projection,
                                                       PhongSamplerChoice sampler, bool alphaTest);

// What Forward+ (forward_plus.h) changes in forward's passes: the depth test (its opaque pass
// runs after a depth pre-pass with LESS_EQUAL, its transparent pass LESS_EQUAL too) and the
// light loop (the pass's tile list instead of every light). The defaults are forward's.
struct ForwardPassOverrides {
    ComparisonFunc depthFunc = ComparisonFunc::Less;
    const TileLightList* tileLights = nullptr;  // every precision (reference shades the listed lights in double)
};

// The targets of forward's passes in `registry` (forward, Forward+ and its AMD variant): colors[0]
// the back buffer (multisampled with MSAA), colors[1] its float copy at precision reference, the
// depth-stencil buffer "depth".
RenderTargets forwardPassTargets(const ForwardPassSetup& setup, BufferRegistry& registry);

// The tile light list one Forward+ pass reads (TileLightList), bound to the registry's
// "lightgrid.<opaque|transparent>" and "lightindex.<opaque|transparent>" buffers: `indexCount`
// entries of the index list (the culling's capacity), tiles of `tileSizePx` px.
TileLightList bindTileLightList(BufferRegistry& registry, bool transparentPass, std::uint32_t indexCount,
                                std::uint32_t tileSizePx);

// The demo's OpaquePass (g_pOpaquePipeline: depth LESS with writes, cull back; glTF doubleSided
// culls none) or TransparentPass (g_pTransparentPipeline: SrcAlpha / InvSrcAlpha, depth LESS
// without writes, cull none) over the scene's draw items in order, through the Phong PS.
// `targets`: colors[0] the back buffer (and colors[1] the float copy at precision reference),
// the depth-stencil buffer.
void drawForwardPass(const ForwardPassSetup& setup, Device& device, const SceneResources& resources,
                     const RenderTargets& targets, bool transparentPass, DrawStats* stats,
                     std::map<std::string, std::uint64_t>* variantCounts, const ForwardPassOverrides& overrides = {});

} // namespace tessera
