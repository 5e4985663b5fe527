// The arguments of `tessera render` (and `probe`, which forwards to it): the usage error every
// command throws (exit 2), bounded integers, --option values, and the parse of render's flags.
// Parsing touches no file and renders nothing, so the tests and the fuzz target call it directly.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include <glm/glm.hpp>

#include <tessera/io/image_writer.h>
#include <tessera/raster/device.h>
#include <tessera/state/precision.h>

#include "progress.h"

namespace tessera::cli {

// Bad usage: the command prints it with a pointer to its --help and exits 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// `text` as an integer in [lo, hi], else a UsageError naming `flag` and the range.
std::uint32_t parseUint(std::string_view flag, std::string_view text, std::uint32_t lo, std::uint32_t hi);

// "forward, forward-plus, ...": every technique id of the registry, for messages.
std::string knownTechniqueIds();
// Throws UsageError "FLAG: unknown technique 'ID' (one of ...)" when no technique has id `id`.
void requireKnownTechnique(std::string_view flag, const std::string& id);

// "X,Y,Z": three finite numbers, else a UsageError naming `flag`.
glm::vec3 parseVec3(std::string_view flag, std::string_view text);

// --option KEY=VALUE: VALUE as JSON (true, 32, "x", [..]), else the bare text as a string.
std::pair<std::string, nlohmann::json> parseOptionArg(std::string_view text);

struct RenderOptions {
    std::string scene = "default";
    std::string technique;
    std::string out = "tessera.png";
    std::string dumpDir;
    std::vector<std::string> dumpAfter;  // pass names
    bool dumpAfterAll = false;              // `--dump-after all` (checkDumpAfter names the passes)
    std::vector<std::uint32_t> dumpLights;  // light indices
    // `--dump-lights all` (every light of the loaded scene) or `--dump-lights A-B`: the lights of
    // [A, B] that the scene has (light steps of a technique that has none: nothing)
    std::optional<std::array<std::uint32_t, 2>> dumpLightsRange;
    float exposure = 1.0f;
    std::uint32_t viewTileSize = 0;  // the technique's light-grid tile, for the overlay views (0: none)
    std::optional<std::array<std::uint32_t, 2>> probe;  // --probe X,Y: window px
    bool probeJson = false;
    ExrPixelType exrType = ExrPixelType::Float;
    std::uint32_t width = 0, height = 0;  // 0: the scene's
    std::optional<Precision> precision;
    std::optional<std::uint32_t> lights;
    // --camera-position / --camera-target X,Y,Z (world units) and --fov DEG (vertical), over the
    // scene's camera: both points make a look-at camera, as a scene file's {position, target};
    // a position alone looks at the scene's bounds' centre; a target alone re-aims the camera.
    std::optional<glm::vec3> cameraPosition, cameraTarget;
    std::optional<float> fovDeg;
    std::optional<glm::vec2> orbitDeg;  // --orbit AZIMUTH,ELEVATION: on a sphere around the scene's bounds
    std::vector<std::pair<std::string, nlohmann::json>> options;  // --option, in command-line order
    DeviceConfig device;
    std::uint32_t msaa = 1;
    std::uint32_t repeat = 1, warmup = 0;
    std::optional<double> memoryLimitGiB;  // --memory-limit; default: frame/memory_limit.h
    bool stats = false, quiet = false, noOutput = false, outGiven = false, exrTypeGiven = false, noDefaultLights = false;
    // --double-sided-normals keep: back faces of double-sided glTF materials keep the unreversed
    // normal (glTF 2.0 §3.9.5 reverses it: the default, reverse), for comparison.
    bool keepBackFaceNormals = false;
    // --generated-bitangent up|down: tangents generated for primitives without TANGENT take the
    // bitangent up the image, as glTF 2.0 §3.9.3 reads a normal texture (up, the default), or down
    // it, tessera's generator before the correction (ERRATA #33), for comparison.
    bool generatedBitangentUp = true;
    bool generatedBitangentGiven = false;
    Progress::Mode progress = Progress::Mode::Auto;
};

// Parses render's flags (the scene argument and every option; `help` is set by --help / -h).
// Throws UsageError for a bad flag or value. Flags that change nothing (--exr with a .png
// output, ...) add one line each to `warnings`, or print "tessera: warning: ..." to stderr when
// it is null.
RenderOptions parseRenderArgs(const std::vector<std::string_view>& args, bool& help,
                              std::vector<std::string>* warnings = nullptr);

// The --option values checked against the technique's catalogue (techniques/option_catalog.h)
// and laid over the scene file's options. Throws UsageError for an unknown key or a bad value.
void applyOptionArgs(const RenderOptions& o, const std::string& technique, nlohmann::json& options);

} // namespace tessera::cli
