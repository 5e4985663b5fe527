// The sampling kernels behind texture/sampling.h (the rules and choices are documented there):
// LOD from derivatives with a libm-independent log2, D3D min/max clamps, mip selection, range
// reduction, point and bilinear filtering of one level, trilinear blend. The per-texel decoder
// is a template parameter, so each format's path is one inlined loop with no per-texel switch.
#include <tessera/texture/sampling.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include <tessera/buffers/conversion.h>
#include <tessera/math/det_math.h>  // detLog2: LOD without libm

namespace tessera {
namespace {

constexpr float kRangeReductionMax = 10.0f;  // D3D11_COMMONSHADER_TEXCOORD_RANGE_REDUCTION_MAX (§7.18.6)

// ---- Scalar rules ------------------------------------------------------------------------

// §3.1 "Floating Point Rules": min/max with one NaN operand return the other operand.
inline float d3dMin(float a, float b) {
    if (std::isnan(a)) return b;
    if (std::isnan(b)) return a;
    return b < a ? b : a;
}
inline float d3dMax(float a, float b) {
    if (std::isnan(a)) return b;
    if (std::isnan(b)) return a;
    return b > a ? b : a;
}
inline double d3dMax(double a, double b) {
    if (std::isnan(a)) return b;
    if (std::isnan(b)) return a;
    return b > a ? b : a;
}

// §7.18.11 isotropic LOD (the formula choice is documented in sampling.h): derivatives in
// texels of level 0; LOD = log2(max(|dX|, |dY|)) = 0.5 * log2(max(|dX|^2, |dY|^2)). Every
// float * size product is exact in double.
float computeLodFromDerivatives(std::uint32_t width0, std::uint32_t height0, glm::vec2 ddxUv, glm::vec2 ddyUv) {
    const double width = double(width0), height = double(height0);
    const double dxU = double(ddxUv.x) * width, dxV = double(ddxUv.y) * height;
    const double dyU = double(ddyUv.x) * width, dyV = double(ddyUv.y) * height;
    const double lengthSqX = dxU * dxU + dxV * dxV;
    const double lengthSqY = dyU * dyU + dyV * dyV;
    return float(0.5 * detLog2(d3dMax(lengthSqX, lengthSqY)));
}

// The LOD is a pure function of level 0's size and the four derivatives, and the rasteriser hands
// every pixel of a 2x2 quad the same (coarse) derivatives, while a material samples several
// textures of one size through one texture coordinate: one pixel shader's samples mostly repeat
// the same arguments. Each thread keeps the last kLodMemoEntries (arguments -> LOD) and reuses a
// result only when every argument matches bit for bit, so a reused LOD is the value the
// computation would return (detLog2 is deterministic), whatever the thread or the order
// (tests/texture: a fresh thread's cold memo is the oracle). A deferred frame of
// sponza-small-lights reuses 88% of its LODs (bench/RESULTS.md, "glm inlined, LOD memo").
constexpr std::size_t kLodMemoEntries = 4;  // entries per thread, replaced round robin
struct LodMemo {
    struct Entry {
        std::uint32_t width = 0, height = 0;  // 0: empty (a bound texture has width >= 1)
        std::uint64_t ddxBits = 0, ddyBits = 0;  // (x, y) bit patterns, x in the low half
        float lod = 0.0f;
    };
    std::array<Entry, kLodMemoEntries> entries{};
    std::size_t next = 0;
};
thread_local LodMemo tLodMemo;

float lodFromDerivatives(const Texture2D& texture, glm::vec2 ddxUv, glm::vec2 ddyUv) {
    const std::uint32_t width = texture.width(0), height = texture.height(0);
    const auto bitsOf = [](glm::vec2 v) {
        return std::uint64_t(std::bit_cast<std::uint32_t>(v.x)) | (std::uint64_t(std::bit_cast<std::uint32_t>(v.y)) << 32);
    };
    const std::uint64_t ddxBits = bitsOf(ddxUv), ddyBits = bitsOf(ddyUv);
    LodMemo& memo = tLodMemo;
    for (const LodMemo::Entry& e : memo.entries)
        if (e.width == width && e.height == height && e.ddxBits == ddxBits && e.ddyBits == ddyBits) return e.lod;
    const float lod = computeLodFromDerivatives(width, height, ddxUv, ddyUv);
    memo.entries[memo.next] = LodMemo::Entry{width, height, ddxBits, ddyBits, lod};
    memo.next = (memo.next + 1) % kLodMemoEntries;
    return lod;
}

// §7.18.11: clampedLOD = max(MinLOD, min(MaxLOD, biasedLOD)) with D3D min/max.
inline float clampLodToSampler(const SamplerState& sampler, float biasedLod) {
    return d3dMax(sampler.minLod, d3dMin(sampler.maxLod, biasedLod));
}

// §7.18.6 ReduceRange on a normalized coordinate.
inline float reduceRange(float u, AddressMode mode) {
    switch (mode) {
    case AddressMode::Wrap: return u - std::floor(u);                     // frac(u): [0, 1)
    case AddressMode::Mirror: {                                           // signedFrac(u/2) * 2: (-2, 2)
        const float half = u * 0.5f;
        return (half - std::trunc(half)) * 2.0f;
    }
    case AddressMode::Clamp:
    case AddressMode::Border:
    case AddressMode::MirrorOnce:                                         // [-10, 10]
        if (u <= -kRangeReductionMax) return -kRangeReductionMax;
        if (u >= kRangeReductionMax) return kRangeReductionMax;
        return u;                                                         // NaN passes through
    }
    return 0.0f;
}

// A texel-space coordinate before its integer part is taken: NaN -> 0 (§3.2.4.1 FLOAT -> FIXED).
// After range reduction |coordinate| <= 10 * 16384 + 1, so int(floor(x)) cannot overflow.
inline float nanToZero(float x) { return std::isnan(x) ? 0.0f : x; }

inline glm::vec4 lerp(const glm::vec4& a, const glm::vec4& b, float weightB) { return a + (b - a) * weightB; }

// ---- Texel decoders ------------------------------------------------------------------------

// The value of each 8-bit code, built once from conversion.h so that filtering sees exactly the
// values Load returns: UNORM code / 255 (§3.2.3.5), sRGB code -> linear (§3.2.3.7).
struct DecodeTables {
    std::array<float, 256> unorm{};
    std::array<float, 256> srgb{};
};

const DecodeTables& decodeTables() {
    static const DecodeTables tables = [] {
        DecodeTables t;
        for (std::uint32_t code = 0; code < 256; ++code) {
            t.unorm[code] = convert::unormToFloat(code, 8);
            t.srgb[code] = convert::srgb8ToLinear(std::uint8_t(code));
        }
        return t;
    }();
    return tables;
}

// R8G8B8A8_UNORM and _SRGB: R, G, B through `rgb` (UNORM or sRGB table), A always UNORM
// (§19.1.3.2: _SRGB leaves alpha linear).
struct Rgba8Decoder {
    static constexpr std::size_t kBytesPerTexel = 4;
    const float* rgb;
    const float* alpha;
    glm::vec4 operator()(const std::byte* texel) const {
        return {rgb[std::to_integer<std::uint8_t>(texel[0])], rgb[std::to_integer<std::uint8_t>(texel[1])],
                rgb[std::to_integer<std::uint8_t>(texel[2])], alpha[std::to_integer<std::uint8_t>(texel[3])]};
    }
};

// R32G32B32A32_FLOAT: four float32 as stored.
struct Float4Decoder {
    static constexpr std::size_t kBytesPerTexel = 16;
    glm::vec4 operator()(const std::byte* texel) const {
        static_assert(sizeof(glm::vec4) == kBytesPerTexel, "glm::vec4 is four packed floats");
        glm::vec4 value;
        std::memcpy(&value, texel, kBytesPerTexel);
        return value;
    }
};

// ---- Filtering -----------------------------------------------------------------------------

struct LevelView {
    const std::byte* texels;
    int width, height;  // texels
};

template <class Decoder>
class LevelSampler {
public:
    LevelSampler(const Texture2D& texture, const SamplerState& sampler, Decoder decoder, glm::vec4 border)
        : mTexture(texture), mSampler(sampler), mDecoder(decoder), mBorder(border) {}

    // §7.18.10 mip selection on a sampler-clamped LOD, then §7.18.7/§7.18.8 per level.
    glm::vec4 sample(glm::vec2 uvReduced, float lodClamped) const {
        const Filter filter = lodClamped > 0.0f ? mSampler.minFilter : mSampler.magFilter;  // LOD <= 0 magnifies
        const float lastLevel = float(mTexture.levels() - 1);
        const float lod = d3dMin(lodClamped > 0.0f ? lodClamped : 0.0f, lastLevel);  // [0, levels - 1], NaN -> 0
        const float lodFloor = std::floor(lod);
        const int level = int(lodFloor);
        const float fraction = lod - lodFloor;  // exact: 0 <= lod < 2^4
        glm::vec4 nearer;
        if (mSampler.mipFilter == Filter::Point) {  // nearest level: fraction >= 0.5 rounds up
            filterLevel(level + (fraction >= 0.5f ? 1 : 0), filter, uvReduced, nearer);
            return nearer;
        }
        filterLevel(level, filter, uvReduced, nearer);
        if (fraction == 0.0f) return nearer;  // also the last level: nothing to blend
        glm::vec4 further;
        filterLevel(level + 1, filter, uvReduced, further);
        return lerp(nearer, further, fraction);
    }

private:
    LevelView view(int level) const {
        return {mTexture.levelBytes(level).data(), int(mTexture.width(level)), int(mTexture.height(level))};
    }

    // x, y already through addressTexel: -1 means Border on that axis (§7.18.9).
    glm::vec4 texel(const LevelView& level, int x, int y) const {
        if (x < 0 || y < 0) return mBorder;
        return mDecoder(level.texels + (std::size_t(y) * std::size_t(level.width) + std::size_t(x)) *
                                           Decoder::kBytesPerTexel);
    }

    // The filtered value is stored through `out`, not returned: a returned glm::vec4 travels in two
    // register halves (SysV x86-64 ABI) that the caller reassembles through the stack (a
    // store-forwarding stall). With sampleClampedLod inlined (below), the sampler's CPU samples in
    // a deferred frame fell by 22% (bench/RESULTS.md, "glm inlined, LOD memo").
    void filterLevel(int levelIndex, Filter filter, glm::vec2 uvReduced, glm::vec4& out) const {
        const LevelView level = view(levelIndex);
        if (filter == Filter::Point) {
            // §7.18.7: t = floor(u * size).
            const int tu = int(std::floor(nanToZero(uvReduced.x * float(level.width))));
            const int tv = int(std::floor(nanToZero(uvReduced.y * float(level.height))));
            out = texel(level, addressTexel(tu, level.width, mSampler.addressU),
                        addressTexel(tv, level.height, mSampler.addressV));
            return;
        }
        // §7.18.8: s = u * size - 0.5; tFloor = floor(s), tCeil = tFloor + 1, wCeil = frac(s).
        const float su = nanToZero(uvReduced.x * float(level.width) - 0.5f);
        const float sv = nanToZero(uvReduced.y * float(level.height) - 0.5f);
        const float floorU = std::floor(su), floorV = std::floor(sv);
        const float weightU = su - floorU, weightV = sv - floorV;  // wCeilU, wCeilV in [0, 1)
        const int u0 = addressTexel(int(floorU), level.width, mSampler.addressU);
        const int v0 = addressTexel(int(floorV), level.height, mSampler.addressV);
        // Taps with weight 0 are not fetched (§7.18.16.2 lets their NaN/INF go unpropagated).
        const int u1 = weightU != 0.0f ? addressTexel(int(floorU) + 1, level.width, mSampler.addressU) : u0;
        glm::vec4 top = texel(level, u0, v0);
        if (weightU != 0.0f) top = lerp(top, texel(level, u1, v0), weightU);
        if (weightV == 0.0f) {
            out = top;
            return;
        }
        const int v1 = addressTexel(int(floorV) + 1, level.height, mSampler.addressV);
        glm::vec4 bottom = texel(level, u0, v1);
        if (weightU != 0.0f) bottom = lerp(bottom, texel(level, u1, v1), weightU);
        out = lerp(top, bottom, weightV);
    }

    const Texture2D& mTexture;
    const SamplerState& mSampler;
    Decoder mDecoder;
    glm::vec4 mBorder;  // §7.18.9.1, already clamped to the format's range
};

// §7.18.9.1: the border colour is clamped into the format's range before filtering (UNORM:
// [0, 1], NaN -> 0); float formats use it as given.
glm::vec4 unormBorder(const glm::vec4& color) {
    glm::vec4 clamped;
    for (int c = 0; c < 4; ++c) {
        const float value = color[c];
        clamped[c] = std::isnan(value) ? 0.0f : (value < 0.0f ? 0.0f : (value > 1.0f ? 1.0f : value));
    }
    return clamped;
}

// Every sample* ends here with the LOD after bias and the MinLOD/MaxLOD clamp.
// Inlined into each public entry point, so that a sample's vec4 crosses one call boundary (the
// entry point's return), not two (see filterLevel).
[[gnu::always_inline]] inline glm::vec4 sampleClampedLod(const Texture2D& texture, const SamplerState& sampler, glm::vec2 uv,
                                                         float lodClamped) {
    if (texture.levels() == 0) return glm::vec4(0.0f);  // unbound: 0 (§22.4.15)
    const glm::vec2 uvReduced(reduceRange(uv.x, sampler.addressU), reduceRange(uv.y, sampler.addressV));
    if (texture.format() == Format::R32G32B32A32_FLOAT)
        return LevelSampler<Float4Decoder>(texture, sampler, Float4Decoder{}, sampler.borderColor)
            .sample(uvReduced, lodClamped);
    const DecodeTables& tables = decodeTables();
    const Rgba8Decoder decoder{texture.srgb() ? tables.srgb.data() : tables.unorm.data(), tables.unorm.data()};
    return LevelSampler<Rgba8Decoder>(texture, sampler, decoder, unormBorder(sampler.borderColor))
        .sample(uvReduced, lodClamped);
}

} // namespace

// ---- Public entry points -------------------------------------------------------------------

float calculateLodUnclamped(const Texture2D& texture, glm::vec2 ddxUv, glm::vec2 ddyUv) {
    if (texture.levels() == 0) return 0.0f;
    return lodFromDerivatives(texture, ddxUv, ddyUv);
}

float calculateLod(const Texture2D& texture, const SamplerState& sampler, glm::vec2 ddxUv, glm::vec2 ddyUv) {
    if (texture.levels() == 0) return 0.0f;
    const float clamped = clampLodToSampler(sampler, lodFromDerivatives(texture, ddxUv, ddyUv) + sampler.mipLodBias);
    return d3dMin(clamped > 0.0f ? clamped : 0.0f, float(texture.levels() - 1));
}

glm::vec4 sample(const Texture2D& texture, const SamplerState& sampler, glm::vec2 uv, glm::vec2 ddxUv,
                 glm::vec2 ddyUv) {
    if (texture.levels() == 0) return glm::vec4(0.0f);
    const float lod = lodFromDerivatives(texture, ddxUv, ddyUv);
    return sampleClampedLod(texture, sampler, uv, clampLodToSampler(sampler, lod + sampler.mipLodBias));
}

glm::vec4 sampleBias(const Texture2D& texture, const SamplerState& sampler, glm::vec2 uv, glm::vec2 ddxUv,
                     glm::vec2 ddyUv, float lodBias) {
    if (texture.levels() == 0) return glm::vec4(0.0f);
    const float lod = lodFromDerivatives(texture, ddxUv, ddyUv);
    // §7.18.11: biasedLOD = LOD + MipLODBias; biasedLOD += srcLODBias (sample_b).
    return sampleClampedLod(texture, sampler, uv, clampLodToSampler(sampler, (lod + sampler.mipLodBias) + lodBias));
}

glm::vec4 sampleLevel(const Texture2D& texture, const SamplerState& sampler, glm::vec2 uv, float lod) {
    return sampleClampedLod(texture, sampler, uv, clampLodToSampler(sampler, lod + sampler.mipLodBias));
}

// Texture2D's shader-style spellings (declared in texture2d.h).
glm::vec4 Texture2D::sample(const SamplerState& sampler, glm::vec2 uv, glm::vec2 ddxUv, glm::vec2 ddyUv) const {
    return tessera::sample(*this, sampler, uv, ddxUv, ddyUv);
}
glm::vec4 Texture2D::sampleBias(const SamplerState& sampler, glm::vec2 uv, glm::vec2 ddxUv, glm::vec2 ddyUv,
                                float lodBias) const {
    return tessera::sampleBias(*this, sampler, uv, ddxUv, ddyUv, lodBias);
}
glm::vec4 Texture2D::sampleGrad(const SamplerState& sampler, glm::vec2 uv, glm::vec2 ddxUv, glm::vec2 ddyUv) const {
    return tessera::sampleGrad(*this, sampler, uv, ddxUv, ddyUv);
}
glm::vec4 Texture2D::sampleLevel(const SamplerState& sampler, glm::vec2 uv, float lod) const {
    return tessera::sampleLevel(*this, sampler, uv, lod);
}
float Texture2D::calculateLevelOfDetail(const SamplerState& sampler, glm::vec2 ddxUv, glm::vec2 ddyUv) const {
    return tessera::calculateLod(*this, sampler, ddxUv, ddyUv);
}
float Texture2D::calculateLevelOfDetailUnclamped(glm::vec2 ddxUv, glm::vec2 ddyUv) const {
    return tessera::calculateLodUnclamped(*this, ddxUv, ddyUv);
}

} // namespace tessera
