// The `deferred-classic` technique: classic deferred shading as Practical Rendering and Computation
// with Direct3D 11 builds it (Zink, Pettineo, Hoxley 2011, ch. 11 §11.2 and the light-shading
// optimizations of §11.4.2): a 4 x R32G32B32A32_FLOAT G-buffer (world normal, diffuse albedo,
// specular albedo + power, world position; 64 B/px), then one additive pass per light that reads it
// at the pixel and evaluates Listing 11.3's CalcLighting, over a full-screen quad, a quad cut by the
// light's scissor rectangle (Listing 11.14), or the light's volume; then forward's transparent pass.
#pragma once

#include <array>
#include <string_view>

#include <tessera/techniques/technique.h>

namespace tessera {

// Its options (techniques/option_catalog.h): keys, values, the faithful default, the correction and its
// ERRATA.md row; read through OptionReader, listed by `tessera options`.
namespace option_values {
inline constexpr std::array<std::string_view, 3> kClassicGeometry{"quads", "scissor", "volumes"};
inline constexpr std::array<std::string_view, 2> kViewVector{"printed", "normalized"};
inline constexpr std::array<std::string_view, 2> kScissorRound{"truncate", "out"};
inline constexpr std::array<std::string_view, 2> kClassicGBuffer{"plain", "optimized"};
inline constexpr std::array<std::string_view, 2> kNormalEncoding{"printed", "safe"};
} // namespace option_values

inline constexpr OptionInfo kClassicGeometryOption{"lightGeometry", OptionInfo::Kind::Word, option_values::kClassicGeometry, -1, "quads", "", 0,
                                            "a full-screen quad per light (§11.2), the quad cut by the light's scissor "
                                            "rectangle, or its volume (§11.4.2)"};
inline constexpr OptionInfo kViewVectorOption{"viewVector", OptionInfo::Kind::Word, option_values::kViewVector, -1, "printed", "normalized", 27,
                                       "Listing 11.3's unnormalized V in H = normalize(L + V), or Eq. 11.1's unit V"};
inline constexpr OptionInfo kScissorRoundOption{"scissorRound", OptionInfo::Kind::Word, option_values::kScissorRound, -1, "truncate", "out", 28,
                                         "Listing 11.14 truncates the rectangle's right and bottom edges, or rounds them up"};
inline constexpr OptionInfo kStencilMaskOption{"stencil", OptionInfo::Kind::Bool, option_values::kBool, -1, "false", "", 0,
                                        "the stencil mask of lit geometry (G-buffer REPLACE 1, lights EQUAL 1)"};
inline constexpr std::array<OptionInfo, 9> kDeferredClassicOptions{
    kClassicGeometryOption,
    kViewVectorOption,
    kScissorRoundOption,
    kStencilMaskOption,
    OptionInfo{"gbuffer", OptionInfo::Kind::Word, option_values::kClassicGBuffer, -1, "plain", "", 0,
               "Listing 11.1's four RGBA32F targets (64 B/px), or the optimized 16 B/px layout with position from depth"},
    OptionInfo{"normalEncoding", OptionInfo::Kind::Word, option_values::kNormalEncoding, -1, "printed", "safe", 29,
               "Listing 11.8's sphere map (NaN at and near the camera-facing pole: black pixels), or a codec defined there"},
    kSamplerOption,
    kAlphaTestOption,
    kEdgesPrcOption};

// Options (scene file "options", `render --option`); defaults are faithful to the chapter:
//   "lightGeometry": "quads" | "scissor" | "volumes"   quads: §11.2, every light a full-screen
//       quad; scissor: the quad cut by Listing 11.14's rectangle (point and spot lights); volumes:
//       the 3dgep sphere and cone meshes scaled to contain the light, drawn as the chapter's
//       companion code chooses: a volume crossing both clip planes as the quad, one crossing the
//       far plane with its front faces and LESS_EQUAL, any other with its back faces and
//       GREATER_EQUAL (works with the eye inside). All three shade the same pixels' light.
//   "viewVector": "printed" | "normalized"   printed: Listing 11.3's V = CameraPos - position,
//       not normalized, in H = normalize(L + V) (ERRATA #27); normalized: Eq. 11.1's unit V.
//   "scissorRound": "truncate" | "out"   truncate: Listing 11.14's static_cast<LONG> of the right
//       and bottom edges, which drops the last partly covered column and row (ERRATA #28);
//       out: rounded up.
//   "stencil": false | true   §11.4.2's stencil mask: the G-buffer pass writes 1 under geometry
//       (ALWAYS / REPLACE) and the light passes test EQUAL 1 (sky pixels skip the shader).
//   "gbuffer": "plain" | "optimized"   plain: Listing 11.1's four RGBA32F targets (64 B/px);
//       optimized (§11.4.1, the companion code's layout): R16G16_SNORM sphere-mapped view-space
//       normal, R10G10B10A2_UNORM diffuse, R8G8B8A8_UNORM specular albedo + power / 255, the
//       position from depth (Listing 11.12), 16 B/px with depth. deferred-classic only.
//   "normalEncoding": "printed" | "safe"   with gbuffer optimized: Listing 11.8's codec, whose
//       encoder is NaN at n = (0, 0, +-1) (stored as 0, decoded as +z: a head-on normal faces away)
//       and whose decoder takes sqrt(1 - |e|^2) of SNORM codes that can round past |e| = 1 near
//       z = -1, facing the camera: NaN, a black pixel (ERRATA #29); or the codec defined there.
//   "sampler", "alphaTest": as forward (the transparent pass).
// What each pass does (TechniqueInfo::passes; "clear", "edges", "transparent", "resolve" are shared).
inline constexpr std::array<PassCaption, 3> kDeferredClassicPassCaptions{{
    {"gbuffer", "Four R32G32B32A32_FLOAT targets: world normal, diffuse albedo, specular albedo and power, world "
                "position, 64 bytes a pixel (PR&C D3D11 ch. 11 §11.2, Listing 11.1)."},
    {"lights", "One additive full-screen pass per light reading the G-buffer at the pixel (PR&C D3D11 ch. 11 §11.2, "
               "Listing 11.3; ERRATA #27); scissor rectangles and light volumes (§11.4.2) are options that shade the "
               "same pixels for less work."},
    {"present", "The float light sum converted to the back buffer (precision reference)."},
}};

// Buffers: "backbuffer" R8G8B8A8_UNORM, cleared to black (the lights' sum; the chapter has no
// ambient term); "gbuffer.normal", "gbuffer.diffuse", "gbuffer.specular", "gbuffer.position"
// R32G32B32A32_FLOAT (Listing 11.1: (N, 1), (albedo, 1), (specular albedo, power), (P, 1), world
// space); "depth" D24_UNORM_S8_UINT; precision reference adds "accumulation" and
// "backbuffer.reference" R32G32B32A32_FLOAT. Passes: clear, gbuffer, lights (step "shade" per
// light for --dump-lights), [present], transparent.
// MSAA (TechniqueContext::sampleCount > 1; README "MSAA"): the G-buffer, depth and colour
// targets above hold that many samples (per-tile, per-light and heat-map buffers one), the image is drawn into "backbuffer.msaa" and resolved into "backbuffer", and the
// G-buffer pass adds "msaa.surface" and "msaa.coverage" (the edge detectors' inputs, RGBA32F) and
// "edges" (R32_FLOAT, 1 at the samples of pixels shaded per sample; option "msaaEdges").
Frame buildDeferredClassic(const TechniqueContext& context);

} // namespace tessera
