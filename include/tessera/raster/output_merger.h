// The output merger (D3D11.3 §17 "Output Merger Stage"): depth/stencil test and update on
// the values as stored in the buffer's format, and blending + write masks per render target.
// Per-sample functions; the rasterizer calls them for covered samples in submission order.
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

#include <tessera/buffers/format.h>
#include <tessera/state/blend_state.h>
#include <tessera/state/depth_stencil_state.h>

namespace tessera {

enum class DepthStencilResult : std::uint8_t { StencilFail, DepthFail, Pass };

// The depth-stencil state of one draw bound to one buffer format.
struct DepthStencilUnit {
    Format format = Format::Unknown;  // Unknown: no depth-stencil buffer bound (always pass)
    DepthStencilState desc;
    std::uint8_t ref = 0;

    bool hasStencil() const { return format == Format::D24_UNORM_S8_UINT || format == Format::D32_FLOAT_S8X24_UINT; }
    bool stencilActive() const { return desc.stencilEnable && hasStencil(); }
    bool depthActive() const { return desc.depthEnable && format != Format::Unknown; }
    // True when a sample that fails a test can still change the buffer (fail ops not KEEP),
    // so a pixel shader that may discard must run even where every sample fails.
    bool failCanWrite(bool frontFace) const;

    // Tests incoming depth z (already clamped to the viewport range) against the stored texel.
    // Stencil first, then depth (D3D11.3 §17.? "Depth/Stencil Test"): (ref & readMask) OP
    // (stored & readMask); depth compares the incoming value converted to the buffer format.
    DepthStencilResult test(const std::byte* texel, float z, bool frontFace) const;
    // Applies the stencil op chosen by `result` (write mask honoured) and, on Pass with depth
    // writes on, stores z in the buffer format.
    void update(std::byte* texel, float z, bool frontFace, DepthStencilResult result) const;
};

// Blends `src` (a pixel shader output) into the stored texel of a colour target and writes
// it with the target's write mask. UNORM/SNORM sources and blend factors are clamped to the
// format's range first (D3D11.3 §17.? "Blending Precision"); sRGB targets blend in linear.
// UINT formats take the bit patterns of src (glm::floatBitsToUint) and never blend.
void writeColorSample(Format format, std::byte* texel, const glm::vec4& src, const RenderTargetBlendDesc& blend,
                      const glm::vec4& blendFactor);

} // namespace tessera
