// Draw-level history of one watched pixel: for every primitive that covers it, what the
// rasterizer did there (coverage, the incoming depth, the depth/stencil outcome, the shader's
// output, and the render target's and depth-stencil texels before and after). Device::setPixelWatch
// turns it on; `tessera probe` prints it. The watched pixel always takes the per-quad path.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include <tessera/buffers/format.h>

namespace tessera {

struct PixelDrawEvent {
    std::uint64_t draw = 0;       // the device's draw number (every draw() call counts, from 0)
    std::uint32_t primitive = 0;  // triangle index within the draw (a clipped triangle's pieces share it)
    std::uint32_t coverage = 0;   // covered samples resolved by this event (bit s = sample s)
    std::uint32_t passed = 0;     // samples that passed depth/stencil and were written (not discarded)
    bool frontFacing = true;
    bool shaded = false, discarded = false;
    float z = 0.0f;               // incoming depth of the first covered sample, clamped to the viewport range
    glm::vec4 output{0.0f};       // SV_Target0 when shaded
    Format colorFormat = Format::Unknown, depthFormat = Format::Unknown;  // Unknown: no such target
    std::array<std::byte, 16> colorBefore{}, colorAfter{};  // render target 0, sample 0
    std::array<std::byte, 8> depthBefore{}, depthAfter{};   // the depth-stencil texel, sample 0
};

struct PixelWatch {
    std::uint32_t x = 0, y = 0;          // window px
    std::vector<PixelDrawEvent> events;  // in draw, then primitive order (one thread owns the pixel's tile)
};

} // namespace tessera
