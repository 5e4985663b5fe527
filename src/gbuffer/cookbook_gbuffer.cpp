// The HLSL Development Cookbook's G-buffer packing and reconstruction (gbuffer/cookbook_gbuffer.h),
// in the shaders' operation order, float throughout.
#include <tessera/gbuffer/cookbook_gbuffer.h>

#include <cmath>

#include <tessera/buffers/conversion.h>

namespace tessera {

float packCookbookSpecPower(float specPower) { return (specPower - kCookbookSpecPowerMin) / kCookbookSpecPowerRange; }

float unpackCookbookSpecPower(float norm) { return kCookbookSpecPowerMin + kCookbookSpecPowerRange * norm; }

float unpackCookbookSpecPowerAsPrinted(float norm) {
    const float unpacked = norm + norm * kCookbookSpecPowerRange;  // UnpackGBuffer as printed
    return kCookbookSpecPowerMin + kCookbookSpecPowerRange * unpacked;  // the light PS's decode
}

std::uint8_t cookbookSpecPowerCode(float specPower) {
    return std::uint8_t(convert::floatToUnorm(packCookbookSpecPower(specPower), 8));
}

glm::vec3 packCookbookNormal(const glm::vec3& normal) { return normal * 0.5f + 0.5f; }

glm::vec3 unpackCookbookNormal(const glm::vec3& stored) {
    const glm::vec3 n = stored * 2.0f - 1.0f;
    return n / std::sqrt((n.x * n.x + n.y * n.y) + n.z * n.z);
}

CookbookPerspectiveValues cookbookPerspectiveValues(const glm::mat4& projectionLh) {
    // glm indexes [column][row] of the column-vector matrix, which is the row-vector Pm's
    // [row][column]: Pm[i][j] == projectionLh[i][j]. Pm[3][2] = -Q Zn, Pm[2][2] = Q.
    CookbookPerspectiveValues pv;
    pv.x = 1.0f / projectionLh[0][0];
    pv.y = 1.0f / projectionLh[1][1];
    pv.z = projectionLh[3][2];
    pv.w = -projectionLh[2][2];
    return pv;
}

} // namespace tessera
