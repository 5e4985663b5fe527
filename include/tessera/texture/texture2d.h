// A sampled 2D texture with Direct3D 11 semantics: a mip chain of R8G8B8A8_UNORM,
// R8G8B8A8_UNORM_SRGB or R32G32B32A32_FLOAT texels, built once at load from an Image (glTF
// images) or from float RGBA data. Pixel shaders read it through Load and the sample* functions
// of texture/sampling.h; it is immutable after construction, so any number of threads may read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/buffers/format.h>
#include <tessera/texture/image.h>
#include <tessera/texture/sampler_state.h>

namespace tessera {

// How an Image's bytes encode colour. glTF 2.0 §3.9 "Materials": baseColorTexture and
// emissiveTexture are sRGB; metallicRoughness, normal and occlusion textures are linear.
enum class TexelEncoding : std::uint8_t {
    Linear,  // R8G8B8A8_UNORM
    Srgb     // R8G8B8A8_UNORM_SRGB: R, G, B sRGB-encoded, A linear (D3D11.3 §19.1.3.2)
};

// A Texture2D shader resource (D3D11.3 §5.3.6) with its full mip chain.
//
// Mip sizes (D3D11.3 §5.3.6: each level halves the previous, rounded down, never below 1):
// level L is max(1, floor(width / 2^L)) x max(1, floor(height / 2^L)); a full chain has
// 1 + floor(log2(max(width, height))) levels (5x3 -> 2x1 -> 1x1; 16384 -> 15 levels).
//
// Mip filter (D3D leaves GenerateMips' filter to the implementation; tessera fixes this one):
//   * Each level is built from the previous, stored level (cascaded, like GenerateMips).
//   * Separable box filter over the exact footprint of a destination texel. Per axis, with
//     source size s and destination size d = max(1, floor(s / 2)), destination texel x reads:
//       s even:           texels 2x, 2x+1                  weights 1/2, 1/2
//       s odd, s = 2d+1:  texels 2x, 2x+1, 2x+2            weights (d-x)/s, d/s, (x+1)/s
//       s == 1:           texel 0                          weight 1
//     The odd case is the polyphase box filter of NVIDIA's "Non-Power-of-Two Mipmap Creation"
//     (Sander/Wyman): every source texel contributes d/s of its area, so the level average is
//     preserved and no edge row or column is dropped. 5 -> 2: x=0 takes 2/5, 2/5, 1/5 of texels
//     0,1,2; x=1 takes 1/5, 2/5, 2/5 of texels 2,3,4. 3 -> 1: 1/3 each.
//   * Filtering happens on the decoded values: UNORM as code/255, sRGB decoded to linear
//     (D3D11.3 §3.2.3.7), float as stored. Alpha is averaged as it is (not premultiplied).
//   * Arithmetic is deterministic: weights are integer numerators over one denominator; the
//     sum  sum_j sum_i (numX_i * numY_j) * value(i, j)  runs rows outer, columns inner in double
//     (each product is exact; -ffp-contract=off, so no FMA), is divided once by (denX * denY),
//     converted to float, then encoded with the D3D11.3 rules: §3.2.3.6 FLOAT -> UNORM,
//     §3.2.3.8 FLOAT -> SRGB (through encodeTexel, texel_codec.h). Float textures store the
//     float result as it is.
//
// A default-constructed Texture2D has no levels and behaves like an unbound slot: Load and
// every sample function return (0, 0, 0, 0) (D3D11.3 §22.4.15 "nothing bound").
class Texture2D {
public:
    // D3D11_REQ_TEXTURE2D_U_OR_V_DIMENSION: the largest width or height, texels.
    static constexpr std::uint32_t kMaxDimension = 16384;
    // 1 + log2(16384): levels of a full chain at the largest size.
    static constexpr int kMaxLevels = 15;

    Texture2D() = default;

    // From a decoded image: R8G8B8A8_UNORM (Linear) or R8G8B8A8_UNORM_SRGB (Srgb), bytes copied
    // as they are. Throws InputError naming image.source when the image is empty (width or
    // height 0), larger than kMaxDimension, or rgba8 does not hold width * height * 4 bytes.
    static Texture2D fromImage(const Image& image, TexelEncoding encoding, bool generateMips = true);

    // From float RGBA data (width * height * 4 floats, row-major, row 0 at the top):
    // R32G32B32A32_FLOAT, values kept bit for bit (NaN and INF included). Throws InputError
    // naming `source` on the same conditions as fromImage.
    static Texture2D fromFloatRgba(std::uint32_t width, std::uint32_t height, std::span<const float> rgba,
                                   std::string_view source, bool generateMips = true);

    Format format() const { return mFormat; }
    bool srgb() const { return mFormat == Format::R8G8B8A8_UNORM_SRGB; }
    const std::string& source() const { return mSource; }
    int levels() const { return static_cast<int>(mLevels.size()); }
    // Texels of `level`; 0 for a level the texture does not have (resinfo, D3D11.3 §22.4.14).
    std::uint32_t width(int level = 0) const { return hasLevel(level) ? mLevels[level].width : 0; }
    std::uint32_t height(int level = 0) const { return hasLevel(level) ? mLevels[level].height : 0; }
    // Bytes of all levels as stored (texels only).
    std::size_t memoryBytes() const { return mTexels.size(); }
    // The bytes of one level as stored: row-major, row 0 at the top, formatInfo(format())
    // .bytesPerTexel each; empty for a level the texture does not have.
    std::span<const std::byte> levelBytes(int level) const {
        if (!hasLevel(level)) return {};
        const MipLevel& mip = mLevels[level];
        return {mTexels.data() + mip.offsetBytes, std::size_t(mip.width) * mip.height * mBytesPerTexel};
    }

    // HLSL Texture2D.Load(int3(texelCoord, level)) (D3D11.3 §22.4.6 ld): the texel converted to
    // float (sRGB decoded to linear, §3.2.3.7). An out-of-range coordinate or level returns
    // (0, 0, 0, 0).
    glm::vec4 load(glm::ivec2 texelCoord, int level = 0) const;

    // Shader-style spellings of texture/sampling.h (defined in src/texture/sampling.cpp):
    // texture.sample(sampler, in.varyings.uv, in.ddx.uv, in.ddy.uv) is HLSL Texture2D.Sample.
    glm::vec4 sample(const SamplerState& sampler, glm::vec2 uv, glm::vec2 ddxUv, glm::vec2 ddyUv) const;
    glm::vec4 sampleBias(const SamplerState& sampler, glm::vec2 uv, glm::vec2 ddxUv, glm::vec2 ddyUv,
                         float lodBias) const;
    glm::vec4 sampleGrad(const SamplerState& sampler, glm::vec2 uv, glm::vec2 ddxUv, glm::vec2 ddyUv) const;
    glm::vec4 sampleLevel(const SamplerState& sampler, glm::vec2 uv, float lod) const;
    float calculateLevelOfDetail(const SamplerState& sampler, glm::vec2 ddxUv, glm::vec2 ddyUv) const;
    float calculateLevelOfDetailUnclamped(glm::vec2 ddxUv, glm::vec2 ddyUv) const;

private:
    struct MipLevel {
        std::uint32_t width = 0, height = 0;  // texels
        std::size_t offsetBytes = 0;          // into mTexels
    };

    bool hasLevel(int level) const { return level >= 0 && level < levels(); }
    void allocateChain(std::uint32_t width, std::uint32_t height, bool generateMips);
    void generateMipChain();

    Format mFormat = Format::Unknown;
    std::uint32_t mBytesPerTexel = 0;
    std::string mSource;            // for messages: file path, "<gltf>#/images/N", ...
    std::vector<MipLevel> mLevels;  // level 0 first
    std::vector<std::byte> mTexels; // every level, level 0 first, each row-major
};

} // namespace tessera
