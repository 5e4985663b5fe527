// A camera: a view transform and a vertical-FOV perspective (or orthographic) projection.
// Projection matrices are built by the technique (D3D or the demo's GL form, per its options).
#pragma once

#include <string>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace tessera {

enum class ProjectionKind { Perspective, Orthographic };

struct Camera {
    std::string name;
    glm::vec3 positionWorld{0.0f};
    glm::quat orientationWorld{1.0f, 0.0f, 0.0f, 0.0f};  // camera looks down its local -Z, +Y up (glTF)
    ProjectionKind projection = ProjectionKind::Perspective;
    float fovYDeg = 45.0f;     // perspective: vertical field of view, degrees, in (0, 180)
    float xMag = 1.0f, yMag = 1.0f;  // orthographic half extents (glTF xmag/ymag)
    float nearZ = 0.1f;        // distance to the near plane, > 0
    float farZ = 1000.0f;      // distance to the far plane, > nearZ (glTF infinite: +inf)
    float aspect = 0.0f;       // width / height; 0 = take it from the render resolution

    // View matrix: world -> view (right-handed, camera at the origin looking down -Z).
    glm::mat4 viewFromWorld() const;
};

// A look-at orientation: a camera at positionWorld whose -Z looks at targetWorld, +Y towards
// upWorld (right-handed), as a scene file's camera {position, target, up} and the command line's
// --camera-position / --camera-target build it. A problem leaves the orientation unset.
struct LookAt {
    enum class Problem { None, SamePoint, Overflow, UpParallel };
    glm::quat orientationWorld{1.0f, 0.0f, 0.0f, 0.0f};
    Problem problem = Problem::None;
    const char* why() const;  // the problem in words ("the target equals the position", ...)
};
LookAt lookAtOrientation(glm::vec3 positionWorld, glm::vec3 targetWorld, glm::vec3 upWorld);

} // namespace tessera
