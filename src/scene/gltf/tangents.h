// Tangents generated for glTF primitives without TANGENT (MikkTSpace-like; tangents.cpp tells
// how it differs from MikkTSpace, and ERRATA #33 which way the bitangent points).
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include <tessera/scene/mesh.h>

namespace tessera::gltf_detail {

// Sets prim.tangentsObject (w: the bitangent sign) and tangentsGenerated from the UV set `uvs`;
// may append vertices (those shared by UV-preserving and UV-mirrored triangles are split).
void generateTangents(MeshPrimitive& prim, const std::vector<glm::vec2>& uvs, bool bitangentUp);

} // namespace tessera::gltf_detail
