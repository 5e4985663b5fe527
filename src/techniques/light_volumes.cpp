// Light-volume meshes (assimp NFF sphere and cone as the 3dgep demo loads them), their
// circumscribed scales and the per-light model matrix (3dgep demo DeferredLightingPass.cpp).
#include <tessera/techniques/light_volumes.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include <tessera/math/det_math.h>

namespace tessera {

namespace {

// sin and cos of 2 pi k / n in double without the libm: exact quadrant and half-quadrant
// reduction in integers, then Taylor series on [0, pi/4] (terms to x^21: truncation < 1e-20).
// Fixed operation order, so the results are the same on every IEEE machine.
void sinCosOfTurn(std::uint64_t k, std::uint64_t n, double& sinOut, double& cosOut) {
    constexpr double kHalfPi = 1.57079632679489661923;
    k %= n;
    const std::uint64_t quadrant = (4 * k) / n, rem = 4 * k - quadrant * n;  // angle = (q + rem/n) pi/2
    const bool reflect = 2 * rem > n;                                        // alpha > pi/4
    const double x = kHalfPi * (double(reflect ? n - rem : rem) / double(n)); // in [0, pi/4]
    const double x2 = x * x;
    double sinX = 0.0, cosX = 0.0, termSin = x, termCos = 1.0;
    for (int i = 1; i <= 11; ++i) {
        sinX += termSin;
        cosX += termCos;
        termSin *= -x2 / double((2 * i) * (2 * i + 1));
        termCos *= -x2 / double((2 * i - 1) * (2 * i));
    }
    const double sinA = reflect ? cosX : sinX, cosA = reflect ? sinX : cosX;  // of alpha
    switch (quadrant) {
    case 0: sinOut = sinA; cosOut = cosA; break;
    case 1: sinOut = cosA; cosOut = -sinA; break;
    case 2: sinOut = -sinA; cosOut = -cosA; break;
    default: sinOut = -cosA; cosOut = sinA; break;
    }
}

// "<what>: <n> <problem>" built piecewise (GCC 12 -O3 misfires -Wrestrict on "literal" + string).
std::invalid_argument countError(const char* what, unsigned n, const char* problem) {
    std::string message(what);
    message += ": ";
    message += std::to_string(n);
    message += problem;
    return std::invalid_argument(message);
}

// The smallest float >= x (x > 0, finite).
float roundUpToFloat(double x) {
    float f = static_cast<float>(x);
    if (double(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
}

// aiVector3D::Length / Normalize / operator* as assimp 3.x writes them (aiVector3D.inl):
// Length = sqrt(x*x + y*y + z*z), Normalize divides each component, v * f = (f*x, f*y, f*z).
float aiLength(const glm::vec3& v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }
glm::vec3 aiNormalize(const glm::vec3& v) {
    const float len = aiLength(v);
    return glm::vec3(v.x / len, v.y / len, v.z / len);
}
glm::vec3 aiScale(const glm::vec3& v, float f) { return glm::vec3(f * v.x, f * v.y, f * v.z); }

// Triangle soup -> indexed mesh; positions with equal coordinates share one index, numbered in
// order of first use.
VolumeMesh joinIdenticalVertices(const std::vector<glm::vec3>& soup) {
    VolumeMesh mesh;
    std::map<std::tuple<float, float, float>, std::uint32_t> index;  // -0 == +0 as in assimp
    mesh.indices.reserve(soup.size());
    for (const glm::vec3& p : soup) {
        const auto key = std::make_tuple(p.x + 0.0f, p.y + 0.0f, p.z + 0.0f);
        const auto [it, inserted] = index.try_emplace(key, static_cast<std::uint32_t>(mesh.positions.size()));
        if (inserted) mesh.positions.push_back(p);
        mesh.indices.push_back(it->second);
    }
    return mesh;
}

} // namespace

VolumeMesh makeIcosphere(unsigned subdivisions) {
    if (subdivisions > 8) throw countError("makeIcosphere: subdivisions", subdivisions, " > 8");
    // assimp StandardShapes::MakeIcosahedron (geometrictools PlatonicSolids): 12 vertices
    // (+-t, +-1, 0), (+-1, 0, +-t), (0, +-t, +-1) divided by sqrt(1 + t^2); v / s is v * (1/s).
    const float t = (1.0f + 2.236067977f) / 2.0f;
    const float invS = 1.0f / std::sqrt(1.0f + t * t);
    const glm::vec3 v[12] = {
        aiScale({t, 1.0f, 0.0f}, invS),  aiScale({-t, 1.0f, 0.0f}, invS), aiScale({t, -1.0f, 0.0f}, invS),
        aiScale({-t, -1.0f, 0.0f}, invS), aiScale({1.0f, 0.0f, t}, invS),  aiScale({1.0f, 0.0f, -t}, invS),
        aiScale({-1.0f, 0.0f, t}, invS), aiScale({-1.0f, 0.0f, -t}, invS), aiScale({0.0f, t, 1.0f}, invS),
        aiScale({0.0f, -t, 1.0f}, invS), aiScale({0.0f, t, -1.0f}, invS), aiScale({0.0f, -t, -1.0f}, invS)};
    static constexpr int kFaces[20][3] = {{0, 8, 4},  {0, 5, 10}, {2, 4, 9},  {2, 11, 5}, {1, 6, 8},
                                          {1, 10, 7}, {3, 9, 6},  {3, 7, 11}, {0, 10, 8}, {1, 8, 10},
                                          {2, 9, 11}, {3, 11, 9}, {4, 2, 0},  {5, 0, 2},  {6, 1, 3},
                                          {7, 3, 1},  {8, 6, 4},  {9, 4, 6},  {10, 5, 7}, {11, 7, 5}};
    std::vector<glm::vec3> soup;
    soup.reserve(std::size_t(60) << (2 * subdivisions));
    for (const auto& f : kFaces)
        for (int i : f) soup.push_back(v[i]);
    // assimp Subdivide(): each triangle (a, b, c) becomes (ab, bc, ac) in place and appends
    // (ab, ac, a), (ac, bc, c), (bc, ab, b); midpoints are normalize(a + b) * |positions[0]|.
    for (unsigned level = 0; level < subdivisions; ++level) {
        const float radius = aiLength(soup[0]);
        const std::size_t count = soup.size();
        for (std::size_t i = 0; i < count; i += 3) {
            const glm::vec3 a = soup[i], b = soup[i + 1], c = soup[i + 2];
            const glm::vec3 ab = aiScale(aiNormalize(a + b), radius);
            const glm::vec3 ac = aiScale(aiNormalize(a + c), radius);
            const glm::vec3 bc = aiScale(aiNormalize(b + c), radius);
            soup[i] = ab;
            soup[i + 1] = bc;
            soup[i + 2] = ac;
            soup.insert(soup.end(), {ab, ac, a, ac, bc, c, bc, ab, b});
        }
    }
    return joinIdenticalVertices(soup);
}

VolumeMesh makeUnitCone(unsigned slices) {
    if (slices < 3) throw countError("makeUnitCone", slices, " slices < 3");
    VolumeMesh mesh;
    mesh.positions.reserve(slices + 2);
    mesh.positions.push_back(glm::vec3(0.0f, 0.0f, 0.0f));  // 0: apex (the light's position)
    mesh.positions.push_back(glm::vec3(0.0f, 0.0f, 1.0f));  // 1: base centre
    for (unsigned k = 0; k < slices; ++k) {
        double s = 0.0, c = 0.0;
        sinCosOfTurn(k, slices, s, c);
        mesh.positions.push_back(glm::vec3(static_cast<float>(c), static_cast<float>(-s), 1.0f));
    }
    mesh.indices.reserve(std::size_t(6) * slices);
    for (unsigned k = 0; k < slices; ++k) {
        const std::uint32_t rim = 2 + k, rimNext = 2 + (k + 1) % slices;
        mesh.indices.insert(mesh.indices.end(), {0u, rim, rimNext});  // side: outward normal ~ (cos, -sin, -1)
        mesh.indices.insert(mesh.indices.end(), {1u, rimNext, rim});  // base: outward normal +Z
    }
    return mesh;
}

float circumscribedSphereScale(const VolumeMesh& inscribedSphere) {
    double minDistance = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 2 < inscribedSphere.indices.size(); i += 3) {
        const glm::dvec3 a(inscribedSphere.positions[inscribedSphere.indices[i]]);
        const glm::dvec3 b(inscribedSphere.positions[inscribedSphere.indices[i + 1]]);
        const glm::dvec3 c(inscribedSphere.positions[inscribedSphere.indices[i + 2]]);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        minDistance = std::min(minDistance, std::fabs(glm::dot(n, a)) / std::sqrt(glm::dot(n, n)));
    }
    if (!(minDistance > 0.0) || !std::isfinite(minDistance))
        throw std::invalid_argument("circumscribedSphereScale: mesh has no face plane away from the origin");
    return roundUpToFloat(1.0 / minDistance);
}

float circumscribedConeRadialScale(unsigned slices) {
    if (slices < 3) throw countError("circumscribedConeRadialScale", slices, " slices < 3");
    double s = 0.0, c = 0.0;
    sinCosOfTurn(1, 2 * std::uint64_t(slices), s, c);  // cos(pi / slices)
    return roundUpToFloat(1.0 / c);
}

glm::quat rotationBetween(const glm::vec3& from, const glm::vec3& to, VolumeRotation mode) {
    if (mode == VolumeRotation::Glm096) {
        // glm 0.9.6 tquat(u, v): q = (1 + dot(u, v), cross(u, v)); normalize() returns identity
        // for a zero-length quaternion ("if(len <= T(0)) // Problem").
        const glm::vec3 w = glm::cross(from, to);
        const glm::quat q(1.0f + glm::dot(from, to), w.x, w.y, w.z);
        const float len = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
        if (len <= 0.0f) return glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
        const float inv = 1.0f / len;
        return glm::quat(q.w * inv, q.x * inv, q.y * inv, q.z * inv);
    }
    // RenderDeviceDX11.cpp RotationFromTwoVectors (lolengine "quaternion from two vectors: the
    // final version"): real = |u||v| + u.v; if real < 1e-6 |u||v| the vectors are opposite and
    // the rotation is 180 degrees about an axis orthogonal to u.
    const float normUV = std::sqrt(glm::dot(from, from) * glm::dot(to, to));
    float real = normUV + glm::dot(from, to);
    glm::vec3 axis;
    if (real < 1.e-6f * normUV) {
        real = 0.0f;
        axis = std::fabs(from.x) > std::fabs(from.z) ? glm::vec3(-from.y, from.x, 0.0f) : glm::vec3(0.0f, -from.z, from.y);
    } else {
        axis = glm::cross(from, to);
    }
    return glm::normalize(glm::quat(real, axis.x, axis.y, axis.z));
}

LightVolumes::LightVolumes(unsigned sphereTessellation, unsigned coneSlices)
    : mSphere(makeIcosphere(sphereTessellation)), mCone(makeUnitCone(coneSlices)),
      mSphereScale(circumscribedSphereScale(mSphere)), mConeRadialScale(circumscribedConeRadialScale(coneSlices)) {}

const VolumeMesh& LightVolumes::meshFor(LightType type) const {
    switch (type) {
    case LightType::Point: return mSphere;
    case LightType::Spot: return mCone;
    case LightType::Directional: break;
    case LightType::Capsule: throw std::invalid_argument("LightVolumes::meshFor: the 3dgep volumes have no capsule");
    }
    throw std::invalid_argument("LightVolumes::meshFor: directional lights have no volume (full-screen quad)");
}

float frustumReachWorld(const glm::vec3& posWorld, const glm::mat4& clipFromWorld) {
    const glm::dmat4 worldFromClip = glm::inverse(glm::dmat4(clipFromWorld));
    double reach = 0.0;
    for (const double z : {-1.0, 0.0, 1.0})
        for (const double y : {-1.0, 1.0})
            for (const double x : {-1.0, 1.0}) {
                const glm::dvec4 h = worldFromClip * glm::dvec4(x, y, z, 1.0);
                const glm::dvec3 cornerWorld = glm::dvec3(h) / h.w;
                const double distance = glm::length(cornerWorld - glm::dvec3(posWorld));
                if (!std::isfinite(distance)) return std::numeric_limits<float>::infinity();
                reach = std::max(reach, distance);
            }
    return static_cast<float>(std::min(reach, double(std::numeric_limits<float>::max())));
}

glm::mat4 LightVolumes::worldFromObject(const Light& light, const LightVolumeOptions& options, const glm::mat4* clipFromWorld) const {
    if (light.type == LightType::Directional)
        throw std::invalid_argument("LightVolumes::worldFromObject: directional lights have no volume (full-screen quad)");
    const bool circumscribed = options.fit == VolumeFit::Circumscribed;
    glm::vec3 scale(light.range);
    if (light.type == LightType::Point) {
        if (circumscribed) scale *= mSphereScale;
    } else {
        const float radius = detTan(glm::radians(light.spotHalfAngleDeg)) * light.range;  // cone base radius
        scale = glm::vec3(radius, radius, light.range);
        if (circumscribed) {
            scale.x *= mConeRadialScale;
            scale.y *= mConeRadialScale;
        }
    }
    if (light.range > kVolumeOverflowRange && clipFromWorld != nullptr) {
        const float reachWorld = frustumReachWorld(light.positionWorld, *clipFromWorld);
        if (std::isfinite(reachWorld) && light.range > 2.0f * reachWorld) scale *= (2.0f * reachWorld) / light.range;
    }
    glm::quat rotation(1.0f, 0.0f, 0.0f, 0.0f);
    const float dirLength = glm::length(light.directionWorld);
    if (dirLength > 0.0f && std::isfinite(dirLength))
        rotation = rotationBetween(glm::vec3(0.0f, 0.0f, 1.0f), glm::normalize(light.directionWorld), options.rotation);
    const glm::mat4 translation = glm::translate(glm::mat4(1.0f), light.positionWorld);
    return translation * glm::mat4_cast(rotation) * glm::scale(glm::mat4(1.0f), scale);
}

} // namespace tessera
