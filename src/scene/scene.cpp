// Scene-wide queries over the loaded meshes and instances: the world-space bounds, the
// triangle count as drawn (each instance counts), and the memory the geometry and decoded
// images take. Called by the CLI (`tessera info`, framing) and the light generators.
#include <tessera/scene/scene.h>

namespace tessera {

Bounds Scene::bounds() const {
    Bounds bounds;
    for (const MeshInstance& instance : instances) {
        if (instance.mesh < 0 || std::size_t(instance.mesh) >= meshes.size()) continue;
        for (const MeshPrimitive& prim : meshes[std::size_t(instance.mesh)].primitives) {
            for (const glm::vec3& positionObject : prim.positionsObject) {
                bounds.extend(glm::vec3(instance.worldFromObject * glm::vec4(positionObject, 1.0f)));
            }
        }
    }
    return bounds;
}

std::uint64_t Scene::triangleCount() const {
    std::uint64_t count = 0;
    for (const MeshInstance& instance : instances) {
        if (instance.mesh < 0 || std::size_t(instance.mesh) >= meshes.size()) continue;
        for (const MeshPrimitive& prim : meshes[std::size_t(instance.mesh)].primitives) count += prim.triangleCount();
    }
    return count;
}

std::size_t Scene::memoryBytes() const {
    auto bytesOf = [](const auto& v) { return v.size() * sizeof(v[0]); };
    std::size_t bytes = 0;
    for (const Mesh& mesh : meshes) {
        for (const MeshPrimitive& prim : mesh.primitives) {
            bytes += bytesOf(prim.positionsObject) + bytesOf(prim.normalsObject) + bytesOf(prim.tangentsObject) +
                     bytesOf(prim.texCoords0) + bytesOf(prim.texCoords1) + bytesOf(prim.colors0) +
                     bytesOf(prim.indices);
        }
    }
    for (const Image& image : images) bytes += image.rgba8.size();
    return bytes;
}

bool Scene::usesLightGroups() const {
    for (const MeshInstance& i : instances)
        if (i.lightGroups != kDefaultGeometryLightGroups) return true;
    for (const Light& l : lights)
        if (l.lightGroups != kAllLightGroups) return true;
    return false;
}

} // namespace tessera
