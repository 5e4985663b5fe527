// GltfReader's node hierarchy: the nodes checked to form strict trees, the scene's roots walked
// depth-first with each node's local transform, and the meshes, cameras and lights they place.
// "§" numbers cite the glTF 2.0 specification.
#include "reader.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "paths.h"

namespace tessera::gltf_detail {

// §3.5.3: matrix, or T * R * S from translation, rotation (unit quaternion xyzw) and scale.
glm::mat4 GltfReader::localFromNode(const tinygltf::Node& node, const std::string& path) const {
    auto finite = [&](const std::vector<double>& values, const char* key) {
        for (double v : values) {
            if (!std::isfinite(v)) fail(path + "/" + key, "holds a non-finite value");
        }
    };
    if (!node.matrix.empty()) {
        if (node.matrix.size() != 16) fail(path + "/matrix", "needs 16 numbers");
        finite(node.matrix, "matrix");
        glm::mat4 m;
        for (int column = 0; column < 4; ++column) {
            for (int row = 0; row < 4; ++row) m[column][row] = float(node.matrix[std::size_t(column * 4 + row)]);
        }
        return m;
    }
    glm::vec3 translation(0.0f), scale(1.0f);
    glm::quat rotation(1.0f, 0.0f, 0.0f, 0.0f);
    if (!node.translation.empty()) {
        if (node.translation.size() != 3) fail(path + "/translation", "needs 3 numbers");
        finite(node.translation, "translation");
        translation = {float(node.translation[0]), float(node.translation[1]), float(node.translation[2])};
    }
    if (!node.rotation.empty()) {
        if (node.rotation.size() != 4) fail(path + "/rotation", "needs 4 numbers (x, y, z, w)");
        finite(node.rotation, "rotation");
        rotation = glm::quat(float(node.rotation[3]), float(node.rotation[0]), float(node.rotation[1]),
                             float(node.rotation[2]));
        const float length = glm::length(rotation);
        if (!(length > 0.0f)) fail(path + "/rotation", "is a zero quaternion");
        rotation = rotation / length;
    }
    if (!node.scale.empty()) {
        if (node.scale.size() != 3) fail(path + "/scale", "needs 3 numbers");
        finite(node.scale, "scale");
        scale = {float(node.scale[0]), float(node.scale[1]), float(node.scale[2])};
    }
    return glm::translate(glm::mat4(1.0f), translation) * glm::mat4_cast(rotation) *
           glm::scale(glm::mat4(1.0f), scale);
}

void GltfReader::readNodes() {
    const std::size_t nodeCount = mModel.nodes.size();
    // §3.5.1: the nodes form disjoint strict trees: one parent at most, no cycles.
    std::vector<int> parent(nodeCount, -1);
    for (std::size_t n = 0; n < nodeCount; ++n) {
        const auto& children = mModel.nodes[n].children;
        for (std::size_t k = 0; k < children.size(); ++k) {
            const std::string childPath = indexPath(indexPath("/nodes", n) + "/children", k);
            checkIndex(children[k], nodeCount, childPath, "node");
            int& childParent = parent[std::size_t(children[k])];
            if (childParent != -1) {
                fail(childPath, "node " + std::to_string(children[k]) + " already has parent " +
                                    std::to_string(childParent) + " (nodes must form strict trees)");
            }
            childParent = int(n);
        }
    }
    for (std::size_t n = 0; n < nodeCount; ++n) {  // walk up: more steps than nodes means a cycle
        std::size_t steps = 0;
        for (int at = parent[n]; at != -1; at = parent[std::size_t(at)]) {
            if (std::size_t(at) == n || ++steps > nodeCount) {
                fail(indexPath("/nodes", n), "the node is its own ancestor (a cycle in children)");
            }
        }
    }
    std::vector<int> roots;
    std::string rootsPath;
    if (!mModel.scenes.empty()) {
        int sceneIndex = mOptions.sceneIndex >= 0 ? mOptions.sceneIndex : std::max(mModel.defaultScene, 0);
        if (mOptions.sceneIndex >= 0) checkIndex(sceneIndex, mModel.scenes.size(), "/scenes", "scene");
        else checkIndex(sceneIndex, mModel.scenes.size(), "/scene", "scene");
        roots = mModel.scenes[std::size_t(sceneIndex)].nodes;
        rootsPath = indexPath("/scenes", std::size_t(sceneIndex)) + "/nodes";
    } else {
        if (mOptions.sceneIndex >= 0) checkIndex(mOptions.sceneIndex, 0, "/scenes", "scene");
        for (std::size_t n = 0; n < nodeCount; ++n) {  // no scenes: every root node
            if (parent[n] == -1) roots.push_back(int(n));
        }
        rootsPath = "/nodes";
    }
    std::vector<std::uint8_t> visited(nodeCount, 0);
    for (std::size_t r = 0; r < roots.size(); ++r) {
        const std::string rootPath = indexPath(rootsPath, r);
        checkIndex(roots[r], nodeCount, rootPath, "node");
        if (parent[std::size_t(roots[r])] != -1) {
            fail(rootPath, "node " + std::to_string(roots[r]) + " is a child of node " +
                               std::to_string(parent[std::size_t(roots[r])]) + ", not a root");
        }
        if (visited[std::size_t(roots[r])]) fail(rootPath, "node " + std::to_string(roots[r]) + " is listed twice");
        // Depth-first, children in order, with an explicit stack (deep hierarchies are fine).
        std::vector<std::pair<int, glm::mat4>> stack{{roots[r], mOptions.worldFromFile}};
        while (!stack.empty()) {
            const auto [index, worldFromParent] = stack.back();
            stack.pop_back();
            visited[std::size_t(index)] = 1;
            visitNode(index, worldFromParent, stack);
        }
    }
}

void GltfReader::visitNode(int index, const glm::mat4& worldFromParent, std::vector<std::pair<int, glm::mat4>>& stack) {
    const tinygltf::Node& node = mModel.nodes[std::size_t(index)];
    const std::string path = indexPath("/nodes", std::size_t(index));
    const glm::mat4 worldFromNode = worldFromParent * localFromNode(node, path);
    if (node.mesh != -1) {
        checkIndex(node.mesh, mModel.meshes.size(), path + "/mesh", "mesh");
        mOut.instances.push_back({mMeshBase + node.mesh, worldFromNode, node.name, mOptions.lightGroups});
    }
    if (node.skin != -1 && !mSkinWarned) {
        warn(path + "/skin: skins are ignored (meshes are drawn in their bind pose)");
        mSkinWarned = true;
    }
    if (node.camera != -1) {
        checkIndex(node.camera, mModel.cameras.size(), path + "/camera", "camera");
        mOut.cameras.push_back(cameraFrom(node.camera, worldFromNode, node.name));
    }
    const auto lightExtension = node.extensions.find("KHR_lights_punctual");
    if (lightExtension != node.extensions.end() && lightExtension->second.Has("light")) {
        const tinygltf::Value& value = lightExtension->second.Get("light");
        const std::string lightPath = path + "/extensions/KHR_lights_punctual/light";
        if (!value.IsNumber()) fail(lightPath, "is not a number");
        const int light = value.GetNumberAsInt();
        checkIndex(light, mModel.lights.size(), lightPath, "light");
        mOut.lights.push_back(lightFrom(light, worldFromNode, node.name));
    }
    for (auto child = node.children.rbegin(); child != node.children.rend(); ++child) {
        stack.emplace_back(*child, worldFromNode);  // reversed: popped in file order
    }
}

} // namespace tessera::gltf_detail
