// The scene file: strict JSON validation into a SceneDescription (every error an InputError
// naming the file and the JSON-pointer key path), camera resolution, and loadScene, which loads
// the glTF models and builds the light list (explicit, glTF, generated, in that order).
#include <tessera/scene/scene_file.h>

#include <tessera/errors/input_error.h>
#include <tessera/io/json_depth.h>
#include <tessera/math/unit_length.h>
#include <tessera/scene/gltf_loader.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <string_view>
#include <system_error>
#include <unordered_set>

namespace tessera {

namespace {

using Json = nlohmann::json;

constexpr std::uint32_t kMaxResolution = 16384;         // texels per side
constexpr std::uint32_t kMaxGeneratedLights = 1000000;  // per generator, and all generators together
constexpr float kDefaultExplicitRange = 100.0f;         // world units; 3dgep Light.h's default Range

const std::vector<std::string> kTopLevelKeys = {
    "$schema", "description", "models", "camera", "resolution", "technique",
    "options", "precision", "lights", "gltfLights", "generate", "shadowCasters"};

// Levenshtein distance, for "did you mean" suggestions.
std::size_t editDistance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            const std::size_t substitution = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitution});
            diagonal = above;
        }
    }
    return row[b.size()];
}

// RFC 6901 escaping of one reference token.
std::string pointerToken(std::string_view key) {
    std::string out;
    for (char c : key) {
        if (c == '~') out += "~0";
        else if (c == '/') out += "~1";
        else out += c;
    }
    return out;
}

std::string typeName(const Json& value) {
    switch (value.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::boolean: return "boolean";
    case Json::value_t::string: return "string";
    case Json::value_t::array: return "array";
    case Json::value_t::object: return "object";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned: return "integer";
    case Json::value_t::number_float: return "number";
    default: return "value";
    }
}

// "[json.exception.parse_error.101] parse error at line 1, ..." -> "parse error at line 1, ...".
std::string withoutExceptionPrefix(std::string what) {
    const std::size_t bracket = what.find("] ");
    if (what.rfind("[json.exception.", 0) == 0 && bracket != std::string::npos) what = what.substr(bracket + 2);
    return what;
}

std::string formatNumber(double v) {
    std::ostringstream out;
    out.precision(9);
    out << v;
    return out.str();
}

// All generators together make at most kMaxGeneratedLights lights: one generator's limit alone
// would let a 2 KB file with a thousand generators ask for 100 GB of lights. Throws InputError
// at the count that takes the sum past the limit.
void checkGeneratedTotal(const std::vector<LightGeneratorSpec>& generators, const std::string& file) {
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < generators.size(); ++i) {
        total += std::uint64_t(generators[i].count) + generators[i].spotCount;
        if (total > kMaxGeneratedLights)
            throw inputError(file, "/generate/" + std::to_string(i) + "/count",
                             "the generators make " + std::to_string(total) + " lights up to this one; all generators together make at most " +
                                 std::to_string(kMaxGeneratedLights));
    }
}

// Validating reader: every check throws inputError(file, path, what).

class Reader {
public:
    explicit Reader(std::string file) : mFile(std::move(file)) {}

    [[noreturn]] void fail(const std::string& path, const std::string& what) const {
        throw inputError(mFile, path, what);
    }

    static std::string at(const std::string& path, std::string_view key) { return path + "/" + pointerToken(key); }
    static std::string at(const std::string& path, std::size_t index) { return path + "/" + std::to_string(index); }

    void requireObject(const Json& value, const std::string& path) const {
        if (!value.is_object()) fail(path, "expected an object, got " + typeName(value));
    }
    void requireArray(const Json& value, const std::string& path) const {
        if (!value.is_array()) fail(path, "expected an array, got " + typeName(value));
    }
    void requireSize(const Json& value, const std::string& path, std::size_t size) const {
        requireArray(value, path);
        if (value.size() != size)
            fail(path, "expected an array of " + std::to_string(size) + " elements, got " + std::to_string(value.size()));
    }

    // Unknown keys are errors; the nearest known key is suggested when it is close.
    void checkKeys(const Json& object, const std::string& path, const std::vector<std::string_view>& allowed) const {
        for (const auto& item : object.items()) {
            const std::string& key = item.key();
            if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
            std::string_view best;
            std::size_t bestDistance = std::numeric_limits<std::size_t>::max();
            for (std::string_view candidate : allowed) {
                const std::size_t d = editDistance(key, candidate);
                if (d < bestDistance) { bestDistance = d; best = candidate; }
            }
            std::string what = "unknown key \"" + key + "\"";
            if (!best.empty() && bestDistance <= std::max<std::size_t>(2, key.size() / 3))
                what += " (did you mean \"" + std::string(best) + "\"?)";
            else {
                what += " (known keys:";
                for (std::string_view candidate : allowed) {
                    what += ' ';  // appended piecewise: GCC 12 -O3 -Wrestrict misfires on " " + string
                    what += candidate;
                }
                what += ")";
            }
            fail(at(path, key), what);
        }
    }
    void requireKey(const Json& object, const std::string& path, std::string_view key) const {
        if (!object.contains(key)) fail(path, "missing required key \"" + std::string(key) + "\"");
    }

    // A finite number that is also finite in binary32 (1e999 parses to inf, 1e39 overflows float).
    float number(const Json& value, const std::string& path) const {
        if (!value.is_number()) fail(path, "expected a number, got " + typeName(value));
        const double v = value.get<double>();
        if (!std::isfinite(v)) fail(path, "the number is not finite");
        // Checked before the conversion: a double beyond the float range converts with undefined behaviour.
        if (std::abs(v) > double(std::numeric_limits<float>::max())) fail(path, formatNumber(v) + " is outside the binary32 range");
        return static_cast<float>(v);
    }
    float numberIn(const Json& value, const std::string& path, float lo, float hi, bool loOpen, bool hiOpen) const {
        const float f = number(value, path);
        const bool belowLo = loOpen ? !(f > lo) : !(f >= lo);
        const bool aboveHi = hiOpen ? !(f < hi) : !(f <= hi);
        if (belowLo || aboveHi)
            fail(path, formatNumber(f) + " is outside " + (loOpen ? "(" : "[") + formatNumber(lo) + ", " +
                           formatNumber(hi) + (hiOpen ? ")" : "]"));
        return f;
    }
    float positive(const Json& value, const std::string& path) const {
        const float f = number(value, path);
        if (f < 0.0f) fail(path, formatNumber(f) + " is negative");
        if (!(f > 0.0f)) fail(path, "0 is not allowed (must be > 0)");
        return f;
    }
    float nonNegative(const Json& value, const std::string& path) const {
        const float f = number(value, path);
        if (f < 0.0f) fail(path, formatNumber(f) + " is negative");
        return f;
    }
    std::uint64_t unsignedInteger(const Json& value, const std::string& path, std::uint64_t lo, std::uint64_t hi) const {
        if (!value.is_number_integer()) fail(path, "expected an integer, got " + typeName(value));
        if (value.is_number_unsigned()) {
            const auto v = value.get<std::uint64_t>();
            if (v < lo || v > hi)
                fail(path, std::to_string(v) + " is outside " + std::to_string(lo) + ".." + std::to_string(hi));
            return v;
        }
        const auto v = value.get<std::int64_t>();
        if (v < 0 || static_cast<std::uint64_t>(v) < lo || static_cast<std::uint64_t>(v) > hi)
            fail(path, std::to_string(v) + " is outside " + std::to_string(lo) + ".." + std::to_string(hi));
        return static_cast<std::uint64_t>(v);
    }
    // "lightGroups": an array of distinct group numbers 0..7 (PR&C D3D11 §11.4.2: one stencil bit
    // each), as a bit mask.
    std::uint8_t lightGroups(const Json& value, const std::string& path) const {
        if (!value.is_array()) fail(path, "expected an array of light groups 0..7, got " + typeName(value));
        std::uint32_t mask = 0;
        for (std::size_t i = 0; i < value.size(); ++i) {
            const std::uint64_t g = unsignedInteger(value[i], path + "/" + std::to_string(i), 0, 7);
            if (mask & (1u << g)) fail(path + "/" + std::to_string(i), "light group " + std::to_string(g) + " is listed twice");
            mask |= 1u << g;
        }
        return static_cast<std::uint8_t>(mask);
    }
    bool boolean(const Json& value, const std::string& path) const {
        if (!value.is_boolean()) fail(path, "expected a boolean, got " + typeName(value));
        return value.get<bool>();
    }
    std::string string(const Json& value, const std::string& path) const {
        if (!value.is_string()) fail(path, "expected a string, got " + typeName(value));
        return value.get<std::string>();
    }
    std::string nonEmptyString(const Json& value, const std::string& path) const {
        std::string s = string(value, path);
        if (s.empty()) fail(path, "the string is empty");
        return s;
    }
    // The common case, three ordinary numbers, builds no element paths ("/lights/7/color/2"): they
    // are made only to name a failing element (a million lights' file builds six million fewer
    // strings). The checks and the values are those of number() and nonNegative().
    static bool plainFloat(const Json& value, float& out) {
        if (!value.is_number()) return false;
        const double v = value.get<double>();
        if (!std::isfinite(v) || std::abs(v) > double(std::numeric_limits<float>::max())) return false;
        out = static_cast<float>(v);
        return true;
    }
    glm::vec3 vec3(const Json& value, const std::string& path) const {
        requireSize(value, path, 3);
        glm::vec3 v;
        if (plainFloat(value[0], v.x) && plainFloat(value[1], v.y) && plainFloat(value[2], v.z)) return v;
        return {number(value[0], at(path, 0)), number(value[1], at(path, 1)), number(value[2], at(path, 2))};
    }
    glm::vec3 colour(const Json& value, const std::string& path) const {
        requireSize(value, path, 3);
        glm::vec3 c;
        if (plainFloat(value[0], c.x) && plainFloat(value[1], c.y) && plainFloat(value[2], c.z) && c.x >= 0.0f &&
            c.y >= 0.0f && c.z >= 0.0f)
            return c;
        return {nonNegative(value[0], at(path, 0)), nonNegative(value[1], at(path, 1)), nonNegative(value[2], at(path, 2))};
    }
    // A nonzero vector, normalized in binary32 (v / sqrt(dot(v, v))).
    glm::vec3 direction(const Json& value, const std::string& path) const {
        const std::optional<glm::vec3> unit = unitLength(vec3(value, path));
        if (!unit) fail(path, "the direction is zero");
        return *unit;
    }
    // [x, y, z, w], nonzero, normalized.
    glm::quat quaternion(const Json& value, const std::string& path) const {
        requireSize(value, path, 4);
        const glm::quat q(number(value[3], at(path, 3)), number(value[0], at(path, 0)), number(value[1], at(path, 1)),
                          number(value[2], at(path, 2)));
        const std::optional<glm::vec4> unit = unitLength(glm::vec4(q.x, q.y, q.z, q.w));
        if (!unit) fail(path, "the quaternion is zero");
        return glm::quat(unit->w, unit->x, unit->y, unit->z);
    }
    // [a, b] with a <= b, each checked by `element`.
    template <class Element>
    glm::vec2 interval(const Json& value, const std::string& path, Element element) const {
        requireSize(value, path, 2);
        const glm::vec2 v{element(value[0], at(path, 0)), element(value[1], at(path, 1))};
        if (v.x > v.y) fail(path, "min " + formatNumber(v.x) + " is greater than max " + formatNumber(v.y));
        return v;
    }

    const std::string& file() const { return mFile; }

private:
    std::string mFile;
};

std::vector<ModelRef> parseModels(const Reader& r, const Json& value, const std::filesystem::path& sceneFile) {
    const std::string path = "/models";
    r.requireArray(value, path);
    if (value.empty()) r.fail(path, "expected at least one model");
    std::vector<ModelRef> models;
    for (std::size_t i = 0; i < value.size(); ++i) {
        const Json& m = value[i];
        const std::string at = Reader::at(path, i);
        r.requireObject(m, at);
        r.checkKeys(m, at, {"path", "translation", "rotation", "scale", "lightGroups"});
        r.requireKey(m, at, "path");
        ModelRef model;
        std::filesystem::path file = r.nonEmptyString(m["path"], Reader::at(at, "path"));
        model.path = file.is_relative() ? (sceneFile.parent_path() / file).lexically_normal() : file;
        glm::vec3 translation{0.0f}, scale{1.0f};
        glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
        if (m.contains("translation")) translation = r.vec3(m["translation"], Reader::at(at, "translation"));
        if (m.contains("rotation")) rotation = r.quaternion(m["rotation"], Reader::at(at, "rotation"));
        if (m.contains("scale")) {
            const Json& s = m["scale"];
            const std::string sp = Reader::at(at, "scale");
            if (s.is_number()) {
                scale = glm::vec3(r.positive(s, sp));
            } else if (s.is_array()) {
                r.requireSize(s, sp, 3);
                scale = {r.positive(s[0], Reader::at(sp, 0)), r.positive(s[1], Reader::at(sp, 1)),
                         r.positive(s[2], Reader::at(sp, 2))};
            } else {
                r.fail(sp, "expected a number or an array of 3 numbers, got " + typeName(s));
            }
        }
        // glTF's node order: T * R * S.
        model.worldFromFile = glm::translate(glm::mat4(1.0f), translation) * glm::mat4_cast(rotation) *
                              glm::scale(glm::mat4(1.0f), scale);
        if (m.contains("lightGroups")) model.lightGroups = r.lightGroups(m["lightGroups"], Reader::at(at, "lightGroups"));
        models.push_back(std::move(model));
    }
    return models;
}

// glTF 2.0 §5.14 camera.perspective.znear "> 0"; the perspective divide by view z and the
// projection's n f / (f - n) need it. Orthographic cameras may take 0 (§5.13 ">= 0").
constexpr const char* kPerspectiveNearZero =
    "0 is not allowed for a perspective camera (near must be > 0; only an orthographic camera may take near 0)";

void parseCamera(const Reader& r, const Json& value, SceneDescription& d) {
    const std::string path = "/camera";
    r.requireObject(value, path);
    r.checkKeys(value, path, {"position", "rotation", "target", "up", "gltf", "fovYDeg", "near", "far"});
    if (value.contains("fovYDeg")) d.cameraFovYDeg = r.numberIn(value["fovYDeg"], "/camera/fovYDeg", 0.0f, 180.0f, true, true);
    // near 0 is kept here: an orthographic camera (from a glTF file) may take it (glTF 2.0
    // §5.13 camera.orthographic.znear ">= 0"); a perspective one is refused where the camera is
    // resolved (resolveCamera) and by checkFrameInputs.
    if (value.contains("near")) d.cameraNearZ = r.nonNegative(value["near"], "/camera/near");
    if (value.contains("far")) d.cameraFarZ = r.positive(value["far"], "/camera/far");
    if (d.cameraNearZ && d.cameraFarZ && !(*d.cameraFarZ > *d.cameraNearZ))
        r.fail("/camera/far", formatNumber(*d.cameraFarZ) + " is not greater than near " + formatNumber(*d.cameraNearZ));

    const bool hasPosition = value.contains("position"), hasRotation = value.contains("rotation");
    const bool hasTarget = value.contains("target"), hasUp = value.contains("up");
    if (value.contains("gltf")) {
        for (std::string_view key : {"position", "rotation", "target", "up"})
            if (value.contains(key)) r.fail(Reader::at(path, key), "not allowed together with \"gltf\"");
        d.gltfCameraIndex = static_cast<int>(r.unsignedInteger(value["gltf"], "/camera/gltf", 0, 1u << 20));
        d.cameraFromGltf = true;
        d.cameraSource = CameraSource::Gltf;
        return;
    }
    if (!hasPosition) {
        for (std::string_view key : {"rotation", "target", "up"})
            if (value.contains(key)) r.fail(Reader::at(path, key), "needs \"position\"");
        d.cameraSource = CameraSource::Framing;
        return;
    }
    Camera camera;
    camera.positionWorld = r.vec3(value["position"], "/camera/position");
    if (hasRotation && (hasTarget || hasUp))
        r.fail(hasTarget ? "/camera/target" : "/camera/up", "give either \"rotation\" or \"target\" (+ \"up\"), not both");
    if (hasRotation) {
        camera.orientationWorld = r.quaternion(value["rotation"], "/camera/rotation");
    } else if (hasTarget) {
        const glm::vec3 target = r.vec3(value["target"], "/camera/target");
        const glm::vec3 up = hasUp ? r.direction(value["up"], "/camera/up") : glm::vec3(0.0f, 1.0f, 0.0f);
        const LookAt look = lookAtOrientation(camera.positionWorld, target, up);
        if (look.problem == LookAt::Problem::UpParallel) r.fail(hasUp ? "/camera/up" : "/camera/target", look.why());
        if (look.problem != LookAt::Problem::None) r.fail("/camera/target", look.why());
        camera.orientationWorld = look.orientationWorld;
    } else {
        r.fail(path, "\"position\" needs \"rotation\" or \"target\"");
    }
    if (d.cameraFovYDeg) camera.fovYDeg = *d.cameraFovYDeg;
    if (d.cameraNearZ) camera.nearZ = *d.cameraNearZ;
    if (d.cameraFarZ) camera.farZ = *d.cameraFarZ;
    if (!(camera.nearZ > 0.0f)) r.fail("/camera/near", kPerspectiveNearZero);
    if (!(camera.farZ > camera.nearZ))
        r.fail(d.cameraFarZ ? "/camera/far" : "/camera/near", "far " + formatNumber(camera.farZ) +
                                                                  " is not greater than near " + formatNumber(camera.nearZ));
    d.camera = camera;
    d.cameraSource = CameraSource::Explicit;
}

Light parseLight(const Reader& r, const Json& value, const std::string& path) {
    r.requireObject(value, path);
    r.checkKeys(value, path,
                {"type", "name", "position", "direction", "color", "intensity", "range", "spotAngleDeg", "length", "enabled",
                 "lightGroups", "indirect"});
    r.requireKey(value, path, "type");
    const std::string type = r.string(value["type"], Reader::at(path, "type"));
    Light light;
    if (type == "point") light.type = LightType::Point;
    else if (type == "spot") light.type = LightType::Spot;
    else if (type == "directional") light.type = LightType::Directional;
    else if (type == "capsule") light.type = LightType::Capsule;
    else r.fail(Reader::at(path, "type"), "unknown light type \"" + type + "\" (point, spot, directional, capsule)");

    const bool positional = light.type != LightType::Directional;
    const bool directed = light.type != LightType::Point;
    auto notFor = [&](std::string_view key) {
        if (value.contains(key)) r.fail(Reader::at(path, key), "not used by a " + type + " light");
    };
    if (positional) {
        r.requireKey(value, path, "position");
        light.positionWorld = r.vec3(value["position"], Reader::at(path, "position"));
        light.range = value.contains("range") ? r.positive(value["range"], Reader::at(path, "range")) : kDefaultExplicitRange;
    } else {
        notFor("position");
        notFor("range");
    }
    if (directed) {
        r.requireKey(value, path, "direction");
        light.directionWorld = r.direction(value["direction"], Reader::at(path, "direction"));
    } else {
        notFor("direction");
    }
    if (light.type == LightType::Spot) {
        if (value.contains("spotAngleDeg"))
            light.spotHalfAngleDeg = r.numberIn(value["spotAngleDeg"], Reader::at(path, "spotAngleDeg"), 0.0f, 90.0f, true, true);
    } else {
        notFor("spotAngleDeg");
    }
    if (light.type == LightType::Capsule) {  // the segment from "position" along "direction"
        r.requireKey(value, path, "length");
        light.length = r.positive(value["length"], Reader::at(path, "length"));
    } else {
        notFor("length");
    }
    if (value.contains("color")) light.color = r.colour(value["color"], Reader::at(path, "color"));
    if (value.contains("intensity")) light.intensity = r.nonNegative(value["intensity"], Reader::at(path, "intensity"));
    if (value.contains("enabled")) light.enabled = r.boolean(value["enabled"], Reader::at(path, "enabled"));
    if (value.contains("lightGroups")) light.lightGroups = r.lightGroups(value["lightGroups"], Reader::at(path, "lightGroups"));
    if (value.contains("name")) light.name = r.string(value["name"], Reader::at(path, "name"));
    if (value.contains("indirect")) {
        light.indirect = r.boolean(value["indirect"], Reader::at(path, "indirect"));
        if (light.indirect && light.type != LightType::Spot && light.type != LightType::Directional)
            r.fail(Reader::at(path, "indirect"), "a " + type + " light cannot be indirect: the reflective shadow map needs a spot or directional light");
    }
    return light;
}

// A generator's "box": {"min": [x, y, z], "max": [x, y, z]}, min <= max per axis.
Bounds parseBox(const Reader& r, const Json& box, const std::string& bp) {
    r.requireObject(box, bp);
    r.checkKeys(box, bp, {"min", "max"});
    r.requireKey(box, bp, "min");
    r.requireKey(box, bp, "max");
    Bounds bounds;
    bounds.minWorld = r.vec3(box["min"], Reader::at(bp, "min"));
    bounds.maxWorld = r.vec3(box["max"], Reader::at(bp, "max"));
    for (glm::length_t axis = 0; axis < 3; ++axis)
        if (bounds.minWorld[axis] > bounds.maxWorld[axis])
            r.fail(Reader::at(Reader::at(bp, "min"), static_cast<std::size_t>(axis)),
                   "min " + formatNumber(bounds.minWorld[axis]) + " is greater than max " + formatNumber(bounds.maxWorld[axis]));
    return bounds;
}

LightGeneratorSpec parseGenerator(const Reader& r, const Json& value, const std::string& path) {
    r.requireObject(value, path);
    LightGeneratorSpec spec;
    if (value.contains("kind")) {
        const std::string kind = r.string(value["kind"], Reader::at(path, "kind"));
        if (kind == "amd-forwardplus11") spec.kind = LightGeneratorKind::AmdForwardPlus11;
        else if (kind != "uniform")
            r.fail(Reader::at(path, "kind"), "unknown generator kind \"" + kind + "\" (uniform, amd-forwardplus11)");
    }
    if (spec.kind == LightGeneratorKind::AmdForwardPlus11) {
        for (std::string_view key : {"seed", "pointFraction", "range", "spotAngleDeg", "intensity", "colorMin", "colorMax"})
            if (value.contains(key))
                r.fail(Reader::at(path, key), "\"" + std::string(key) +
                                                  "\" does not apply to kind amd-forwardplus11 (the demo fixes it; its keys: kind, "
                                                  "count, spotCount, box, argumentOrder)");
        r.checkKeys(value, path, {"kind", "count", "spotCount", "box", "argumentOrder"});
        r.requireKey(value, path, "count");
        spec.count = static_cast<std::uint32_t>(
            r.unsignedInteger(value["count"], Reader::at(path, "count"), 0, kAmdForwardPlus11MaxLights));
        if (value.contains("spotCount"))
            spec.spotCount = static_cast<std::uint32_t>(
                r.unsignedInteger(value["spotCount"], Reader::at(path, "spotCount"), 0, kAmdForwardPlus11MaxLights));
        if (value.contains("argumentOrder")) {
            const std::string order = r.string(value["argumentOrder"], Reader::at(path, "argumentOrder"));
            if (order == "left-to-right") spec.argumentOrder = CallArgumentOrder::LeftToRight;
            else if (order != "right-to-left")
                r.fail(Reader::at(path, "argumentOrder"), "unknown argument order \"" + order + "\" (right-to-left, left-to-right)");
        }
        if (value.contains("box")) spec.box = parseBox(r, value["box"], Reader::at(path, "box"));
        return spec;
    }
    for (std::string_view key : {"spotCount", "argumentOrder"})
        if (value.contains(key)) r.fail(Reader::at(path, key), "applies to kind amd-forwardplus11 only, not uniform");
    r.checkKeys(value, path,
                {"kind", "count", "seed", "pointFraction", "box", "range", "spotAngleDeg", "intensity", "colorMin", "colorMax"});
    r.requireKey(value, path, "count");
    spec.count = static_cast<std::uint32_t>(r.unsignedInteger(value["count"], Reader::at(path, "count"), 0, kMaxGeneratedLights));
    if (value.contains("seed"))
        spec.seed = r.unsignedInteger(value["seed"], Reader::at(path, "seed"), 0, std::numeric_limits<std::uint64_t>::max());
    if (value.contains("pointFraction"))
        spec.pointFraction = r.numberIn(value["pointFraction"], Reader::at(path, "pointFraction"), 0.0f, 1.0f, false, false);
    if (value.contains("box")) spec.box = parseBox(r, value["box"], Reader::at(path, "box"));
    if (value.contains("range"))
        spec.range = r.interval(value["range"], Reader::at(path, "range"),
                                [&](const Json& v, const std::string& p) { return r.positive(v, p); });
    if (value.contains("spotAngleDeg"))
        spec.spotHalfAngleDeg = r.interval(value["spotAngleDeg"], Reader::at(path, "spotAngleDeg"), [&](const Json& v, const std::string& p) {
            return r.numberIn(v, p, 0.0f, 90.0f, true, true);
        });
    if (value.contains("intensity"))
        spec.intensity = r.interval(value["intensity"], Reader::at(path, "intensity"),
                                    [&](const Json& v, const std::string& p) { return r.nonNegative(v, p); });
    if (value.contains("colorMin")) spec.colorMin = r.colour(value["colorMin"], Reader::at(path, "colorMin"));
    if (value.contains("colorMax")) spec.colorMax = r.colour(value["colorMax"], Reader::at(path, "colorMax"));
    for (glm::length_t c = 0; c < 3; ++c)
        if (spec.colorMin[c] > spec.colorMax[c])
            r.fail(Reader::at(Reader::at(path, "colorMin"), static_cast<std::size_t>(c)),
                   "min " + formatNumber(spec.colorMin[c]) + " is greater than colorMax's " + formatNumber(spec.colorMax[c]));
    return spec;
}

} // namespace

namespace {

// Duplicate keys: RFC 8259 §4 says names within an object SHOULD be unique and leaves the
// meaning open; nlohmann keeps the last one, so a scene file's earlier value would be dropped in
// silence. This SAX handler builds the document as Json::parse does and refuses a repeated key,
// naming its JSON pointer, in the same single pass over the text. (Not Json::parse's callback:
// nlohmann 3.11's callback parser scans the whole parent container for a discarded value after
// every object it closes (json_sax_dom_callback_parser::end_object), quadratic in an array of
// objects, 14 s for 270,000 lights; and not a second SAX pass ahead of the parse: that
// tokenized a million-light file twice.) A syntax error throws Json::parse_error, as
// Json::parse does.
//
// Streaming: the elements of the root object's array under `streamedKey` ("lights": a million
// light objects would otherwise each stay in the document as a std::map of strings) are handed to
// `onElement(index, element)` as each one is complete, and dropped: that array ends up empty.
class CheckedDomBuilder : public nlohmann::json_sax<Json> {
public:
    using ElementFn = std::function<void(std::size_t, const Json&)>;
    CheckedDomBuilder(const Reader& reader, Json& root, std::string_view streamedKey = {}, ElementFn onElement = {})
        : mReader(reader), mRoot(root), mStreamedKey(streamedKey), mOnElement(std::move(onElement)) {}

    bool null() override { return value(Json(nullptr)); }
    bool boolean(bool v) override { return value(Json(v)); }
    bool number_integer(number_integer_t v) override { return value(Json(v)); }
    bool number_unsigned(number_unsigned_t v) override { return value(Json(v)); }
    bool number_float(number_float_t v, const string_t&) override { return value(Json(v)); }
    bool string(string_t& v) override { return value(Json(std::move(v))); }
    bool binary(binary_t& v) override { return value(Json::binary(std::move(v))); }
    bool start_object(std::size_t) override { return open(Json::object(), true); }
    bool key(string_t& name) override {
        Level& top = mStack[mDepth - 1];
        bool repeated = false;
        if (top.many.empty()) {
            repeated = std::find(top.keys.begin(), top.keys.end(), name) != top.keys.end();
            if (!repeated) top.keys.push_back(name);
            if (top.keys.size() > kLinearKeys) top.many.insert(top.keys.begin(), top.keys.end());
        } else {
            repeated = !top.many.insert(name).second;
        }
        if (repeated)
            mReader.fail(Reader::at(pointer(), name), "duplicate key \"" + name + "\" (an earlier value would be silently replaced)");
        top.key = name;
        return true;
    }
    bool end_object() override { return close(); }
    bool start_array(std::size_t) override { return open(Json::array(), false); }
    bool end_array() override { return close(); }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
        // The parser hands over a parse_error (syntax) or an out_of_range (a number beyond
        // binary64); rethrown as the concrete type, as Json::parse throws it.
        if (const auto* syntax = dynamic_cast<const Json::parse_error*>(&e)) throw *syntax;
        if (const auto* range = dynamic_cast<const Json::out_of_range*>(&e)) throw *range;
        throw e;
    }

private:
    // Objects with up to kLinearKeys keys (every light, model and camera) are checked by a
    // linear search, larger ones (an "options" object with thousands of keys) through a hash
    // set: linear in the text either way.
    static constexpr std::size_t kLinearKeys = 16;
    struct Level {
        Json* container = nullptr;            // the object or array being filled
        bool object = false;
        std::size_t index = 0;                // arrays: the index of the element being read
        std::string key;                      // objects: the key being read
        std::vector<std::string> keys;        // objects: keys seen so far (up to kLinearKeys)
        std::unordered_set<std::string> many; // objects: keys seen so far, beyond kLinearKeys
    };
    // Stores v where the parser stands (the root, the open array's next element or the open
    // object's current key) and returns its place.
    Json* place(Json&& v) {
        if (mDepth == 0) {
            mRoot = std::move(v);
            return &mRoot;
        }
        Level& top = mStack[mDepth - 1];
        if (top.object) return &((*top.container)[top.key] = std::move(v));
        ++top.index;
        top.container->push_back(std::move(v));
        return &top.container->back();
    }
    bool value(Json&& v) {
        place(std::move(v));
        elementDone();
        return true;
    }
    // After an element of the innermost open container is complete: a streamed array's element
    // goes to mOnElement and leaves the document.
    void elementDone() {
        if (!mOnElement || mDepth != 2 || !mStack[0].object || mStack[1].object || mStack[0].key != mStreamedKey) return;
        Level& array = mStack[1];
        mOnElement(array.index - 1, array.container->back());
        array.container->get_ref<Json::array_t&>().pop_back();
    }
    // Levels are reused as the parser enters and leaves containers, so a file of a million light
    // objects allocates a handful of times, not per object; the JSON pointer is built only for
    // the error message (pointer()). A container's place stays valid while it is open: only the
    // innermost open container grows.
    bool open(Json&& empty, bool object) {
        Json* container = place(std::move(empty));
        if (mDepth == mStack.size()) mStack.emplace_back();
        Level& level = mStack[mDepth++];
        level.container = container;
        level.object = object;
        level.index = 0;
        level.keys.clear();
        if (!level.many.empty()) level.many = {};  // not clear(): that walks every bucket of a once-large set
        return true;
    }
    bool close() {
        --mDepth;
        elementDone();
        return true;
    }
    // The JSON pointer of the innermost open container.
    std::string pointer() const {
        std::string path;
        for (std::size_t i = 0; i + 1 < mDepth; ++i)
            path = mStack[i].object ? Reader::at(path, mStack[i].key) : Reader::at(path, mStack[i].index - 1);
        return path;
    }
    std::size_t mDepth = 0;
    const Reader& mReader;
    Json& mRoot;
    std::string_view mStreamedKey;
    ElementFn mOnElement;
    std::vector<Level> mStack;
};

} // namespace

const std::vector<std::string>& sceneFileTopLevelKeys() { return kTopLevelKeys; }

SceneDescription parseSceneJson(const std::string& text, const std::filesystem::path& file) {
    const Reader r(file.string());
    // Before any parse: a recursive copy of a deep "options" value would overflow the stack.
    checkJsonDepth(text, file.string());
    Json root;
    // "lights" are parsed as the text streams by (CheckedDomBuilder), each light's first error kept
    // and raised where the lights are read below, so errors keep their order: syntax first, then
    // the keys in the order this function reads them.
    std::vector<Light> streamedLights;
    std::exception_ptr lightError;
    const auto onLight = [&](std::size_t index, const Json& element) {
        if (lightError) return;
        try {
            streamedLights.push_back(parseLight(r, element, Reader::at("/lights", index)));
        } catch (...) {
            lightError = std::current_exception();
        }
    };
    try {
        CheckedDomBuilder builder(r, root, "lights", onLight);
        (void)Json::sax_parse(text, &builder);  // throws InputError on a repeated key, Json's exceptions on bad syntax
    } catch (const Json::parse_error& e) {
        r.fail("", "invalid JSON (byte " + std::to_string(e.byte) + "): " + withoutExceptionPrefix(e.what()));
    } catch (const Json::exception& e) {
        // out_of_range 406, "number overflow parsing '1e999'": nlohmann names the token, not
        // its position, so the first occurrence of the token gives the line and column.
        const std::string what = withoutExceptionPrefix(e.what());
        std::string where;
        const std::size_t open = what.find('\''), close = what.rfind('\'');
        if (open != std::string::npos && close > open + 1) {
            const std::size_t at = text.find(what.substr(open + 1, close - open - 1));
            if (at != std::string::npos) {
                const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
                const std::size_t lineStart = text.rfind('\n', at == 0 ? 0 : at - 1);
                const std::size_t column = lineStart == std::string::npos || at == 0 ? at + 1 : at - lineStart;
                where = " at line " + std::to_string(line) + ", column " + std::to_string(column);
            }
        }
        r.fail("", "invalid JSON" + where + ": " + what + " (numbers must be finite)");
    }
    r.requireObject(root, "");
    r.checkKeys(root, "", std::vector<std::string_view>(kTopLevelKeys.begin(), kTopLevelKeys.end()));
    SceneDescription d;
    d.file = file;
    if (root.contains("$schema")) r.string(root["$schema"], "/$schema");
    if (root.contains("description")) r.string(root["description"], "/description");
    r.requireKey(root, "", "models");
    d.models = parseModels(r, root["models"], file);
    if (root.contains("camera")) parseCamera(r, root["camera"], d);
    if (root.contains("resolution")) {
        const Json& res = root["resolution"];
        r.requireSize(res, "/resolution", 2);
        d.width = static_cast<std::uint32_t>(r.unsignedInteger(res[0], "/resolution/0", 1, kMaxResolution));
        d.height = static_cast<std::uint32_t>(r.unsignedInteger(res[1], "/resolution/1", 1, kMaxResolution));
    }
    if (root.contains("technique")) d.technique = r.nonEmptyString(root["technique"], "/technique");
    if (root.contains("options")) {
        r.requireObject(root["options"], "/options");
        d.techniqueOptions = root["options"];
    }
    if (root.contains("precision")) {
        const std::string name = r.string(root["precision"], "/precision");
        const auto precision = parsePrecision(name);
        if (!precision) r.fail("/precision", "unknown precision \"" + name + "\" (reference, exact, fast)");
        d.precision = *precision;
    }
    if (root.contains("lights")) {
        r.requireArray(root["lights"], "/lights");  // its elements were parsed as they streamed by
        if (lightError) std::rethrow_exception(lightError);
        d.explicitLights = std::move(streamedLights);
    }
    if (root.contains("gltfLights")) {
        const Json& g = root["gltfLights"];
        r.requireObject(g, "/gltfLights");
        r.checkKeys(g, "/gltfLights", {"enabled", "defaultRange"});
        d.useGltfLights = g.contains("enabled") ? r.boolean(g["enabled"], "/gltfLights/enabled") : true;
        if (g.contains("defaultRange")) d.gltfLightDefaultRange = r.nonNegative(g["defaultRange"], "/gltfLights/defaultRange");
    }
    if (root.contains("generate")) {
        const Json& generators = root["generate"];
        r.requireArray(generators, "/generate");
        for (std::size_t i = 0; i < generators.size(); ++i)
            d.generators.push_back(parseGenerator(r, generators[i], Reader::at("/generate", i)));
        checkGeneratedTotal(d.generators, r.file());
    }
    std::size_t indirectLights = 0;
    for (std::size_t i = 0; i < d.explicitLights.size(); ++i)
        if (d.explicitLights[i].indirect && ++indirectLights > 1)
            r.fail(Reader::at(Reader::at("/lights", i), "indirect"), "only one light may be indirect (one reflective shadow map per frame)");
    if (root.contains("shadowCasters")) {
        const Json& casters = root["shadowCasters"];
        if (casters.is_string()) {
            const std::string word = r.string(casters, "/shadowCasters");
            if (word == "all") d.shadowCasters = SceneDescription::ShadowCasters::All;
            else if (word == "none") d.shadowCasters = SceneDescription::ShadowCasters::None;
            else r.fail("/shadowCasters", "\"" + word + "\" is not \"all\", \"none\" or a list of light indices");
        } else {
            r.requireArray(casters, "/shadowCasters");
            d.shadowCasters = SceneDescription::ShadowCasters::List;
            for (std::size_t i = 0; i < casters.size(); ++i)
                d.shadowCasterIndices.push_back(static_cast<std::uint32_t>(
                    r.unsignedInteger(casters[i], Reader::at("/shadowCasters", i), 0, std::numeric_limits<std::uint32_t>::max())));
        }
    }
    return d;
}

SceneDescription parseSceneFile(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        std::error_code ec;
        const bool exists = std::filesystem::exists(file, ec);
        throw inputError(file.string(), "", exists ? "cannot be read" : "no such file");
    }
    // A regular file is read in one piece into a string sized from its length (streaming through
    // an ostringstream grew and copied its buffer, then copied it once more: a second of a 145 MB
    // file of 1,000,000 lights); anything else (a pipe, a directory) streams.
    std::string text;
    std::error_code ec;
    const std::uintmax_t length = std::filesystem::is_regular_file(file, ec) ? std::filesystem::file_size(file, ec) : 0;
    if (!ec && length > 0 && length < std::uintmax_t(PTRDIFF_MAX)) {
        text.resize(static_cast<std::size_t>(length));
        in.read(text.data(), static_cast<std::streamsize>(length));
        if (std::uintmax_t(in.gcount()) != length) throw inputError(file.string(), "", "read error");
    } else {
        std::ostringstream streamed;
        streamed << in.rdbuf();
        if (in.bad()) throw inputError(file.string(), "", "read error");
        text = std::move(streamed).str();
    }
    return parseSceneJson(text, file);
}

Camera resolveCamera(const SceneDescription& d, const Scene& scene) {
    Camera camera;
    CameraSource source = d.cameraSource;
    if (source == CameraSource::Explicit) return d.camera;
    if (source == CameraSource::Auto) source = scene.cameras.empty() ? CameraSource::Framing : CameraSource::Gltf;
    if (source == CameraSource::Gltf) {
        const int index = d.cameraSource == CameraSource::Gltf ? d.gltfCameraIndex : 0;
        if (index < 0 || static_cast<std::size_t>(index) >= scene.cameras.size())
            throw inputError(d.file.string(), "/camera/gltf",
                             "glTF camera " + std::to_string(index) + " does not exist (the models have " +
                                 std::to_string(scene.cameras.size()) + ")");
        camera = scene.cameras[static_cast<std::size_t>(index)];
    } else {
        // Framing: look down -Z at the bounds' centre from a distance at which the bounding
        // sphere fits the narrower of the vertical and horizontal fields of view:
        // distance = radius / sin(halfAngle), tan(halfX) = tan(halfY) * aspect. The trigonometry
        // runs in double (glibc's correctly rounded sin/tan/atan) and is rounded once to float.
        camera.name = "framing";
        const float fovYDeg = d.cameraFovYDeg.value_or(camera.fovYDeg);
        camera.fovYDeg = fovYDeg;
        const Bounds bounds = scene.bounds();
        if (!bounds.empty()) {
            const glm::vec3 centre = (bounds.minWorld + bounds.maxWorld) * 0.5f;
            const glm::vec3 extent = bounds.maxWorld - bounds.minWorld;
            const double radius = 0.5 * std::sqrt(double(extent.x) * extent.x + double(extent.y) * extent.y +
                                                  double(extent.z) * extent.z);
            const double aspect = double(d.width) / double(d.height);
            const double halfY = double(fovYDeg) * (3.14159265358979323846 / 360.0);
            const double halfX = std::atan(std::tan(halfY) * aspect);
            const double half = std::min(halfX, halfY);
            const double distance = radius > 0.0 ? radius / std::sin(half) : 1.0;
            camera.positionWorld = centre + glm::vec3(0.0f, 0.0f, static_cast<float>(distance));
            camera.nearZ = static_cast<float>(std::min(0.1, 0.5 * (distance - radius)));
            if (!(camera.nearZ > 0.0f)) camera.nearZ = 0.1f;
            camera.farZ = static_cast<float>(std::max(1000.0, 2.0 * (distance + radius)));
        }
    }
    if (d.cameraFovYDeg) camera.fovYDeg = *d.cameraFovYDeg;
    if (d.cameraNearZ) camera.nearZ = *d.cameraNearZ;
    if (d.cameraFarZ) camera.farZ = *d.cameraFarZ;
    if (camera.projection == ProjectionKind::Perspective && !(camera.nearZ > 0.0f))
        throw inputError(d.file.string(), "/camera/near", kPerspectiveNearZero);
    if (!(camera.farZ > camera.nearZ))
        throw inputError(d.file.string(), d.cameraFarZ ? "/camera/far" : "/camera/near",
                         "far " + formatNumber(camera.farZ) + " is not greater than near " + formatNumber(camera.nearZ));
    return camera;
}

Scene loadScene(const SceneDescription& d, bool loadImages, Camera* cameraOut) {
    const std::string file = d.file.string();
    Scene scene;
    for (std::size_t i = 0; i < d.models.size(); ++i) {
        const ModelRef& model = d.models[i];
        std::error_code ec;
        if (!std::filesystem::is_regular_file(model.path, ec))
            throw inputError(file, "/models/" + std::to_string(i) + "/path", "model file not found: " + model.path.string());
        GltfLoadOptions options;
        options.loadImages = loadImages;
        options.worldFromFile = model.worldFromFile;
        options.lightGroups = model.lightGroups;
        options.generatedBitangentUp = d.generatedBitangentUp;
        loadGltf(model.path, scene, options);
    }

    // Lights: explicit, then the glTFs' own (loadGltf appended them), then generated.
    std::vector<Light> gltfLights = std::move(scene.lights);
    scene.lights = d.explicitLights;
    if (d.useGltfLights) {
        for (Light& light : gltfLights) {
            if (light.type != LightType::Directional && std::isinf(light.range) && d.gltfLightDefaultRange > 0.0f)
                light.range = d.gltfLightDefaultRange;
            scene.lights.push_back(std::move(light));
        }
    } else {
        scene.gltfLightsNotUsed = gltfLights.size();
    }
    checkGeneratedTotal(d.generators, file);  // again: the counts may have been changed since (--lights)
    Bounds bounds;
    bool boundsKnown = false;
    for (std::size_t i = 0; i < d.generators.size(); ++i) {
        const LightGeneratorSpec& spec = d.generators[i];
        if (!spec.box && !boundsKnown) {
            bounds = scene.bounds();
            boundsKnown = true;
        }
        if (!spec.box && bounds.empty())
            throw inputError(file, "/generate/" + std::to_string(i), "the scene has no geometry to place lights in; give a \"box\"");
        if (spec.kind == LightGeneratorKind::AmdForwardPlus11 && spec.count > kAmdForwardPlus11MaxLights)  // e.g. from --lights
            throw inputError(file, "/generate/" + std::to_string(i) + "/count",
                             std::to_string(spec.count) + " point lights; AMD ForwardPlus11 has at most " +
                                 std::to_string(kAmdForwardPlus11MaxLights) + " (MAX_NUM_LIGHTS)");
        std::vector<Light> generated = generateLights(spec, bounds);
        scene.lights.insert(scene.lights.end(), generated.begin(), generated.end());
    }
    if (d.shadowCasters == SceneDescription::ShadowCasters::All) {
        for (Light& light : scene.lights) light.castsShadows = true;
    } else if (d.shadowCasters == SceneDescription::ShadowCasters::List) {
        for (std::size_t i = 0; i < d.shadowCasterIndices.size(); ++i) {
            const std::uint32_t index = d.shadowCasterIndices[i];
            if (index >= scene.lights.size())
                throw inputError(file, "/shadowCasters/" + std::to_string(i),
                                 "light " + std::to_string(index) + " does not exist (the scene has " +
                                     std::to_string(scene.lights.size()) + " lights: explicit, glTF, generated)");
            scene.lights[index].castsShadows = true;
        }
    }
    if (cameraOut) *cameraOut = resolveCamera(d, scene);
    return scene;
}

} // namespace tessera
