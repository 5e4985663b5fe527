// Builds the draw-ready form of a Scene: interleaved vertices per primitive, one draw item per
// (instance, primitive) with its normal matrix and winding, and every texture a material slot
// uses, decoded with mips in parallel (each texture is independent, so the bytes do not depend
// on scheduling).
#include <tessera/scene/scene_resources.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <set>

#include <tbb/parallel_for.h>


namespace tessera {

namespace {

// The (image, encoding) pairs the materials use, each decoded once; `sizeOnly`: images whose
// pixels are not loaded count too (`tessera info` reads only the headers).
std::set<std::pair<int, TexelEncoding>> wantedTextures(const Scene& scene, TexturePolicy policy, bool sizeOnly) {
    std::set<std::pair<int, TexelEncoding>> wanted;
    auto want = [&](const TextureRef& ref, TexelEncoding enc) {
        if (!ref.present() || std::size_t(ref.texture) >= scene.textures.size()) return;
        const int image = scene.textures[std::size_t(ref.texture)].image;
        if (image < 0 || std::size_t(image) >= scene.images.size()) return;
        const Image& img = scene.images[std::size_t(image)];
        if (sizeOnly ? img.width > 0 && img.height > 0 : !img.rgba8.empty()) wanted.insert({image, enc});
    };
    const TexelEncoding colorEncoding = policy == TexturePolicy::Gltf ? TexelEncoding::Srgb : TexelEncoding::Linear;
    for (const Material& m : scene.materials) {
        want(m.baseColorTexture, colorEncoding);
        want(m.emissiveTexture, colorEncoding);
        want(m.metallicRoughnessTexture, TexelEncoding::Linear);
        want(m.normalTexture, TexelEncoding::Linear);
        want(m.occlusionTexture, TexelEncoding::Linear);
    }
    return wanted;
}

} // namespace

TextureMemoryEstimate SceneResources::estimateTextureMemory(const Scene& scene, TexturePolicy policy, std::size_t threads) {
    TextureMemoryEstimate e;
    std::vector<double> levelZeroWidth;
    for (const auto& [image, encoding] : wantedTextures(scene, policy, true)) {
        const Image& img = scene.images[std::size_t(image)];
        const double texels = double(img.width) * double(img.height);
        // R8G8B8A8 with a full mip chain: at most 4/3 of level 0 (1/4 + 1/16 + ... below it).
        e.textureBytes += texels * 4.0 * 4.0 / 3.0;
        levelZeroWidth.push_back(double(img.width));
    }
    // Texture2D::generateMipChain decodes up to 3 source rows to float4 (16 B per texel) while it
    // builds the chain; the decodes run in parallel, so the widest `threads` of them at once.
    std::sort(levelZeroWidth.rbegin(), levelZeroWidth.rend());
    for (std::size_t i = 0; i < levelZeroWidth.size() && i < std::max<std::size_t>(threads, 1); ++i)
        e.transientBytes += levelZeroWidth[i] * 3.0 * 16.0;
    return e;
}

SceneResources::SceneResources(const Scene& scene, const std::function<void(std::size_t, std::size_t)>& progress,
                               TexturePolicy policy)
    : mScene(&scene) {
    // Vertex buffers: one per mesh primitive; instances share them.
    std::vector<std::uint32_t> firstPrimitiveOfMesh(scene.meshes.size(), 0);
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        firstPrimitiveOfMesh[m] = std::uint32_t(mPrimitives.size());
        for (const MeshPrimitive& prim : scene.meshes[m].primitives) {
            PrimitiveBuffer buf;
            buf.vertices.resize(prim.positionsObject.size());
            for (std::size_t i = 0; i < buf.vertices.size(); ++i) {
                SceneVertex& v = buf.vertices[i];
                v.posObject = prim.positionsObject[i];
                if (i < prim.normalsObject.size()) v.normalObject = prim.normalsObject[i];
                if (i < prim.tangentsObject.size()) v.tangentObject = prim.tangentsObject[i];
                if (i < prim.texCoords0.size()) v.uv0 = prim.texCoords0[i];
                if (i < prim.texCoords1.size()) v.uv1 = prim.texCoords1[i];
            }
            buf.indices = prim.indices;
            buf.material = prim.material;
            mPrimitives.push_back(std::move(buf));
        }
    }
    for (const MeshInstance& inst : scene.instances) {
        if (inst.mesh < 0 || std::size_t(inst.mesh) >= scene.meshes.size()) continue;
        const glm::mat3 upper(inst.worldFromObject);
        const float det = glm::determinant(upper);
        for (std::size_t p = 0; p < scene.meshes[std::size_t(inst.mesh)].primitives.size(); ++p) {
            DrawItem item;
            item.primitive = firstPrimitiveOfMesh[std::size_t(inst.mesh)] + std::uint32_t(p);
            item.worldFromObject = inst.worldFromObject;
            item.normalWorldFromObject = glm::transpose(glm::inverse(upper));
            // glTF 2.0 §3.7.4: a negative determinant of the global transform reverses the winding.
            item.frontCounterClockwise = det >= 0.0f;
            item.material = mPrimitives[item.primitive].material;
            item.lightGroups = inst.lightGroups;
            mDrawItems.push_back(item);
        }
    }

    const std::set<std::pair<int, TexelEncoding>> wanted = wantedTextures(scene, policy, false);
    const std::vector<std::pair<int, TexelEncoding>> keys(wanted.begin(), wanted.end());
    std::vector<Texture2D> decoded(keys.size());
    std::atomic<std::size_t> done{0};
    std::mutex progressMutex;
    tbb::parallel_for(std::size_t(0), keys.size(), [&](std::size_t i) {
        decoded[i] = Texture2D::fromImage(scene.images[std::size_t(keys[i].first)], keys[i].second);
        const std::size_t n = ++done;
        if (progress) {
            const std::lock_guard<std::mutex> lock(progressMutex);
            progress(n, keys.size());
        }
    });
    for (std::size_t i = 0; i < keys.size(); ++i) mTextures.emplace(keys[i], std::move(decoded[i]));
    // glTF 2.0 §3.8.4 default sampler: repeat, filtering left to the implementation (trilinear here).
    mDefaultSampler.addressU = mDefaultSampler.addressV = AddressMode::Wrap;
}

const Texture2D* SceneResources::texture(const TextureRef& ref, TexelEncoding encoding) const {
    if (!ref.present() || std::size_t(ref.texture) >= mScene->textures.size()) return nullptr;
    const auto it = mTextures.find({mScene->textures[std::size_t(ref.texture)].image, encoding});
    return it == mTextures.end() ? nullptr : &it->second;
}

const SamplerState& SceneResources::sampler(const TextureRef& ref) const {
    if (!ref.present() || std::size_t(ref.texture) >= mScene->textures.size()) return mDefaultSampler;
    return mScene->textures[std::size_t(ref.texture)].sampler;
}

const Material& SceneResources::material(int index) const {
    return index >= 0 && std::size_t(index) < mScene->materials.size() ? mScene->materials[std::size_t(index)]
                                                                       : mDefaultMaterial;
}

std::size_t SceneResources::textureBytes() const {
    std::size_t bytes = 0;
    for (const auto& [key, tex] : mTextures) bytes += tex.memoryBytes();
    return bytes;
}

SceneResources::~SceneResources() = default;

} // namespace tessera
