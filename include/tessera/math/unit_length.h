// v / |v| in binary32 for any finite nonzero vector: no overflow or underflow in |v|^2 (scene
// directions, camera view directions).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace tessera {

// v / |v| in binary32 without overflow or underflow in |v|^2: v / sqrt(dot(v, v)) as before
// where the squared length is a finite normal float (so ordinary inputs keep their bits), else
// the vector is first divided by its largest magnitude (exact for powers of two, and any
// finite nonzero vector then has a squared length in [1, 4)). Nullopt: zero or not finite.
template <class V>
std::optional<V> unitLength(const V& v) {
    float dotSum = 0.0f, largest = 0.0f;
    for (int i = 0; i < V::length(); ++i) {
        dotSum += v[i] * v[i];
        largest = std::max(largest, std::fabs(v[i]));
    }
    if (!(largest > 0.0f) || !std::isfinite(largest)) return std::nullopt;
    if (std::isfinite(dotSum) && dotSum >= std::numeric_limits<float>::min()) return v / std::sqrt(dotSum);
    const V scaled = v / largest;
    float scaledSum = 0.0f;
    for (int i = 0; i < V::length(); ++i) scaledSum += scaled[i] * scaled[i];
    return scaled / std::sqrt(scaledSum);
}

} // namespace tessera
