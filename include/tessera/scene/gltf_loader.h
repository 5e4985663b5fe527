// glTF 2.0 (.gltf / .glb) through tinygltf, with OpenImageIO as tinygltf's image loader:
// meshes (all index widths, normalized integer attributes), the node hierarchy, cameras,
// materials, textures and samplers, KHR_lights_punctual, tangents generated when missing.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/scene/mesh.h>

#include <tessera/scene/scene.h>

namespace tessera {

struct GltfLoadOptions {
    bool loadImages = true;          // false: keep texture/image records, leave pixels empty (`tessera info`)
    glm::mat4 worldFromFile{1.0f};   // applied above the glTF's root nodes (the scene file's transform)
    int sceneIndex = -1;             // glTF scene to instantiate; -1: the file's default scene (or 0)
    std::uint8_t lightGroups = kDefaultGeometryLightGroups;  // every instance's light groups (mesh.h)
    // Receives one line per warning (unsupported optional extensions, skipped point/line
    // primitives, ignored skins, ...), each prefixed by the file name; null: printed to stderr.
    std::vector<std::string>* warnings = nullptr;
    // Generated tangents (a primitive without TANGENT): true (default) takes the bitangent up the
    // image, as glTF 2.0 §3.9.3 (+Y up) and explicit tangents from exporters do; false takes it
    // along +v, i.e. down the image, which reads a normal texture's green channel inverted:
    // tessera's generator before the correction, kept for comparison (ERRATA #33;
    // `tessera render --generated-bitangent down`).
    bool generatedBitangentUp = true;
};

// Appends the file's contents to `scene` (indices into scene's vectors are offset accordingly).
// Throws InputError naming the file and the JSON path ("/accessors/3/count", ...) on bad input;
// `scene` is left unchanged then. Tangents: a primitive without TANGENT gets generated ones
// (tangentsGenerated) whenever it has the UV set they follow (the material's normalTexture
// texCoord, else TEXCOORD_0); without that UV set tangentsObject stays empty.
void loadGltf(const std::filesystem::path& file, Scene& scene, const GltfLoadOptions& options = {});

// The same from bytes in memory (a .gltf's JSON text, or a .glb, told apart by the "glTF" magic):
// `name` stands for the file in messages, and external uris resolve against `baseDir` (data:
// uris and a .glb's BIN chunk need no files). Every check of loadGltf applies.
void loadGltfFromMemory(std::string_view bytes, const std::string& name, const std::filesystem::path& baseDir, Scene& scene,
                        const GltfLoadOptions& options = {});

} // namespace tessera
