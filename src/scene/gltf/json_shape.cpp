// The JSON shape checks run on a glTF document before tinygltf parses it: the type of every
// property the loader reads, the asset version, and "extensions" / "name" everywhere.
// "§" numbers cite the glTF 2.0 specification.
#include "json_shape.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include <tessera/errors/input_error.h>

#include "paths.h"

namespace tessera::gltf_detail {
namespace {

// The JSON types of the properties this loader reads (glTF 2.0 JSON schema, §5), checked before
// tinygltf parses the file: tinygltf silently replaces a mistyped value by its default (an
// object for an array of primitives, "-1" for a texture index), which would load a wrong scene.
class JsonShapeChecker {
public:
    using Json = nlohmann::json;
    explicit JsonShapeChecker(const std::string& file) : mFile(file) {}

    void check(const Json& root) {
        if (!root.is_object()) fail("", "the JSON root is not an object");
        assetVersion(root);
        strings(root, "extensionsUsed", "");
        strings(root, "extensionsRequired", "");
        uint(root, "scene", "");
        extensionsEverywhere(root, "");
        objects(root, "accessors", "", [&](const Json& a, const std::string& at) {
            uints(a, at, {"bufferView", "byteOffset", "componentType", "count"});
            boolean(a, "normalized", at);
            string(a, "type", at);
            numbers(a, "min", at, 0);
            numbers(a, "max", at, 0);
            if (const Json* sparse = object(a, "sparse", at)) {
                const std::string sparseAt = at + "/sparse";
                uint(*sparse, "count", sparseAt);
                if (const Json* indices = object(*sparse, "indices", sparseAt)) {
                    uints(*indices, sparseAt + "/indices", {"bufferView", "byteOffset", "componentType"});
                }
                if (const Json* values = object(*sparse, "values", sparseAt)) {
                    uints(*values, sparseAt + "/values", {"bufferView", "byteOffset"});
                }
            }
        });
        objects(root, "bufferViews", "", [&](const Json& v, const std::string& at) {
            uints(v, at, {"buffer", "byteOffset", "byteLength", "byteStride", "target"});
        });
        objects(root, "buffers", "", [&](const Json& b, const std::string& at) {
            string(b, "uri", at);
            uint(b, "byteLength", at);
        });
        objects(root, "cameras", "", [&](const Json& c, const std::string& at) {
            string(c, "type", at);
            for (const char* kind : {"perspective", "orthographic"}) {
                if (const Json* projection = object(c, kind, at)) {
                    for (const char* key : {"aspectRatio", "yfov", "zfar", "znear", "xmag", "ymag"}) {
                        number(*projection, key, at + "/" + kind);
                    }
                }
            }
        });
        objects(root, "images", "", [&](const Json& i, const std::string& at) {
            string(i, "uri", at);
            string(i, "mimeType", at);
            uint(i, "bufferView", at);
        });
        objects(root, "materials", "", [&](const Json& m, const std::string& at) {
            if (const Json* pbr = object(m, "pbrMetallicRoughness", at)) {
                const std::string pbrAt = at + "/pbrMetallicRoughness";
                numbers(*pbr, "baseColorFactor", pbrAt, 4);
                number(*pbr, "metallicFactor", pbrAt);
                number(*pbr, "roughnessFactor", pbrAt);
                textureInfo(*pbr, "baseColorTexture", pbrAt);
                textureInfo(*pbr, "metallicRoughnessTexture", pbrAt);
            }
            textureInfo(m, "normalTexture", at, "scale");
            textureInfo(m, "occlusionTexture", at, "strength");
            textureInfo(m, "emissiveTexture", at);
            numbers(m, "emissiveFactor", at, 3);
            string(m, "alphaMode", at);
            number(m, "alphaCutoff", at);
            boolean(m, "doubleSided", at);
        });
        objects(root, "meshes", "", [&](const Json& mesh, const std::string& at) {
            if (!mesh.contains("primitives")) fail(at + "/primitives", "is missing");
            objects(mesh, "primitives", at, [&](const Json& p, const std::string& primitiveAt) {
                const Json* attributes = object(p, "attributes", primitiveAt);
                if (!attributes) fail(primitiveAt + "/attributes", "is missing");
                for (const auto& [semantic, value] : attributes->items()) {
                    uint(*attributes, semantic.c_str(), primitiveAt + "/attributes");
                }
                uints(p, primitiveAt, {"indices", "material", "mode"});
            });
            numbers(mesh, "weights", at, 0);
        });
        objects(root, "nodes", "", [&](const Json& n, const std::string& at) {
            uints(n, at, {"camera", "skin", "mesh"});
            if (const Json* children = member(n, "children")) {
                if (!children->is_array()) fail(at + "/children", "must be an array");
                for (std::size_t i = 0; i < children->size(); ++i) {
                    if (!isUint((*children)[i])) fail(indexPath(at + "/children", i), "must be a non-negative integer");
                }
            }
            numbers(n, "matrix", at, 16);
            numbers(n, "rotation", at, 4);
            numbers(n, "scale", at, 3);
            numbers(n, "translation", at, 3);
            if (const Json* extensions = member(n, "extensions")) {
                if (const Json* light = member(*extensions, "KHR_lights_punctual")) {
                    uint(*light, "light", at + "/extensions/KHR_lights_punctual");
                }
            }
        });
        objects(root, "samplers", "", [&](const Json& sampler, const std::string& at) {
            uints(sampler, at, {"magFilter", "minFilter", "wrapS", "wrapT"});
        });
        objects(root, "scenes", "", [&](const Json& scene, const std::string& at) {
            if (const Json* nodes = member(scene, "nodes")) {
                if (!nodes->is_array()) fail(at + "/nodes", "must be an array");
                for (std::size_t i = 0; i < nodes->size(); ++i) {
                    if (!isUint((*nodes)[i])) fail(indexPath(at + "/nodes", i), "must be a non-negative integer");
                }
            }
        });
        objects(root, "textures", "", [&](const Json& t, const std::string& at) { uints(t, at, {"sampler", "source"}); });
        if (const Json* extensions = member(root, "extensions")) {
            if (const Json* lights = member(*extensions, "KHR_lights_punctual")) {
                const std::string at = "/extensions/KHR_lights_punctual";
                objects(*lights, "lights", at, [&](const Json& l, const std::string& lightAt) {
                    string(l, "type", lightAt);
                    numbers(l, "color", lightAt, 3);
                    number(l, "intensity", lightAt);
                    number(l, "range", lightAt);
                    if (const Json* spot = object(l, "spot", lightAt)) {
                        number(*spot, "innerConeAngle", lightAt + "/spot");
                        number(*spot, "outerConeAngle", lightAt + "/spot");
                    }
                });
            }
        }
    }

private:
    [[noreturn]] void fail(const std::string& keyPath, const std::string& what) const {
        throw inputError(mFile, keyPath, what);
    }
    // "<major>.<minor>" (§3.2: the pattern ^[0-9]+\.[0-9]+$); nullopt when the value is not one.
    static std::optional<std::pair<unsigned, unsigned>> version(const Json& value) {
        if (!value.is_string()) return std::nullopt;
        const std::string& text = value.get_ref<const std::string&>();
        const std::size_t dot = text.find('.');
        constexpr std::size_t kMaxVersionDigits = 6;  // per part; keeps the parts within unsigned
        auto digits = [&](std::size_t begin, std::size_t end) {
            return end > begin && end - begin <= kMaxVersionDigits &&
                   std::all_of(text.begin() + std::ptrdiff_t(begin), text.begin() + std::ptrdiff_t(end),
                               [](char c) { return c >= '0' && c <= '9'; });
        };
        if (dot == std::string::npos || !digits(0, dot) || !digits(dot + 1, text.size())) return std::nullopt;
        return std::pair<unsigned, unsigned>(unsigned(std::stoul(text.substr(0, dot))), unsigned(std::stoul(text.substr(dot + 1))));
    }
    // §3.2 Asset: this loader reads glTF 2.x (minor versions are backwards compatible), and a
    // file whose minVersion is above 2.0 needs features it does not know. A missing asset or
    // version is left to tinygltf, which requires both.
    void assetVersion(const Json& root) const {
        const Json* asset = object(root, "asset", "");
        if (!asset) return;
        if (const Json* v = member(*asset, "version")) {
            const auto parsed = version(*v);
            if (!parsed) fail("/asset/version", shown(*v) + " is not a version \"<major>.<minor>\"");
            if (parsed->first != 2)
                fail("/asset/version", "glTF " + v->get<std::string>() + " is not supported (this loader reads glTF 2.x)");
        }
        if (const Json* v = member(*asset, "minVersion")) {
            const auto parsed = version(*v);
            if (!parsed) fail("/asset/minVersion", shown(*v) + " is not a version \"<major>.<minor>\"");
            if (*parsed > std::pair<unsigned, unsigned>(2, 0))
                fail("/asset/minVersion", "the file needs glTF " + v->get<std::string>() + " or later; this loader reads glTF 2.0");
        }
    }
    static const Json* member(const Json& parent, const char* key) {
        const auto it = parent.find(key);
        return it == parent.end() ? nullptr : &*it;
    }
    static std::string shown(const Json& value) {
        std::string text = value.dump();
        return text.size() > 40 ? text.substr(0, 37) + "..." : text;
    }
    static bool isUint(const Json& v) {
        if (v.is_number_unsigned()) return true;
        if (v.is_number_integer()) return v.get<std::int64_t>() >= 0;
        if (v.is_number_float()) {
            const double d = v.get<double>();
            return d >= 0.0 && d == std::floor(d) && d < 9.0e15;
        }
        return false;
    }
    void uint(const Json& parent, const char* key, const std::string& at) const {
        if (const Json* v = member(parent, key); v && !isUint(*v)) {
            fail(at + "/" + key, shown(*v) + " is not a non-negative integer");
        }
    }
    void uints(const Json& parent, const std::string& at, std::initializer_list<const char*> keys) const {
        for (const char* key : keys) uint(parent, key, at);
    }
    void number(const Json& parent, const char* key, const std::string& at) const {
        if (const Json* v = member(parent, key); v && !v->is_number()) fail(at + "/" + key, shown(*v) + " is not a number");
    }
    void string(const Json& parent, const char* key, const std::string& at) const {
        if (const Json* v = member(parent, key); v && !v->is_string()) fail(at + "/" + key, shown(*v) + " is not a string");
    }
    void boolean(const Json& parent, const char* key, const std::string& at) const {
        if (const Json* v = member(parent, key); v && !v->is_boolean()) {
            fail(at + "/" + key, shown(*v) + " is not true or false");
        }
    }
    void strings(const Json& parent, const char* key, const std::string& at) const {
        const Json* v = member(parent, key);
        if (!v) return;
        if (!v->is_array()) fail(at + "/" + key, "must be an array of strings");
        for (std::size_t i = 0; i < v->size(); ++i) {
            if (!(*v)[i].is_string()) fail(indexPath(at + "/" + key, i), shown((*v)[i]) + " is not a string");
        }
    }
    void numbers(const Json& parent, const char* key, const std::string& at, std::size_t size) const {
        const Json* v = member(parent, key);
        if (!v) return;
        if (!v->is_array() || (size != 0 && v->size() != size)) {
            fail(at + "/" + key, "must be an array of " + (size ? std::to_string(size) + " " : std::string()) + "numbers");
        }
        for (std::size_t i = 0; i < v->size(); ++i) {
            if (!(*v)[i].is_number()) fail(indexPath(at + "/" + key, i), shown((*v)[i]) + " is not a number");
        }
    }
    const Json* object(const Json& parent, const char* key, const std::string& at) const {
        const Json* v = member(parent, key);
        if (v && !v->is_object()) fail(at + "/" + key, "must be an object, not " + shown(*v));
        return v;
    }
    // A textureInfo (§5.23) with its extra number ("scale", "strength") where it has one.
    void textureInfo(const Json& parent, const char* key, const std::string& at, const char* extra = nullptr) const {
        const Json* info = object(parent, key, at);
        if (!info) return;
        uints(*info, at + "/" + key, {"index", "texCoord"});
        if (extra) number(*info, extra, at + "/" + key);
        if (!info->contains("index")) fail(at + "/" + key + "/index", "is missing");
    }
    template <class Visit>
    void objects(const Json& parent, const char* key, const std::string& at, Visit&& visit) const {
        const Json* v = member(parent, key);
        if (!v) return;
        if (!v->is_array()) fail(at + "/" + key, "must be an array, not " + shown(*v));
        for (std::size_t i = 0; i < v->size(); ++i) {
            const std::string elementAt = indexPath(at + "/" + key, i);
            if (!(*v)[i].is_object()) fail(elementAt, "must be an object, not " + shown((*v)[i]));
            visit((*v)[i], elementAt);
        }
    }
    // Every "extensions" is an object of objects and every "name" a string (not inside "extras").
    void extensionsEverywhere(const Json& value, const std::string& at) const {
        if (value.is_array()) {
            for (std::size_t i = 0; i < value.size(); ++i) extensionsEverywhere(value[i], indexPath(at, i));
            return;
        }
        if (!value.is_object()) return;
        for (const auto& [key, child] : value.items()) {
            const std::string childAt = at + "/" + key;
            if (key == "extras") continue;
            if (key == "name" && !child.is_string()) fail(childAt, shown(child) + " is not a string");
            if (key == "extensions") {
                if (!child.is_object()) fail(childAt, "must be an object, not " + shown(child));
                for (const auto& [name, extension] : child.items()) {
                    if (!extension.is_object()) fail(childAt + "/" + name, "must be an object, not " + shown(extension));
                }
            }
            extensionsEverywhere(child, childAt);
        }
    }

    const std::string& mFile;
};

} // namespace

void checkJsonShape(const nlohmann::json& root, const std::string& file) { JsonShapeChecker(file).check(root); }

} // namespace tessera::gltf_detail
