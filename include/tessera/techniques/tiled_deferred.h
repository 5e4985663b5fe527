// The `tiled-deferred` technique: Intel's compute-shaded tiled deferred shading (Lauritzen,
// SIGGRAPH 2010; Intel 2010 sample ComputeShaderTile.hlsl; tile-frustum note for the tile
// planes): G-buffer, then ONE dispatch with a thread group per tile that reduces
// the tile's view-z range, culls every light against planes taken from the projection, and
// shades the tile's pixels from its list; then a present pass and forward's transparent pass.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include <glm/glm.hpp>

#include <tessera/culling/tile_frustum.h>
#include <tessera/techniques/technique.h>

namespace tessera {

// Its options (techniques/option_catalog.h): keys, values, the faithful default, the correction and its
// ERRATA.md row; read through OptionReader, listed by `tessera options`.
namespace option_values {
inline constexpr std::array<std::string_view, 2> kShadingIntel{"intel", "3dgep"};
inline constexpr std::array<std::string_view, 2> kNormals{"spheremap", "float"};
inline constexpr std::array<std::string_view, 2> kTilePlanes{"sample2010", "tile"};
inline constexpr std::array<std::string_view, 1> kUnbounded{"unbounded"};
inline constexpr std::array<std::string_view, 1> kProjectionD3d{"d3d"};
} // namespace option_values

inline constexpr std::array<OptionInfo, 11> kTiledDeferredOptions{
    OptionInfo{"shading", OptionInfo::Kind::Word, option_values::kShadingIntel, -1, "intel", "", 0,
               "Intel's 2010 sample shading, or the 3dgep article's Phong equations on the same G-buffer"},
    OptionInfo{"gbuffer", OptionInfo::Kind::Word, option_values::kGBuffer, -1, "demo", "float", 7,
               "the sample's quantised G-buffer, or float targets"},
    OptionInfo{"position", OptionInfo::Kind::Word, option_values::kPosition, -1, "reconstruct", "gbuffer", 0,
               "P from the depth buffer (Intel's reconstruction), or the interpolated view position"},
    OptionInfo{"normals", OptionInfo::Kind::Word, option_values::kNormals, -1, "spheremap", "float", 0,
               "intel shading: the normal through the sample's spheremap encoding, or as stored in float"},
    OptionInfo{"tilePlanes", OptionInfo::Kind::Word, option_values::kTilePlanes, -1, "sample2010", "tile", 12,
               "the sample's side planes (c4 +- c1, c4 +- c2: each spans 2x2 tiles), or planes that bound the tile"},
    kTileSizeOption,
    OptionInfo{"tileListCapacity", OptionInfo::Kind::IntegerOrWord, option_values::kUnbounded, 1, "1024", "unbounded", 16,
               "lights one tile's list holds (MAX_LIGHTS); past it lights are dropped and counted", 0.0, 0.0,
               0xFFFFFFFE},
    OptionInfo{"projection", OptionInfo::Kind::Word, option_values::kProjectionD3d, -1, "d3d", "", 0,
               "the only value: Intel's view-z reconstruction needs a D3D-form matrix"},
    kSamplerOption,
    kAlphaTestOption,
    kEdgesIntelOption};

// Options (scene file "options"; unknown keys or values are InputErrors naming /options/KEY).
// Defaults follow Intel's 2010 sample; the other values are named corrections or the 3dgep
// comparison mode.
//   "shading": "intel" | "3dgep"
//       intel (faithful): the sample's AccumulateBRDF (Rendering.hlsl): for a light with
//       d = length(L) < attenuationEnd: attenuation = linstep(end, begin, d) = saturate((d - end)
//       / (begin - end)); Phong with r = reflect(L / d, n), RdotV = max(0, dot(r, normalize(P))),
//       taken only where N.L > 0; lit += albedo.rgb * (attenuation * color * N.L + specAmount *
//       attenuation * color * RdotV^specPower), specAmount 0.9 and specPower 25 for every
//       surface (ComputeSurfaceDataFromGeometry). Scene lights map to Intel's PointLight as
//       attenuationEnd = range, attenuationBegin = 0.8 * range (App::InitializeLightParameters'
//       ratio), color = color * intensity. Intel has point lights only; tessera's mapping:
//       spot lights are point lights whose contribution is also scaled by the scene's cone
//       (3dgep's DoSpotCone); directional lights and infinite-range lights are in every tile's
//       list with attenuation 1 (L = -direction for directional). No ambient term (Intel has none). albedo = gbuffer.diffuse (the 3dgep material's diffuse: base colour x
//       texture), normal = gbuffer.normal (see "normals"). Output: Intel's lit buffer
//       R16G16B16A16_FLOAT (float4(lit, 1); (0, 0, 0, 0) for tiles with no light), presented as
//       SkyboxToneMap does (identity tone map, 1 sample) with the clear colour standing in for
//       the sky box where depth is the cleared 1.
//       3dgep (comparison mode): the tile's lights through 3dgep's DoLighting in list order, then
//       forward's final expression ((ambient + emissive) + diffuse * (D.rgb, 1)) + (p > 1 ?
//       specular * S : 0) with alpha * Opacity from RT0 (deferred.h "accumulate lighting"),
//       written to the back buffer where the G-buffer has geometry.
//   "gbuffer": "demo" | "float"   deferred's G-buffer (deferred.h): RT0-RT2 R8G8B8A8_UNORM with
//       the packed specular power and D24_UNORM_S8_UINT, or R32G32B32A32_FLOAT and D32_FLOAT_S8X24.
//       The view normal is always R32G32B32A32_FLOAT.
//   "position": "reconstruct" | "gbuffer"   P from the depth buffer as Intel's
//       ComputeSurfaceDataFromGBufferSample (pixel centre, viewZ = _43 / (z - _33),
//       positionViewFromDepthIntel below), or the interpolated posView of "gbuffer.position".
//   "normals": "spheremap" | "float"   intel shading only: the view normal passes through
//       Intel's G-buffer storage (spheremap encode, R16G16B16A16_FLOAT, decode; GBuffer.hlsl
//       2010 lines), or is used as stored in gbuffer.normal.
//   "tilePlanes": "sample2010" | "tile"   the side planes: Intel's sample (c4 - c1, c4 + c1,
//       c4 - c2, c4 + c2; each tile frustum spans 2x2 tiles, ERRATA) or the tile-frustum note's (c4 - c1, c1,
//       c4 - c2, c2: exactly the tile). Both conservative; lists and heat map differ, images not.
//   "tileSize": 16 | 8 | 32   COMPUTE_SHADER_TILE_GROUP_DIM (the sample's ShaderDefines.h: 16).
//   "tileListCapacity": integer >= 1 | "unbounded"   sTileLightIndices[MAX_LIGHTS], MAX_LIGHTS
//       = 1024 (default). The sample never has more lights than that; with more, appends past
//       the capacity are dropped (D3D leaves an out-of-range groupshared write undefined) and
//       counted ("tiles.lightCount" > the stored count); "unbounded" never drops.
//   "projection": "d3d"   the only value: Intel's view-z reconstruction needs a D3D-form matrix
//       (3dgep's perspectiveRH_ZO; _11, _22, _33, _43 of its left-handed equivalent).
//   "sampler", "alphaTest": as forward (G-buffer textures; alphaTest: the transparent pass).
// What each pass does (TechniqueInfo::passes; "clear", "edges", "transparent", "resolve" are shared).
inline constexpr std::array<PassCaption, 3> kTiledDeferredPassCaptions{{
    {"gbuffer", "The G-buffer (Intel 2010 sample GBuffer.hlsl)."},
    {"tiles", "One compute dispatch: per tile the depth range, side planes from the projection, the light list and the "
              "shading of the tile's pixels (Intel 2010 sample ComputeShaderTile.hlsl; ERRATA #12, #16)."},
    {"present", "The lit result converted to the back buffer."},
}};

// Buffers (--dump writes them all):
//   "backbuffer"        R8G8B8A8_UNORM, the image
//   "accumulation"      RT0: (ambient + emissive, alpha * Opacity), format per "gbuffer"
//   "gbuffer.diffuse", "gbuffer.specular", "gbuffer.normal", "gbuffer.position" (position
//                       gbuffer only): deferred's G-buffer targets
//   "depth"             the G-buffer's depth-stencil buffer
//   "lit"               intel shading: R16G16B16A16_FLOAT, what the kernel writes (gFramebuffer)
//   "heatmap"           R8G8B8A8_UNORM: Intel's visualizeLightCount view, float(n) / 255 in all
//                       four channels, n = the tile's light count (code n, saturating at 255)
//   "tiles.grid"        R32G32_UINT, one texel per tile: (offset into tiles.lightIndices, stored
//                       count), as 3dgep's light grid
//   "tiles.lightCount"  R32_UINT, one texel per tile: sTileNumLights after culling (the lights
//                       appended; more than the stored count when the list overflowed)
//   "tiles.lightIndices" R32_UINT: every tile's list, tiles in row-major order, each in
//                       ascending light index (the fixed order of the group-shared
//                       InterlockedAdd, compute/dispatch.h); 16384 indices per row
//   "tiles.depthRange"  R32G32_UINT, one texel per tile: the reduction's (sMinZ, sMaxZ) bits
// Every precision mode runs (README "Precision modes").
// MSAA (TechniqueContext::sampleCount > 1; README "MSAA"): the G-buffer, depth and colour
// targets above hold that many samples (per-tile, per-light and heat-map buffers one), the image is drawn into "backbuffer.msaa" and resolved into "backbuffer", and the
// G-buffer pass adds "msaa.surface" and "msaa.coverage" (the edge detectors' inputs, RGBA32F) and
// "edges" (R32_FLOAT, 1 at the samples of pixels shaded per sample; option "msaaEdges").
Frame buildTiledDeferred(const TechniqueContext& context);

// The sample's defaults (ShaderDefines.h).
inline constexpr std::uint32_t kIntelTileDim = 16;        // COMPUTE_SHADER_TILE_GROUP_DIM, px
inline constexpr std::uint32_t kIntelMaxLights = 1024;    // MAX_LIGHTS = 1 << MAX_LIGHTS_POWER
inline constexpr float kIntelSpecularAmount = 0.9f;       // ComputeSurfaceDataFromGeometry
inline constexpr float kIntelSpecularPower = 25.0f;
inline constexpr float kIntelAttenuationBeginRatio = 0.8f;  // attenuationBegin / attenuationEnd

// Intel's PointLight (Rendering.hlsl), left-handed view space.
struct IntelPointLight {
    glm::vec3 positionView{0.0f};
    float attenuationBegin = 0.0f;
    glm::vec3 color{0.0f};
    float attenuationEnd = 0.0f;
};

// linstep(min, max, v) = saturate((v - min) / (max - min)) (Rendering.hlsl).
float intelLinstep(float minValue, float maxValue, float v);

// AccumulateBRDF for one light: adds albedo * (litDiffuse + specularAmount * litSpecular) to
// `lit` when length(L) < attenuationEnd. All vectors in one view space (the result does not
// depend on the handedness: flipping z flips every operand exactly).
void intelAccumulateBrdf(const glm::vec3& posView, const glm::vec3& normalView, const glm::vec3& albedo,
                         float specularAmount, float specularPower, const IntelPointLight& light, glm::vec3& lit);

// ComputeSurfaceDataFromGBufferSample's position: positionScreen = (px + 0.5) * (2, -2) / dim +
// (-1, 1); viewZ = _43 / (zBuffer - _33); xy = positionScreen / (_11, _22) * viewZ.
// projectionLh: the left-handed D3D matrix (glm layout, _rc = m[r-1][c-1]). Left-handed result.
glm::vec3 positionViewFromDepthIntel(std::uint32_t pxX, std::uint32_t pxY, float zBuffer, glm::uvec2 framebufferPx,
                                     const glm::mat4& projectionLh);

// The left-handed equivalent of a right-handed D3D projection (3dgep's perspectiveRH_ZO): the
// same clip coordinates for p_lh = (x, y, -z): column 2 negated (m[2] = -m[2]), so _33 = f/(f-n),
// _34 = 1, _43 = -f n / (f - n) as D3DXMatrixPerspectiveFovLH.
glm::mat4 projectionLhFromRh(const glm::mat4& projectionRh);

// Intel's G-buffer normal storage (GBuffer.hlsl, the 2010 lines): p = sqrt(x^2 + y^2 + (1 - z)^2),
// e = n.xy / p * 0.5 + 0.5, each component rounded to half (R16G16B16A16_FLOAT); decode f =
// (e.x - e.x^2) + (e.y - e.y^2), m = sqrt(4 f - 1), n = (m (4 e - 2), 3 - 8 f). Left-handed n.
glm::vec3 intelSpheremapRoundTrip(const glm::vec3& normalView);

} // namespace tessera
