// Tessera's light binning for the tiled culling kernels (not in any seed): for one light, the
// tile columns and rows outside which the kernel's side-plane test cannot pass, so a kernel only
// visits candidate lights and still gives the bytes of its all-lights loop. Used by forward-plus
// (3dgep grid frustums) and forward-plus-amd (GPU Pro 4 side planes). Internal header.
#pragma once

#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace tessera::binning {

// The padding of every binning test: a light is put outside a column or row only when it is
// outside by more than kPadRelative * (|c| + |r|) (view units). The side planes of every tile in
// a column are mathematically one plane through the eye and a vertical screen line (rows: a
// horizontal one); per tile they are computed in binary32 from that tile's corner rays, which
// differ by rounding of relative ~1e-5 even for 8 px tiles (two corner rays 1e-3 rad apart), far
// below the padding. So a light the padded test puts outside a column fails the kernel's test
// on every tile of it.
inline constexpr double kPadRelative = 1.0 / 1024.0;
inline constexpr double kPadAbsolute = 1e-6;  // view units: the pad of a sphere at the eye with r = 0

inline double padFor(const glm::dvec3& centreView, double radius) {
    return kPadRelative * (glm::length(centreView) + std::abs(radius)) + kPadAbsolute;
}

// Kept columns and rows: up to two runs per axis, inclusive; a run is empty when its first index
// is greater than its last. The second runs are used only for a sphere that reaches the eye's
// plane (see scanRuns).
struct TileRuns {
    std::uint32_t x0 = 1, x1 = 0, y0 = 1, y1 = 0;
    std::uint32_t x2 = 1, x3 = 0, y2 = 1, y3 = 0;

    bool empty() const { return x0 > x1 || y0 > y1; }
    static TileRuns all(glm::uvec2 tiles) { return TileRuns{0, tiles.x - 1, 0, tiles.y - 1}; }
};

// First index in [0, n) where pred is true (n when none); pred must be false...true.
template <class Pred>
std::uint32_t firstTrue(std::uint32_t n, Pred&& pred) {
    std::uint32_t lo = 0, hi = n;
    while (lo < hi) {
        const std::uint32_t mid = lo + (hi - lo) / 2;
        if (pred(mid)) hi = mid;
        else lo = mid + 1;
    }
    return lo;
}

// Every index i in [0, n) with kept(i), as up to two runs [a0, a1], [b0, b1]: the second starts at
// the first kept index after a gap, and a third and later runs are merged into it (conservative).
// For a sphere that reaches the eye's plane, a plane through the eye has it wholly outside on a
// middle run of columns, not on a prefix (the planes' halves behind the eye keep the far
// columns), so no binary search applies and every column is tested.
template <class Kept>
void scanRuns(std::uint32_t n, Kept&& kept, std::uint32_t& a0, std::uint32_t& a1, std::uint32_t& b0, std::uint32_t& b1) {
    for (std::uint32_t i = 0; i < n; ++i) {
        if (!kept(i)) continue;
        if (a0 > a1) a0 = a1 = i;
        else if (b0 > b1 && a1 + 1 == i) a1 = i;
        else if (b0 > b1) b0 = b1 = i;
        else b1 = i;
    }
}

// One axis of a sphere wholly in front of the eye: keptFromLow(i) holds for a suffix of [0, n)
// (the light is not beyond tile i's low-side plane), keptToHigh(i) for a prefix; the kept tiles
// are their intersection [first, last]. Returns false when it is empty.
template <class KeptFromLow, class KeptToHigh>
bool searchRun(std::uint32_t n, KeptFromLow&& keptFromLow, KeptToHigh&& keptToHigh, std::uint32_t& first, std::uint32_t& last) {
    first = firstTrue(n, keptFromLow);
    const std::uint32_t end = firstTrue(n, [&](std::uint32_t i) { return !keptToHigh(i); });
    if (end == 0 || first >= end) return false;
    last = end - 1;
    return true;
}

}  // namespace tessera::binning
