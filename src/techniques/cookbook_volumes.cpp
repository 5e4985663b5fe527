// The Cookbook's tessellated light volumes (techniques/cookbook_volumes.h): the domain shaders in
// float, the quad patch grid, the outward winding and the enlargements that make them conservative.
#include <tessera/techniques/cookbook_volumes.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tessera {
namespace {

float saturate(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }
float sign(float x) { return x > 0.0f ? 1.0f : (x < 0.0f ? -1.0f : 0.0f); }  // HLSL sign
glm::vec3 normalize(const glm::vec3& v) { return v / std::sqrt((v.x * v.x + v.y * v.y) + v.z * v.z); }

// One patch of `factor` x `factor` cells, mapped by `domain`, appended to `mesh`; every triangle
// wound so that (b - a) x (c - a) points away from `inside` (a left-handed space's clockwise-on-
// screen, D3D11's default front face, seen from outside). Degenerate triangles (domain points the
// shader collapses onto one position) are kept: the rasterizer drops zero-area triangles.
template <class Domain>
void appendPatch(CookbookVolumeMesh& mesh, std::uint32_t factor, glm::vec3 inside, Domain&& domain) {
    const auto base = std::uint32_t(mesh.positions.size());
    const float step = 1.0f / float(factor);
    for (std::uint32_t j = 0; j <= factor; ++j)
        for (std::uint32_t i = 0; i <= factor; ++i) mesh.positions.push_back(domain(glm::vec2(float(i) * step, float(j) * step)));
    const auto at = [&](std::uint32_t i, std::uint32_t j) { return base + j * (factor + 1) + i; };
    const auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        const glm::dvec3 pa(mesh.positions[a]), pb(mesh.positions[b]), pc(mesh.positions[c]);
        const glm::dvec3 n = glm::cross(pb - pa, pc - pa);
        const glm::dvec3 out = (pa + pb + pc) / 3.0 - glm::dvec3(inside);
        if (glm::dot(n, out) < 0.0) std::swap(b, c);
        mesh.indices.insert(mesh.indices.end(), {a, b, c});
    };
    // Diagonals radiate from the patch centre (the D3D11 tessellator builds the quad domain in
    // rings from the outside in, which gives this symmetry): a cell in the quadrants where
    // (i - f/2) and (j - f/2) share a sign is split along (i, j)-(i+1, j+1), the others along
    // (i+1, j)-(i, j+1). A corner cell's triangles then both hold its inner vertex; one diagonal
    // everywhere would leave two corner triangles made only of rim vertices, flat on the rim plane.
    const auto half = std::int64_t(factor);  // compare 2i + 1 with f: the cell centre against the patch centre
    for (std::uint32_t j = 0; j < factor; ++j)
        for (std::uint32_t i = 0; i < factor; ++i) {
            const bool sameSide = ((2 * std::int64_t(i) + 1 - half) > 0) == ((2 * std::int64_t(j) + 1 - half) > 0);
            if (sameSide) {
                add(at(i, j), at(i + 1, j), at(i + 1, j + 1));
                add(at(i, j), at(i + 1, j + 1), at(i, j + 1));
            } else {
                add(at(i, j), at(i + 1, j), at(i, j + 1));
                add(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            }
        }
}

// The mesh's face planes n.x <= d (n unit, outward), non-degenerate faces only.
struct Face {
    glm::dvec3 n;
    double d;
};
std::vector<Face> faces(const CookbookVolumeMesh& mesh) {
    std::vector<Face> out;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const glm::dvec3 a(mesh.positions[mesh.indices[t]]), b(mesh.positions[mesh.indices[t + 1]]),
            c(mesh.positions[mesh.indices[t + 2]]);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        const double len = glm::length(n);
        if (len < 1e-6) continue;  // degenerate, or a float-rounding sliver along the spot axis (area ~1e-8)
        out.push_back({n / len, glm::dot(n / len, a)});
    }
    return out;
}

// Support function of the cone of half angle `alpha` about +z, apex at the origin, cut by the
// unit sphere: max over its points x of n.x.
double spotSupport(const glm::dvec3& n, double alpha) {
    const double theta = std::acos(std::clamp(n.z, -1.0, 1.0));
    if (theta <= alpha) return 1.0;
    if (theta - alpha < std::numbers::pi / 2.0) return std::cos(theta - alpha);
    return 0.0;
}

} // namespace

glm::vec3 cookbookPointDomain(glm::vec2 uv, glm::vec3 hemiDir) {
    const glm::vec2 posClipSpace = uv * 2.0f - 1.0f;
    const glm::vec2 posClipSpaceAbs = glm::abs(posClipSpace);
    const float maxLen = std::max(posClipSpaceAbs.x, posClipSpaceAbs.y);
    return normalize(glm::vec3(posClipSpace, maxLen - 1.0f) * hemiDir);
}

glm::vec3 cookbookCapsuleDomain(glm::vec2 uv, glm::vec3 capsuleDir, float halfSegmentLen, float capsuleRange) {
    constexpr float kCylinderPortion = 0.3f;
    constexpr float kSpherePortion = 1.0f - kCylinderPortion;
    constexpr float kExpendAmount = 1.0f + kCylinderPortion;
    const glm::vec2 posClipSpace = uv * 2.0f - 1.0f;
    const glm::vec2 posClipSpaceAbs = glm::abs(posClipSpace);
    const float maxLen = std::max(posClipSpaceAbs.x, posClipSpaceAbs.y);
    const glm::vec2 noCylAbs(saturate(posClipSpaceAbs.x * kExpendAmount), saturate(posClipSpaceAbs.y * kExpendAmount));
    const glm::vec2 noCyl(sign(posClipSpace.x) * noCylAbs.x, sign(posClipSpace.y) * noCylAbs.y);
    const float maxLenNoCapsule = std::max(noCylAbs.x, noCylAbs.y);
    const glm::vec3 normDir = normalize(glm::vec3(noCyl, maxLenNoCapsule - 1.0f)) * capsuleRange;
    const float cylinderOffsetZ = saturate(maxLen - std::min(maxLenNoCapsule, kSpherePortion)) / kCylinderPortion;
    const glm::vec3 posLocal(normDir.x, normDir.y, normDir.z + cylinderOffsetZ * halfSegmentLen - halfSegmentLen);
    return posLocal * capsuleDir;
}

glm::vec3 cookbookSpotDomain(glm::vec2 uv, float sinAngle, float cosAngle) {
    constexpr float kCylinderPortion = 0.2f;
    constexpr float kExpendAmount = 1.0f + kCylinderPortion;
    const glm::vec2 posClipSpace = uv * glm::vec2(2.0f, -2.0f) + glm::vec2(-1.0f, 1.0f);
    const glm::vec2 posClipSpaceAbs = glm::abs(posClipSpace);
    const float maxLen = std::max(posClipSpaceAbs.x, posClipSpaceAbs.y);
    const glm::vec2 noCylAbs(saturate(posClipSpaceAbs.x * kExpendAmount), saturate(posClipSpaceAbs.y * kExpendAmount));
    const float maxLenNoCapsule = std::max(noCylAbs.x, noCylAbs.y);
    const glm::vec2 noCyl(sign(posClipSpace.x) * noCylAbs.x, sign(posClipSpace.y) * noCylAbs.y);
    glm::vec3 halfSpherePos = normalize(glm::vec3(noCyl, 1.0f - maxLenNoCapsule));
    halfSpherePos = normalize(glm::vec3(glm::vec2(halfSpherePos) * sinAngle, cosAngle));
    const float cylinderOffsetZ = saturate((maxLen * kExpendAmount - 1.0f) / kCylinderPortion);
    return {glm::vec2(halfSpherePos) * (1.0f - cylinderOffsetZ), halfSpherePos.z - cylinderOffsetZ * cosAngle};
}

CookbookVolumeMesh cookbookPointVolume() {
    CookbookVolumeMesh mesh;
    for (const glm::vec3 hemiDir : {glm::vec3(1.0f, 1.0f, 1.0f), glm::vec3(-1.0f, 1.0f, -1.0f)})
        appendPatch(mesh, kCookbookPointTessFactor, glm::vec3(0.0f), [&](glm::vec2 uv) { return cookbookPointDomain(uv, hemiDir); });
    return mesh;
}

CookbookVolumeMesh cookbookCapsuleVolume(float halfSegmentLen, float capsuleRange) {
    CookbookVolumeMesh mesh;
    for (const glm::vec3 dir : {glm::vec3(1.0f, 1.0f, 1.0f), glm::vec3(-1.0f, 1.0f, -1.0f)})
        appendPatch(mesh, kCookbookCapsuleTessFactor, glm::vec3(0.0f),
                    [&](glm::vec2 uv) { return cookbookCapsuleDomain(uv, dir, halfSegmentLen, capsuleRange); });
    return mesh;
}

CookbookVolumeMesh cookbookSpotVolume(float sinAngle, float cosAngle) {
    CookbookVolumeMesh mesh;
    // A point inside the cone for any half angle: on the axis, halfway to the base.
    appendPatch(mesh, kCookbookSpotTessFactor, glm::vec3(0.0f, 0.0f, 0.5f * cosAngle),
                [&](glm::vec2 uv) { return cookbookSpotDomain(uv, sinAngle, cosAngle); });
    return mesh;
}

float cookbookPointPadding() {
    double minD = 1.0;
    for (const Face& f : faces(cookbookPointVolume())) minD = std::min(minD, f.d);
    return float(1.0 / minD) * (1.0f + 1e-6f);  // rounded up past float's rounding of the vertices
}

float cookbookCapsulePaddedRange(float halfSegmentLen, float range) {
    const auto contains = [&](float capsuleRange) {
        for (const Face& f : faces(cookbookCapsuleVolume(halfSegmentLen, capsuleRange)))
            if (std::abs(f.n.z) * halfSegmentLen + range > f.d) return false;
        return true;
    };
    float lo = range, hi = range * 2.0f;
    while (!contains(hi)) hi *= 2.0f;
    for (int i = 0; i < 40 && hi - lo > hi * 1e-6f; ++i) {  // bounded: adjacent floats stop halving
        const float mid = 0.5f * (lo + hi);
        (contains(mid) ? hi : lo) = mid;
    }
    return hi;
}

CookbookSpotPadding cookbookSpotPadding(float halfAngle) {
    // Faces through the apex cannot be moved by a scale about it: widen the angle until each of
    // them has the light's cone behind its plane, then scale the rounded base's faces out.
    const auto apexFacesHold = [&](float angle) {
        for (const Face& f : faces(cookbookSpotVolume(std::sin(angle), std::cos(angle))))
            if (std::abs(f.d) < 1e-6 && spotSupport(f.n, halfAngle) > 1e-6) return false;
        return true;
    };
    float lo = halfAngle, hi = std::min(halfAngle * 1.5f + 1e-3f, float(std::numbers::pi / 2.0) - 1e-3f);
    for (int i = 0; i < 40 && hi - lo > 1e-7f; ++i) {  // bounded: adjacent floats stop halving
        const float mid = 0.5f * (lo + hi);
        (apexFacesHold(mid) ? hi : lo) = mid;
    }
    CookbookSpotPadding p;
    p.halfAngle = hi;
    double scale = 1.0;
    for (const Face& f : faces(cookbookSpotVolume(std::sin(hi), std::cos(hi))))
        if (f.d > 1e-6) scale = std::max(scale, spotSupport(f.n, halfAngle) / f.d);
    p.scale = float(scale) * (1.0f + 1e-6f);
    return p;
}

} // namespace tessera
