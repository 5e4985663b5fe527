// A Scene made ready to draw: one interleaved vertex buffer per mesh primitive (shared by every
// instance), a draw item per (instance, primitive), and each texture decoded into a Texture2D
// with its mip chain, in the encoding its material slot calls for (glTF 2.0 §3.9.2: base colour
// and emissive are sRGB, the rest linear). Built once per scene; techniques only read it.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <typeindex>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/scene/scene.h>
#include <tessera/texture/texture2d.h>

namespace tessera {

struct SceneVertex {
    glm::vec3 posObject{0.0f};
    glm::vec3 normalObject{0.0f, 0.0f, 1.0f};
    glm::vec4 tangentObject{1.0f, 0.0f, 0.0f, 1.0f};  // w: bitangent sign (glTF)
    glm::vec2 uv0{0.0f};
    glm::vec2 uv1{0.0f};
};

struct PrimitiveBuffer {
    std::vector<SceneVertex> vertices;
    std::span<const std::uint32_t> indices;  // the MeshPrimitive's own index list
    int material = -1;
};

struct DrawItem {
    std::uint32_t primitive = 0;             // SceneResources::primitives index
    glm::mat4 worldFromObject{1.0f};
    glm::mat3 normalWorldFromObject{1.0f};   // inverse transpose of the upper 3x3
    bool frontCounterClockwise = true;       // glTF: CCW unless the transform mirrors (det < 0)
    int material = -1;
    std::uint8_t lightGroups = kDefaultGeometryLightGroups;  // its instance's (mesh.h)
};

// Which encoding each material slot's texture is decoded with.
enum class TexturePolicy {
    Gltf,       // glTF 2.0 §3.9.2: base colour and emissive sRGB (decoded to linear), the rest linear
    AllLinear   // every slot as UNORM, no sRGB decode: the 3dgep demo shades gamma-space values
};

// What SceneResources will allocate for textures, before it decodes any (scene images' sizes).
struct TextureMemoryEstimate {
    double textureBytes = 0.0;    // kept: every (image, encoding) pair with its mip chain
    double transientBytes = 0.0;  // while decoding: the float4 rows of the mip filters in flight
};

class SceneResources {
public:
    // The texture memory `scene` will take with `policy` when `threads` textures decode at once.
    static TextureMemoryEstimate estimateTextureMemory(const Scene& scene, TexturePolicy policy, std::size_t threads);

    // `progress(done, total)` is called after each texture is decoded (from one thread at a
    // time, in no fixed order); may be empty.
    explicit SceneResources(const Scene& scene, const std::function<void(std::size_t, std::size_t)>& progress = {},
                            TexturePolicy policy = TexturePolicy::Gltf);
    ~SceneResources();
    SceneResources(const SceneResources&) = delete;
    SceneResources& operator=(const SceneResources&) = delete;

    const Scene& scene() const { return *mScene; }
    const std::vector<PrimitiveBuffer>& primitives() const { return mPrimitives; }
    const std::vector<DrawItem>& drawItems() const { return mDrawItems; }
    // The decoded texture for a material slot (nullptr when the slot is empty) and its sampler.
    const Texture2D* texture(const TextureRef& ref, TexelEncoding encoding) const;
    const SamplerState& sampler(const TextureRef& ref) const;
    // The glTF default material (glTF 2.0 §3.9.1) for primitives with material -1.
    const Material& material(int index) const;
    std::size_t textureCount() const { return mTextures.size(); }
    std::size_t textureBytes() const;
    // An object derived from these resources by a layer above (raytrace/shadow_ray_scene.h's
    // BVH: shadowRaySceneOf), built by `make()` (a std::unique_ptr<T>) on the first call, thread
    // safe, then the same object for every frame of this scene; one per type T.
    template <class T, class Make>
    const T& derived(Make&& make) const {
        std::lock_guard<std::mutex> lock(mDerived->mutex);
        std::shared_ptr<const void>& slot = mDerived->objects[std::type_index(typeid(T))];
        if (!slot) slot = std::shared_ptr<const T>(make());
        return *static_cast<const T*>(slot.get());
    }

private:
    const Scene* mScene;
    std::vector<PrimitiveBuffer> mPrimitives;
    std::vector<DrawItem> mDrawItems;
    std::map<std::pair<int, TexelEncoding>, Texture2D> mTextures;  // (image, encoding)
    Material mDefaultMaterial;
    SamplerState mDefaultSampler;
    struct Derived {
        std::mutex mutex;
        std::map<std::type_index, std::shared_ptr<const void>> objects;
    };
    std::unique_ptr<Derived> mDerived = std::make_unique<Derived>();
};

} // namespace tessera
