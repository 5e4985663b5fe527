// glTF 2.0 loader entry points (loadGltf, loadGltfFromMemory): JSON checks, then tinygltf parses
// the JSON and buffers (OpenImageIO as its image callback), then GltfReader (src/scene/gltf/)
// converts the model into tessera's Scene, checking all it reads. Bad input throws InputError
// "FILE: /json/pointer: what"; "§" numbers cite the glTF 2.0 specification.
#include <tessera/scene/gltf_loader.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <tessera/errors/input_error.h>
#include <tessera/io/json_depth.h>

#include "gltf/images.h"
#include "gltf/json_shape.h"
#include "gltf/paths.h"
#include "gltf/reader.h"

namespace tessera {
namespace {

namespace fs = std::filesystem;

using gltf_detail::checkJsonShape;
using gltf_detail::GltfReader;
using gltf_detail::ImageLoaderState;
using gltf_detail::indexPath;
using gltf_detail::loadImageData;
using gltf_detail::percentDecoded;

// The JSON text of a .gltf, or of a .glb's first chunk (§4.4.3: 12-byte header, then chunk
// length, type "JSON" and the text). Empty when the chunk is not there.
std::string gltfJsonText(std::string_view bytes, bool binary) {
    if (!binary) return std::string(bytes);
    if (bytes.size() < 20 || bytes.substr(16, 4) != "JSON") return {};
    std::uint32_t length;
    std::memcpy(&length, bytes.data() + 12, 4);
    if (length > bytes.size() - 20) return {};
    return std::string(bytes.substr(20, length));
}

// A .glb whose BIN chunk (§4.4.3.3: length, type "BIN", data) runs past the header's total
// length: tinygltf 2.7.0 checks the chunk's data length against the length without its 8-byte
// chunk header, and then copies up to 8 bytes past the end of the data. Empty when the chunk
// fits (other malformed layouts are left to tinygltf, which refuses them).
std::string glbBinChunkOverrun(std::string_view bytes) {
    if (bytes.size() < 20) return {};
    std::uint32_t length, jsonLength;
    std::memcpy(&length, bytes.data() + 8, 4);
    std::memcpy(&jsonLength, bytes.data() + 12, 4);
    const std::uint64_t binAt = 20 + std::uint64_t(jsonLength);  // the BIN chunk header
    if (length > bytes.size() || binAt + 8 > length) return {};
    std::uint32_t binLength;
    std::memcpy(&binLength, bytes.data() + binAt, 4);
    if (binAt + 8 + binLength <= length) return {};
    return "the BIN chunk's " + std::to_string(binLength) + " bytes at byte " + std::to_string(binAt + 8) +
           " run past the GLB's length of " + std::to_string(length) + " bytes";
}

// tinygltf's error text on one line; for a missing external buffer ("File not found : X"),
// the JSON path of the buffer whose uri names it.
std::pair<std::string, std::string> describeParseError(std::string err, const std::string& jsonText, const fs::path& baseDir) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    std::string keyPath, what = err;
    const std::string notFound = "File not found : ";
    const std::size_t at = err.find(notFound);
    if (at != std::string::npos) {
        const std::size_t begin = at + notFound.size();
        const std::string missing = err.substr(begin, err.find('\n', begin) - begin);
        const nlohmann::json doc = nlohmann::json::parse(jsonText, nullptr, false);
        if (doc.is_object() && doc.contains("buffers") && doc["buffers"].is_array()) {
            for (std::size_t i = 0; i < doc["buffers"].size(); ++i) {
                const nlohmann::json& buffer = doc["buffers"][i];
                if (buffer.is_object() && buffer.contains("uri") && buffer["uri"].is_string() &&
                    percentDecoded(buffer["uri"].get<std::string>()) == missing) {
                    keyPath = indexPath("/buffers", i) + "/uri";
                    what = "cannot read the buffer file '" + (baseDir / missing).string() + "'";
                    break;
                }
            }
        }
    }
    std::replace(what.begin(), what.end(), '\n', ';');
    return {keyPath, what.empty() ? std::string("tinygltf reported an error without a message") : what};
}

// Both entry points: the bytes of a .gltf or .glb, `fileName` for messages, `baseDir` for
// external uris.
void loadGltfBytes(std::string_view bytes, const std::string& fileName, const fs::path& baseDir, Scene& scene,
                   const GltfLoadOptions& options) {
    if (bytes.size() > std::numeric_limits<unsigned int>::max())
        throw inputError(fileName, "", "the file is larger than 4 GiB");  // tinygltf takes an unsigned int size
    const bool binary = bytes.size() >= 4 && bytes.substr(0, 4) == "glTF";  // GLB header (§4.4.2)

    // JSON syntax and types first (tinygltf would default mistyped values silently).
    const std::string jsonText = gltfJsonText(bytes, binary);
    {
        // Before any parse: tinygltf's JSON parse recurses once per nesting level.
        checkJsonDepth(jsonText, fileName);
        if (!jsonText.empty() || !binary) {
            nlohmann::json document;
            try {
                document = nlohmann::json::parse(jsonText);
            } catch (const nlohmann::json::exception& e) {
                // parse_error, and out_of_range 406 for a number beyond double ("1e999").
                throw inputError(fileName, "", std::string("invalid JSON: ") + e.what());
            }
            checkJsonShape(document, fileName);
        }
    }

    if (binary) {
        if (const std::string problem = glbBinChunkOverrun(bytes); !problem.empty()) throw inputError(fileName, "", problem);
    }
    tinygltf::TinyGLTF parser;
    ImageLoaderState imageState;
    imageState.loadImages = options.loadImages;
    parser.SetImageLoader(&loadImageData, &imageState);
    tinygltf::Model model;
    std::string err, warnText;
    const auto size = static_cast<unsigned int>(bytes.size());
    const bool parsed =
        binary ? parser.LoadBinaryFromMemory(&model, &err, &warnText, reinterpret_cast<const unsigned char*>(bytes.data()),
                                             size, baseDir.string())
               : parser.LoadASCIIFromString(&model, &err, &warnText, bytes.data(), size, baseDir.string());
    if (!imageState.errors.empty()) {
        const auto& [index, what] = imageState.errors.front();
        throw inputError(fileName, "/images/" + std::to_string(index), what);
    }
    if (!parsed) {
        const auto [keyPath, what] = describeParseError(err, jsonText, baseDir);
        throw inputError(fileName, keyPath, what);
    }

    GltfReader reader(fileName, baseDir, model, options, scene);
    std::string line;
    for (char c : warnText + "\n") {
        if (c != '\n') { line += c; continue; }
        // tinygltf warns about unreadable external images; readImages() turns those into errors.
        if (!line.empty() && line.rfind("File not found", 0) != 0 && line.rfind("Failed to load external 'uri' for image", 0) != 0) {
            reader.mWarnings.push_back(fileName + ": " + line);
        }
        line.clear();
    }
    reader.read();

    // Everything passed: append (the target scene is untouched when the file is rejected).
    auto append = [](auto& to, auto& from) {
        to.insert(to.end(), std::make_move_iterator(from.begin()), std::make_move_iterator(from.end()));
    };
    append(scene.meshes, reader.mOut.meshes);
    append(scene.instances, reader.mOut.instances);
    append(scene.materials, reader.mOut.materials);
    append(scene.images, reader.mOut.images);
    append(scene.textures, reader.mOut.textures);
    append(scene.cameras, reader.mOut.cameras);
    append(scene.lights, reader.mOut.lights);
    for (const std::string& warning : reader.mWarnings) {
        if (options.warnings) options.warnings->push_back(warning);
        else std::fprintf(stderr, "tessera: warning: %s\n", warning.c_str());
    }
}

} // namespace

void loadGltf(const fs::path& file, Scene& scene, const GltfLoadOptions& options) {
    const std::string fileName = file.string();
    std::ifstream in(file, std::ios::binary);
    std::error_code ec;
    if (!in || !fs::is_regular_file(file, ec)) throw inputError(fileName, "", "cannot open the file");
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw inputError(fileName, "", "read error");
    loadGltfBytes(bytes, fileName, file.parent_path(), scene, options);
}

void loadGltfFromMemory(std::string_view bytes, const std::string& name, const fs::path& baseDir, Scene& scene,
                        const GltfLoadOptions& options) {
    loadGltfBytes(bytes, name, baseDir, scene, options);
}

} // namespace tessera
