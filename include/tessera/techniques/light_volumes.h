// The 3dgep demo's light-volume meshes and their transforms (3dgep
// demo Engine/src/DX11/RenderDeviceDX11.cpp and GraphicsTest/src/DeferredLightingPass.cpp):
// a subdivided icosahedron for point lights, a closed cone for spot lights, and the
// T * R * S model matrix; plus the circumscribed fit that corrects the inscribed polygons.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <tessera/scene/light.h>

namespace tessera {

// A closed, convex triangle mesh in object space: an indexed triangle list whose triangles run
// counter-clockwise seen from outside (outward normals by the right-hand rule). Drawn with the
// demo's FrontCounterClockwise = TRUE (deferred_states.h), the outside is the front face.
struct VolumeMesh {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;  // 3 per triangle
    std::size_t triangleCount() const { return indices.size() / 3; }
};

// Point volume: the demo's `CreateSphere(1.0f)` writes the NFF lines `tess 4` and `s 0 0 0 1`;
// assimp's NFF loader builds it with StandardShapes::MakeSphere(4): an icosahedron whose
// triangles are split in four `tess` times, new vertices pushed out to the unit sphere.
inline constexpr unsigned kDemoSphereTessellation = 4;
// Spot volume: the demo's `CreateCylinder(0, 1, 1, (0,0,1))` writes an NFF `c` cone without a
// `tess` line, so assimp's default tessellation 4 applies and the NFF loader calls
// StandardShapes::MakeCone with integer_pow(4, 4) = 256 segments.
inline constexpr unsigned kDemoConeSlices = 256;

// assimp StandardShapes::MakeSphere(subdivisions), same float operation order (icosahedron
// from t = (1 + 2.236067977f)/2 scaled by 1/sqrt(1 + t^2); midpoints normalize(a + b) * |v0|),
// same triangle order, then identical positions joined (assimp JoinIdenticalVertices).
// 20 * 4^s triangles and 10 * 4^s + 2 vertices (s = 4: 5120 and 2562), every vertex on the
// unit sphere to float precision: the polyhedron is INSCRIBED in the sphere.
// Throws std::invalid_argument for subdivisions > 8 (index range).
VolumeMesh makeIcosphere(unsigned subdivisions);

// The demo's spot volume: apex at the origin, base of radius 1 at z = 1, axis +Z, closed by the
// base disc. Rim vertex k is (cos a_k, -sin a_k, 1), a_k = 2 pi k / slices, which is where
// assimp's MakeCone (y axis) lands after the NFF node transform (rotation Y -> Z, centre
// (0,0,0.5)). slices + 2 vertices, 2 * slices triangles (assimp also emits 2 * slices
// degenerate ones at the apex, which its FindDegenerates + SortByPType steps remove). The rim is
// closed exactly; assimp accumulates the angle in float and its last segment ends ~1e-5 rad past
// 2 pi. sin/cos come from a fixed double-precision series, not the libm.
// Throws std::invalid_argument for slices < 3.
VolumeMesh makeUnitCone(unsigned slices);

// Uniform scale that makes an inscribed convex mesh contain the unit sphere:
// 1 / (smallest distance from the origin to a face plane), computed in double from the float
// positions and rounded up to float.
float circumscribedSphereScale(const VolumeMesh& inscribedSphere);
// XY scale that makes makeUnitCone(slices) contain the circular cone (r <= z, 0 <= z <= 1): the
// rim polygon's edges then touch the unit circle, 1 / cos(pi / slices), rounded up to float.
float circumscribedConeRadialScale(unsigned slices);

// Which volume is drawn: the demo's polygons inscribed in the light's sphere or cone (faithful;
// pixels near the range lose the light that forward shading gives them, an erratum), or scaled
// so that they contain it (corrected).
enum class VolumeFit : std::uint8_t { Inscribed, Circumscribed };

// How the model matrix turns +Z towards the light direction.
enum class VolumeRotation : std::uint8_t {
    // faithful: glm 0.9.6 `quat(vec3(0,0,1), dir)` = normalize(quat(1 + dot, cross)); for
    // dir = -Z that quaternion is 0 and glm's normalize returns identity, so the volume keeps
    // pointing along +Z (a spot light aimed straight down -Z gets the wrong cone).
    Glm096,
    // corrected: the demo's own RotationFromTwoVectors (RenderDeviceDX11.cpp, after lolengine
    // 2014): antiparallel vectors rotate 180 degrees about an orthogonal axis.
    Robust,
};

// The unit quaternion that turns `from` into `to` (both unit length) per `mode`.
glm::quat rotationBetween(const glm::vec3& from, const glm::vec3& to, VolumeRotation mode);

struct LightVolumeOptions {
    VolumeFit fit = VolumeFit::Inscribed;
    VolumeRotation rotation = VolumeRotation::Glm096;
};

// Ranges beyond this (world units) are scaled to the view's reach (LightVolumes::worldFromObject).
inline constexpr float kVolumeOverflowRange = 1e30f;

// The largest distance from posWorld to the view frustum of clipFromWorld: its corners at NDC
// x, y = +-1 and z = -1, 0, 1 (both depth conventions' near and far planes), unprojected in
// double. +inf when a corner is not finite (an infinite far plane).
float frustumReachWorld(const glm::vec3& posWorld, const glm::mat4& clipFromWorld);

// The two meshes of a frame with their circumscribe scales.
class LightVolumes {
public:
    explicit LightVolumes(unsigned sphereTessellation = kDemoSphereTessellation, unsigned coneSlices = kDemoConeSlices);

    const VolumeMesh& sphere() const { return mSphere; }
    const VolumeMesh& cone() const { return mCone; }
    float sphereCircumscribeScale() const { return mSphereScale; }
    float coneCircumscribeRadialScale() const { return mConeRadialScale; }
    // Point -> sphere, Spot -> cone. Throws std::invalid_argument for directional lights (they
    // are drawn as a full-screen quad).
    const VolumeMesh& meshFor(LightType type) const;

    // Model matrix of the light's volume (DeferredLightingPass.cpp Visit):
    //   T(positionWorld) * R(rotationBetween((0,0,1), normalize(directionWorld))) * S,
    //   point: S = Range (times the sphere scale when circumscribed);
    //   spot:  S = (tan(radians(angle)) * Range, same, Range), XY times the cone's radial scale
    //          when circumscribed; `angle` is the half angle, valid in (0, 90) degrees; tan is
    //          det_math.h's detTan (libm-independent).
    // A zero or non-finite direction gives no rotation. Throws std::invalid_argument for
    // directional lights.
    // clipFromWorld (the frame's, or null): where Range exceeds kVolumeOverflowRange, the
    // clip-space transform of a volume that large overflows binary32 (range 3e38 x the
    // projection's 2.4: every vertex at infinity, the light lost), so S is scaled down uniformly
    // until Range is twice the view's reach (frustumReachWorld): the volume still holds every
    // visible point the light reaches, and the shading keeps the light's own range. Other volumes
    // are untouched, and the reach is computed only for those beyond the threshold.
    glm::mat4 worldFromObject(const Light& light, const LightVolumeOptions& options = {},
                              const glm::mat4* clipFromWorld = nullptr) const;

private:
    VolumeMesh mSphere, mCone;
    float mSphereScale = 1.0f, mConeRadialScale = 1.0f;
};

} // namespace tessera
