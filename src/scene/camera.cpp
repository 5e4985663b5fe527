// The camera's view transform: world -> view is the inverse of the camera's placement
// (translate to positionWorld, then rotate by orientationWorld), i.e. R^T * T(-position).
// The projection is built by each technique (D3D or the demo's GL convention).
#include <tessera/scene/camera.h>

#include <glm/gtc/matrix_transform.hpp>

#include <tessera/math/unit_length.h>

namespace tessera {

glm::mat4 Camera::viewFromWorld() const {
    const glm::mat4 viewFromWorldRotation = glm::mat4_cast(glm::conjugate(glm::normalize(orientationWorld)));
    return glm::translate(viewFromWorldRotation, -positionWorld);
}

const char* LookAt::why() const {
    switch (problem) {
    case Problem::None: return "";
    case Problem::SamePoint: return "the target equals the position";
    case Problem::Overflow: return "target - position overflows binary32 (a component beyond 3.4e38)";
    case Problem::UpParallel: return "\"up\" is parallel to the view direction";
    }
    return "";
}

LookAt lookAtOrientation(glm::vec3 positionWorld, glm::vec3 targetWorld, glm::vec3 upWorld) {
    LookAt look;
    const glm::vec3 forward = targetWorld - positionWorld;
    if (forward == glm::vec3(0.0f)) {
        look.problem = LookAt::Problem::SamePoint;
        return look;
    }
    // Finite inputs can still differ by more than FLT_MAX (position 3e38, target -3e38).
    const std::optional<glm::vec3> unit = unitLength(forward);
    if (!unit) {
        look.problem = LookAt::Problem::Overflow;
        return look;
    }
    const glm::vec3 side = glm::cross(*unit, upWorld);
    if (!(glm::dot(side, side) > 1e-12f)) {
        look.problem = LookAt::Problem::UpParallel;
        return look;
    }
    look.orientationWorld = glm::quatLookAtRH(*unit, upWorld);  // -Z along the view direction
    return look;
}

} // namespace tessera
