// A loaded scene: meshes placed by instances, glTF materials, images and the textures that
// sample them, cameras and lights, all in world space. One or more glTF files (and a scene
// file's lights) merge into one Scene.
#pragma once

#include <cstddef>
#include <limits>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/scene/camera.h>
#include <tessera/scene/light.h>
#include <tessera/scene/material.h>
#include <tessera/scene/mesh.h>
#include <tessera/texture/image.h>
#include <tessera/texture/sampler_state.h>

namespace tessera {

// A glTF texture: an image and how to sample it.
struct TextureBinding {
    int image = -1;          // Scene::images index
    SamplerState sampler;    // from the glTF sampler (or glTF's default: repeat, linear-mip-linear)
};

struct Bounds {
    glm::vec3 minWorld{std::numeric_limits<float>::infinity()};
    glm::vec3 maxWorld{-std::numeric_limits<float>::infinity()};
    bool empty() const { return !(minWorld.x <= maxWorld.x); }
    void extend(const glm::vec3& p) { minWorld = glm::min(minWorld, p); maxWorld = glm::max(maxWorld, p); }
};

struct Scene {
    std::vector<Mesh> meshes;
    std::vector<MeshInstance> instances;
    std::vector<Material> materials;
    std::vector<Image> images;
    std::vector<TextureBinding> textures;
    std::vector<Camera> cameras;
    std::vector<Light> lights;
    // KHR_lights_punctual lights the glTF files place but the scene file leaves out (no
    // "gltfLights"): counted so that the command line can say why they do not light the scene.
    std::size_t gltfLightsNotUsed = 0;

    // World-space AABB of every instance's transformed positions.
    Bounds bounds() const;
    std::uint64_t triangleCount() const;   // over instances (an instanced mesh counts each time)
    std::size_t memoryBytes() const;       // geometry + decoded images (without mips)
    // Whether any instance is outside group 0 alone or any light outside every group (mesh.h).
    bool usesLightGroups() const;
};

} // namespace tessera
