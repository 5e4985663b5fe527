// The technique registry: every rendering technique tessera knows, by id, with where it comes
// from and whether it is implemented yet. A technique turns a scene into a Frame: an ordered
// list of named passes that declare the buffers they read and write.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include <tessera/frame/frame.h>
#include <tessera/frame/frame_notes.h>
#include <tessera/raster/device.h>
#include <tessera/state/precision.h>
#include <tessera/scene/scene_resources.h>
#include <tessera/techniques/option_catalog.h>

namespace tessera {

struct TechniqueContext {
    Device* device = nullptr;
    const SceneResources* resources = nullptr;
    Camera camera;
    std::uint32_t width = 0, height = 0;       // render target size, px
    // MSAA samples per pixel, 1, 2, 4 or 8 (D3D11's standard patterns, raster/sample_pattern.h);
    // only techniques whose TechniqueInfo::msaa is true accept more than 1.
    std::uint32_t sampleCount = 1;
    nlohmann::json options = nlohmann::json::object();  // the scene file's "options"
    Precision precision = Precision::Exact;
    DrawStats* stats = nullptr;                // accumulated over every draw of the frame
    // Draws per shader variant ("exact:diffuse+normal", ...), for --stats; may be null.
    std::map<std::string, std::uint64_t>* variantCounts = nullptr;
    // What the frame skipped or clamped (lights, list entries, draws), each kind counted with its
    // erratum and remedy, for the command line's warnings and the report; may be null.
    FrameNotes* notes = nullptr;
    std::string sceneFile;                     // named in the InputErrors of option values
    // Per-light techniques (deferred, deferred-killzone) call this after each step of every light
    // (light index in scene order; "unmark" and "shade", or Killzone's "mark", "count", "shade")
    // with the registry as the step left it, so the stencil trick can be watched (--dump-lights).
    // Empty: no calls.
    std::function<void(std::size_t light, std::string_view step, const BufferRegistry& registry)> afterLightStep;

    // The frame's lights; null: the scene's (resources->scene().lights). estimateFrameMemory
    // renders its probe frames with a prefix of the list.
    const std::vector<Light>* lightsOverride = nullptr;

    // The file InputErrors name: sceneFile, or "scene" for an in-memory scene.
    std::string errorFile() const { return sceneFile.empty() ? std::string("scene") : sceneFile; }
    const std::vector<Light>& lights() const { return lightsOverride ? *lightsOverride : resources->scene().lights; }
};


// One pass a technique's frames can hold, as the report and the inspector show it: what it does
// and where its source describes it (the short names of docs/sources.md).
struct PassCaption {
    std::string_view pass;
    std::string_view text;
};

// Everything the command line, the report, the tests and the benchmarks know of a technique,
// declared once in the technique's own header: they ask this and never compare ids.
struct TechniqueInfo {
    std::string_view id;
    std::string_view summary;
    std::string_view source;       // the source it follows (docs/sources.md)
    // Null while the technique is planned but not implemented.
    Frame (*build)(const TechniqueContext&) = nullptr;
    // Every key the technique accepts in "options", with its values, faithful default, correction
    // and erratum (option_catalog.h); buildTechnique rejects any other key.
    std::span<const OptionInfo> options;
    // A caption for each pass its frames can hold, except the passes every technique shares
    // (kCommonPassCaptions: "clear", "transparent", "resolve"); a test holds every pass of every
    // option set captioned.
    std::span<const PassCaption> passes;
    // How SceneResources should decode colour textures for this technique.
    TexturePolicy textures = TexturePolicy::Gltf;
    // Renders with TechniqueContext::sampleCount > 1 (multisampled targets and a resolve).
    bool msaa = false;
    // What the technique does with the scene's lights beyond plain point, spot and directional
    // ones, and its role among the others (TechniqueFeature bits): the command line warns about
    // what a scene asks for and the technique leaves out, without comparing technique ids.
    std::uint32_t features = 0;
    // The edge of its per-tile light lists ("lightgrid*" buffers) in px: the "tileSize" option when
    // the technique has one, else this; 0 for techniques without tiles.
    std::uint32_t tileSize = 0;
};

// TechniqueInfo::features.
enum TechniqueFeature : std::uint32_t {
    kShadesCapsuleLights = 1u << 0,  // capsule lights (others skip them)
    kHonoursLightGroups = 1u << 1,   // the scene's lightGroups (others light every surface with every light)
    kShadowRaysAndVpls = 1u << 2,    // shadow-casting and indirect lights (others light them as plain lights)
    kOwnHeadLight = 1u << 3,         // lights without the scene's lights (no default rig for a scene without any)
    kPerLightSteps = 1u << 4,        // calls TechniqueContext::afterLightStep (--dump-lights)
    kInspectionView = 1u << 5,       // no light model (preview): left out of the report's comparisons
    kComparisonBaseline = 1u << 6,   // the image every other technique is compared against (forward)
};

// The registry as JSON, for scripts (`tessera options --json`, bench/sweep.py): per technique (every
// one, or only the id `only`) its id, summary, source, whether it is ready, renders MSAA, is the
// comparison baseline or an inspection view, its tile size, pass captions and options (key, kind,
// values, minInteger / maxInteger, range, faithful, corrected, erratum, meaning).
nlohmann::json techniqueRegistryJson(std::string_view only = {});

// The passes every technique may hold, captioned once.
extern const std::span<const PassCaption> kCommonPassCaptions;

// The built-in techniques, then those added by registerTechnique, in that order.
std::span<const TechniqueInfo> techniques();
// Adds a technique to the registry (a test's or an embedding program's own): from then on it is
// listed, built, optioned and captioned as the built-in ones are. Throws std::invalid_argument for
// an empty id, an id already registered, a missing build function, or a full registry (64
// techniques). Rows never move: pointers and spans from the functions here stay valid, though a
// span from techniques() does not see later registrations.
void registerTechnique(const TechniqueInfo& info);
// Null when no technique has this id.
const TechniqueInfo* findTechnique(std::string_view id);
// The technique with this id (ready or planned); throws InputError naming `sceneFile` and
// "/technique" with the known ids when there is none.
const TechniqueInfo& requireTechnique(std::string_view id, const std::string& sceneFile);
// The options of technique `id` (TechniqueInfo::options; empty for an unknown id or one without
// options), and its option `key` or null.
std::span<const OptionInfo> techniqueOptions(std::string_view id);
const OptionInfo* findOption(std::string_view id, std::string_view key);
// What pass `pass` of `info` does: its own caption, else the shared one; empty when neither has it.
std::string_view passCaption(const TechniqueInfo& info, std::string_view pass);

// Builds the frame; throws InputError for an unknown or unimplemented technique id or an
// unknown option key (naming "/technique" or "/options/KEY").
Frame buildTechnique(std::string_view id, const TechniqueContext& context, const std::string& sceneFile);

// The final image of every technique is the buffer named "backbuffer".
inline constexpr std::string_view kBackBufferName = "backbuffer";
// Precision reference: the back buffer's colour before quantization (R32G32B32A32_FLOAT, the
// double shading rounded once to float, clamped to [0, 1] as the UNORM back buffer clamps),
// written beside the back buffer by every technique.
inline constexpr std::string_view kReferenceBufferName = "backbuffer.reference";
// The bytes a frame's buffers will hold (BufferRegistry::bytes after run) for `context`, from four
// probe frames rendered with the same technique, options, samples, precision and camera (its
// aspect kept): 64x64 and 128x64 px, with the first min(L, 32) and min(L, 64) of the L lights.
// Buffers grow with pixels (targets, per-tile lists, shadow jobs), with lights (light arrays,
// unbounded lists) and with both, so the estimate is the bilinear fit
// a + b P + c L + d P L through the four totals, evaluated at the frame's P = width x height.
// Structured buffers, stored in rows of 16384 elements, get one more row each (they grow in whole
// rows). Transient memory inside passes (scratch lists, per-thread tiles) is not included.
struct FrameMemoryEstimate {
    double bytes = 0.0;            // the estimate for the frame
    double bytesPerPixel = 0.0;    // b + d L: what each pixel adds
    double fixedBytes = 0.0;       // a + c L: what does not grow with pixels
};
FrameMemoryEstimate estimateFrameMemory(std::string_view id, const TechniqueContext& context, const std::string& sceneFile);

// What every technique needs of its inputs, checked by buildTechnique before anything is built:
// near a positive normal float and far > near (far may be +inf), a perspective field of view in
// (0, 180) degrees or positive orthographic magnifications, a finite camera position, and for
// every light a finite colour x intensity in binary32 and a positive range. Throws InputError
// naming `sceneFile` and the key ("/camera/near", "/lights": "light 3 ('key'): ...").
void checkFrameInputs(const TechniqueContext& context, const std::string& sceneFile);

// `names` (a pass's buffer list that starts with the back buffer) with kReferenceBufferName
// inserted after the back buffer when `precision` is Reference.
std::vector<std::string> withReferenceBuffer(std::vector<std::string> names, Precision precision);

// The target a technique draws its image into: the back buffer itself, or with MSAA
// "backbuffer.msaa" (N samples), which the frame's last pass resolves into the back buffer; and
// the same for the precision reference's float copy ("backbuffer.reference.msaa").
std::string backBufferTarget(std::uint32_t sampleCount);
std::string referenceBufferTarget(std::uint32_t sampleCount);
// `names` with every "backbuffer" and "backbuffer.reference" replaced by its target above.
std::vector<std::string> withBackBufferTargets(std::vector<std::string> names, std::uint32_t sampleCount);
// The last pass of an MSAA frame: ResolveSubresource (the samples' average, in the format's
// linear values) of the targets into the back buffer (their format) and, with precision
// reference, its float copy.
Pass resolveBackBufferPass(std::uint32_t sampleCount, Precision precision);
// Throws InputError naming `sceneFile` and "/technique" when `info` cannot render `sampleCount`
// samples per pixel (a technique without MSAA, or a count other than 1, 2, 4, 8).
void checkSampleCount(const TechniqueInfo& info, std::uint32_t sampleCount, const std::string& sceneFile);

// Writes a float target into `to` as the output merger converts a PS value for an UNORM target
// without blending: NaN -> 0, clamp to [0, 1] (D3D11.3 §3.2.3.6), then `to`'s own encode (the
// 8-bit rounding for the back buffer; none for precision reference's float copy). `from` may be `to`.
void storeAsUnorm(const Surface& from, Surface& to);

} // namespace tessera
