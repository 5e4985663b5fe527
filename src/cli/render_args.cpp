// The parse of `tessera render`'s arguments (render_args.h): bounded integers, --option values
// and every flag, checked against each other before anything loads.
#include "render_args.h"

#include "arg_cursor.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <thread>

#include <tessera/state/viewport.h>
#include <tessera/techniques/option_catalog.h>
#include <tessera/techniques/technique.h>

namespace tessera::cli {

std::uint32_t parseUint(std::string_view flag, std::string_view text, std::uint32_t lo, std::uint32_t hi) {
    std::uint64_t v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || v < lo || v > hi)
        throw UsageError(std::string(flag) + ": '" + std::string(text) + "' is not an integer in " + std::to_string(lo) + ".." +
                         std::to_string(hi));
    return std::uint32_t(v);
}

glm::vec3 parseVec3(std::string_view flag, std::string_view text) {
    glm::vec3 v(0.0f);
    std::size_t start = 0;
    for (int i = 0; i < 3; ++i) {
        const std::size_t comma = i < 2 ? text.find(',', start) : text.size();
        if (comma == std::string_view::npos) break;
        const std::string part(text.substr(start, comma - start));
        char* end = nullptr;
        v[i] = std::strtof(part.c_str(), &end);
        if (part.empty() || end != part.c_str() + part.size() || !std::isfinite(v[i]))
            throw UsageError(std::string(flag) + ": '" + std::string(text) + "' is not X,Y,Z (three finite numbers)");
        start = comma + 1;
        if (i == 2) return v;
    }
    throw UsageError(std::string(flag) + ": '" + std::string(text) + "' is not X,Y,Z (three finite numbers)");
}

std::pair<std::string, nlohmann::json> parseOptionArg(std::string_view text) {
    const std::size_t eq = text.find('=');
    if (eq == std::string_view::npos || eq == 0)
        throw UsageError("--option: '" + std::string(text) + "' is not KEY=VALUE (see tessera options)");
    // The key and value end up in JSON (the technique's options, messages, the dump's manifest),
    // whose dump() throws on bytes that are not UTF-8: such an argument is refused here.
    try {
        (void)nlohmann::json(std::string(text)).dump();
    } catch (const nlohmann::json::type_error& e) {
        std::string why = e.what();
        const std::size_t bracket = why.find("] ");
        if (bracket != std::string::npos) why = why.substr(bracket + 2);
        throw UsageError("--option: the argument is not valid UTF-8 (" + why + ")");
    }
    const std::string key(text.substr(0, eq)), valueText(text.substr(eq + 1));
    nlohmann::json value = nlohmann::json::parse(valueText, nullptr, false);
    if (value.is_discarded()) value = valueText;
    return {key, value};
}

void applyOptionArgs(const RenderOptions& o, const std::string& technique, nlohmann::json& options) {
    for (const auto& [key, value] : o.options) {
        const OptionInfo* info = findOption(technique, key);
        if (!info) {
            std::string known;
            for (const OptionInfo& k : techniqueOptions(technique)) known += (known.empty() ? "" : ", ") + std::string(k.key);
            throw UsageError("--option " + key + ": " + technique + " has no option '" + key + "'" +
                             (known.empty() ? " (it has none)" : " (it has " + known + ")"));
        }
        if (const auto problem = optionValueProblem(*info, value))
            throw UsageError("--option " + key + "=" + value.dump() + ": " + *problem + " (technique " + technique + ")");
        if (!options.is_object()) options = nlohmann::json::object();
        options[key] = value;
    }
}

std::string knownTechniqueIds() {
    std::string ids;
    for (const TechniqueInfo& t : techniques()) ids += (ids.empty() ? "" : ", ") + std::string(t.id);
    return ids;
}

void requireKnownTechnique(std::string_view flag, const std::string& id) {
    if (!findTechnique(id)) throw UsageError(std::string(flag) + ": unknown technique '" + id + "' (one of " + knownTechniqueIds() + ")");
}

RenderOptions parseRenderArgs(const std::vector<std::string_view>& args, bool& help, std::vector<std::string>* warnings) {
    const auto warn = [warnings](const std::string& text) {
        if (warnings) warnings->push_back(text);
        else std::fprintf(stderr, "tessera: warning: %s\n", text.c_str());
    };
    RenderOptions o;
    bool sceneGiven = false, drawByDrawGiven = false, binnedGiven = false;
    ArgCursor cursor(args);
    while (cursor.next()) {
        const std::string_view a = cursor.flag();
        const auto value = [&cursor] { return cursor.value(); };
        if (a == "--help" || a == "-h") help = true;
        else if (a == "--technique") o.technique = std::string(value());
        else if (a == "--option") o.options.push_back(parseOptionArg(value()));
        else if (a == "--out" || a == "-o") {
            o.out = std::string(value());
            o.outGiven = true;
        } else if (a == "--no-output") o.noOutput = true;
        else if (a == "--scalar-raster") o.device.simdBlocks = false;
        else if (a == "--draw-by-draw") {
            o.device.binPasses = false;
            drawByDrawGiven = true;
        } else if (a == "--binned") binnedGiven = true;
        else if (a == "--no-default-lights") o.noDefaultLights = true;
        else if (a == "--double-sided-normals") {
            const std::string_view mode = value();
            if (mode == "reverse") o.keepBackFaceNormals = false;
            else if (mode == "keep") o.keepBackFaceNormals = true;
            else throw UsageError("--double-sided-normals: '" + std::string(mode) + "' is not reverse or keep");
        } else if (a == "--generated-bitangent") {
            const std::string_view mode = value();
            o.generatedBitangentGiven = true;
            if (mode == "down") o.generatedBitangentUp = false;
            else if (mode == "up") o.generatedBitangentUp = true;
            else throw UsageError("--generated-bitangent: '" + std::string(mode) + "' is not down or up");
        }
        else if (a == "--exr") {
            o.exrTypeGiven = true;
            const std::string_view t = value();
            if (t == "half") o.exrType = ExrPixelType::Half;
            else if (t == "float") o.exrType = ExrPixelType::Float;
            else throw UsageError("--exr: '" + std::string(t) + "' is not half or float");
        } else if (a == "--width") o.width = parseUint(a, value(), 1, kMaxSurfaceDimension);
        else if (a == "--height") o.height = parseUint(a, value(), 1, kMaxSurfaceDimension);
        else if (a == "--precision") {
            const std::string_view p = value();
            o.precision = parsePrecision(p);
            if (!o.precision) throw UsageError("--precision: '" + std::string(p) + "' is not reference, exact or fast");
        } else if (a == "--lights") o.lights = parseUint(a, value(), 0, 1000000);
        else if (a == "--threads") o.device.threads = parseUint(a, value(), 0, 256);
        else if (a == "--tile") {
            o.device.tileSize = parseUint(a, value(), 8, 1024);
            if (o.device.tileSize % 2) throw UsageError("--tile: " + std::to_string(o.device.tileSize) + " is odd; tiles hold whole 2x2 quads");
        } else if (a == "--msaa") {
            o.msaa = parseUint(a, value(), 1, 8);
            if (o.msaa != 1 && o.msaa != 2 && o.msaa != 4 && o.msaa != 8)
                throw UsageError("--msaa: " + std::to_string(o.msaa) + " is not 1, 2, 4 or 8");
        } else if (a == "--repeat") o.repeat = parseUint(a, value(), 1, 100000);
        else if (a == "--warmup") o.warmup = parseUint(a, value(), 0, 100000);
        else if (a == "--dump") o.dumpDir = std::string(value());
        else if (a == "--dump-after") {
            const std::string list(value());
            if (list == "all") o.dumpAfterAll = true;
            for (std::size_t start = 0; start <= list.size() && !o.dumpAfterAll;) {
                const std::size_t comma = std::min(list.find(',', start), list.size());
                if (comma == start) throw UsageError("--dump-after: '" + list + "' has an empty pass name");
                o.dumpAfter.push_back(list.substr(start, comma - start));
                start = comma + 1;
            }
        } else if (a == "--dump-lights") {
            const std::string list(value());
            const std::size_t dash = list.find('-');
            if (list == "all") o.dumpLightsRange = std::array<std::uint32_t, 2>{0, 999999};
            else if (dash != std::string::npos)
                o.dumpLightsRange = std::array<std::uint32_t, 2>{parseUint("--dump-lights", std::string_view(list).substr(0, dash), 0, 999999),
                                                                 parseUint("--dump-lights", std::string_view(list).substr(dash + 1), 0, 999999)};
            if (o.dumpLightsRange && (*o.dumpLightsRange)[0] > (*o.dumpLightsRange)[1])
                throw UsageError("--dump-lights: '" + list + "' is an empty range (A-B needs A <= B)");
            for (std::size_t start = 0; start <= list.size() && !o.dumpLightsRange;) {
                const std::size_t comma = std::min(list.find(',', start), list.size());
                o.dumpLights.push_back(parseUint("--dump-lights", std::string_view(list).substr(start, comma - start), 0, 999999));
                start = comma + 1;
            }
        } else if (a == "--probe") {
            const std::string text(value());
            const std::size_t comma = text.find(',');
            if (comma == std::string::npos) throw UsageError("--probe: '" + text + "' is not X,Y (window pixels)");
            o.probe = std::array<std::uint32_t, 2>{parseUint("--probe", std::string_view(text).substr(0, comma), 0, kMaxSurfaceDimension - 1),
                                                   parseUint("--probe", std::string_view(text).substr(comma + 1), 0, kMaxSurfaceDimension - 1)};
        } else if (a == "--camera-position" || a == "--camera-target") {
            (a == "--camera-position" ? o.cameraPosition : o.cameraTarget) = parseVec3(a, value());
        } else if (a == "--orbit") {
            const std::string text(value());
            const std::size_t comma = text.find(',');
            const auto number = [&text](std::string part, float lo, float hi) {
                char* end = nullptr;
                const float v = std::strtof(part.c_str(), &end);
                if (part.empty() || end != part.c_str() + part.size() || !(v >= lo && v <= hi))
                    throw UsageError("--orbit: '" + text + "' is not AZIMUTH,ELEVATION in degrees (elevation from -89 to 89)");
                return v;
            };
            if (comma == std::string::npos) number("", 0.0f, 0.0f);
            o.orbitDeg = glm::vec2(number(text.substr(0, comma), -1.0e6f, 1.0e6f), number(text.substr(comma + 1), -89.0f, 89.0f));
        } else if (a == "--fov") {
            const std::string text(value());
            char* end = nullptr;
            const float deg = std::strtof(text.c_str(), &end);
            if (end != text.c_str() + text.size() || !(deg > 0.0f && deg < 180.0f))
                throw UsageError("--fov: '" + text + "' is not a vertical field of view in degrees, between 0 and 180");
            o.fovDeg = deg;
        } else if (a == "--json") {
            o.probeJson = true;
        } else if (a == "--exposure") {
            const std::string text(value());
            char* end = nullptr;
            o.exposure = std::strtof(text.c_str(), &end);
            if (end != text.c_str() + text.size() || !(o.exposure > 0.0f) || !std::isfinite(o.exposure))
                throw UsageError("--exposure: '" + text + "' is not a positive number");
        }
        else if (a == "--memory-limit") {
            const std::string text(value());
            char* end = nullptr;
            const double gib = std::strtod(text.c_str(), &end);
            if (end != text.c_str() + text.size() || !(gib > 0.0) || !(gib <= 1048576.0))
                throw UsageError("--memory-limit: '" + text + "' is not a number of GiB in (0, 1048576]");
            o.memoryLimitGiB = gib;
        }
        else if (a == "--stats") o.stats = true;
        else if (a == "--quiet") o.quiet = true;
        else if (a == "--progress") o.progress = Progress::Mode::On;
        else if (cursor.isOption()) throw UsageError("unknown option '" + std::string(a) + "' (see tessera render --help)");
        else if (sceneGiven) throw UsageError("one scene only: '" + o.scene + "' and '" + std::string(a) + "'");
        else {
            o.scene = std::string(a);
            sceneGiven = true;
        }
    }
    if (o.quiet) o.progress = Progress::Mode::Off;
    if (drawByDrawGiven && binnedGiven) throw UsageError("--draw-by-draw and --binned: choose one");
    // One thread has no barrier between draws to save, and a tile that replays every draw of a pass
    // reads set-up triangles and textures that drawing draw by draw keeps in cache: deferred's
    // passes ran 8-15% slower binned at 1 thread (bench/RESULTS.md, "Whole-pass binning"). The bytes
    // are the same either way.
    const unsigned threads = o.device.threads != 0 ? o.device.threads : std::thread::hardware_concurrency();
    if (threads == 1 && !binnedGiven) o.device.binPasses = false;
    // An unknown technique is an error on every scene, the builtin one included.
    if (!o.technique.empty()) requireKnownTechnique("--technique", o.technique);
    if (o.noOutput && o.outGiven) throw UsageError("--no-output and --out: choose one");
    if (o.noOutput && !o.dumpDir.empty()) throw UsageError("--no-output and --dump: choose one");
    if ((!o.dumpAfter.empty() || o.dumpAfterAll) && o.dumpDir.empty()) throw UsageError("--dump-after needs --dump DIR");
    if ((!o.dumpLights.empty() || o.dumpLightsRange) && o.dumpDir.empty()) throw UsageError("--dump-lights needs --dump DIR");
    if (o.probeJson && !o.probe) throw UsageError("--json: only with --probe (the pixel history as JSON)");
    if (o.orbitDeg && (o.cameraPosition || o.cameraTarget))
        throw UsageError("--orbit places the camera itself: give it without --camera-position and --camera-target");
    if (!o.dumpLights.empty() && o.scene == "builtin") throw UsageError("--dump-lights: the builtin scene has no lights to step through");
    const std::string ext = std::filesystem::path(o.out).extension().string();
    if (ext != ".png" && ext != ".exr") throw UsageError("--out: '" + o.out + "' must end in .png or .exr");
    if (!o.options.empty() && o.scene == "builtin")
        throw UsageError("--option: the builtin scene has no technique options (render a scene file to use them)");
    if (o.exrTypeGiven && ext != ".exr") warn("--exr: the output '" + o.out + "' is not .exr; the flag changes nothing");
    if (o.scene == "builtin") {
        if (!o.technique.empty()) warn("--technique: the builtin scene draws with its own shading; the flag changes nothing");
        if (o.lights) warn("--lights: the builtin scene has no light generators; the flag changes nothing");
        if (o.cameraPosition || o.cameraTarget || o.fovDeg || o.orbitDeg)
            warn("--camera-position, --camera-target, --fov, --orbit: the builtin scene has its own camera; the flags change nothing");
    }
    return o;
}

} // namespace tessera::cli
