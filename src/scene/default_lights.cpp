// defaultLightRig (scene/default_lights.h): two point lights from the camera and the bounds.
#include <tessera/scene/default_lights.h>

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>

namespace tessera {

std::vector<Light> defaultLightRig(const Bounds& bounds, const Camera& camera) {
    if (bounds.empty()) return {};
    const glm::vec3 extent = bounds.maxWorld - bounds.minWorld;
    const float diagonal = glm::length(extent);
    if (!std::isfinite(diagonal) || !std::isfinite(glm::length(camera.positionWorld))) return {};
    const glm::vec3 right = camera.orientationWorld * glm::vec3(1.0f, 0.0f, 0.0f);
    const glm::vec3 up = camera.orientationWorld * glm::vec3(0.0f, 1.0f, 0.0f);
    const auto makeLight = [&](const char* name, glm::vec3 position, float intensity) {
        Light l;
        l.type = LightType::Point;
        l.name = name;
        l.positionWorld = position;
        l.intensity = intensity;
        float farthest = 0.0f;
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 c((corner & 1) ? bounds.maxWorld.x : bounds.minWorld.x, (corner & 2) ? bounds.maxWorld.y : bounds.minWorld.y,
                              (corner & 4) ? bounds.maxWorld.z : bounds.minWorld.z);
            farthest = std::max(farthest, glm::length(c - position));
        }
        l.range = std::max(farthest, 1e-6f) / 0.75f;
        return l;
    };
    return {makeLight("default key", camera.positionWorld + (up - right) * (0.5f * diagonal), 1.0f),
            makeLight("default fill", camera.positionWorld + right * (0.5f * diagonal) - up * (0.1f * diagonal), 0.5f)};
}

} // namespace tessera
