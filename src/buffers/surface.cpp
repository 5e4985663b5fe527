// Surface storage, clears, typed loads and MSAA resolve. Depth-stencil texel layouts:
// D24_UNORM_S8_UINT = uint32 (depth bits 0..23, stencil 24..31); D32_FLOAT = float;
// D32_FLOAT_S8X24_UINT = float depth, then stencil byte, then 3 unused bytes.
#include <tessera/buffers/surface.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include <tessera/buffers/conversion.h>
#include <tessera/buffers/fill.h>
#include <tessera/buffers/texel_codec.h>
#include <tessera/state/viewport.h>

namespace tessera {

Surface::Surface(const SurfaceDesc& desc) : mDesc(desc) {
    if (desc.width == 0 || desc.width > kMaxSurfaceDimension)
        throw std::invalid_argument("surface width " + std::to_string(desc.width) + " outside 1.." +
                                    std::to_string(kMaxSurfaceDimension));
    if (desc.height == 0 || desc.height > kMaxSurfaceDimension)
        throw std::invalid_argument("surface height " + std::to_string(desc.height) + " outside 1.." +
                                    std::to_string(kMaxSurfaceDimension));
    if (desc.sampleCount != 1 && desc.sampleCount != 2 && desc.sampleCount != 4 && desc.sampleCount != 8)
        throw std::invalid_argument("surface sample count " + std::to_string(desc.sampleCount) +
                                    " is not 1, 2, 4 or 8");
    if (desc.format == Format::Unknown) throw std::invalid_argument("surface format UNKNOWN");
    mBytesPerTexel = formatInfo(desc.format).bytesPerTexel;
    mBytes.assign(std::size_t(desc.width) * desc.height * desc.sampleCount * mBytesPerTexel, std::byte{0});
}

glm::vec4 Surface::load(std::uint32_t x, std::uint32_t y, std::uint32_t sample) const {
    return decodeTexel(mDesc.format, texel(x, y, sample));
}

void Surface::store(std::uint32_t x, std::uint32_t y, std::uint32_t sample, const glm::vec4& value) {
    encodeTexel(mDesc.format, value, texel(x, y, sample));
}

glm::uvec4 Surface::loadUint(std::uint32_t x, std::uint32_t y, std::uint32_t sample) const {
    return decodeTexelUint(mDesc.format, texel(x, y, sample));
}

float Surface::loadDepth(std::uint32_t x, std::uint32_t y, std::uint32_t sample) const {
    const std::byte* p = texel(x, y, sample);
    switch (mDesc.format) {
    case Format::D24_UNORM_S8_UINT: {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return convert::d24ToDepth(v & 0xFFFFFFu);
    }
    case Format::D32_FLOAT:
    case Format::D32_FLOAT_S8X24_UINT: {
        float z;
        std::memcpy(&z, p, 4);
        return z;
    }
    default: throw std::invalid_argument("loadDepth on non-depth format " + std::string(formatInfo(mDesc.format).name));
    }
}

std::uint8_t Surface::loadStencil(std::uint32_t x, std::uint32_t y, std::uint32_t sample) const {
    const std::byte* p = texel(x, y, sample);
    switch (mDesc.format) {
    case Format::D24_UNORM_S8_UINT: return std::to_integer<std::uint8_t>(p[3]);
    case Format::D32_FLOAT_S8X24_UINT: return std::to_integer<std::uint8_t>(p[4]);
    default: throw std::invalid_argument("loadStencil on format without stencil " + std::string(formatInfo(mDesc.format).name));
    }
}

namespace {
void fillPattern(std::vector<std::byte>& bytes, const std::byte* pattern, std::uint32_t size) {
    const std::byte keep[16]{};  // overwrite every byte
    maskedFill(bytes, keep, pattern, size);
}
} // namespace

void Surface::clearColor(const glm::vec4& value) {
    std::byte pattern[16];
    encodeTexel(mDesc.format, value, pattern);
    fillPattern(mBytes, pattern, mBytesPerTexel);
}

void Surface::clearUint(const glm::uvec4& value) {
    std::byte pattern[16];
    encodeTexelUint(mDesc.format, value, pattern);
    fillPattern(mBytes, pattern, mBytesPerTexel);
}

void Surface::clearDepthStencil(bool clearDepth, float depth, bool clearStencil, std::uint8_t stencil,
                                std::uint8_t stencilWriteMask) {
    clearDepthStencilRect(0, 0, mDesc.width, mDesc.height, clearDepth, depth, clearStencil, stencil, stencilWriteMask);
}

void Surface::clearDepthStencilRect(std::uint32_t x0, std::uint32_t y0, std::uint32_t x1, std::uint32_t y1, bool clearDepth,
                                    float depth, bool clearStencil, std::uint8_t stencil, std::uint8_t stencilWriteMask) {
    const FormatInfo& info = formatInfo(mDesc.format);
    if (!info.hasDepth) throw std::invalid_argument("clearDepthStencil on " + std::string(info.name));
    // D3D11 ClearDepthStencilView: depth is clamped to [0,1] before conversion.
    const float z = depth != depth ? 0.0f : (depth < 0.0f ? 0.0f : (depth > 1.0f ? 1.0f : depth));
    // One texel's keep mask and set bytes, then the masked fill (buffers/fill.h).
    std::byte keep[8], set[8]{};
    std::fill(std::begin(keep), std::end(keep), std::byte{0xFF});
    if (mDesc.format == Format::D24_UNORM_S8_UINT) {
        std::uint32_t keepBits = 0xFFFFFFFFu, setBits = 0;
        if (clearDepth) {
            keepBits &= 0xFF000000u;
            setBits |= convert::depthToD24(z);
        }
        if (clearStencil) {
            keepBits &= 0x00FFFFFFu | (std::uint32_t(std::uint8_t(~stencilWriteMask)) << 24);
            setBits |= std::uint32_t(stencil & stencilWriteMask) << 24;
        }
        std::memcpy(keep, &keepBits, 4);
        std::memcpy(set, &setBits, 4);
    } else {
        if (clearDepth) {
            std::fill(keep, keep + 4, std::byte{0});
            std::memcpy(set, &z, 4);
        }
        if (clearStencil && info.hasStencil) {
            keep[4] = std::byte(std::uint8_t(~stencilWriteMask));
            set[4] = std::byte(std::uint8_t(stencil & stencilWriteMask));
        }
    }
    x1 = std::min(x1, mDesc.width);
    y1 = std::min(y1, mDesc.height);
    if (x0 >= x1 || y0 >= y1) return;
    const std::size_t rowBytes = std::size_t(mDesc.width) * mDesc.sampleCount * mBytesPerTexel;
    if (x0 == 0 && x1 == mDesc.width) {  // whole rows: one contiguous run
        maskedFill(std::span<std::byte>(mBytes).subspan(y0 * rowBytes, (y1 - y0) * rowBytes), keep, set, mBytesPerTexel);
        return;
    }
    // A row's samples of x0..x1 are contiguous (and 4-byte aligned: depth texels are 4 or 8 bytes).
    const std::size_t runBytes = std::size_t(x1 - x0) * mDesc.sampleCount * mBytesPerTexel;
    for (std::uint32_t y = y0; y < y1; ++y)
        maskedFill(std::span<std::byte>(texel(x0, y), runBytes), keep, set, mBytesPerTexel);
}

Surface Surface::resolve(Format format) const {
    Surface out(SurfaceDesc{mDesc.width, mDesc.height, format, 1});
    const float invCount = 1.0f / float(mDesc.sampleCount);
    for (std::uint32_t y = 0; y < mDesc.height; ++y)
        for (std::uint32_t x = 0; x < mDesc.width; ++x) {
            glm::vec4 sum(0.0f);
            for (std::uint32_t s = 0; s < mDesc.sampleCount; ++s) sum += load(x, y, s);
            out.store(x, y, 0, sum * invCount);
        }
    return out;
}

} // namespace tessera
