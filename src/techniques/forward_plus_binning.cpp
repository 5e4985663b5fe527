// forward-plus's binning pre-pass (tessera's, not the demo's): per light, the tile columns and
// rows outside which CS_main's test cannot pass (forward_plus_detail.h "binning pre-pass"), from
// a padded bounding-sphere test against the column and row planes (tile_binning.h).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "forward_plus_detail.h"

namespace tessera::forward_plus_detail {
namespace {

// The padded "sphere wholly in the negative half-space" (plane.h sphereInsidePlane), in double.
bool paddedInside(const BoundingSphere& s, const Plane& plane) {
    const double distance = (double(plane.N.x) * s.c.x + double(plane.N.y) * s.c.y) + double(plane.N.z) * s.c.z - double(plane.d);
    return distance < -(s.r + s.pad);
}

} // namespace

// The sphere around a cone's tip and base disc, in double: centre T + d h / 2, radius
// sqrt((h |d| / 2)^2 + (r |m|max)^2), where |m|max bounds the offset of ConeInsidePlane's Q from
// the base centre in units of r: |cross(cross(N, d), d)| <= |d|^2 for a unit N (the faithful
// test), 1 for the corrected one; 1e-6 more covers N's rounding. It holds T and both tests' Q.
BoundingSphere coneBoundingSphere(const Cone& cone) {
    const glm::dvec3 T(cone.T), d(cone.d);
    const double h = double(cone.h), dLength = glm::length(d);
    BoundingSphere s;
    s.c = T + d * (h * 0.5);
    const double mReach = double(std::abs(cone.r)) * std::max(1.0, dLength * dLength) * (1.0 + 1e-6);
    s.r = std::sqrt(0.25 * h * h * dLength * dLength + mReach * mReach);
    s.pad = binning::padFor(s.c, s.r);
    return s;
}

// The binning of a point light (bound: its sphere) or a spot light (bound: coneBoundingSphere).
LightTileRect lightTileRect(const ViewLight<float>& light, const BoundingSphere& s, const std::vector<Frustum>& frustums,
                            glm::uvec2 tiles, float nearClipVS) {
    LightTileRect rect;
    if (!light.enabled) return rect;
    if (light.type == LightType::Directional) return LightTileRect::all(tiles);
    if (s.c.z - s.r > double(nearClipVS) + s.pad) return rect;  // wholly behind the near clip plane
    const auto plane = [&](std::uint32_t tx, std::uint32_t ty, int i) -> const Plane& {
        return frustums[tx + std::size_t{ty} * tiles.x].planes[std::size_t(i)];
    };
    // Planes 0..3: left, right, top, bottom, normals into the tile.
    const auto keptColumn = [&](std::uint32_t tx) { return !paddedInside(s, plane(tx, 0, 0)) && !paddedInside(s, plane(tx, 0, 1)); };
    const auto keptRow = [&](std::uint32_t ty) { return !paddedInside(s, plane(0, ty, 2)) && !paddedInside(s, plane(0, ty, 3)); };
    if (s.c.z + s.r + s.pad >= 0.0) {  // reaches the eye's plane z = 0
        binning::scanRuns(tiles.x, keptColumn, rect.x0, rect.x1, rect.x2, rect.x3);
        binning::scanRuns(tiles.y, keptRow, rect.y0, rect.y1, rect.y2, rect.y3);
        return rect.empty() ? LightTileRect{} : rect;
    }
    // Wholly in front of the eye: inside(right plane of tx) holds for tx left of the sphere;
    // inside(left plane) for tx right of it. Rows: inside(bottom plane of ty) above the sphere,
    // inside(top) below it.
    const bool columns = binning::searchRun(
        tiles.x, [&](std::uint32_t tx) { return !paddedInside(s, plane(tx, 0, 1)); },
        [&](std::uint32_t tx) { return !paddedInside(s, plane(tx, 0, 0)); }, rect.x0, rect.x1);
    const bool rows = binning::searchRun(
        tiles.y, [&](std::uint32_t ty) { return !paddedInside(s, plane(0, ty, 3)); },
        [&](std::uint32_t ty) { return !paddedInside(s, plane(0, ty, 2)); }, rect.y0, rect.y1);
    return columns && rows ? rect : LightTileRect{};
}

} // namespace tessera::forward_plus_detail
