// The output merger (D3D11.3 §17 "Output Merger Stage"): depth/stencil test and update on
// the values as stored in the buffer's format, and blending + write masks per render target.
// Per-sample functions; the rasterizer calls them for covered samples in submission order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>

#include <tessera/buffers/format.h>
#include <tessera/state/blend_state.h>
#include <tessera/state/depth_stencil_state.h>

namespace tessera {

enum class DepthStencilResult : std::uint8_t { StencilFail, DepthFail, Pass };

// How the rasterizer runs a draw's depth/stencil stage, chosen once per draw so that the
// per-sample loop has no format or state switch:
//   Off      - nothing to test or write (no buffer, or depth and stencil both off): Pass.
//   D32      - stencil inactive, depth on, float depth in bytes 0..3 (D32_FLOAT, D32_FLOAT_S8X24).
//   D24      - stencil inactive, depth on, D24_UNORM_S8_UINT.
//   General  - anything else: DepthStencilUnit::test / update.
// Each fast path does exactly what test + update do for that state (same comparisons, bytes).
enum class DepthPath : std::uint8_t { Off, D32, D24, General };

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
    DepthPath path() const;
};

// Blends `src` (a pixel shader output) into the stored texel of a colour target and writes
// it with the target's write mask. UNORM/SNORM sources and blend factors are clamped to the
// format's range first (D3D11.3 §17.? "Blending Precision"); sRGB targets blend in linear.
// UINT formats take the bit patterns of src (glm::floatBitsToUint) and never blend.
void writeColorSample(Format format, std::byte* texel, const glm::vec4& src, const RenderTargetBlendDesc& blend,
                      const glm::vec4& blendFactor);
// True when writeColorSample would simply encode src into an R8G8B8A8_UNORM texel (blending
// off, all four channels written); writeColorRgba8Unorm then writes the same four bytes
// without the per-sample format lookup.
bool isRgba8UnormOverwrite(Format format, const RenderTargetBlendDesc& blend);

// writeColorSample's UNORM clamp followed by encodeTexel's R8G8B8A8_UNORM case, with
// convert::floatToUnorm(x, 8) spelled out so that it inlines and vectorizes: the clamp to
// [0, 1] (NaN -> 0), then the same operations in the same order as floatToUnorm (x * 255 in
// double, truncate, round half up on the exact fraction). Truncating to int32 equals
// floatToUnorm's uint64 truncation because 0 <= p <= 255. Checked equal to writeColorSample
// for all 2^32 float inputs.
inline void writeColorRgba8Unorm(std::byte* texel, const glm::vec4& src) {
    std::uint8_t code[4];
    for (int c = 0; c < 4; ++c) {
        const float x = src[c] > 0.0f ? (src[c] < 1.0f ? src[c] : 1.0f) : 0.0f;
        const double p = static_cast<double>(x) * 255.0;
        const auto i = static_cast<std::int32_t>(p);
        const double frac = p - static_cast<double>(i);
        code[c] = std::uint8_t(i + (frac >= 0.5 ? 1 : 0));
    }
    std::memcpy(texel, code, 4);
}

// Precision fast: the same clamp, then round(x * 255) in float as x * 255 + 0.5 truncated.
// Differs from writeColorRgba8Unorm by at most one code, where x * 255 lies within a float
// rounding of a half-integer (tests/precision measures how often).
inline void writeColorRgba8UnormFast(std::byte* texel, const glm::vec4& src) {
    std::uint8_t code[4];
    for (int c = 0; c < 4; ++c) {
        const float x = src[c] > 0.0f ? (src[c] < 1.0f ? src[c] : 1.0f) : 0.0f;
        code[c] = std::uint8_t(x * 255.0f + 0.5f);
    }
    std::memcpy(texel, code, 4);
}

} // namespace tessera
