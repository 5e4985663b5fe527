// The option catalogue (techniques/option_catalog.h): one table per technique, in the order the
// technique's header documents its options. The meanings are short; the headers say more.
#include <tessera/techniques/option_catalog.h>

#include <array>

namespace tessera {
namespace {

using Kind = OptionInfo::Kind;

constexpr std::array<std::string_view, 2> kBool{"false", "true"};
constexpr std::array<std::string_view, 2> kProjection{"demo-gl", "d3d"};
constexpr std::array<std::string_view, 2> kProjectionAmd{"d3d", "demo-gl"};
constexpr std::array<std::string_view, 1> kProjectionD3d{"d3d"};
constexpr std::array<std::string_view, 2> kSampler{"demo", "gltf"};
constexpr std::array<std::string_view, 2> kReconstruct{"corner", "centre"};
constexpr std::array<std::string_view, 2> kVolumes{"inscribed", "circumscribed"};
constexpr std::array<std::string_view, 2> kRotation{"glm096", "robust"};
constexpr std::array<std::string_view, 2> kGBuffer{"demo", "float"};
constexpr std::array<std::string_view, 2> kPosition{"reconstruct", "gbuffer"};
constexpr std::array<std::string_view, 2> kAccumulate{"color", "lighting"};
constexpr std::array<std::string_view, 2> kLightLists{"demo", "unbounded"};
constexpr std::array<std::string_view, 2> kConeTest{"demo", "corrected"};
constexpr std::array<std::string_view, 3> kTileSize{"16", "8", "32"};
constexpr std::array<std::string_view, 2> kCulling{"binned", "brute"};
constexpr std::array<std::string_view, 2> kShadingAmd{"amd", "3dgep"};
constexpr std::array<std::string_view, 2> kCullingAmd{"depth-mask", "min-max"};
constexpr std::array<std::string_view, 2> kLightLoop{"binned", "all-lights"};
constexpr std::array<std::string_view, 2> kShadingIntel{"intel", "3dgep"};
constexpr std::array<std::string_view, 2> kNormals{"spheremap", "float"};
constexpr std::array<std::string_view, 2> kTilePlanes{"sample2010", "tile"};
constexpr std::array<std::string_view, 1> kUnbounded{"unbounded"};
constexpr std::array<std::string_view, 2> kSpecPowerUnpack{"printed", "once"};
constexpr std::array<std::string_view, 2> kVolumeCull{"table", "front"};
constexpr std::array<std::string_view, 2> kSpotVolume{"book", "demo"};
constexpr std::array<std::string_view, 2> kCpPos{"vertex", "pixel"};
constexpr std::array<std::string_view, 2> kBackground{"book", "stencil"};
constexpr std::array<std::string_view, 2> kVolumeScale{"padded", "range"};
constexpr std::array<std::string_view, 2> kLightGeometry{"volumes", "quads"};
constexpr std::array<std::string_view, 3> kClassicGeometry{"quads", "scissor", "volumes"};
constexpr std::array<std::string_view, 2> kViewVector{"printed", "normalized"};
constexpr std::array<std::string_view, 2> kScissorRound{"truncate", "out"};
constexpr std::array<std::string_view, 2> kClassicGBuffer{"plain", "optimized"};
constexpr std::array<std::string_view, 2> kNormalEncoding{"printed", "safe"};
constexpr std::array<std::string_view, 3> kEdgesPrc{"coverage", "depthNormal", "all"};
constexpr std::array<std::string_view, 3> kEdgesIntel{"depthNormal", "coverage", "all"};
constexpr std::array<std::string_view, 2> kMsaaFinal{"coverage", "perSample"};
constexpr std::array<std::string_view, 3> kAutoOnOff{"auto", "on", "off"};
constexpr std::array<std::string_view, 3> kShadowBackfaces{"mask", "lit", "cast"};
constexpr std::array<std::string_view, 2> kShadowOverflow{"lit", "unlit"};
constexpr std::array<std::string_view, 2> kVplDirection{"reflect", "normal"};
constexpr std::array<std::string_view, 0> kNone{};

constexpr OptionInfo kProjectionOption{"projection", Kind::Word, kProjection, -1, "demo-gl", "d3d", 1,
                                       "the demo's OpenGL-form perspective under D3D clipping (near plane at 0.19998), or "
                                       "perspectiveRH_ZO"};
constexpr OptionInfo kSamplerOption{"sampler", Kind::Word, kSampler, -1, "demo", "", 0,
                                    "the demo's trilinear wrap sampler for every texture, or each texture's glTF sampler"};
constexpr OptionInfo kAlphaTestOption{"alphaTest", Kind::Bool, kBool, -1, "false", "true", 2,
                                      "discard where alpha * Opacity < AlphaThreshold in the forward-shaded pass, which the "
                                      "demo's forward PS never does"};
constexpr OptionInfo kTileSizeOption{"tileSize", Kind::Integer, kTileSize, -1, "16", "", 0,
                                     "tile edge in px, one thread group per tile (BLOCK_SIZE)"};

// With --msaa N: which pixels the light passes shade per sample (techniques/msaa_deferred.h).
constexpr OptionInfo kEdgesPrcOption{"msaaEdges", Kind::Word, kEdgesPrc, -1, "coverage", "", 0,
                                     "MSAA: per-sample shading where a triangle covered the pixel partly (Listing 11.17), "
                                     "where depth or normal differ (Intel 2010), or everywhere"};
constexpr OptionInfo kEdgesIntelOption{"msaaEdges", Kind::Word, kEdgesIntel, -1, "depthNormal", "", 0,
                                       "MSAA: per-sample shading where depth or normal differ (Intel 2010), where a triangle "
                                       "covered the pixel partly (PR&C Listing 11.17), or everywhere"};

constexpr std::array<OptionInfo, 3> kForward{kProjectionOption, kSamplerOption, kAlphaTestOption};

constexpr std::array<OptionInfo, 10> kDeferredCookbook{
    OptionInfo{"specPowerUnpack", Kind::Word, kSpecPowerUnpack, -1, "printed", "once", 22,
               "the chapter's printed unpack (251 x norm, then decoded again) or 0.1 + 250 x norm once"},
    OptionInfo{"volumeCull", Kind::Word, kVolumeCull, -1, "table", "front", 23,
               "the recipe table's CULL_BACK (lights what is in front of the volume) or CULL_FRONT (its far side)"},
    OptionInfo{"spotVolume", Kind::Word, kSpotVolume, -1, "book", "demo", 24,
               "ScaleXY = R tan(a)/sqrt(1/2) on a 45-degree unit cone, or the outer angle's cone scaled by R (enlarged)"},
    OptionInfo{"cpPos", Kind::Word, kCpPos, -1, "vertex", "pixel", 25,
               "clip-space xy divided per vertex and interpolated, or the pixel centre's"},
    OptionInfo{"background", Kind::Word, kBackground, -1, "book", "stencil", 26,
               "the directional quad without depth-stencil shades the background too, or stencil marks the geometry"},
    OptionInfo{"volumeScale", Kind::Word, kVolumeScale, -1, "padded", "", 0,
               "volumes enlarged to contain the light's range (the book's 'plus a small value'), or exactly the range"},
    OptionInfo{"lightGeometry", Kind::Word, kLightGeometry, -1, "volumes", "", 0,
               "the recipes' volumes, or every light as a full-screen quad (the baseline the volumes must match)"},
    kSamplerOption,
    kAlphaTestOption,
    kEdgesIntelOption};

constexpr OptionInfo kClassicGeometryOption{"lightGeometry", Kind::Word, kClassicGeometry, -1, "quads", "", 0,
                                            "a full-screen quad per light (§11.2), the quad cut by the light's scissor "
                                            "rectangle, or its volume (§11.4.2)"};
constexpr OptionInfo kViewVectorOption{"viewVector", Kind::Word, kViewVector, -1, "printed", "normalized", 27,
                                       "Listing 11.3's unnormalized V in H = normalize(L + V), or Eq. 11.1's unit V"};
constexpr OptionInfo kScissorRoundOption{"scissorRound", Kind::Word, kScissorRound, -1, "truncate", "out", 28,
                                         "Listing 11.14 truncates the rectangle's right and bottom edges, or rounds them up"};
constexpr OptionInfo kStencilMaskOption{"stencil", Kind::Bool, kBool, -1, "false", "", 0,
                                        "the stencil mask of lit geometry (G-buffer REPLACE 1, lights EQUAL 1)"};

constexpr std::array<OptionInfo, 9> kDeferredClassic{
    kClassicGeometryOption,
    kViewVectorOption,
    kScissorRoundOption,
    kStencilMaskOption,
    OptionInfo{"gbuffer", Kind::Word, kClassicGBuffer, -1, "plain", "", 0,
               "Listing 11.1's four RGBA32F targets (64 B/px), or the optimized 16 B/px layout with position from depth"},
    OptionInfo{"normalEncoding", Kind::Word, kNormalEncoding, -1, "printed", "safe", 29,
               "Listing 11.8's sphere map (NaN at and near the camera-facing pole: black pixels), or a codec defined there"},
    kSamplerOption,
    kAlphaTestOption,
    kEdgesPrcOption};

constexpr std::array<OptionInfo, 8> kLightPrePass{
    kClassicGeometryOption, kViewVectorOption, kScissorRoundOption, kStencilMaskOption, kSamplerOption, kAlphaTestOption,
    kEdgesPrcOption,
    OptionInfo{"msaaFinal", Kind::Word, kMsaaFinal, -1, "coverage", "perSample", 30,
               "MSAA second geometry pass: Listing 11.19's loop over SV_Coverage (which counts samples of surfaces in "
               "front), or per sample at edge pixels"}};

constexpr std::array<OptionInfo, 10> kDeferred{
    kProjectionOption,
    OptionInfo{"reconstruct", Kind::Word, kReconstruct, -1, "corner", "centre", 3,
               "where the light pass rebuilds P from depth: the pixel's top-left corner, or its centre"},
    OptionInfo{"lightVolumes", Kind::Word, kVolumes, -1, "inscribed", "circumscribed", 4,
               "the demo's sphere and cone meshes inside the light's range, or scaled to contain it"},
    OptionInfo{"volumeRotation", Kind::Word, kRotation, -1, "glm096", "robust", 5,
               "glm 0.9.6's quat(u, v) (identity for a spot aimed down -Z), or a rotation that handles it"},
    OptionInfo{"gbuffer", Kind::Word, kGBuffer, -1, "demo", "float", 7,
               "RGBA8 targets with log2(p)/10.5 specular power and D24S8, or float targets and D32S8"},
    OptionInfo{"position", Kind::Word, kPosition, -1, "reconstruct", "gbuffer", 0,
               "P from the depth buffer, or the interpolated view position stored in gbuffer.position"},
    OptionInfo{"accumulate", Kind::Word, kAccumulate, -1, "color", "lighting", 0,
               "each light blends its colour into RT0, or lighting is summed apart and composed as forward does (the "
               "order that reproduces forward's bits)"},
    kSamplerOption,
    kAlphaTestOption,
    kEdgesIntelOption};

// deferred's options and one more.
template <std::size_t N>
constexpr std::array<OptionInfo, N + 1> withOption(const std::array<OptionInfo, N>& base, const OptionInfo& extra) {
    std::array<OptionInfo, N + 1> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = base[i];
    out[N] = extra;
    return out;
}

constexpr std::array<OptionInfo, 11> kKillzone = withOption(
    kDeferred, OptionInfo{"threshold", Kind::Integer, kNone, 0, "0", "", 0,
                          "a light's shade draw runs only when its occlusion query passed more than this many samples"});

constexpr std::array<OptionInfo, 7> kForwardPlus{
    kProjectionOption,
    kSamplerOption,
    kAlphaTestOption,
    OptionInfo{"lightLists", Kind::Word, kLightLists, -1, "demo", "unbounded", 15,
               "the demo's fixed light lists (1024 per tile, 200 per tile globally) that overflow silently, or lists "
               "that never drop a light"},
    OptionInfo{"coneTest", Kind::Word, kConeTest, -1, "demo", "corrected", 10,
               "the article's ConeInsidePlane (m not normalised: not conservative), or the corrected test"},
    kTileSizeOption,
    OptionInfo{"culling", Kind::Word, kCulling, -1, "binned", "", 0,
               "how the culling dispatch finds each tile's lights: binned by tile rows, or every light in every tile "
               "(the same lists)"}};

constexpr std::array<OptionInfo, 19> kForwardPlusAmd{
    OptionInfo{"shading", Kind::Word, kShadingAmd, -1, "amd", "", 0,
               "ForwardPlus11's pixel shader (AMD falloff and lighting), or the 3dgep article's Phong shader"},
    OptionInfo{"culling", Kind::Word, kCullingAmd, -1, "depth-mask", "", 0,
               "GPU Pro 4's 2.5D culling (32-cell depth mask), or side planes and the tile's depth slab"},
    OptionInfo{"halfZ", Kind::Bool, kBool, -1, "false", "", 21,
               "TiledLighting11's two lists per tile split at the middle of its depth range (shading amd only)"},
    OptionInfo{"projection", Kind::Word, kProjectionAmd, -1, "d3d (shading 3dgep: demo-gl)", "d3d", 1,
               "as forward; AMD's sample builds a D3D matrix, the 3dgep shading follows the 3dgep demo"},
    kSamplerOption,
    kAlphaTestOption,
    OptionInfo{"lightLoop", Kind::Word, kLightLoop, -1, "binned", "", 0,
               "which lights each tile's culling loop visits: binned by tile rows, or all (GPU Pro 4's kernel); the "
               "same lists"},
    OptionInfo{"shadows", Kind::Word, kAutoOnOff, -1, "auto", "", 0,
               "GPU Pro 4 5.6.2 ray-cast shadows when the scene has shadow-casting lights and the configuration allows "
               "(on: an error otherwise), or never"},
    OptionInfo{"shadowNormalOffset", Kind::Number, kNone, -1, "0.01", "", 0,
               "world units along the G-pass normal from the rebuilt position to the shadow ray's origin", 0.0, 1e6},
    OptionInfo{"shadowBackfaces", Kind::Word, kShadowBackfaces, -1, "mask", "", 0,
               "a light behind the surface: masked without a ray, left lit, or ray cast"},
    OptionInfo{"shadowOverflow", Kind::Word, kShadowOverflow, -1, "lit", "unlit", 31,
               "lights past the 128 mask slots of a pixel: shaded unshadowed, or dropped"},
    OptionInfo{"indirect", Kind::Word, kAutoOnOff, -1, "auto", "", 0,
               "GPU Pro 4 5.5 one-bounce VPLs when the scene has an indirect light (on: an error otherwise), or never"},
    OptionInfo{"rsmSize", Kind::Integer, kNone, 1, "256", "", 0, "reflective shadow map edge in texels (at most 4096)"},
    OptionInfo{"vplGrid", Kind::Integer, kNone, 1, "16", "", 0, "N: N x N VPLs from the RSM's grid-cell centres (at most 128)"},
    OptionInfo{"vplConeDeg", Kind::Number, kNone, -1, "60", "", 0, "each VPL's spot half angle in degrees", 1.0, 89.0},
    OptionInfo{"vplRange", Kind::Number, kNone, -1, "4", "", 0, "each VPL's range in world units", 1e-6, 1e6},
    OptionInfo{"vplIntensity", Kind::Number, kNone, -1, "1", "", 0, "scale of the VPLs' summed colour", 0.0, 1e6},
    OptionInfo{"vplDirection", Kind::Word, kVplDirection, -1, "reflect", "", 0,
               "VPL axis: the reflection of the light direction about the normal (the chapter's), or the normal"},
    OptionInfo{"vplOffset", Kind::Number, kNone, -1, "0.01", "", 0, "world units a VPL sits off its surface", 0.0, 1e6}};

constexpr std::array<OptionInfo, 11> kTiledDeferred{
    OptionInfo{"shading", Kind::Word, kShadingIntel, -1, "intel", "", 0,
               "Intel's 2010 sample shading, or the 3dgep article's Phong equations on the same G-buffer"},
    OptionInfo{"gbuffer", Kind::Word, kGBuffer, -1, "demo", "float", 7,
               "the sample's quantised G-buffer, or float targets"},
    OptionInfo{"position", Kind::Word, kPosition, -1, "reconstruct", "gbuffer", 0,
               "P from the depth buffer (Intel's reconstruction), or the interpolated view position"},
    OptionInfo{"normals", Kind::Word, kNormals, -1, "spheremap", "float", 0,
               "intel shading: the normal through the sample's spheremap encoding, or as stored in float"},
    OptionInfo{"tilePlanes", Kind::Word, kTilePlanes, -1, "sample2010", "tile", 12,
               "the sample's side planes (c4 +- c1, c4 +- c2: each spans 2x2 tiles), or planes that bound the tile"},
    kTileSizeOption,
    OptionInfo{"tileListCapacity", Kind::IntegerOrWord, kUnbounded, 1, "1024", "unbounded", 16,
               "lights one tile's list holds (MAX_LIGHTS); past it lights are dropped and counted"},
    OptionInfo{"projection", Kind::Word, kProjectionD3d, -1, "d3d", "", 0,
               "the only value: Intel's view-z reconstruction needs a D3D-form matrix"},
    kSamplerOption,
    kAlphaTestOption,
    kEdgesIntelOption};

struct TechniqueOptions {
    std::string_view id;
    std::span<const OptionInfo> options;
};

constexpr std::array<TechniqueOptions, 9> kCatalog{{{"forward", kForward},
                                                    {"deferred", kDeferred},
                                                    {"deferred-killzone", kKillzone},
                                                    {"forward-plus", kForwardPlus},
                                                    {"forward-plus-amd", kForwardPlusAmd},
                                                    {"tiled-deferred", kTiledDeferred},
                                                    {"deferred-cookbook", kDeferredCookbook},
                                                    {"deferred-classic", kDeferredClassic},
                                                    {"light-prepass", kLightPrePass}}};

bool listed(const OptionInfo& option, std::string_view text) {
    for (const std::string_view v : option.values)
        if (v == text) return true;
    return false;
}

} // namespace

std::span<const OptionInfo> builtinOptionCatalog(std::string_view id) {
    for (const TechniqueOptions& t : kCatalog)
        if (t.id == id) return t.options;
    return {};
}

std::string optionValuesText(const OptionInfo& option) {
    if (option.kind == Kind::Number)
        return "number in [" + nlohmann::json(option.minNumber).dump() + ", " + nlohmann::json(option.maxNumber).dump() + "]";
    std::string text;
    if (option.minInteger >= 0) text = "integer >= " + std::to_string(option.minInteger);
    for (const std::string_view v : option.values) {
        if (!text.empty()) text += " | ";
        text += v;
    }
    return text;
}

std::optional<std::string> optionValueProblem(const OptionInfo& option, const nlohmann::json& value) {
    const std::string expected = optionValuesText(option);
    const std::string given = value.dump();
    switch (option.kind) {
    case Kind::Bool:
        if (value.is_boolean()) return std::nullopt;
        break;
    case Kind::Number:
        if (value.is_number() && value.get<double>() >= option.minNumber && value.get<double>() <= option.maxNumber)
            return std::nullopt;
        return given + " is not a " + expected;
    case Kind::Word:
        if (value.is_string() && listed(option, value.get<std::string>())) return std::nullopt;
        break;
    case Kind::IntegerOrWord:
        if (value.is_string() && listed(option, value.get<std::string>())) return std::nullopt;
        [[fallthrough]];
    case Kind::Integer:
        if (value.is_number_integer()) {
            const std::int64_t n = value.is_number_unsigned() ? std::int64_t(std::min<std::uint64_t>(value.get<std::uint64_t>(), INT64_MAX))
                                                              : value.get<std::int64_t>();
            if (option.minInteger >= 0 && n >= option.minInteger) return std::nullopt;
            if (option.kind == Kind::Integer && listed(option, std::to_string(n))) return std::nullopt;
        }
        break;
    }
    return given + " is not " + (option.values.size() + (option.minInteger >= 0 ? 1 : 0) > 1 ? "one of " : "") + expected;
}

} // namespace tessera
