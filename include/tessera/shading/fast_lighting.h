// The `fast` precision mode's light loop: every light of a pixel evaluated 4, 8 or 16 at a time
// (Highway, runtime dispatch) with fused multiply-adds, a reciprocal-square-root estimate refined
// by one Newton step instead of sqrt and division, and approximate exp/log for pow, from lights
// stored as structure of arrays once per frame (with the smoothstep spans' reciprocals). Same
// equations as doLighting (phong_lighting.h); the error against `reference` is measured by
// tests/precision, not assumed (the summation order differs too).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/shading/phong_lighting.h>

namespace tessera {

// View-space lights as arrays, padded with disabled lights to a multiple of 16.
struct FastLightSet {
    std::vector<float> px, py, pz;   // positionView (point, spot)
    std::vector<float> ax, ay, az;   // spot: directionView; directional: normalize(-directionView)
    std::vector<float> r, g, b;      // colour x intensity
    std::vector<float> range;        // view-space units
    // DoAttenuation's smoothstep edges as the loop uses them: 0.75 range and 1 / (range - 0.75 range).
    std::vector<float> attenuationStart, invAttenuationSpan;
    std::vector<float> minCos, maxCos;  // DoSpotCone's constants (spot)
    std::vector<float> invConeSpan;     // 1 / (maxCos - minCos)
    std::vector<float> kind;         // 0 point, 1 spot, 2 directional, -1 disabled or padding
    std::size_t count = 0;           // padded length

    static FastLightSet build(std::span<const ViewLight<float>> lights);
};

// DoLighting's sums (rgb; w unused) for one pixel: posView and normalView as the pixel shader
// has them, specular evaluated only when withSpecular.
LightingResult<float> fastLighting(const FastLightSet& lights, float specularPower, const glm::vec3& posView,
                                   const glm::vec3& normalView, bool withSpecular);

} // namespace tessera
