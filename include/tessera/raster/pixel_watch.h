// Draw-level history of one watched pixel: for every primitive that covers it, what the
// rasterizer did there (coverage, the shader's inputs and output, the depth/stencil outcome, and
// the render target's and depth-stencil texels before and after), plus what each light added
// there. Device::setPixelWatch turns it on; `tessera probe` prints it. The watched pixel always
// takes the per-quad path.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include <tessera/buffers/format.h>
#include <tessera/shading/light_term.h>
#include <tessera/shaders/shader_stages.h>
#include <tessera/state/depth_stencil_state.h>

namespace tessera {

struct PixelDrawEvent {
    std::uint64_t draw = 0;       // the device's draw number (every draw() call counts, from 0)
    std::uint32_t primitive = 0;  // triangle index within the draw (a clipped triangle's pieces share it)
    std::uint32_t coverage = 0;   // covered samples resolved by this event (bit s = sample s)
    std::uint32_t passed = 0;     // samples that passed depth/stencil and were written (not discarded)
    bool frontFacing = true;
    bool shaded = false, discarded = false;
    bool compute = false;         // a compute pass's thread for the pixel, not a draw (draw, primitive: 0)
    float z = 0.0f;               // incoming depth of the first covered sample, clamped to the viewport range
    // The depth/stencil test at the first covered sample (NotTested: discarded before it, or a
    // compute event) and, when the stencil test ran, the op it chose and the reference value.
    enum class Outcome : std::uint8_t { NotTested, StencilFail, DepthFail, Pass };
    Outcome outcome = Outcome::NotTested;
    bool stencilTested = false;
    StencilOp stencilOp = StencilOp::Keep;
    std::uint8_t stencilRef = 0;
    // The shader's inputs when shaded: SV_Position, SV_SampleIndex and the interpolated varyings
    // as floats in declaration order, named by inputFields when the varyings type has kFields.
    glm::vec4 posWindow{0.0f};
    std::uint32_t sampleIndex = 0;
    std::uint32_t inputCount = 0;
    std::array<float, kMaxVaryingFloats> inputs{};
    std::span<const VaryingField> inputFields;
    glm::vec4 output{0.0f};       // SV_Target0 when shaded
    std::vector<LightTerm> lights;  // what each light added, in loop order (empty: the shader reported none)
    WatchedSurface surface;         // the material the shader gathered (recorded: Phong materials)
    Format colorFormat = Format::Unknown, depthFormat = Format::Unknown;  // Unknown: no such target
    std::array<std::byte, 16> colorBefore{}, colorAfter{};  // render target 0, sample 0
    std::array<std::byte, 8> depthBefore{}, depthAfter{};   // the depth-stencil texel, sample 0
};

struct PixelWatch {
    std::uint32_t x = 0, y = 0;          // window px
    std::vector<PixelDrawEvent> events;  // in draw, then primitive order (one thread owns the pixel's tile)
};

// Pixel-shader invocations per pixel over every draw while Device::setShadeCounts holds it: the
// selectivity tests' view of which pixels a light's shading pass ran on (a light that adds 0 to a
// pixel leaves no trace in any image). A per-sample shader counts once per sample it runs for;
// helper lanes do not count. Only counting: no shader input or output changes. Each pixel is
// counted by the one thread that owns its tile, so the counts need no atomics.
struct ShadeCounts {
    std::uint32_t width = 0, height = 0;  // px; draws to larger targets count only inside this
    std::vector<std::uint32_t> invocations;  // row-major, width x height: every invocation
    std::vector<std::uint32_t> perSample;    // of those, the invocations of per-sample shaders
    ShadeCounts() = default;
    ShadeCounts(std::uint32_t widthPx, std::uint32_t heightPx)
        : width(widthPx), height(heightPx), invocations(std::size_t(widthPx) * heightPx, 0u),
          perSample(std::size_t(widthPx) * heightPx, 0u) {}
    void add(std::uint32_t xPx, std::uint32_t yPx, bool sampleRate) {
        if (xPx >= width || yPx >= height) return;
        ++invocations[std::size_t(yPx) * width + xPx];
        if (sampleRate) ++perSample[std::size_t(yPx) * width + xPx];
    }
    std::uint32_t at(std::uint32_t xPx, std::uint32_t yPx) const { return invocations[std::size_t(yPx) * width + xPx]; }
};

} // namespace tessera
