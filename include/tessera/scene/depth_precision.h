// How finely a 24-bit (or binary32) depth buffer resolves view distances for a camera, and the
// warning a render prints when a scene lies where it cannot: surfaces that all get depth 1.0
// (the cleared value) or a depth step wider than 1% of the distance.
#pragma once

#include <optional>
#include <string>

#include <tessera/scene/camera.h>
#include <tessera/scene/scene.h>

namespace tessera {

// One depth-buffer step below 1.0: D24 UNORM's 1/(2^24 - 1), and binary32's spacing in [0.5, 1)
// (2^-24) is the same to 7 digits.
inline constexpr double kDepthStepNearOne = 1.0 / 16777215.0;
// The relative resolution (depth step in view units / distance) beyond which a render warns.
inline constexpr double kDepthWarnRelativeStep = 0.01;

struct DepthResolution {
    // D3D depth d(z) = f/(f - n) (1 - n/z) (perspective, D3D11.3 §15.5 depth range [0, 1]):
    // d rounds to 1.0 (the cleared value) once 1 - d < half a step, i.e. beyond
    // z = n / (step/2 (f - n)/f + n/f) ~ 2^25 n.
    double collapseDistance = 0.0;
    // The view distance one depth step spans at distance z: step / d'(z), d'(z) = f n / ((f - n) z^2).
    double stepAt(double distance) const;
    double nearZ = 0.0, farZ = 0.0;
};

// Perspective cameras only (an orthographic depth is linear: one step is (f - n) / 2^24).
DepthResolution depthResolution(const Camera& camera);

// A warning, or nothing, for rendering a scene with these bounds: the bounds' farthest corner
// (in view depth, clamped to far) against collapseDistance and kDepthWarnRelativeStep. Names the
// distances and the near plane that would resolve the scene.
std::optional<std::string> depthPrecisionWarning(const Camera& camera, const Bounds& sceneWorld);

} // namespace tessera
