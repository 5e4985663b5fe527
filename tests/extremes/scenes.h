// Scene transforms the extremes cases build on the unit tests' room (support/room_scene.h):
// the whole world scaled or moved (geometry, lights, camera and its near/far together, so the
// image should not change), and a camera with a chosen projection.
#pragma once

#include <glm/gtc/matrix_transform.hpp>

#include "support/room_scene.h"

namespace tessera::test::extremes {

// The room with its default lights.
inline TestScene room() { return makeScene(defaultLights()); }

// Every length times `s`: instance transforms, light positions and ranges, the camera position
// and its near and far distances.
inline TestScene scaled(TestScene t, float s) {
    for (MeshInstance& i : t.scene.instances) i.worldFromObject = glm::scale(glm::mat4(1.0f), glm::vec3(s)) * i.worldFromObject;
    for (Light& l : t.scene.lights) {
        l.positionWorld *= s;
        if (l.type != LightType::Directional) l.range *= s;
    }
    t.camera.positionWorld *= s;
    t.camera.nearZ *= s;
    t.camera.farZ *= s;
    return t;
}

// Everything moved by `offsetWorld`.
inline TestScene translated(TestScene t, glm::vec3 offsetWorld) {
    for (MeshInstance& i : t.scene.instances) i.worldFromObject = glm::translate(glm::mat4(1.0f), offsetWorld) * i.worldFromObject;
    for (Light& l : t.scene.lights) l.positionWorld += offsetWorld;
    t.camera.positionWorld += offsetWorld;
    return t;
}

inline TestScene withNearFar(TestScene t, float nearZ, float farZ) {
    t.camera.nearZ = nearZ;
    t.camera.farZ = farZ;
    return t;
}

inline TestScene withLights(TestScene t, std::vector<Light> lights) {
    t.scene.lights = std::move(lights);
    return t;
}

} // namespace tessera::test::extremes
