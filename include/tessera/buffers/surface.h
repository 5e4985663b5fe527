// A 2D surface (render target, depth-stencil buffer or texture) of one Format with 1/2/4/8
// samples per pixel. Memory layout, row 0 at the top (D3D window space):
//   byte offset = ((y * width + x) * sampleCount + sample) * bytesPerTexel
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/buffers/format.h>

namespace tessera {

struct SurfaceDesc {
    std::uint32_t width = 0, height = 0;   // px, 1..kMaxSurfaceDimension (16384)
    Format format = Format::Unknown;
    std::uint32_t sampleCount = 1;         // 1, 2, 4 or 8
};

class Surface {
public:
    Surface() = default;
    // Throws std::invalid_argument naming the bad value (size 0 or > 16384, sample count not
    // 1/2/4/8, unknown format). Contents start as zero bytes.
    explicit Surface(const SurfaceDesc& desc);

    const SurfaceDesc& desc() const { return mDesc; }
    std::uint32_t width() const { return mDesc.width; }
    std::uint32_t height() const { return mDesc.height; }
    std::uint32_t sampleCount() const { return mDesc.sampleCount; }
    Format format() const { return mDesc.format; }
    std::uint32_t bytesPerTexel() const { return mBytesPerTexel; }

    std::byte* texel(std::uint32_t x, std::uint32_t y, std::uint32_t sample = 0) {
        return mBytes.data() + texelOffset(x, y, sample);
    }
    const std::byte* texel(std::uint32_t x, std::uint32_t y, std::uint32_t sample = 0) const {
        return mBytes.data() + texelOffset(x, y, sample);
    }
    std::span<std::byte> bytes() { return mBytes; }
    std::span<const std::byte> bytes() const { return mBytes; }

    // Colour formats: the shader-visible value of a texel (D3D11.3 conversion rules).
    glm::vec4 load(std::uint32_t x, std::uint32_t y, std::uint32_t sample = 0) const;
    void store(std::uint32_t x, std::uint32_t y, std::uint32_t sample, const glm::vec4& value);
    // UINT formats.
    glm::uvec4 loadUint(std::uint32_t x, std::uint32_t y, std::uint32_t sample = 0) const;

    // Depth-stencil formats: depth as a float in [0,1] (D24 decoded), stencil as stored.
    float loadDepth(std::uint32_t x, std::uint32_t y, std::uint32_t sample = 0) const;
    std::uint8_t loadStencil(std::uint32_t x, std::uint32_t y, std::uint32_t sample = 0) const;

    // ClearRenderTargetView: every sample of every pixel gets `value` encoded in the format.
    void clearColor(const glm::vec4& value);
    // ClearUnorderedAccessViewUint equivalent for UINT formats.
    void clearUint(const glm::uvec4& value);
    // ClearDepthStencilView: depth converted to the format (D24 quantized), stencil as given.
    // stencilWriteMask < 0xFF changes only those stencil bits: what a full-screen stencil REPLACE
    // draw with that StencilWriteMask leaves (a D3D11 clear itself writes all eight).
    void clearDepthStencil(bool clearDepth, float depth, bool clearStencil, std::uint8_t stencil,
                           std::uint8_t stencilWriteMask = 0xFF);
    // The same clear on the texels (all samples) of pixels x0 <= x < x1, y0 <= y < y1 only
    // (clamped to the surface), as D3D11.1's ClearView with a rectangle does.
    void clearDepthStencilRect(std::uint32_t x0, std::uint32_t y0, std::uint32_t x1, std::uint32_t y1, bool clearDepth,
                               float depth, bool clearStencil, std::uint8_t stencil, std::uint8_t stencilWriteMask = 0xFF);

    // ResolveSubresource for float-convertible formats: the average of the samples of each
    // pixel, accumulated in float in sample order, into a single-sample surface of `format`.
    Surface resolve(Format format) const;

private:
    std::size_t texelOffset(std::uint32_t x, std::uint32_t y, std::uint32_t sample) const {
        return ((std::size_t(y) * mDesc.width + x) * mDesc.sampleCount + sample) * mBytesPerTexel;
    }
    SurfaceDesc mDesc{};
    std::uint32_t mBytesPerTexel = 0;
    std::vector<std::byte> mBytes;
};

} // namespace tessera
