// The `forward-plus-amd` technique of GPU Pro 4 ch. 5 (Forward+, with AMD's ForwardPlus11 /
// TiledLighting11 demos where the chapter is silent): clear, depth pre-pass, the 8x8 culling
// dispatch (techniques/amd_light_culling.h: two-level list, 2.5D, optional half-Z), final shading
// with AMD's lighting (shading/amd_lighting.h) or the 3dgep Phong shader over the AMD lists.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include <glm/glm.hpp>

#include <tessera/techniques/technique.h>

namespace tessera {

// Its options (techniques/option_catalog.h): keys, values, the faithful default, the correction and its
// ERRATA.md row; read through OptionReader, listed by `tessera options`.
namespace option_values {
inline constexpr std::array<std::string_view, 2> kShadingAmd{"amd", "3dgep"};
inline constexpr std::array<std::string_view, 2> kCullingAmd{"depth-mask", "min-max"};
inline constexpr std::array<std::string_view, 2> kProjectionAmd{"d3d", "demo-gl"};
inline constexpr std::array<std::string_view, 2> kLightLoop{"binned", "all-lights"};
inline constexpr std::array<std::string_view, 3> kAutoOnOff{"auto", "on", "off"};
inline constexpr std::array<std::string_view, 3> kShadowBackfaces{"mask", "lit", "cast"};
inline constexpr std::array<std::string_view, 2> kShadowOverflow{"lit", "unlit"};
inline constexpr std::array<std::string_view, 2> kVplDirection{"reflect", "normal"};
} // namespace option_values

inline constexpr std::int64_t kAmdMaxRsmSize = 4096;  // texels per side of the reflective shadow map
inline constexpr std::int64_t kAmdMaxVplGrid = 128;   // N: at most 16,384 VPLs

inline constexpr std::array<OptionInfo, 19> kForwardPlusAmdOptions{
    OptionInfo{"shading", OptionInfo::Kind::Word, option_values::kShadingAmd, -1, "amd", "", 0,
               "ForwardPlus11's pixel shader (AMD falloff and lighting), or the 3dgep article's Phong shader"},
    OptionInfo{"culling", OptionInfo::Kind::Word, option_values::kCullingAmd, -1, "depth-mask", "", 0,
               "GPU Pro 4's 2.5D culling (32-cell depth mask), or side planes and the tile's depth slab"},
    OptionInfo{"halfZ", OptionInfo::Kind::Bool, option_values::kBool, -1, "false", "", 21,
               "TiledLighting11's two lists per tile split at the middle of its depth range (shading amd only)"},
    OptionInfo{"projection", OptionInfo::Kind::Word, option_values::kProjectionAmd, -1, "d3d (shading 3dgep: demo-gl)", "d3d", 1,
               "as forward; AMD's sample builds a D3D matrix, the 3dgep shading follows the 3dgep demo"},
    kSamplerOption,
    kAlphaTestOption,
    OptionInfo{"lightLoop", OptionInfo::Kind::Word, option_values::kLightLoop, -1, "binned", "", 0,
               "which lights each tile's culling loop visits: binned by tile rows, or all (GPU Pro 4's kernel); the "
               "same lists"},
    OptionInfo{"shadows", OptionInfo::Kind::Word, option_values::kAutoOnOff, -1, "auto", "", 0,
               "GPU Pro 4 5.6.2 ray-cast shadows when the scene has shadow-casting lights and the configuration allows "
               "(on: an error otherwise), or never"},
    OptionInfo{"shadowNormalOffset", OptionInfo::Kind::Number, option_values::kNone, -1, "0.01", "", 0,
               "world units along the G-pass normal from the rebuilt position to the shadow ray's origin", 0.0, 1e6},
    OptionInfo{"shadowBackfaces", OptionInfo::Kind::Word, option_values::kShadowBackfaces, -1, "mask", "", 0,
               "a light behind the surface: masked without a ray, left lit, or ray cast"},
    OptionInfo{"shadowOverflow", OptionInfo::Kind::Word, option_values::kShadowOverflow, -1, "lit", "unlit", 31,
               "lights past the 128 mask slots of a pixel: shaded unshadowed, or dropped"},
    OptionInfo{"indirect", OptionInfo::Kind::Word, option_values::kAutoOnOff, -1, "auto", "", 0,
               "GPU Pro 4 5.5 one-bounce VPLs when the scene has an indirect light (on: an error otherwise), or never"},
    OptionInfo{"rsmSize", OptionInfo::Kind::Integer, option_values::kNone, 1, "256", "", 0,
               "reflective shadow map edge in texels", 0.0, 0.0, kAmdMaxRsmSize},
    OptionInfo{"vplGrid", OptionInfo::Kind::Integer, option_values::kNone, 1, "16", "", 0,
               "N: N x N VPLs from the RSM's grid-cell centres (default: 16, at most rsmSize)", 0.0, 0.0, kAmdMaxVplGrid},
    OptionInfo{"vplConeDeg", OptionInfo::Kind::Number, option_values::kNone, -1, "60", "", 0, "each VPL's spot half angle in degrees", 1.0, 89.0},
    OptionInfo{"vplRange", OptionInfo::Kind::Number, option_values::kNone, -1, "4", "", 0, "each VPL's range in world units", 1e-6, 1e6},
    OptionInfo{"vplIntensity", OptionInfo::Kind::Number, option_values::kNone, -1, "1", "", 0, "scale of the VPLs' summed colour", 0.0, 1e6},
    OptionInfo{"vplDirection", OptionInfo::Kind::Word, option_values::kVplDirection, -1, "reflect", "", 0,
               "VPL axis: the reflection of the light direction about the normal (the chapter's), or the normal"},
    OptionInfo{"vplOffset", OptionInfo::Kind::Number, option_values::kNone, -1, "0.01", "", 0, "world units a VPL sits off its surface", 0.0, 1e6}};

// Options (scene file "options"; unknown keys or values are InputErrors naming /options/KEY):
//   "shading": "amd" (default) | "3dgep"
//       amd: ForwardPlus11's RenderScenePS (amd_lighting.h) in world space: falloff
//       -0.05 + 1.05/(1 + 20x^2), Lambert + Blinn-Phong power 8, squared spot cone, x2 / x8 pump,
//       up/down ambient, out = DiffuseTex.rgb * ((D + A) + S * DiffuseTex.a). DiffuseTex is the
//       3dgep material's diffuse (colour x texture, the same rule as phong_material_shader.h);
//       the normal is the interpolated vertex normal (tessera: no normal map; ForwardPlus11 reads
//       one). Lists: points first, then spots, each in ascending light index, as the demo's two
//       loops. Directional lights: AMD has none; they are listed (infinite sphere) but not shaded.
//       3dgep: the article's Phong PS (forward.h drawForwardPass) reading the AMD list through
//       TileLightList (tile 8 px): on opaque geometry the image equals `forward` bit for bit.
//   "culling": "depth-mask" (default, GPU Pro 4 §5.6.1 2.5D) | "min-max" (side planes + slab)
//   "halfZ": false (default) | true   TiledLighting11's two lists per tile; a pixel reads list
//       A iff its view z < (minZ + maxZ) / 2 (depth_mask.h pixelUsesNearHalfAmd), its view z
//       being clipToView(0, 0, SV_Position.z, 1).z with the culling's inverse projection.
//       Needs "shading": "amd" (the 3dgep PS reads one list per tile): InputError otherwise.
//   "projection": "d3d" (default for shading amd) | "demo-gl" (default for shading 3dgep), as
//       forward.h. The culling runs in AMD's LEFT-handed view space: P_lh = P_rh * diag(1,1,-1,1)
//       (the same clip coordinates, view z negated), inverse(P_lh) for projToView.
//   "sampler": "demo" | "gltf", "alphaTest": false | true   as forward.
//   "lightLoop": "binned" (default) | "all-lights"   which lights each tile's culling loop visits
//       (amd_light_culling.h AmdLightLoop): the same lists either way; "all-lights" is the kernel
//       as GPU Pro 4 writes it, every tile over every light (2 s for 16384 lights at 1280x720).
// GPU Pro 4 §5.6.2, many-light shadows by ray casting (techniques/amd_shadow_rays.h), when the
// scene marks shadow-casting lights ("shadowCasters") and "shadows" is "auto" (default) or "on";
// "off" skips them. The pre-pass also writes "gbuffer.normal"; "shadow-jobs" packs (pixel, slot) jobs;
// "shadow-rays" casts one Embree ray each (raytrace/shadow_ray_scene.h: opaque triangles, robust
// mode, BVH built once per scene) into "shadow.mask"; the opaque pass skips masked slots.
//   "shadowNormalOffset": number >= 0, world units (default 0.01): ray origin off the surface
//   "shadowBackfaces": "mask" (default) | "lit" | "cast"   lights behind the surface (ShadowBackfaces)
//   "shadowOverflow": "lit" (default) | "unlit"   lights past the 128th slot of a tile list
// Needs shading amd, halfZ false and 1 sample per pixel: "auto" then runs without shadows, "on"
// is an InputError naming the reason (as is "on" for a scene without casters). The transparent
// pass is not shadowed (no G-pass there). Alpha-tested geometry occludes as opaque triangles.
// GPU Pro 4 §5.5 (the Leo demo's one-bounce light; techniques/amd_vpl.h), when a light has
// "indirect": true and "indirect" is "auto" (default) or "on" ("on" without such a light, or with
// shading 3dgep, is an InputError; "auto" then skips it; "off" always does): pass "rsm" renders the
// light's reflective shadow map, "vpl" makes vplGrid^2 spot VPLs appended after the scene's lights
// (culled like them); shading adds DiffuseTex * their diffuse light (isIndirectLight: index >=
// scene light count), and pass "indirect" writes that term alone.
//   "rsmSize": integer 1..4096 (256)   "vplGrid": integer 1..128, <= rsmSize (16, or rsmSize if less)
//   "vplConeDeg": 1..89 (60)   "vplRange": world units (4)   "vplIntensity": >= 0 (1)
//   "vplDirection": "reflect" (default, the chapter's) | "normal"   "vplOffset": world units (0.01)
// Depth: GPU Pro 4's convention (cleared to 1.0, pre-pass LESS, shading LESS_EQUAL without a
// second write); ForwardPlus11's reversed depth is not modelled here.
// Transparent (blended) geometry: neither GPU Pro 4 nor ForwardPlus11 shade it; tessera draws it
// after the opaque pass as forward does (alpha blend, no depth write, cull none) with a second
// list per tile over [near plane, maxZ] (cleared pixels count as the far plane; MinMax only), the
// choice of 3dgep's transparent list. Shading amd outputs alpha = DiffuseTex.a * Opacity there.
// What each pass does (TechniqueInfo::passes; "clear", "transparent", "resolve" are shared).
inline constexpr std::array<PassCaption, 8> kForwardPlusAmdPassCaptions{{
    {"depth-prepass", "Depth pre-pass (GPU Pro 4 ch. 5 §5.2)."},
    {"light-culling", "Gather-based culling over 8x8 px tiles with the 2.5D depth mask (GPU Pro 4 ch. 5 §5.3.1, §5.6.1; "
                      "ForwardPlus11 CullLightsCS)."},
    {"rsm", "indirect: a reflective shadow map per VPL-casting light, position, normal and colour (GPU Pro 4 ch. 5 §5.6.3)."},
    {"vpl", "indirect: virtual point lights placed on a grid over the reflective shadow map (GPU Pro 4 ch. 5 §5.6.3)."},
    {"shadow-jobs", "shadows: one ray job per pixel and shadow-casting light in the tile's list (GPU Pro 4 ch. 5 §5.6.2)."},
    {"shadow-rays", "shadows: the jobs' rays cast against the scene, their hits packed into per-pixel masks "
                    "(GPU Pro 4 ch. 5 §5.6.2; Embree stands in for the DXR-less chapter's compute ray caster)."},
    {"opaque", "Final shading with the tile's lists and AMD's falloff (GPU Pro 4 ch. 5 §5.3.2; ForwardPlus11 "
               "RenderScenePS; ERRATA #18)."},
    {"indirect", "indirect: each pixel adds its tile's VPLs (GPU Pro 4 ch. 5 §5.6.3)."},
}};

// Buffers (--dump writes them all; tiles = ceil(W / 8) x ceil(H / 8)):
//   "backbuffer" R8G8B8A8_UNORM, "depth" D24_UNORM_S8_UINT (the pre-pass depth)
//   "lightgrid.opaque"      R32G32_UINT, tiles: (ptLowerBound, count) of the opaque list (half-Z:
//                           list A, the near half)
//   "lightgrid.opaque.far"  R32G32_UINT, tiles: half-Z list B (only with halfZ)
//   "lightindex.opaque"     R32_UINT: gLightIdx, the global pool (element e at (e % W, e / W),
//                           W = min(entries, 16384)); half-Z: each tile's A entries, then its B
//   "lightgrid.transparent", "lightindex.transparent"   the [near, maxZ] lists, same layout
//   "tiles.depthRange"      R32G32_UINT, tiles: asuint of (ldsZMin, ldsZMax), LH view z
//   "tiles.depthMask"       R32_UINT, tiles: the 2.5D occupancy mask (0 with culling min-max)
//   "heatmap.radar"         R8G8B8A8_UNORM, the screen size: ForwardPlus11's radar colour of the
//                           tile's unclamped count (half-Z: the larger of A and B) against the
//                           maximum LIGHT_CAPACITY = 256: 0 black, 256 light purple, > 256 white
//   "gbuffer.normal"        R32G32B32A32_FLOAT, shadows only: unit world normal, w = 1 (0: empty)
//   "shadow.jobs"           R32_UINT: the job buffer, laid out as the light index pool
//   "shadow.mask"           R32G32B32A32_UINT: the per-pixel int4 mask, bit s = slot s shadowed
//   "shadow.counters"       R32_UINT, 5 x 1: jobs, occluded rays, backface-masked slots, pixels
//                           whose list passes 128 lights, overlapping lights past slot 127
//   "rsm.position", "rsm.normal", "rsm.color" R32G32B32A32_FLOAT rsmSize^2, "rsm.depth" D32_FLOAT
//   "vpl.position" (w: 1 valid), "vpl.direction" (w: cos cone), "vpl.color" (w: range), N x N
//   "indirect"              R32G32B32A32_FLOAT: DiffuseTex * the VPLs' diffuse light
//   "lightlist.counters"    R32_UINT, 8 x 3: LightListCounters (forward_plus.h) rows: opaque
//                           (A), transparent, opaque far (B; zeros without half-Z).
//                           requested = pool entries used, capacity = pool entries,
//                           tilesOverLocal / droppedLocal = tiles past LIGHT_CAPACITY and the
//                           lights they lost, global fields 0 (the pool is sized to fit),
//                           maxTileCount = largest unclamped count, nonEmptyTiles.
// Every precision mode runs (README "Precision modes"). With MSAA the back buffer and depth hold
// TechniqueContext::sampleCount samples, the tile bounds take every sample, and the image is
// resolved last (README "MSAA").
Frame buildForwardPlusAmd(const TechniqueContext& context);

// The smallest sphere around a spot light's lit region: the spherical sector of radius R (the
// range) and half angle theta about the axis, apex at the light. Centre on the axis at distance
// `centerOffset` from the apex. Derivation (tests/techniques/forward_plus_amd_test.cpp checks it against
// sampled sector points): a sphere centred at distance h on the axis must reach the apex (h) and
// the rim circle (distance^2 = R^2 + h^2 - 2 R h cos(theta)); every other sector point is nearer
// (for points at range R the distance grows with the angle to the axis, up to theta; along a
// straight edge it is convex, so largest at an end). Equal distances give h = R / (2 cos theta),
// the minimum while h <= R cos(theta), i.e. theta <= 45 deg: radius = h = R / (2 cos theta).
// For 45 < theta < 90 deg the rim distance is least at h = R cos(theta): radius R sin(theta),
// which also covers the apex (cos <= sin) and the cap tip (R (1 - cos) <= R sin). theta >= 90 deg
// (not convex): the apex sphere, h = 0, radius R. The radius is rounded up by 2^-20 relative so
// that float rounding of the centre cannot leave a rim point outside.
struct SpotBoundingSphere {
    float centerOffset = 0.0f;  // along the spot direction from the apex, world / view units
    float radius = 0.0f;
};
SpotBoundingSphere spotBoundingSphere(float range, float halfAngleDeg);

} // namespace tessera
