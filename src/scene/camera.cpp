// The camera's view transform: world -> view is the inverse of the camera's placement
// (translate to positionWorld, then rotate by orientationWorld), i.e. R^T * T(-position).
// The projection is built by each technique (D3D or the demo's GL convention).
#include <tessera/scene/camera.h>

#include <glm/gtc/matrix_transform.hpp>

namespace tessera {

glm::mat4 Camera::viewFromWorld() const {
    const glm::mat4 viewFromWorldRotation = glm::mat4_cast(glm::conjugate(glm::normalize(orientationWorld)));
    return glm::translate(viewFromWorldRotation, -positionWorld);
}

} // namespace tessera
