// Generated tangents for glTF primitives without TANGENT: per-triangle UV derivatives
// accumulated per vertex, mirrored-UV vertices split, then orthogonalized against the normal.
// "§" numbers cite the glTF 2.0 specification.
#include "tangents.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tessera::gltf_detail {
namespace {

// A unit vector perpendicular to n (for vertices whose UVs give no tangent direction).
glm::vec3 anyPerpendicular(const glm::vec3& n) {
    const glm::vec3 axis = std::abs(n.x) < 0.9f ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    const glm::vec3 t = axis - n * glm::dot(n, axis);
    const float length = glm::length(t);
    return length > 0.0f ? t / length : glm::vec3(1.0f, 0.0f, 0.0f);
}

// Appends a copy of vertex `v` (every attribute) and returns its index.
std::uint32_t duplicateVertex(MeshPrimitive& prim, std::uint32_t v) {
    const auto copyOf = [v](auto& attribute) {
        if (!attribute.empty()) attribute.push_back(attribute[v]);
    };
    copyOf(prim.positionsObject);
    copyOf(prim.normalsObject);
    copyOf(prim.texCoords0);
    copyOf(prim.texCoords1);
    copyOf(prim.colors0);
    return std::uint32_t(prim.positionsObject.size() - 1);
}

} // namespace


// MikkTSpace-like tangents (Mikkelsen 2008, "Simulation of Wrinkled Surfaces Revisited"): per
// triangle T = dP/du and B = dP/dv from the UV derivatives, projected into each corner's
// tangent plane, normalized and accumulated per vertex weighted by the corner angle; vertices
// shared by UV-preserving and UV-mirrored triangles are split in two, as MikkTSpace does; then
// T is Gram-Schmidt orthogonalized against N and w = sign(dot(cross(N, T), B)), so that
// bitangent = cross(normal, tangent.xyz) * w (§3.7.2.1). Differences from MikkTSpace: it
// also splits vertices whose accumulated frames diverge by angle thresholds, and gives
// UV-degenerate triangles their neighbours' tangents (here: such vertices get any unit
// vector perpendicular to N, w = +1).
// bitangentUp (GltfLoadOptions::generatedBitangentUp, ERRATA #33): B = -dP/dv instead, the
// direction of decreasing v, which is "up" in the image (glTF 2.0 §3.8, Texture Data: the UV origin is the image's top-left;
// §3.9.3: the normal texture's +Y is up), so w comes out negated.
void generateTangents(MeshPrimitive& prim, const std::vector<glm::vec2>& uvs, bool bitangentUp) {
    struct Accumulated {
        glm::vec3 tangent{0.0f}, bitangent{0.0f};
        bool used = false;
    };
    const std::size_t vertexCount = prim.positionsObject.size();
    const std::size_t triangleCount = prim.indices.size() / 3;
    std::vector<Accumulated> accumulated(vertexCount * 2);  // [vertex * 2 + mirrored]
    std::vector<std::uint8_t> mirrored(triangleCount, 0);

    for (std::size_t tri = 0; tri < triangleCount; ++tri) {
        const std::uint32_t* corner = &prim.indices[tri * 3];
        const glm::vec3 p[3] = {prim.positionsObject[corner[0]], prim.positionsObject[corner[1]],
                                prim.positionsObject[corner[2]]};
        const glm::vec2 uv[3] = {uvs[corner[0]], uvs[corner[1]], uvs[corner[2]]};
        const glm::vec3 edge1 = p[1] - p[0], edge2 = p[2] - p[0];
        const glm::vec2 duv1 = uv[1] - uv[0], duv2 = uv[2] - uv[0];
        const float signedUvArea2 = duv1.x * duv2.y - duv2.x * duv1.y;
        if (!(std::abs(signedUvArea2) > 0.0f)) continue;  // UV-degenerate: no direction
        const float orientation = signedUvArea2 > 0.0f ? 1.0f : -1.0f;
        mirrored[tri] = signedUvArea2 < 0.0f ? 1 : 0;
        // dP/du and dP/dv times the UV area (its magnitude drops out when normalized).
        const glm::vec3 tangentDir = (edge1 * duv2.y - edge2 * duv1.y) * orientation;
        const glm::vec3 bitangentDir = (edge2 * duv1.x - edge1 * duv2.x) * orientation;
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 toNext = p[(k + 1) % 3] - p[k], toPrev = p[(k + 2) % 3] - p[k];
            const float lengths = glm::length(toNext) * glm::length(toPrev);
            if (!(lengths > 0.0f)) continue;
            const float angle = std::acos(std::clamp(glm::dot(toNext, toPrev) / lengths, -1.0f, 1.0f));
            const glm::vec3& n = prim.normalsObject[corner[k]];
            glm::vec3 t = tangentDir - n * glm::dot(n, tangentDir);
            glm::vec3 b = bitangentDir - n * glm::dot(n, bitangentDir);
            const float tLength = glm::length(t), bLength = glm::length(b);
            if (tLength > 0.0f) t /= tLength;
            if (bLength > 0.0f) b /= bLength;
            Accumulated& slot = accumulated[std::size_t(corner[k]) * 2 + mirrored[tri]];
            slot.tangent += t * angle;
            slot.bitangent += b * angle;
            slot.used = true;
        }
    }

    // Split vertices used by both orientations: the mirrored triangles get a copy.
    std::vector<std::uint32_t> mirroredCopy(vertexCount, UINT32_MAX);
    for (std::size_t v = 0; v < vertexCount; ++v) {
        if (accumulated[v * 2].used && accumulated[v * 2 + 1].used) {
            mirroredCopy[v] = duplicateVertex(prim, std::uint32_t(v));
        }
    }
    for (std::size_t tri = 0; tri < triangleCount; ++tri) {
        if (!mirrored[tri]) continue;
        for (std::size_t k = 0; k < 3; ++k) {
            std::uint32_t& index = prim.indices[tri * 3 + k];
            if (index < vertexCount && mirroredCopy[index] != UINT32_MAX) index = mirroredCopy[index];
        }
    }

    prim.tangentsObject.assign(prim.positionsObject.size(), glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    auto finish = [&](std::size_t vertex, const Accumulated& slot, bool mirroredSlot) {
        const glm::vec3& n = prim.normalsObject[vertex];
        glm::vec3 t = slot.tangent - n * glm::dot(n, slot.tangent);  // Gram-Schmidt against N
        const float length = glm::length(t);
        if (!(length > 1e-12f)) {
            prim.tangentsObject[vertex] = glm::vec4(anyPerpendicular(n), 1.0f);
            return;
        }
        t /= length;
        const float handedness = glm::dot(glm::cross(n, t), slot.bitangent);
        const float w = handedness < 0.0f ? -1.0f : handedness > 0.0f ? 1.0f : (mirroredSlot ? -1.0f : 1.0f);
        prim.tangentsObject[vertex] = glm::vec4(t, bitangentUp ? -w : w);
    };
    for (std::size_t v = 0; v < vertexCount; ++v) {
        const Accumulated& preserving = accumulated[v * 2];
        const Accumulated& flipped = accumulated[v * 2 + 1];
        if (mirroredCopy[v] != UINT32_MAX) {
            finish(v, preserving, false);
            finish(mirroredCopy[v], flipped, true);
        } else {
            finish(v, flipped.used ? flipped : preserving, flipped.used);
        }
    }
    prim.tangentsGenerated = true;
}

} // namespace tessera::gltf_detail
