// GltfReader's meshes: each primitive's attributes and indices, its topology as a triangle list,
// flat normals where NORMAL is absent, and generated tangents where TANGENT is.
// "§" numbers cite the glTF 2.0 specification.
#include "reader.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "paths.h"
#include "tangents.h"

namespace tessera::gltf_detail {

void GltfReader::readMeshes() {
    std::vector<std::string> skipped;
    bool morphWarned = false;
    for (std::size_t m = 0; m < mModel.meshes.size(); ++m) {
        const tinygltf::Mesh& gltfMesh = mModel.meshes[m];
        Mesh mesh;
        mesh.name = gltfMesh.name;
        for (std::size_t p = 0; p < gltfMesh.primitives.size(); ++p) {
            const std::string path = indexPath(indexPath("/meshes", m) + "/primitives", p);
            const tinygltf::Primitive& primitive = gltfMesh.primitives[p];
            if (!primitive.targets.empty() && !morphWarned) {
                warn(path + "/targets: morph targets are ignored (the base shape is drawn)");
                morphWarned = true;
            }
            std::optional<MeshPrimitive> prim = readPrimitive(primitive, path);
            if (prim) mesh.primitives.push_back(std::move(*prim));
            else skipped.push_back(path);
        }
        mOut.meshes.push_back(std::move(mesh));
    }
    if (!skipped.empty()) {
        std::string list;
        for (std::size_t i = 0; i < skipped.size() && i < 8; ++i) list += (i ? ", " : "") + skipped[i];
        if (skipped.size() > 8) list += ", ...";
        warn(std::to_string(skipped.size()) + " primitive(s) without triangles (points, lines, or fewer than 3 "
             "vertices) skipped: " + list);
    }
}

// The triangle list of a primitive (§3.7.2.1 "Topology types"); empty for points and lines.
std::vector<std::uint32_t> GltfReader::triangleList(std::vector<std::uint32_t> vertices, int mode, const std::string& path) const {
    std::vector<std::uint32_t> triangles;
    const std::size_t n = vertices.size();
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (n % 3 != 0) {
            fail(path, std::to_string(n) + " vertices (after indexing) are not a multiple of 3 for TRIANGLES");
        }
        return vertices;
    }
    if (n < 3) return triangles;
    triangles.reserve((n - 2) * 3);
    for (std::size_t i = 0; i + 2 < n; ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            // p_i = {v_i, v_{i+(1+i%2)}, v_{i+(2-i%2)}}: odd triangles swap to keep the winding.
            triangles.insert(triangles.end(), {vertices[i], vertices[i + 1 + i % 2], vertices[i + 2 - i % 2]});
        } else {
            // TRIANGLE_FAN: p_i = {v_{i+1}, v_{i+2}, v_0}
            triangles.insert(triangles.end(), {vertices[i + 1], vertices[i + 2], vertices[0]});
        }
    }
    return triangles;
}

std::optional<MeshPrimitive> GltfReader::readPrimitive(const tinygltf::Primitive& primitive, const std::string& path) {
    const int mode = primitive.mode == -1 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode < TINYGLTF_MODE_POINTS || mode > TINYGLTF_MODE_TRIANGLE_FAN) {
        fail(path + "/mode", std::to_string(mode) + " is not a glTF primitive mode (0..6)");
    }
    if (mode < TINYGLTF_MODE_TRIANGLES) return std::nullopt;
    if (primitive.material != -1) checkIndex(primitive.material, mModel.materials.size(), path + "/material", "material");
    if (primitive.attributes.count("POSITION") == 0) fail(path + "/attributes", "POSITION is missing");

    MeshPrimitive prim;
    prim.material = primitive.material == -1 ? -1 : mMaterialBase + primitive.material;
    const int positionAccessor = primitive.attributes.at("POSITION");
    const std::vector<float> positions = readAttribute(primitive, "POSITION", path, 0);
    const std::size_t vertexCount = positions.size() / 3;
    for (std::size_t i = 0; i < positions.size(); ++i) {
        if (!std::isfinite(positions[i])) {
            fail(indexPath("/accessors", std::size_t(positionAccessor)),
                 "POSITION holds a non-finite value (element " + std::to_string(i / 3) + ")");
        }
    }
    prim.positionsObject.resize(vertexCount);
    for (std::size_t v = 0; v < vertexCount; ++v) {
        prim.positionsObject[v] = {positions[v * 3], positions[v * 3 + 1], positions[v * 3 + 2]};
    }
    auto has = [&](const char* semantic) { return primitive.attributes.count(semantic) != 0; };
    if (has("NORMAL")) {
        const std::vector<float> normals = readAttribute(primitive, "NORMAL", path, vertexCount);
        prim.normalsObject.resize(vertexCount);
        for (std::size_t v = 0; v < vertexCount; ++v) {
            prim.normalsObject[v] = {normals[v * 3], normals[v * 3 + 1], normals[v * 3 + 2]};
        }
    }
    // §3.7.2.1: without normals, flat normals are used and any TANGENT is ignored.
    if (has("TANGENT") && has("NORMAL")) {
        const std::vector<float> tangents = readAttribute(primitive, "TANGENT", path, vertexCount);
        prim.tangentsObject.resize(vertexCount);
        for (std::size_t v = 0; v < vertexCount; ++v) {
            const float w = tangents[v * 4 + 3] < 0.0f ? -1.0f : 1.0f;  // the bitangent sign as given
            prim.tangentsObject[v] = {tangents[v * 4], tangents[v * 4 + 1], tangents[v * 4 + 2], w};
        }
    }
    auto readUv = [&](const char* semantic, std::vector<glm::vec2>& out) {
        if (!has(semantic)) return;
        const std::vector<float> uv = readAttribute(primitive, semantic, path, vertexCount);
        out.resize(vertexCount);
        for (std::size_t v = 0; v < vertexCount; ++v) out[v] = {uv[v * 2], uv[v * 2 + 1]};
    };
    readUv("TEXCOORD_0", prim.texCoords0);
    readUv("TEXCOORD_1", prim.texCoords1);
    if (has("COLOR_0")) {
        const std::vector<float> colors = readAttribute(primitive, "COLOR_0", path, vertexCount);
        const std::size_t components = colors.size() / vertexCount;
        prim.colors0.resize(vertexCount);
        for (std::size_t v = 0; v < vertexCount; ++v) {
            const float* c = &colors[v * components];
            prim.colors0[v] = {c[0], c[1], c[2], components == 4 ? c[3] : 1.0f};
        }
    }

    std::vector<std::uint32_t> vertices;
    if (primitive.indices != -1) {
        const std::string indicesPath = path + "/indices";
        vertices = readIndices(primitive.indices, indicesPath);
        for (std::size_t i = 0; i < vertices.size(); ++i) {
            if (vertices[i] >= vertexCount) {
                fail(indexPath("/accessors", std::size_t(primitive.indices)),
                     "index " + std::to_string(vertices[i]) + " (element " + std::to_string(i) +
                         ") is not below the vertex count " + std::to_string(vertexCount) + " of " + path);
            }
        }
    } else {
        vertices.resize(vertexCount);
        for (std::size_t v = 0; v < vertexCount; ++v) vertices[v] = std::uint32_t(v);
    }
    prim.indices = triangleList(std::move(vertices), mode, path);
    if (prim.indices.empty()) return std::nullopt;

    if (prim.normalsObject.empty()) makeFlatNormals(prim);

    // Tangents: generated whenever TANGENT is absent and the UV set they follow exists (the
    // normal texture's texCoord when the material has one, else TEXCOORD_0).
    if (prim.tangentsObject.empty()) {
        int uvSet = 0;
        if (primitive.material != -1) {
            const TextureRef& normalMap = mOut.materials[std::size_t(primitive.material)].normalTexture;
            if (normalMap.present()) uvSet = normalMap.texCoord;
        }
        const std::vector<glm::vec2>& uvs = uvSet == 1 ? prim.texCoords1 : prim.texCoords0;
        if (!uvs.empty()) {
            const std::vector<glm::vec2> uvCopy = uvs;  // generateTangents may append vertices
            generateTangents(prim, uvCopy, mOptions.generatedBitangentUp);
        }
    }
    return prim;
}

// Flat normals (§3.7.2.1): every triangle gets its own three vertices and the face normal
// normalize(cross(p1 - p0, p2 - p0)) (counter-clockwise front faces, §3.7.2.1).
void GltfReader::makeFlatNormals(MeshPrimitive& prim) {
    MeshPrimitive flat;
    const std::size_t corners = prim.indices.size();
    auto unweld = [&](const auto& from, auto& to) {
        if (from.empty()) return;
        to.resize(corners);
        for (std::size_t c = 0; c < corners; ++c) to[c] = from[prim.indices[c]];
    };
    unweld(prim.positionsObject, flat.positionsObject);
    unweld(prim.texCoords0, flat.texCoords0);
    unweld(prim.texCoords1, flat.texCoords1);
    unweld(prim.colors0, flat.colors0);
    flat.normalsObject.resize(corners);
    flat.indices.resize(corners);
    for (std::size_t c = 0; c < corners; c += 3) {
        const glm::vec3 n = glm::cross(flat.positionsObject[c + 1] - flat.positionsObject[c],
                                       flat.positionsObject[c + 2] - flat.positionsObject[c]);
        const float length = glm::length(n);
        const glm::vec3 unit = length > 0.0f && std::isfinite(length) ? n / length : glm::vec3(0.0f, 0.0f, 1.0f);
        for (std::size_t k = 0; k < 3; ++k) {
            flat.normalsObject[c + k] = unit;
            flat.indices[c + k] = std::uint32_t(c + k);
        }
    }
    prim.positionsObject = std::move(flat.positionsObject);
    prim.normalsObject = std::move(flat.normalsObject);
    prim.texCoords0 = std::move(flat.texCoords0);
    prim.texCoords1 = std::move(flat.texCoords1);
    prim.colors0 = std::move(flat.colors0);
    prim.indices = std::move(flat.indices);
    prim.tangentsObject.clear();
}

} // namespace tessera::gltf_detail
