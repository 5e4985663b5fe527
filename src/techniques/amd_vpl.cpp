// Reflective shadow map views and VPL creation for forward-plus-amd's indirect light (GPU Pro 4
// ch. 5 §5.5): the light's camera, the grid of texels the VPLs come from, and each VPL's spot light.
#include <tessera/techniques/amd_vpl.h>

#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>

#include <tessera/buffers/surface.h>
#include <tessera/math/det_math.h>
#include <tessera/shading/phong_lighting.h>

namespace tessera {
namespace {

constexpr float kNearFraction = 1.0f / 1000.0f;  // spot RSM near plane, as a fraction of the range
constexpr float kUpParallelCos = 0.99f;          // |dir . +Y| above this: +X is "up" (about 8.1 deg)

glm::vec4 texelOf(const Surface& s, glm::uvec2 t) {
    glm::vec4 v;
    std::memcpy(&v, s.texel(t.x, t.y), sizeof(v));
    return v;
}

} // namespace

RsmView rsmView(const Light& light, const Bounds& sceneBounds) {
    RsmView view;
    view.directional = light.type == LightType::Directional;
    view.lightDirectionWorld = glm::normalize(light.directionWorld);
    const glm::vec3 up = std::fabs(view.lightDirectionWorld.y) > kUpParallelCos ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    if (view.directional) {
        const glm::vec3 centre = sceneBounds.empty() ? glm::vec3(0.0f) : (sceneBounds.minWorld + sceneBounds.maxWorld) * 0.5f;
        const float radius = sceneBounds.empty() ? 1.0f : std::max(glm::length(sceneBounds.maxWorld - centre), 1e-6f);
        const glm::vec3 eye = centre - view.lightDirectionWorld * radius;
        view.lightPositionWorld = eye;
        const glm::mat4 viewFromWorld = glm::lookAtRH(eye, centre, up);
        view.clipFromWorld = glm::orthoRH_ZO(-radius, radius, -radius, radius, 0.0f, 2.0f * radius) * viewFromWorld;
    } else {
        view.lightPositionWorld = light.positionWorld;
        const float range = std::isfinite(light.range) ? light.range : 1000.0f;
        const glm::mat4 viewFromWorld =
            glm::lookAtRH(light.positionWorld, light.positionWorld + view.lightDirectionWorld, up);
        view.clipFromWorld =
            glm::perspectiveRH_ZO(2.0f * hlsl::radians(light.spotHalfAngleDeg), 1.0f, range * kNearFraction, range) * viewFromWorld;
    }
    return view;
}

glm::uvec2 vplTexel(std::uint32_t i, std::uint32_t j, std::uint32_t rsmSize, std::uint32_t grid) {
    return {std::uint32_t((2ull * i + 1) * rsmSize / (2ull * grid)), std::uint32_t((2ull * j + 1) * rsmSize / (2ull * grid))};
}

std::vector<Vpl> vplsFromRsm(const Surface& position, const Surface& normal, const Surface& color, const RsmView& view,
                             const VplOptions& options) {
    const std::uint32_t n = options.grid;
    std::vector<Vpl> vpls(std::size_t{n} * n);
    const float scale = options.intensity / float(std::size_t{n} * n);
    for (std::uint32_t j = 0; j < n; ++j)
        for (std::uint32_t i = 0; i < n; ++i) {
            Vpl& v = vpls[std::size_t{j} * n + i];
            v.texel = vplTexel(i, j, options.rsmSize, n);
            const glm::vec4 p = texelOf(position, v.texel);
            if (!(p.w > 0.0f)) continue;
            v.valid = true;
            const glm::vec3 nrm(texelOf(normal, v.texel));
            const glm::vec3 toLight =
                view.directional ? -view.lightDirectionWorld : glm::normalize(view.lightPositionWorld - glm::vec3(p));
            v.positionWorld = glm::vec3(p) + nrm * options.normalOffset;
            v.directionWorld = options.direction == VplDirection::Reflect
                                   ? glm::normalize(2.0f * glm::dot(nrm, toLight) * nrm - toLight)
                                   : nrm;
            v.color = glm::vec3(texelOf(color, v.texel)) * scale;
        }
    return vpls;
}

Light vplLight(const Vpl& vpl, const VplOptions& options) {
    Light light;
    light.type = LightType::Spot;
    light.positionWorld = vpl.positionWorld;
    light.directionWorld = vpl.valid ? vpl.directionWorld : glm::vec3(0.0f, 0.0f, -1.0f);
    light.color = vpl.color;
    light.intensity = 1.0f;
    light.range = options.range;
    light.spotHalfAngleDeg = options.coneDeg;
    light.enabled = vpl.valid;
    light.name = "vpl";
    return light;
}

} // namespace tessera
