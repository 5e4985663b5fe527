// Triangle meshes as the loader produces them: one primitive per glTF mesh primitive, with
// attributes decoded to float (normalized integers per glTF's KHR_mesh_quantization rules),
// 32-bit indices, and tangents whose w is the bitangent sign (glTF 2.0 §3.7.2.1).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace tessera {

struct MeshPrimitive {
    std::vector<glm::vec3> positionsObject;   // POSITION
    std::vector<glm::vec3> normalsObject;     // NORMAL (generated flat when absent)
    std::vector<glm::vec4> tangentsObject;    // TANGENT xyz + w = bitangent sign (+1 or -1)
    std::vector<glm::vec2> texCoords0;        // TEXCOORD_0 (empty when absent)
    std::vector<glm::vec2> texCoords1;        // TEXCOORD_1 (empty when absent)
    std::vector<glm::vec4> colors0;           // COLOR_0 as linear RGBA (empty when absent)
    std::vector<std::uint32_t> indices;       // triangle list, 3 per triangle
    int material = -1;                        // Scene::materials index; -1: the glTF default material
    bool tangentsGenerated = false;           // true when TANGENT was absent and computed
    std::uint32_t triangleCount() const { return std::uint32_t(indices.size() / 3); }
};

struct Mesh {
    std::string name;
    std::vector<MeshPrimitive> primitives;
};

// One placement of a mesh in the world (a glTF node with a mesh).
// Light groups (PR&C D3D11 §11.4.2): geometry belongs to groups, a light lights the geometry of
// its groups; one bit per group, 0..7. Defaults: geometry in group 0, lights in every group.
inline constexpr std::uint8_t kDefaultGeometryLightGroups = 0x01;
inline constexpr std::uint8_t kAllLightGroups = 0xFF;

struct MeshInstance {
    int mesh = -1;              // Scene::meshes index
    glm::mat4 worldFromObject{1.0f};
    std::string nodeName;
    std::uint8_t lightGroups = kDefaultGeometryLightGroups;  // the scene file model's "lightGroups"
};

} // namespace tessera
