// The D3D11 standard multisample patterns (D3D11_STANDARD_MULTISAMPLE_PATTERN), as offsets
// from the pixel centre in 1/16 px, and the helpers that turn them into 16.8 fixed point.
// Source: D3D11.3 §19.2.4 "Standard Multisample Pattern" (the same table as MSDN's
// D3D11_STANDARD_MULTISAMPLE_QUALITY_LEVELS page).
#pragma once

#include <array>
#include <cstdint>
#include <span>

namespace tessera {

struct SampleOffset {
    std::int8_t x, y;  // 1/16 px, relative to the pixel centre, y down
};

inline constexpr std::array<SampleOffset, 1> kSamples1{{{0, 0}}};
inline constexpr std::array<SampleOffset, 2> kSamples2{{{4, 4}, {-4, -4}}};
inline constexpr std::array<SampleOffset, 4> kSamples4{{{-2, -6}, {6, -2}, {-6, 2}, {2, 6}}};
inline constexpr std::array<SampleOffset, 8> kSamples8{
    {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}}};

// The standard pattern for 1, 2, 4 or 8 samples; an empty span for other counts.
constexpr std::span<const SampleOffset> standardSamplePattern(std::uint32_t sampleCount) {
    switch (sampleCount) {
    case 1: return kSamples1;
    case 2: return kSamples2;
    case 4: return kSamples4;
    case 8: return kSamples8;
    default: return {};
    }
}

} // namespace tessera
