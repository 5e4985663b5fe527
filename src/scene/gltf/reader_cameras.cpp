// GltfReader's cameras: a camera placed by a node, its orientation from the node's world
// transform, and its perspective or orthographic projection checked.
#include "reader.h"

#include <cmath>
#include <cstddef>
#include <limits>
#include <string>

#include <glm/gtc/quaternion.hpp>

#include "paths.h"

namespace tessera::gltf_detail {

Camera GltfReader::cameraFrom(int index, const glm::mat4& worldFromNode, const std::string& nodeName) const {
    const tinygltf::Camera& c = mModel.cameras[std::size_t(index)];
    const std::string path = indexPath("/cameras", std::size_t(index));
    Camera camera;
    camera.name = c.name.empty() ? nodeName : c.name;
    camera.positionWorld = glm::vec3(worldFromNode[3]);
    // Orientation: the node's rotation with scale removed (Gram-Schmidt of the basis).
    glm::vec3 x = glm::vec3(worldFromNode[0]), y = glm::vec3(worldFromNode[1]);
    if (!(glm::length(x) > 0.0f) || !(glm::length(y) > 0.0f)) fail(path, "the camera's node has a zero scale");
    x = glm::normalize(x);
    y = glm::normalize(y - x * glm::dot(x, y));
    camera.orientationWorld = glm::normalize(glm::quat_cast(glm::mat3(x, y, glm::cross(x, y))));
    if (c.type == "perspective") {
        const auto& p = c.perspective;
        camera.projection = ProjectionKind::Perspective;
        if (!(p.yfov > 0.0 && p.yfov < PI)) {
            fail(path + "/perspective/yfov", std::to_string(p.yfov) + " is outside (0, pi)");
        }
        if (!(p.znear > 0.0)) fail(path + "/perspective/znear", std::to_string(p.znear) + " is not positive");
        if (p.zfar != 0.0 && !(p.zfar > p.znear)) {
            fail(path + "/perspective/zfar", std::to_string(p.zfar) + " is not greater than znear");
        }
        if (!(p.aspectRatio >= 0.0)) fail(path + "/perspective/aspectRatio", "is negative");
        camera.fovYDeg = float(p.yfov * 180.0 / PI);
        camera.nearZ = float(p.znear);
        camera.farZ = p.zfar == 0.0 ? std::numeric_limits<float>::infinity() : float(p.zfar);  // absent: infinite
        camera.aspect = float(p.aspectRatio);
    } else if (c.type == "orthographic") {
        const auto& o = c.orthographic;
        camera.projection = ProjectionKind::Orthographic;
        if (o.xmag == 0.0 || !std::isfinite(o.xmag)) fail(path + "/orthographic/xmag", "must be finite and non-zero");
        if (o.ymag == 0.0 || !std::isfinite(o.ymag)) fail(path + "/orthographic/ymag", "must be finite and non-zero");
        if (!(o.znear >= 0.0)) fail(path + "/orthographic/znear", "is negative");
        if (!(o.zfar > o.znear) || !std::isfinite(o.zfar)) {
            fail(path + "/orthographic/zfar", std::to_string(o.zfar) + " is not a finite value greater than znear");
        }
        camera.xMag = float(o.xmag);
        camera.yMag = float(o.ymag);
        camera.nearZ = float(o.znear);
        camera.farZ = float(o.zfar);
    } else {
        fail(path + "/type", "'" + c.type + "' is not perspective or orthographic");
    }
    return camera;
}

} // namespace tessera::gltf_detail
