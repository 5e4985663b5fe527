// The `deferred-cookbook` technique: deferred shading as the HLSL Development Cookbook builds it
// (Feinstein 2013, ch. 2; the book's companion code where the chapter is silent): a G-buffer of
// D24S8 depth, RGBA8 base colour + specular intensity, R11G11B10_FLOAT normal and RGBA8 packed
// specular power; the directional light and the hemispheric ambient as a full-screen quad; point,
// spot and capsule lights as the recipes' tessellated volumes (cookbook_volumes.h) with additive
// blending; the position rebuilt from linear depth; then forward's transparent pass.
#pragma once

#include <array>
#include <string_view>

#include <glm/glm.hpp>

#include <tessera/techniques/technique.h>

namespace tessera {

// Its options (techniques/option_catalog.h): keys, values, the faithful default, the correction and its
// ERRATA.md row; read through OptionReader, listed by `tessera options`.
namespace option_values {
inline constexpr std::array<std::string_view, 2> kSpecPowerUnpack{"printed", "once"};
inline constexpr std::array<std::string_view, 2> kVolumeCull{"table", "front"};
inline constexpr std::array<std::string_view, 2> kSpotVolume{"book", "demo"};
inline constexpr std::array<std::string_view, 2> kCpPos{"vertex", "pixel"};
inline constexpr std::array<std::string_view, 2> kBackground{"book", "stencil"};
inline constexpr std::array<std::string_view, 2> kVolumeScale{"padded", "range"};
inline constexpr std::array<std::string_view, 2> kLightGeometry{"volumes", "quads"};
} // namespace option_values

inline constexpr std::array<OptionInfo, 10> kDeferredCookbookOptions{
    OptionInfo{"specPowerUnpack", OptionInfo::Kind::Word, option_values::kSpecPowerUnpack, -1, "printed", "once", 22,
               "the chapter's printed unpack (251 x norm, then decoded again) or 0.1 + 250 x norm once"},
    OptionInfo{"volumeCull", OptionInfo::Kind::Word, option_values::kVolumeCull, -1, "table", "front", 23,
               "the recipe table's CULL_BACK (lights what is in front of the volume) or CULL_FRONT (its far side)"},
    OptionInfo{"spotVolume", OptionInfo::Kind::Word, option_values::kSpotVolume, -1, "book", "demo", 24,
               "ScaleXY = R tan(a)/sqrt(1/2) on a 45-degree unit cone, or the outer angle's cone scaled by R (enlarged)"},
    OptionInfo{"cpPos", OptionInfo::Kind::Word, option_values::kCpPos, -1, "vertex", "pixel", 25,
               "clip-space xy divided per vertex and interpolated, or the pixel centre's"},
    OptionInfo{"background", OptionInfo::Kind::Word, option_values::kBackground, -1, "book", "stencil", 26,
               "the directional quad without depth-stencil shades the background too, or stencil marks the geometry"},
    OptionInfo{"volumeScale", OptionInfo::Kind::Word, option_values::kVolumeScale, -1, "padded", "", 0,
               "volumes enlarged to contain the light's range (the book's 'plus a small value'), or exactly the range"},
    OptionInfo{"lightGeometry", OptionInfo::Kind::Word, option_values::kLightGeometry, -1, "volumes", "", 0,
               "the recipes' volumes, or every light as a full-screen quad (the baseline the volumes must match)"},
    kSamplerOption,
    kAlphaTestOption,
    kEdgesIntelOption};

// Options (scene file "options", `render --option`); defaults are faithful to the chapter, each
// other value a named correction (ERRATA.md):
//   "specPowerUnpack": "printed" | "once"   printed: UnpackGBuffer's `norm + norm * 250` and the
//       light PS's second decode, 0.1 + 250 * (251 norm) (ERRATA #22); once: 0.1 + 250 norm.
//   "volumeCull": "table" | "front"   the volumes' rasterizer state: the recipe's table
//       (D3D11_CULL_BACK, which keeps the faces towards the camera, so GREATER_EQUAL lights the
//       geometry in front of the volume instead of inside it; ERRATA #23) or the prose and the
//       companion code (D3D11_CULL_FRONT: the far side).
//   "spotVolume": "book" | "demo"   book: the unit volume with SinAngle = CosAngle = sqrt(1/2)
//       scaled by (R tan(outer) / sqrt(1/2), same, R), which misses the light's range off the axis
//       for outer angles below 45 degrees (ERRATA #24); demo: the outer angle's sine and cosine in
//       the domain shader and a uniform scale R (the companion code), enlarged to contain the cone.
//   "cpPos": "vertex" | "pixel"   vertex: the clip-space xy the domain shader divides by w per
//       vertex and the rasterizer interpolates (perspective-correct), so the rebuilt position is
//       off inside the triangle and wrong where a volume crosses the eye plane (ERRATA #25);
//       pixel: the pixel centre's clip-space xy from SV_Position (the later chapters' fix).
//   "background": "book" | "stencil"   book: the directional pass runs with no depth-stencil view
//       and shades every pixel, the background included (black: the cleared G-buffer); stencil:
//       the companion code's G-buffer marks stencil 1 and every light tests EQUAL 1 (ERRATA #26).
//   "volumeScale": "padded" | "range"   padded: the book's "range plus a small value", as the
//       smallest enlargement that contains the light's region (cookbook_volumes.h); range: the
//       companion code's exact range, whose flat faces cut inside the sphere.
//   "lightGeometry": "volumes" | "quads"   volumes: the recipes; quads: every light as the
//       full-screen quad (the baseline the volumes save work against: with conservative volumes,
//       stencil and the pixel's cpPos the two images are equal bit for bit, tests/techniques/deferred_cookbook_test.cpp).
//   "sampler", "alphaTest": as forward (the transparent pass).
// What each pass does (TechniqueInfo::passes; "clear", "edges", "transparent", "resolve" are shared).
inline constexpr std::array<PassCaption, 3> kDeferredCookbookPassCaptions{{
    {"gbuffer", "PackGBuffer: base colour and specular intensity (RGBA8), the world normal as n * 0.5 + 0.5 "
                "(R11G11B10_FLOAT), the specular power packed over [0.1, 250.1] (RGBA8) and depth (Cookbook ch. 2, "
                "recipe GBuffer generation)."},
    {"lights", "The directional light and the hemispheric ambient as a full-screen quad, then each point, spot and "
               "capsule light as its tessellated volume, additive; each pixel unpacks the G-buffer and rebuilds its "
               "world position from linear depth (Cookbook ch. 2, recipes GBuffer unpacking, Directional/Point/Capsule/"
               "Spot light; ERRATA #22-#26)."},
    {"present", "The float accumulation converted to the back buffer (precision reference)."},
}};

// CalcAmbient's constants (the companion code's AmbientDown / AmbientRange are set by its sample
// app; tessera takes the 3dgep demo's global ambient (0.1, 0.1, 0.15) as the upper colour and a
// tenth of it as the lower one).
inline constexpr glm::vec3 kCookbookAmbientDown{0.01f, 0.01f, 0.015f};
inline constexpr glm::vec3 kCookbookAmbientUp{0.1f, 0.1f, 0.15f};

// Buffers: "backbuffer" R8G8B8A8_UNORM (the lights accumulate into it); "gbuffer.color"
// R8G8B8A8_UNORM (base colour, specular intensity), "gbuffer.normal" R11G11B10_FLOAT (world
// normal * 0.5 + 0.5), "gbuffer.specpow" R8G8B8A8_UNORM (R: packed power), "depth" D24_UNORM_S8_UINT;
// precision reference adds "accumulation" R32G32B32A32_FLOAT (the double lighting) and
// "backbuffer.reference". Passes: clear, gbuffer, lights (one step "shade" per light for
// --dump-lights), [present], transparent.
// MSAA (TechniqueContext::sampleCount > 1; README "MSAA"): the G-buffer, depth and colour
// targets above hold that many samples (per-tile, per-light and heat-map buffers one), the image is drawn into "backbuffer.msaa" and resolved into "backbuffer", and the
// G-buffer pass adds "msaa.surface" and "msaa.coverage" (the edge detectors' inputs, RGBA32F) and
// "edges" (R32_FLOAT, 1 at the samples of pixels shaded per sample; option "msaaEdges").
Frame buildDeferredCookbook(const TechniqueContext& context);

} // namespace tessera
