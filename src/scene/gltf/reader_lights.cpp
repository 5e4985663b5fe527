// GltfReader's KHR_lights_punctual lights: every light the file defines checked, each light a
// node places converted, and a warning for the lights no node places.
#include "reader.h"

#include <cmath>
#include <cstddef>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>

#include "paths.h"

namespace tessera::gltf_detail {
namespace {

constexpr double kHalfPi = PI / 2;  // outerConeAngle's bound, radians

} // namespace

// KHR_lights_punctual README ("Light Shared Properties", "Range Property", "Spot Properties")
// and its schema light.schema.json, for EVERY light the file defines, referenced by a node or
// not (an unplaced light with a bad range is still a bad file, and was passed in silence):
//   type      "directional", "point" or "spot" (required)
//   color     3 numbers, each in [0, 1] (schema minimum 0, maximum 1); default [1, 1, 1]
//   intensity a finite number >= 0 (candela for point and spot, lux for directional); default 1
//   range     > 0 when given (schema exclusiveMinimum 0); absent: infinite (tinygltf: 0)
//   spot      0 <= innerConeAngle < outerConeAngle <= pi/2 (radians, half angles)
// Errors name the light's JSON pointer, /extensions/KHR_lights_punctual/lights/<i>/<key>.
void GltfReader::checkLights() const {
    for (std::size_t i = 0; i < mModel.lights.size(); ++i) {
        const tinygltf::Light& l = mModel.lights[i];
        const std::string path = indexPath("/extensions/KHR_lights_punctual/lights", i);
        if (l.type != "point" && l.type != "spot" && l.type != "directional")
            fail(path + "/type", "'" + l.type + "' is not point, spot or directional");
        if (!l.color.empty()) {
            if (l.color.size() != 3) fail(path + "/color", "needs 3 numbers, has " + std::to_string(l.color.size()));
            for (std::size_t c = 0; c < 3; ++c)
                if (!(l.color[c] >= 0.0 && l.color[c] <= 1.0))
                    fail(indexPath(path + "/color", c), formatDouble(l.color[c]) + " is outside [0, 1] (a linear RGB colour)");
        }
        if (!(l.intensity >= 0.0) || !std::isfinite(l.intensity))
            fail(path + "/intensity", formatDouble(l.intensity) + " is not a finite number >= 0");
        if (l.range < 0.0 || !std::isfinite(l.range))
            fail(path + "/range", formatDouble(l.range) + " is not positive (absent means infinite)");
        if (l.type == "spot") {
            const double inner = l.spot.innerConeAngle, outer = l.spot.outerConeAngle;
            // The bound pi/2 as written in a file may round either side of the double pi/2:
            // 1e-6 rad of slack (spotHalfAngleDeg is a float of degrees anyway).
            if (!(outer > 0.0 && outer <= kHalfPi + 1e-6))
                fail(path + "/spot/outerConeAngle", formatDouble(outer) + " is outside (0, pi/2]");
            if (!(inner >= 0.0 && inner < outer))
                fail(path + "/spot/innerConeAngle", formatDouble(inner) + " is outside [0, outerConeAngle = " +
                                                        formatDouble(outer) + ")");
        }
    }
}

// The lights the file defines against those its scene's nodes place (a light may be placed
// by several nodes, or by none: then it lights nothing, and the file's author should know).
void GltfReader::reportLights() {
    if (mModel.lights.empty()) return;
    const std::size_t defined = mModel.lights.size(), placed = mPlacedLights.size();
    if (placed == defined) return;
    warn("defines " + std::to_string(defined) + (defined == 1 ? " light, " : " lights, ") + std::to_string(placed) +
         (placed == 1 ? " placed by a node; " : " placed by nodes; ") + std::to_string(defined - placed) +
         " unreferenced (KHR_lights_punctual: a light shines only where a node of the scene places it)");
}

std::string GltfReader::formatDouble(double v) {
    std::ostringstream out;
    out << std::setprecision(17) << v;
    return out.str();
}

Light GltfReader::lightFrom(int index, const glm::mat4& worldFromNode, const std::string& nodeName) {
    const tinygltf::Light& l = mModel.lights[std::size_t(index)];
    const std::string path = indexPath("/extensions/KHR_lights_punctual/lights", std::size_t(index));
    mPlacedLights.insert(index);
    Light light;
    light.name = l.name.empty() ? nodeName : l.name;
    if (l.type == "point") light.type = LightType::Point;
    else if (l.type == "spot") light.type = LightType::Spot;
    else light.type = LightType::Directional;  // checkLights: one of the three
    light.color = vectorOf<3>(l.color, glm::vec3(1.0f), path + "/color");
    light.intensity = float(l.intensity);
    // tinygltf reads an absent range as 0; KHR_lights_punctual: absent = infinite.
    light.range = l.range == 0.0 ? std::numeric_limits<float>::infinity() : float(l.range);
    if (light.type == LightType::Spot) {
        light.spotHalfAngleDeg = float(l.spot.outerConeAngle * 180.0 / PI);
        light.spotInnerHalfAngleDeg = float(l.spot.innerConeAngle * 180.0 / PI);
    }
    light.positionWorld = glm::vec3(worldFromNode[3]);
    const glm::vec3 direction = glm::mat3(worldFromNode) * glm::vec3(0.0f, 0.0f, -1.0f);  // the node's -Z
    const float length = glm::length(direction);
    if (light.type != LightType::Point && !(length > 0.0f)) fail(path, "the light's node has a zero scale");
    light.directionWorld = length > 0.0f ? direction / length : glm::vec3(0.0f, 0.0f, -1.0f);
    return light;
}

} // namespace tessera::gltf_detail
