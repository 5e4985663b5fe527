// PR&C D3D11 ch. 11 G-buffer math (gbuffer/prc_gbuffer.h), in the listings' operation order.
#include <tessera/gbuffer/prc_gbuffer.h>
#include <tessera/math/projection_terms.h>

#include <algorithm>
#include <cmath>

namespace tessera {

glm::vec2 prcSpheremapEncode(const glm::vec3& n) {
    const glm::vec2 xy(n.x, n.y);
    const glm::vec2 dir = xy / std::sqrt(xy.x * xy.x + xy.y * xy.y);  // normalize(normal.xy)
    return dir * std::sqrt(-n.z * 0.5f + 0.5f);
}

glm::vec2 prcSpheremapEncodeSafe(const glm::vec3& n) {
    if (n.x == 0.0f && n.y == 0.0f) return n.z < 0.0f ? glm::vec2(1.0f, 0.0f) : glm::vec2(0.0f);
    return prcSpheremapEncode(n);
}

glm::vec3 prcSpheremapDecode(const glm::vec2& e) {
    glm::vec4 nn(e.x, e.y, 1.0f, -1.0f);
    const float l = (nn.x * -nn.x + nn.y * -nn.y) + nn.z * -nn.w;  // dot(nn.xyz, -nn.xyw)
    nn.z = l;
    const float s = std::sqrt(l);
    nn.x *= s;
    nn.y *= s;
    return glm::vec3(nn) * 2.0f + glm::vec3(0.0f, 0.0f, -1.0f);
}

glm::vec3 prcSpheremapDecodeSafe(const glm::vec2& e) {
    const float l = std::max(0.0f, (e.x * -e.x + e.y * -e.y) + 1.0f);
    const float s = std::sqrt(l);
    return glm::vec3(e.x * s, e.y * s, l) * 2.0f + glm::vec3(0.0f, 0.0f, -1.0f);
}

glm::vec3 prcNormalFromXy(const glm::vec2& xy, bool positiveZ) {
    const float z = std::sqrt(std::max(0.0f, 1.0f - (xy.x * xy.x + xy.y * xy.y)));
    return {xy.x, xy.y, positiveZ ? z : -z};
}

PrcProjectionAB prcProjectionAB(float nearZ, float farZ) {
    // (-Far * Near) / (Far - Near) = nearFarTerm(f, n, 1) bit for bit where f n is a normal
    // float; finite beyond (math/projection_terms.h).
    return {farZ / (farZ - nearZ), nearFarTerm(farZ, nearZ, 1.0f)};
}

float prcLinearDepth(float depth, const PrcProjectionAB& ab) { return ab.b / (depth - ab.a); }

glm::vec3 prcPositionFromDistance(const glm::vec3& cameraPos, const glm::vec3& viewRay, float distance) {
    return cameraPos + glm::normalize(viewRay) * distance;
}

glm::vec3 prcPositionFromNormalizedDepth(const glm::vec3& volumePositionVS, float farZ, float storedDepth) {
    const glm::vec3 ray(glm::vec2(volumePositionVS) * (farZ / volumePositionVS.z), farZ);
    return ray * storedDepth;
}

glm::vec3 prcPositionAnySpace(const glm::vec3& cameraPos, const glm::vec3& eyeZAxis, const glm::vec3& viewRay, float linearDepth) {
    const glm::vec3 ray = glm::normalize(viewRay);
    const float viewZProj = glm::dot(eyeZAxis, ray);
    return cameraPos + ray * (linearDepth / viewZProj);
}

PrcScissorRect prcPointLightScissor(const glm::vec3& c, float radius, float proj00, float proj11, float nearZ, float farZ,
                                    std::uint32_t widthPx, std::uint32_t heightPx, bool roundOut) {
    glm::vec3 top = c + glm::vec3(0.0f, radius, 0.0f), bottom = c - glm::vec3(0.0f, radius, 0.0f);
    glm::vec3 left = c - glm::vec3(radius, 0.0f, 0.0f), right = c + glm::vec3(radius, 0.0f, 0.0f);
    left.z = left.x < 0.0f ? left.z - radius : left.z + radius;
    right.z = right.x < 0.0f ? right.z + radius : right.z - radius;
    top.z = top.y < 0.0f ? top.z + radius : top.z - radius;
    bottom.z = bottom.y < 0.0f ? bottom.z - radius : bottom.z + radius;
    for (glm::vec3* p : {&left, &right, &top, &bottom}) p->z = std::clamp(p->z, nearZ, farZ);
    float leftCs = std::clamp(left.x * proj00 / left.z, -1.0f, 1.0f);
    float rightCs = std::clamp(right.x * proj00 / right.z, -1.0f, 1.0f);
    float topCs = std::clamp(top.y * proj11 / top.z, -1.0f, 1.0f);
    float bottomCs = std::clamp(bottom.y * proj11 / bottom.z, -1.0f, 1.0f);
    const float leftSs = leftCs * 0.5f + 0.5f, rightSs = rightCs * 0.5f + 0.5f;
    const float topSs = 1.0f - (topCs * 0.5f + 0.5f), bottomSs = 1.0f - (bottomCs * 0.5f + 0.5f);
    PrcScissorRect r;
    r.left = static_cast<std::int32_t>(leftSs * float(widthPx));
    r.right = roundOut ? static_cast<std::int32_t>(std::ceil(rightSs * float(widthPx))) : static_cast<std::int32_t>(rightSs * float(widthPx));
    r.top = static_cast<std::int32_t>(topSs * float(heightPx));
    r.bottom = roundOut ? static_cast<std::int32_t>(std::ceil(bottomSs * float(heightPx)))
                        : static_cast<std::int32_t>(bottomSs * float(heightPx));
    r.left = std::max(r.left, 0);
    r.top = std::max(r.top, 0);
    r.right = std::min(r.right, std::int32_t(widthPx));
    r.bottom = std::min(r.bottom, std::int32_t(heightPx));
    return r;
}

} // namespace tessera
