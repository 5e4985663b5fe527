// Lights in tessera's world units: point, spot and directional, the union of what
// KHR_lights_punctual, the scene file's explicit lists and its generators describe, and the
// capsule lights of the HLSL Development Cookbook (scene files only; only deferred-cookbook
// shades them, every other technique skips them with a warning). The 3dgep shading model reads
// range and spotHalfAngleDeg exactly as its Light struct does (3dgep article §2.2.3).
#pragma once

#include <limits>
#include <string>

#include <glm/glm.hpp>

#include <tessera/scene/mesh.h>

namespace tessera {

// 3dgep's POINT, SPOT, DIRECTIONAL; Capsule: the Cookbook's segment light (ch. 1 "Capsule light").
enum class LightType { Point = 0, Spot = 1, Directional = 2, Capsule = 3 };

struct Light {
    LightType type = LightType::Point;
    glm::vec3 positionWorld{0.0f};
    glm::vec3 directionWorld{0.0f, 0.0f, -1.0f};  // unit; spot and directional (direction light travels)
    glm::vec3 color{1.0f};                         // linear RGB
    float intensity = 1.0f;
    float range = std::numeric_limits<float>::infinity();  // world units; KHR: absent = infinite
    float spotHalfAngleDeg = 45.0f;       // 3dgep SpotlightAngle: the cone's half angle (outer), degrees
    float spotInnerHalfAngleDeg = 0.0f;   // KHR innerConeAngle in degrees (3dgep ignores it)
    float length = 0.0f;  // capsule: the segment from positionWorld along directionWorld, world units
    bool enabled = true;
    std::uint8_t lightGroups = kAllLightGroups;  // the geometry groups it lights (mesh.h; deferred-classic, light-prepass)
    // GPU Pro 4 ch. 5 (forward-plus-amd only): castsShadows: shadow rays to this light (§5.6.2);
    // indirect: a spot or directional light whose reflective shadow map spawns VPLs (§5.5).
    bool castsShadows = false;
    bool indirect = false;
    std::string name;
};

} // namespace tessera
