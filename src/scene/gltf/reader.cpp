// GltfReader's core: construction (the decode budget from the file's buffers), the order in
// which read() converts the document, error and warning helpers, the extension checks, and the
// index check every reference goes through.
#include "reader.h"

#include <algorithm>
#include <array>
#include <string>
#include <string_view>
#include <utility>

#include <tessera/errors/input_error.h>

#include "paths.h"

namespace tessera::gltf_detail {
namespace {

// Extensions this loader implements; any other one in extensionsRequired is an error.
constexpr std::array<std::string_view, 3> SUPPORTED_EXTENSIONS = {
    "KHR_lights_punctual", "KHR_mesh_quantization", "KHR_materials_emissive_strength"};

} // namespace

GltfReader::GltfReader(std::string file, fs::path folder, tinygltf::Model& model, const GltfLoadOptions& options,
                       const Scene& target)
    : mFile(std::move(file)), mFolder(std::move(folder)), mModel(model), mOptions(options),
      mMeshBase(int(target.meshes.size())), mMaterialBase(int(target.materials.size())),
      mImageBase(int(target.images.size())), mTextureBase(int(target.textures.size())) {
    mDecodeBudget = DECODE_BUDGET_BASE;
    for (const tinygltf::Buffer& buffer : mModel.buffers) mDecodeBudget += DECODE_BUDGET_PER_BUFFER_BYTE * buffer.data.size();
}

void GltfReader::read() {
    checkExtensions();
    readImages();
    readTextures();
    readMaterials();
    readMeshes();
    checkLights();
    readNodes();
    reportLights();
}

[[noreturn]] void GltfReader::fail(const std::string& keyPath, const std::string& what) const {
    throw inputError(mFile, keyPath, what);
}
void GltfReader::warn(const std::string& what) { mWarnings.push_back(mFile + ": " + what); }

bool GltfReader::extensionUsed(std::string_view name) const {
    return std::find(mModel.extensionsUsed.begin(), mModel.extensionsUsed.end(), name) !=
           mModel.extensionsUsed.end();
}

void GltfReader::checkExtensions() {
    auto supported = [](const std::string& name) {
        return std::find(SUPPORTED_EXTENSIONS.begin(), SUPPORTED_EXTENSIONS.end(), name) !=
               SUPPORTED_EXTENSIONS.end();
    };
    for (std::size_t i = 0; i < mModel.extensionsRequired.size(); ++i) {
        const std::string& name = mModel.extensionsRequired[i];
        if (!supported(name)) fail(indexPath("/extensionsRequired", i), "extension '" + name + "' is required but not supported");
    }
    for (const std::string& name : mModel.extensionsUsed) {
        if (!supported(name)) warn("extension '" + name + "' is not supported and is ignored");
    }
    mQuantization = extensionUsed("KHR_mesh_quantization");
}

// Checks index `index` into an array of `size` elements referenced at `keyPath`.
void GltfReader::checkIndex(int index, std::size_t size, const std::string& keyPath, std::string_view what) const {
    if (index < 0 || std::size_t(index) >= size) {
        fail(keyPath, std::string(what) + " " + std::to_string(index) + " does not exist (the file has " +
                          std::to_string(size) + ")");
    }
}

} // namespace tessera::gltf_detail
