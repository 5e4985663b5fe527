// GltfReader: converts a parsed tinygltf::Model into tessera's Scene, checking every index,
// accessor range and value it reads (bad input throws InputError "FILE: /json/pointer: what").
// Its members are defined by concept in reader.cpp (core, extensions), reader_accessors.cpp,
// reader_materials.cpp, reader_meshes.cpp, reader_nodes.cpp, reader_cameras.cpp, reader_lights.cpp.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <tiny_gltf.h>

#include <tessera/scene/gltf_loader.h>

#include "accessors.h"

namespace tessera::gltf_detail {

namespace fs = std::filesystem;

inline constexpr double PI = 3.14159265358979323846;

class GltfReader {
public:
    GltfReader(std::string file, fs::path folder, tinygltf::Model& model, const GltfLoadOptions& options,
               const Scene& target);

    void read();

    Scene mOut;  // what the file adds (appended to the target scene once everything passed)
    std::vector<std::string> mWarnings;

private:
    // reader.cpp
    [[noreturn]] void fail(const std::string& keyPath, const std::string& what) const;
    void warn(const std::string& what);
    bool extensionUsed(std::string_view name) const;
    void checkExtensions();
    void checkIndex(int index, std::size_t size, const std::string& keyPath, std::string_view what) const;

    // ---- accessors (reader_accessors.cpp)
    const unsigned char* bufferViewData(int index, const std::string& referencedAt) const;
    AccessorLayout layoutOf(int index, const std::string& referencedAt) const;
    template <class Store>
    void applySparse(int index, const AccessorLayout& layout, Store&& store) const;
    void chargeDecode(std::size_t values, int index) const;
    std::vector<float> readFloats(int index, const std::string& referencedAt) const;
    std::vector<std::uint32_t> readIndices(int index, const std::string& referencedAt) const;
    bool attributeFormatAllowed(const std::string& semantic, int type, int componentType, bool normalized) const;
    std::vector<float> readAttribute(const tinygltf::Primitive& primitive, const std::string& semantic,
                                     const std::string& primitivePath, std::size_t expectedCount) const;

    // ---- images, textures, materials (reader_materials.cpp)
    void readImages();
    static SamplerState samplerFrom(const tinygltf::Sampler& sampler, const std::string& path, const GltfReader& self);
    void readTextures();
    TextureRef textureRef(int index, int texCoord, double scale, const std::string& path);
    // A vector of N floats from the file's numbers (materials and lights): `fallback` when absent.
    template <std::size_t N>
    glm::vec<int(N), float> vectorOf(const std::vector<double>& values, glm::vec<int(N), float> fallback,
                                     const std::string& path) const {
        if (values.empty()) return fallback;
        if (values.size() != N) fail(path, "needs " + std::to_string(N) + " numbers, has " + std::to_string(values.size()));
        glm::vec<int(N), float> out;
        for (std::size_t i = 0; i < N; ++i) {
            if (!std::isfinite(values[i])) fail(path, "holds a non-finite value");
            out[int(i)] = float(values[i]);
        }
        return out;
    }
    void readMaterials();

    // ---- meshes (reader_meshes.cpp)
    void readMeshes();
    std::vector<std::uint32_t> triangleList(std::vector<std::uint32_t> vertices, int mode, const std::string& path) const;
    std::optional<MeshPrimitive> readPrimitive(const tinygltf::Primitive& primitive, const std::string& path);
    static void makeFlatNormals(MeshPrimitive& prim);

    // ---- nodes, cameras, lights (reader_nodes.cpp, reader_cameras.cpp, reader_lights.cpp)
    glm::mat4 localFromNode(const tinygltf::Node& node, const std::string& path) const;
    Camera cameraFrom(int index, const glm::mat4& worldFromNode, const std::string& nodeName) const;
    void checkLights() const;
    void reportLights();
    static std::string formatDouble(double v);
    Light lightFrom(int index, const glm::mat4& worldFromNode, const std::string& nodeName);
    void readNodes();
    void visitNode(int index, const glm::mat4& worldFromParent, std::vector<std::pair<int, glm::mat4>>& stack);

    std::string mFile;
    fs::path mFolder;
    tinygltf::Model& mModel;
    const GltfLoadOptions& mOptions;
    int mMeshBase, mMaterialBase, mImageBase, mTextureBase;
    bool mQuantization = false;
    std::uint64_t mDecodeBudget = 0;     // bytes (DECODE_BUDGET_BASE + per buffer byte)
    mutable std::uint64_t mDecoded = 0;  // bytes charged so far
    bool mSkinWarned = false;
    std::set<int> mPlacedLights;  // indices of the lights a node of the scene places
};

} // namespace tessera::gltf_detail
