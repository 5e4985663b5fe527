// The `deferred` and `deferred-killzone` techniques of the 3dgep article (§3; the demo's
// g_DeferredTechnique, DeferredRendering.hlsl, DeferredLightingPass.cpp): G-buffer, depth copy,
// per-light stencil light volumes (3dgep unmark + shade, or Killzone 2 mark + count + shade),
// directional lights as a far-plane quad, then forward's transparent pass.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>

#include <tessera/techniques/technique.h>

namespace tessera {

// Its options (techniques/option_catalog.h): keys, values, the faithful default, the correction and its
// ERRATA.md row; read through OptionReader, listed by `tessera options`.
namespace option_values {
inline constexpr std::array<std::string_view, 2> kReconstruct{"corner", "centre"};
inline constexpr std::array<std::string_view, 2> kVolumes{"inscribed", "circumscribed"};
inline constexpr std::array<std::string_view, 2> kRotation{"glm096", "robust"};
inline constexpr std::array<std::string_view, 2> kAccumulate{"color", "lighting"};
} // namespace option_values

inline constexpr std::array<OptionInfo, 10> kDeferredOptions{
    kProjectionOption,
    OptionInfo{"reconstruct", OptionInfo::Kind::Word, option_values::kReconstruct, -1, "corner", "centre", 3,
               "where the light pass rebuilds P from depth: the pixel's top-left corner, or its centre"},
    OptionInfo{"lightVolumes", OptionInfo::Kind::Word, option_values::kVolumes, -1, "inscribed", "circumscribed", 4,
               "the demo's sphere and cone meshes inside the light's range, or scaled to contain it"},
    OptionInfo{"volumeRotation", OptionInfo::Kind::Word, option_values::kRotation, -1, "glm096", "robust", 5,
               "glm 0.9.6's quat(u, v) (identity for a spot aimed down -Z), or a rotation that handles it"},
    OptionInfo{"gbuffer", OptionInfo::Kind::Word, option_values::kGBuffer, -1, "demo", "float", 7,
               "RGBA8 targets with log2(p)/10.5 specular power and D24S8, or float targets and D32S8"},
    OptionInfo{"position", OptionInfo::Kind::Word, option_values::kPosition, -1, "reconstruct", "gbuffer", 0,
               "P from the depth buffer, or the interpolated view position stored in gbuffer.position"},
    OptionInfo{"accumulate", OptionInfo::Kind::Word, option_values::kAccumulate, -1, "color", "lighting", 0,
               "each light blends its colour into RT0, or lighting is summed apart and composed as forward does (the "
               "order that reproduces forward's bits)"},
    kSamplerOption,
    kAlphaTestOption,
    kEdgesIntelOption};
inline constexpr std::array<OptionInfo, 11> kKillzoneOptions = withOption(
    kDeferredOptions,
    OptionInfo{"threshold", OptionInfo::Kind::Integer, option_values::kNone, 0, "0", "", 0,
               "a light's shade draw runs only when its occlusion query passed more than this many samples"});

// Options (scene file "options"; unknown keys or values are InputErrors naming /options/KEY).
// Defaults are faithful to the demo; every other value is a named correction (ERRATA.md).
//   "projection": "demo-gl" | "d3d"      as forward (forward.h): the demo's GL-form matrix.
//   "reconstruct": "corner" | "centre"   where ScreenToView evaluates P: the integer pixel
//       int2(SV_Position.xy) (faithful, 3dgep article §3.3.3) or its centre (x + 0.5, y + 0.5).
//   "lightVolumes": "inscribed" | "circumscribed"   the demo's polygons inside the light's
//       sphere / cone, or scaled to contain them (light_volumes.h).
//   "volumeRotation": "glm096" | "robust"   light_volumes.h VolumeRotation.
//   "gbuffer": "demo" | "float"   demo: RT0 = back buffer, RT1 diffuse, RT2 specular with
//       a = log2(p)/10.5, all R8G8B8A8_UNORM, RT3 R32G32B32A32_FLOAT normal, D24_UNORM_S8_UINT.
//       float: RT0-RT2 R32G32B32A32_FLOAT with p stored unpacked in RT2.a, RT0 the separate
//       "accumulation" buffer converted to the back buffer after the lights,
//       D32_FLOAT_S8X24_UINT depth.
//   "position": "reconstruct" | "gbuffer"   P from depth by ScreenToView (faithful), or the
//       interpolated positionVS written by the G-buffer PS to "gbuffer.position" (corrected:
//       the value forward shades with).
//   "accumulate": "color" | "lighting"   color (faithful): each light blends
//       diffuse * lit.Diffuse + specular * lit.Specular into RT0. lighting (corrected): each
//       light blends lit.Diffuse and lit.Specular into the float targets "light.diffuse" and
//       "light.specular" (cleared to 0), and a final pass composes forward's expression
//       ((ambient + emissive) + diffuse * (D.rgb, 1)) + (p > 1 ? specular * S : 0) with RT0
//       holding ((ambient + emissive).rgb, alpha * Opacity). Float addition is commutative but
//       neither associative nor distributive, so only this order reproduces forward's bits.
//   "sampler": "demo" | "gltf"   as forward.
//   "alphaTest": false | true    the transparent (forward) pass only, as forward; the G-buffer
//       PS always discards alpha * Opacity < AlphaThreshold (the demo's PS_Geometry).
//   deferred-killzone adds "threshold": an integer >= 0 (default 0); a light's shade draw runs
//       only when its count query passed more than `threshold` samples.
// With projection d3d, gbuffer float, position gbuffer, accumulate lighting and circumscribed
// volumes, the image equals forward's (projection d3d) bit for bit on opaque scenes whose light
// volumes do not cross the near plane (tests/techniques/deferred_test.cpp).
// What each pass does (TechniqueInfo::passes; "clear", "edges", "transparent", "resolve" are shared).
inline constexpr std::array<PassCaption, 5> kDeferredPassCaptions{{
    {"gbuffer", "The G-buffer pass: diffuse, specular with the packed specular power, view-space normal and depth, no "
                "lighting (3dgep article §3 Deferred Shading; demo DeferredRendering.hlsl)."},
    {"copy depth", "Depth copied so that the light pass can read it while the stencil is written (3dgep demo's main.cpp)."},
    {"lights", "Per light: the unmark pass clears the stencil where geometry lies in front of the light volume's front "
               "faces, the shade pass lights the pixels whose stencil stayed 1 behind its back faces (3dgep article §3; "
               "ERRATA #3, #4). The steps of one light are below."},
    {"present", "Precision reference: the float light accumulation rounded once into the back buffer."},
    {"compose", "accumulate=lighting: the summed lighting multiplied by the G-buffer's albedos once, into the back buffer."},
}};
inline constexpr std::array<PassCaption, 5> kKillzonePassCaptions{{
    kDeferredPassCaptions[0],
    kDeferredPassCaptions[1],
    {"lights", "Per light: Killzone 2's stencil marking and an occlusion query decide whether the shade draw runs "
               "(3dgep article §3; ERRATA #6: the eye inside a volume loses it)."},
    kDeferredPassCaptions[3],
    kDeferredPassCaptions[4],
}};

// Buffers (--dump writes them all):
//   "backbuffer"       R8G8B8A8_UNORM: the image (the demo's RT0 with gbuffer demo)
//   "accumulation"     RT0 when separate from the back buffer (gbuffer float: R32G32B32A32_FLOAT;
//                      accumulate lighting with gbuffer demo: R8G8B8A8_UNORM)
//   "gbuffer.diffuse", "gbuffer.specular"   RT1, RT2 (formats as above)
//   "gbuffer.normal"   RT3 R32G32B32A32_FLOAT, view-space N, w = 0
//   "gbuffer.position" R32G32B32A32_FLOAT (posView, 1), with position gbuffer only
//   "light.diffuse", "light.specular"   R32G32B32A32_FLOAT, with accumulate lighting only
//   "depth"            the depth-stencil buffer (depth from the G-buffer pass; the stencil left
//                      by the last light)
//   "depth.copy"       the demo's CopyTexturePass(depthStencilBuffer, depthStencilTexture) after
//                      the G-buffer pass: the lighting PS reads depth from this copy (SRV
//                      R24_UNORM_X8) while the original is bound as the depth-stencil target
//   "killzone.samples" deferred-killzone only: R32_UINT, one texel per scene light in order
//                      (16384 per row): the count query's samples, 0xFFFFFFFF for directional
//                      and disabled lights (not counted)
// All G-buffer targets are cleared to the demo's clear colour (ClearRenderTargetPass on
// g_pGBufferRenderTarget), depth to 1, stencil to 0. Every precision mode runs (README
// "Precision modes").
// MSAA (TechniqueContext::sampleCount > 1; README "MSAA"): the G-buffer, depth and colour
// targets above hold that many samples (per-tile, per-light and heat-map buffers one), the image is drawn into "backbuffer.msaa" and resolved into "backbuffer", and the
// G-buffer pass adds "msaa.surface" and "msaa.coverage" (the edge detectors' inputs, RGBA32F) and
// "edges" (R32_FLOAT, 1 at the samples of pixels shaded per sample; option "msaaEdges").
Frame buildDeferred(const TechniqueContext& context);
Frame buildDeferredKillzone(const TechniqueContext& context);

struct ForwardPassSetup;

// The G-buffer pass (PS_Geometry over the opaque draw items, g_pGeometryPipeline: depth LESS with
// writes, cull back) as a building block, also used by tiled-deferred. Targets: colors[0] RT0
// (ambient + emissive, with a = alpha * Opacity when forwardAlpha), colors[1] diffuse, colors[2] specular (a = log2(p) / 10.5, or p itself when
// floatTargets), colors[3] view normal, colors[4] (optional, non-null) (posView, 1); the
// depth-stencil target. Formats are the caller's (see "gbuffer" above).
// positionTarget: colors[4] is bound. With multisampled targets the MSAA edge detectors' two
// targets follow the layout's (src/techniques/msaa_deferred.h).
void drawDeferredGBuffer(const ForwardPassSetup& forward, Device& device, const SceneResources& resources,
                         const RenderTargets& targets, bool floatTargets, bool forwardAlpha, bool positionTarget, DrawStats* stats,
                         std::map<std::string, std::uint64_t>* variantCounts);

// "killzone.samples" value of a light that has no count query.
inline constexpr std::uint32_t kKillzoneNotCounted = 0xFFFFFFFFu;

} // namespace tessera
