// The default light rig: what a lighting technique shades a scene with when the scene brings no
// lights at all (a bare glTF file), as glTF viewers light such files instead of showing them
// ambient-only and dark. `tessera render` announces it on stderr; --no-default-lights turns it off.
#pragma once

#include <vector>

#include <tessera/scene/camera.h>
#include <tessera/scene/light.h>
#include <tessera/scene/scene.h>

namespace tessera {

// Two white point lights placed from the render camera and the scene's world bounds (d = the
// bounds' diagonal; right/up = the camera's axes in world space):
//   "default key"  at camera + (up - right) * d / 2, intensity 1;
//   "default fill" at camera + right * d / 2 - up * d / 10, intensity 0.5.
// Point lights because every technique shades them (forward-plus-amd ignores directional ones).
// Each light's range is its largest distance to a corner of the bounds divided by 0.75, so the
// whole scene lies where the 3dgep attenuation 1 - smoothstep(0.75 range, range, d) is still 1.
// Empty when the bounds are empty or not finite.
std::vector<Light> defaultLightRig(const Bounds& bounds, const Camera& camera);

} // namespace tessera
