// GPU Pro 4 ch. 5 §5.5 (AMD's Leo demo), one-bounce indirect light: a reflective shadow map
// (Dachsbacher and Stamminger 2005) rendered from the scene's indirect spot or directional light,
// and an N x N grid of virtual spot lights taken from its texels, appended to the light list and
// culled like every other light. The chapter leaves the texel choice and the VPL parameters open:
// tessera's choices are below, each an option of forward-plus-amd.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/scene/light.h>
#include <tessera/scene/scene.h>

namespace tessera {

class Surface;

// "reflect" (default): the chapter's spot direction, "the reflection of the vector from the world
// position to the original indirect light around the normal", R = 2 (N.L) N - L; "normal": N
// (the axis of a diffuse reflector's cosine lobe).
enum class VplDirection : std::uint8_t { Reflect, Normal };

struct VplOptions {
    std::uint32_t rsmSize = 256;   // RSM edge, texels (square)
    std::uint32_t grid = 16;       // N: N x N VPLs
    float coneDeg = 60.0f;         // each VPL's spot half angle, degrees
    float range = 4.0f;            // each VPL's range, world units
    float intensity = 1.0f;        // scale of the VPLs' total colour (see vplsFromRsm)
    VplDirection direction = VplDirection::Reflect;
    float normalOffset = 0.01f;    // world units: the VPL sits this far off its surface along N
};

// The light's view of the scene for its RSM: a spot light looks down its axis through a square
// perspective of FOV 2 x half angle, near range / 1000, far range; a directional light through an
// orthographic box around the scene's bounding sphere (centre - direction * radius, depth 2 radius).
// D3D depth convention (z in [0, 1]); up is +Y unless the direction is within ~8 deg of it (+X).
struct RsmView {
    glm::mat4 clipFromWorld{1.0f};
    bool directional = false;
    glm::vec3 lightPositionWorld{0.0f};   // spot apex
    glm::vec3 lightDirectionWorld{0.0f};  // the direction light travels
};
RsmView rsmView(const Light& light, const Bounds& sceneBounds);

// The RSM texel VPL (i, j) comes from: the centre texel of grid cell (i, j), i.e.
// ((2 i + 1) * size / (2 N), (2 j + 1) * size / (2 N)) in integer arithmetic.
glm::uvec2 vplTexel(std::uint32_t i, std::uint32_t j, std::uint32_t rsmSize, std::uint32_t grid);

struct Vpl {
    glm::uvec2 texel{0u};
    bool valid = false;              // false where the texel saw no geometry (position.w == 0)
    glm::vec3 positionWorld{0.0f};   // the texel's position + normalOffset * normal
    glm::vec3 directionWorld{0.0f};  // VplDirection
    glm::vec3 color{0.0f};           // texel colour * intensity / N^2
};

// The N x N VPLs, row j major (index j * N + i), from the RSM targets (R32G32B32A32_FLOAT each):
// position (world, w = 1 where drawn), normal (world, unit), colour (the flux a texel reflects:
// diffuse albedo x light colour x intensity; the flux through a texel of a light's RSM does not
// depend on the surface's orientation, Dachsbacher and Stamminger 2005 §3). Summed over the grid
// the VPLs carry `intensity` times the average texel's colour.
std::vector<Vpl> vplsFromRsm(const Surface& position, const Surface& normal, const Surface& color, const RsmView& view,
                             const VplOptions& options);

// The VPL as a scene light: a spot at its position and direction with the options' cone and
// range, colour as computed, intensity 1, disabled when the texel was empty.
Light vplLight(const Vpl& vpl, const VplOptions& options);

} // namespace tessera
