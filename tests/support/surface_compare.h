// Comparisons of surfaces shared by the tests: the same stored bytes, how many pixels differ, and
// for RGBA8 images the largest per-channel code difference.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include <tessera/buffers/surface.h>

namespace tessera::test {

struct Difference {
    int maxCodes = 0;       // over R, G, B, A
    int pixelsDiffering = 0;
    std::uint32_t pixels = 0;
    double share() const { return double(pixelsDiffering) / double(pixels); }
};

inline Difference compareRgba8(const Surface& a, const Surface& b) {
    Difference d;
    d.pixels = a.width() * a.height();
    for (std::uint32_t y = 0; y < a.height(); ++y)
        for (std::uint32_t x = 0; x < a.width(); ++x) {
            int worst = 0;
            for (int c = 0; c < 4; ++c)
                worst = std::max(worst, std::abs(std::to_integer<int>(a.texel(x, y)[c]) - std::to_integer<int>(b.texel(x, y)[c])));
            d.maxCodes = std::max(d.maxCodes, worst);
            d.pixelsDiffering += worst > 0;
        }
    return d;
}

// Same size, format and stored bytes.
inline bool sameBytes(const Surface& a, const Surface& b) {
    return a.desc().width == b.desc().width && a.desc().height == b.desc().height && a.format() == b.format() &&
           std::equal(a.bytes().begin(), a.bytes().end(), b.bytes().begin(), b.bytes().end());
}

// Pixels whose stored texel (sample 0) differs; a and b have the same size and format.
inline int differingPixels(const Surface& a, const Surface& b) {
    int n = 0;
    for (std::uint32_t y = 0; y < a.height(); ++y)
        for (std::uint32_t x = 0; x < a.width(); ++x) n += std::memcmp(a.texel(x, y), b.texel(x, y), a.bytesPerTexel()) != 0;
    return n;
}

} // namespace tessera::test
