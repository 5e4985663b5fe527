// GltfReader's images, textures and materials: every image checked, then decoded in parallel;
// samplers and textures; the metallic-roughness materials with their texture references and
// KHR_materials_emissive_strength. "§" numbers cite the glTF 2.0 specification.
#include "reader.h"

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>

#include "images.h"
#include "paths.h"

namespace tessera::gltf_detail {

// Checks every image record in file order, then decodes them all in parallel (each image is
// independent, so the bytes do not depend on scheduling); the first failing image in file
// order is the one reported.
void GltfReader::readImages() {
    struct Pending {
        const unsigned char* bytes = nullptr;
        std::size_t size = 0;
        std::string uri;
    };
    std::vector<Image> images(mModel.images.size());
    std::vector<Pending> pending(mModel.images.size());
    for (std::size_t i = 0; i < mModel.images.size(); ++i) {
        tinygltf::Image& gltfImage = mModel.images[i];
        const std::string path = indexPath("/images", i);
        Image& image = images[i];
        const bool external = !gltfImage.uri.empty() && gltfImage.bufferView < 0;
        image.source = external ? (mFolder / percentDecoded(gltfImage.uri)).string() : mFile + "#" + path;
        if (gltfImage.bufferView >= 0) {
            pending[i].bytes = bufferViewData(gltfImage.bufferView, path + "/bufferView");
            pending[i].size = mModel.bufferViews[std::size_t(gltfImage.bufferView)].byteLength;
        } else if (gltfImage.width < 1) {
            // tinygltf only warns when an external image cannot be read.
            fail(path + "/uri", "cannot read the image file '" + image.source + "'");
        } else {
            image.width = std::uint32_t(gltfImage.width);
            image.height = std::uint32_t(gltfImage.height);
            pending[i] = {gltfImage.image.data(), gltfImage.image.size(), gltfImage.uri};
            if (!mOptions.loadImages) pending[i].bytes = nullptr;  // header already read
        }
    }
    std::vector<std::string> problems(images.size());
    tbb::parallel_for(std::size_t(0), images.size(), [&](std::size_t i) {
        if (pending[i].bytes == nullptr) return;
        problems[i] = decodeImage(pending[i].bytes, pending[i].size, mModel.images[i].mimeType, pending[i].uri,
                                  !mOptions.loadImages, images[i]);
    });
    for (std::size_t i = 0; i < images.size(); ++i) {
        if (!problems[i].empty()) fail(indexPath("/images", i), problems[i]);
        mModel.images[i].image.clear();
        mModel.images[i].image.shrink_to_fit();
        mOut.images.push_back(std::move(images[i]));
    }
}

SamplerState GltfReader::samplerFrom(const tinygltf::Sampler& sampler, const std::string& path, const GltfReader& self) {
    // §5.26 (sampler): absent filters are implementation-defined; tessera uses the common
    // choice linear + linear-mip-linear. Wrap modes default to REPEAT.
    SamplerState state;
    state.minFilter = state.magFilter = state.mipFilter = Filter::Linear;
    switch (sampler.magFilter) {
    case -1:
    case 9729: state.magFilter = Filter::Linear; break;   // LINEAR
    case 9728: state.magFilter = Filter::Point; break;    // NEAREST
    default: self.fail(path + "/magFilter", std::to_string(sampler.magFilter) + " is not 9728 or 9729");
    }
    switch (sampler.minFilter) {
    case -1: break;
    // NEAREST / LINEAR without mipmaps: sample the top level only (maxLod = 0, as in GL).
    case 9728: state.minFilter = Filter::Point; state.mipFilter = Filter::Point; state.maxLod = 0.0f; break;
    case 9729: state.minFilter = Filter::Linear; state.mipFilter = Filter::Point; state.maxLod = 0.0f; break;
    case 9984: state.minFilter = Filter::Point; state.mipFilter = Filter::Point; break;   // NEAREST_MIPMAP_NEAREST
    case 9985: state.minFilter = Filter::Linear; state.mipFilter = Filter::Point; break;  // LINEAR_MIPMAP_NEAREST
    case 9986: state.minFilter = Filter::Point; state.mipFilter = Filter::Linear; break;  // NEAREST_MIPMAP_LINEAR
    case 9987: state.minFilter = Filter::Linear; state.mipFilter = Filter::Linear; break; // LINEAR_MIPMAP_LINEAR
    default: self.fail(path + "/minFilter", std::to_string(sampler.minFilter) + " is not a glTF minFilter");
    }
    auto wrap = [&](int mode, const char* key) {
        switch (mode) {
        case 33071: return AddressMode::Clamp;   // CLAMP_TO_EDGE
        case 33648: return AddressMode::Mirror;  // MIRRORED_REPEAT
        case 10497: return AddressMode::Wrap;    // REPEAT
        default: self.fail(path + "/" + key, std::to_string(mode) + " is not 33071, 33648 or 10497");
        }
    };
    state.addressU = wrap(sampler.wrapS, "wrapS");
    state.addressV = wrap(sampler.wrapT, "wrapT");
    return state;
}

void GltfReader::readTextures() {
    std::vector<SamplerState> samplers;
    for (std::size_t i = 0; i < mModel.samplers.size(); ++i) {
        samplers.push_back(samplerFrom(mModel.samplers[i], indexPath("/samplers", i), *this));
    }
    const SamplerState defaultSampler = samplerFrom(tinygltf::Sampler{}, "/samplers", *this);
    for (std::size_t i = 0; i < mModel.textures.size(); ++i) {
        const tinygltf::Texture& texture = mModel.textures[i];
        const std::string path = indexPath("/textures", i);
        TextureBinding binding;
        if (texture.source == -1) {
            warn(path + ": no source image (an image-format extension?); the texture samples nothing");
        } else {
            checkIndex(texture.source, mModel.images.size(), path + "/source", "image");
            binding.image = mImageBase + texture.source;
        }
        if (texture.sampler == -1) {
            binding.sampler = defaultSampler;
        } else {
            checkIndex(texture.sampler, samplers.size(), path + "/sampler", "sampler");
            binding.sampler = samplers[std::size_t(texture.sampler)];
        }
        mOut.textures.push_back(binding);
    }
}

TextureRef GltfReader::textureRef(int index, int texCoord, double scale, const std::string& path) {
    TextureRef ref;
    if (index == -1) return ref;
    checkIndex(index, mModel.textures.size(), path + "/index", "texture");
    ref.texture = mTextureBase + index;
    if (texCoord < 0) fail(path + "/texCoord", std::to_string(texCoord) + " is negative");
    if (texCoord > 1) {
        warn(path + "/texCoord: TEXCOORD_" + std::to_string(texCoord) + " is not supported; TEXCOORD_0 is used");
        texCoord = 0;
    }
    ref.texCoord = texCoord;
    ref.scale = float(scale);
    return ref;
}

void GltfReader::readMaterials() {
    for (std::size_t i = 0; i < mModel.materials.size(); ++i) {
        const tinygltf::Material& m = mModel.materials[i];
        const std::string path = indexPath("/materials", i);
        const auto& pbr = m.pbrMetallicRoughness;
        const std::string pbrPath = path + "/pbrMetallicRoughness";
        Material material;
        material.name = m.name;
        material.baseColorFactor = vectorOf<4>(pbr.baseColorFactor, glm::vec4(1.0f), pbrPath + "/baseColorFactor");
        material.baseColorTexture = textureRef(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, 1.0,
                                               pbrPath + "/baseColorTexture");
        material.metallicFactor = float(pbr.metallicFactor);
        material.roughnessFactor = float(pbr.roughnessFactor);
        material.metallicRoughnessTexture =
            textureRef(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord, 1.0,
                       pbrPath + "/metallicRoughnessTexture");
        material.normalTexture = textureRef(m.normalTexture.index, m.normalTexture.texCoord, m.normalTexture.scale,
                                            path + "/normalTexture");
        material.occlusionTexture = textureRef(m.occlusionTexture.index, m.occlusionTexture.texCoord,
                                               m.occlusionTexture.strength, path + "/occlusionTexture");
        material.emissiveTexture =
            textureRef(m.emissiveTexture.index, m.emissiveTexture.texCoord, 1.0, path + "/emissiveTexture");
        material.emissiveFactor = vectorOf<3>(m.emissiveFactor, glm::vec3(0.0f), path + "/emissiveFactor");
        const auto strength = m.extensions.find("KHR_materials_emissive_strength");
        if (strength != m.extensions.end() && strength->second.Has("emissiveStrength")) {
            material.emissiveFactor *= float(strength->second.Get("emissiveStrength").GetNumberAsDouble());
        }
        if (m.alphaMode == "OPAQUE") material.alphaMode = AlphaMode::Opaque;
        else if (m.alphaMode == "MASK") material.alphaMode = AlphaMode::Mask;
        else if (m.alphaMode == "BLEND") material.alphaMode = AlphaMode::Blend;
        else fail(path + "/alphaMode", "'" + m.alphaMode + "' is not OPAQUE, MASK or BLEND");
        if (!(m.alphaCutoff >= 0.0)) fail(path + "/alphaCutoff", std::to_string(m.alphaCutoff) + " is negative");
        material.alphaCutoff = float(m.alphaCutoff);
        material.doubleSided = m.doubleSided;
        mOut.materials.push_back(std::move(material));
    }
}

} // namespace tessera::gltf_detail
