// Texture2D construction: validates the source image or float data, lays out the mip chain
// (D3D11 sizes) in one allocation and builds every level below 0 with the box filter documented
// in texture2d.h, through the texel codec's exact D3D11.3 conversions. Runs once per texture
// at scene load; sampling (src/texture/sampling.cpp) only reads the result.
#include <tessera/texture/texture2d.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <string>

#include <tessera/buffers/texel_codec.h>
#include <tessera/errors/input_error.h>

namespace tessera {
namespace {

constexpr std::uint32_t kRgba8BytesPerTexel = 4;     // R8G8B8A8_UNORM(_SRGB)
constexpr std::uint32_t kFloat4BytesPerTexel = 16;   // R32G32B32A32_FLOAT
constexpr std::uint32_t kChannels = 4;               // RGBA
constexpr std::uint32_t kMaxFilterTaps = 3;          // source texels per axis of one mip texel

std::string sourceName(std::string_view source) {
    return source.empty() ? std::string("<unnamed image>") : std::string(source);
}

std::string sizeText(std::uint32_t width, std::uint32_t height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

void validateSize(const std::string& source, std::uint32_t width, std::uint32_t height) {
    if (width == 0 || height == 0)
        throw inputError(source, "", "image is empty (" + sizeText(width, height) + " texels)");
    if (width > Texture2D::kMaxDimension || height > Texture2D::kMaxDimension)
        throw inputError(source, "", "image is " + sizeText(width, height) + " texels; a Direct3D 11 texture is at most " +
                                         std::to_string(Texture2D::kMaxDimension) + " texels on each side");
}

void validateCount(const std::string& source, std::uint32_t width, std::uint32_t height, std::size_t count,
                   const char* unit) {
    const std::size_t expected = std::size_t(width) * height * kChannels;
    if (count != expected)
        throw inputError(source, "", "image data holds " + std::to_string(count) + " " + unit + ", " +
                                         sizeText(width, height) + " RGBA texels need " + std::to_string(expected));
}

// One axis of the mip filter (texture2d.h): destination texel `dst` of a level `dstSize` long
// reads `count` source texels from `first` with weights numerator[i] / denominator.
struct AxisTaps {
    std::uint32_t first = 0;
    std::uint32_t count = 0;
    std::uint32_t numerator[kMaxFilterTaps] = {0, 0, 0};
    std::uint32_t denominator = 1;
};

AxisTaps axisTaps(std::uint32_t srcSize, std::uint32_t dst, std::uint32_t dstSize) {
    AxisTaps taps;
    if (srcSize == 1) {                  // this axis is already 1 texel: copy
        taps.count = 1;
        taps.numerator[0] = 1;
    } else if (srcSize % 2 == 0) {       // 2x2 box: 1/2, 1/2
        taps.first = 2 * dst;
        taps.count = 2;
        taps.numerator[0] = taps.numerator[1] = 1;
        taps.denominator = 2;
    } else {                             // s = 2d + 1: (d - x)/s, d/s, (x + 1)/s
        taps.first = 2 * dst;
        taps.count = 3;
        taps.numerator[0] = dstSize - dst;
        taps.numerator[1] = dstSize;
        taps.numerator[2] = dst + 1;
        taps.denominator = srcSize;
    }
    return taps;
}

} // namespace

Texture2D Texture2D::fromImage(const Image& image, TexelEncoding encoding, bool generateMips) {
    const std::string source = sourceName(image.source);
    validateSize(source, image.width, image.height);
    validateCount(source, image.width, image.height, image.rgba8.size(), "bytes");

    Texture2D texture;
    texture.mFormat = encoding == TexelEncoding::Srgb ? Format::R8G8B8A8_UNORM_SRGB : Format::R8G8B8A8_UNORM;
    texture.mBytesPerTexel = kRgba8BytesPerTexel;
    texture.mSource = source;
    texture.allocateChain(image.width, image.height, generateMips);
    std::memcpy(texture.mTexels.data(), image.rgba8.data(), image.rgba8.size());
    texture.generateMipChain();
    return texture;
}

Texture2D Texture2D::fromFloatRgba(std::uint32_t width, std::uint32_t height, std::span<const float> rgba,
                                   std::string_view source, bool generateMips) {
    const std::string name = sourceName(source);
    validateSize(name, width, height);
    validateCount(name, width, height, rgba.size(), "floats");

    Texture2D texture;
    texture.mFormat = Format::R32G32B32A32_FLOAT;
    texture.mBytesPerTexel = kFloat4BytesPerTexel;
    texture.mSource = name;
    texture.allocateChain(width, height, generateMips);
    // R32G32B32A32_FLOAT is four little-endian float32 per texel (§19.1.3.1): the host layout.
    std::memcpy(texture.mTexels.data(), rgba.data(), rgba.size_bytes());
    texture.generateMipChain();
    return texture;
}

void Texture2D::allocateChain(std::uint32_t width, std::uint32_t height, bool generateMips) {
    // A full chain ends at 1x1: 1 + floor(log2(max(w, h))) = bit_width(max(w, h)) levels.
    const int levelCount = generateMips ? int(std::bit_width(width > height ? width : height)) : 1;
    mLevels.resize(std::size_t(levelCount));
    std::size_t offset = 0;
    for (int level = 0; level < levelCount; ++level) {
        MipLevel& mip = mLevels[level];
        mip.width = std::max<std::uint32_t>(1u, width >> level);    // max(1, floor(w / 2^L))
        mip.height = std::max<std::uint32_t>(1u, height >> level);
        mip.offsetBytes = offset;
        offset += std::size_t(mip.width) * mip.height * mBytesPerTexel;
    }
    mTexels.assign(offset, std::byte{0});
}

void Texture2D::generateMipChain() {
    // The source rows one destination row reads (at most 3: the odd-size filter's taps), decoded
    // to shader values (sRGB -> linear). Decoding a row at a time, not the whole level, keeps the
    // peak at 3 rows of float4 instead of 16 B per texel of level 0 (64 MiB for 2048^2).
    std::vector<glm::vec4> rows;
    for (int level = 1; level < levels(); ++level) {
        const MipLevel& src = mLevels[level - 1];
        const MipLevel& dst = mLevels[level];
        const std::byte* srcBytes = mTexels.data() + src.offsetBytes;
        rows.resize(std::size_t(kMaxFilterTaps) * src.width);

        std::byte* dstBytes = mTexels.data() + dst.offsetBytes;
        for (std::uint32_t y = 0; y < dst.height; ++y) {
            const AxisTaps tapsY = axisTaps(src.height, y, dst.height);
            for (std::uint32_t j = 0; j < tapsY.count; ++j) {
                const std::byte* srcRow = srcBytes + std::size_t(tapsY.first + j) * src.width * mBytesPerTexel;
                glm::vec4* decoded = rows.data() + std::size_t(j) * src.width;
                for (std::uint32_t x = 0; x < src.width; ++x) decoded[x] = decodeTexel(mFormat, srcRow + x * mBytesPerTexel);
            }
            for (std::uint32_t x = 0; x < dst.width; ++x) {
                const AxisTaps tapsX = axisTaps(src.width, x, dst.width);
                double sum[kChannels] = {0.0, 0.0, 0.0, 0.0};
                for (std::uint32_t j = 0; j < tapsY.count; ++j) {
                    const glm::vec4* row = rows.data() + std::size_t(j) * src.width;
                    for (std::uint32_t i = 0; i < tapsX.count; ++i) {
                        // Integer weight <= 8192^2 = 2^26 times a 24-bit float: exact in double.
                        const double weight = double(tapsX.numerator[i] * tapsY.numerator[j]);
                        const glm::vec4& value = row[tapsX.first + i];
                        for (std::uint32_t c = 0; c < kChannels; ++c) sum[c] += weight * double(value[int(c)]);
                    }
                }
                const double denominator = double(tapsX.denominator) * double(tapsY.denominator);
                const glm::vec4 filtered(float(sum[0] / denominator), float(sum[1] / denominator),
                                         float(sum[2] / denominator), float(sum[3] / denominator));
                encodeTexel(mFormat, filtered, dstBytes + (std::size_t(y) * dst.width + x) * mBytesPerTexel);
            }
        }
    }
}

glm::vec4 Texture2D::load(glm::ivec2 texelCoord, int level) const {
    if (!hasLevel(level)) return glm::vec4(0.0f);
    const MipLevel& mip = mLevels[level];
    if (texelCoord.x < 0 || texelCoord.y < 0 || std::uint32_t(texelCoord.x) >= mip.width ||
        std::uint32_t(texelCoord.y) >= mip.height)
        return glm::vec4(0.0f);  // §22.4.6 / §5.8.5: out of bounds -> 0 in each present component
    const std::size_t index = std::size_t(texelCoord.y) * mip.width + std::size_t(texelCoord.x);
    return decodeTexel(mFormat, mTexels.data() + mip.offsetBytes + index * mBytesPerTexel);
}

} // namespace tessera
