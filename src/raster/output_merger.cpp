// Depth/stencil test and update in the buffer's own format, and the blend equation with
// D3D11_BLEND factors and ops. All arithmetic is binary32 in a fixed order (no contraction).
#include <tessera/raster/output_merger.h>

#include <algorithm>
#include <cstring>

#include <tessera/buffers/conversion.h>
#include <tessera/buffers/texel_codec.h>

namespace tessera {

namespace {
struct StoredDepthStencil {
    std::uint32_t depthBits;  // D24 code, or the float's bit pattern
    std::uint8_t stencil;
};

StoredDepthStencil readStored(Format f, const std::byte* texel) {
    std::uint32_t v;
    std::memcpy(&v, texel, 4);
    if (f == Format::D24_UNORM_S8_UINT) return {v & 0xFFFFFFu, std::uint8_t(v >> 24)};
    if (f == Format::D32_FLOAT_S8X24_UINT) return {v, std::to_integer<std::uint8_t>(texel[4])};
    return {v, 0};
}

bool depthPasses(Format f, ComparisonFunc func, float z, std::uint32_t storedBits) {
    if (f == Format::D24_UNORM_S8_UINT) return compare(func, convert::depthToD24(z), storedBits);
    float stored;
    std::memcpy(&stored, &storedBits, 4);
    return compare(func, z, stored);
}
} // namespace

bool DepthStencilUnit::failCanWrite(bool frontFace) const {
    if (!stencilActive()) return false;
    const StencilFaceDesc& face = frontFace ? desc.frontFace : desc.backFace;
    return desc.stencilWriteMask != 0 && (face.failOp != StencilOp::Keep || face.depthFailOp != StencilOp::Keep);
}

DepthStencilResult DepthStencilUnit::test(const std::byte* texel, float z, bool frontFace) const {
    if (format == Format::Unknown) return DepthStencilResult::Pass;
    const StoredDepthStencil s = readStored(format, texel);
    if (stencilActive()) {
        const StencilFaceDesc& face = frontFace ? desc.frontFace : desc.backFace;
        const std::uint8_t m = desc.stencilReadMask;
        if (!compare(face.func, std::uint8_t(ref & m), std::uint8_t(s.stencil & m))) return DepthStencilResult::StencilFail;
    }
    if (desc.depthEnable && !depthPasses(format, desc.depthFunc, z, s.depthBits)) return DepthStencilResult::DepthFail;
    return DepthStencilResult::Pass;
}

void DepthStencilUnit::update(std::byte* texel, float z, bool frontFace, DepthStencilResult result) const {
    if (format == Format::Unknown) return;
    if (stencilActive()) {
        const StencilFaceDesc& face = frontFace ? desc.frontFace : desc.backFace;
        const StencilOp op = result == DepthStencilResult::StencilFail ? face.failOp
                             : result == DepthStencilResult::DepthFail ? face.depthFailOp
                                                                       : face.passOp;
        if (op != StencilOp::Keep) {
            const std::size_t at = format == Format::D24_UNORM_S8_UINT ? 3 : 4;
            const std::uint8_t old = std::to_integer<std::uint8_t>(texel[at]);
            texel[at] = std::byte{writeStencil(old, applyStencilOp(op, old, ref), desc.stencilWriteMask)};
        }
    }
    if (result == DepthStencilResult::Pass && desc.depthEnable && desc.depthWriteEnable) {
        if (format == Format::D24_UNORM_S8_UINT) {
            const std::uint32_t code = convert::depthToD24(z);
            texel[0] = std::byte(code & 0xFF);
            texel[1] = std::byte((code >> 8) & 0xFF);
            texel[2] = std::byte((code >> 16) & 0xFF);
        } else {
            std::memcpy(texel, &z, 4);
        }
    }
}

DepthPath DepthStencilUnit::path() const {
    if (format == Format::Unknown || (!desc.depthEnable && !stencilActive())) return DepthPath::Off;
    if (stencilActive()) return DepthPath::General;
    if (format == Format::D24_UNORM_S8_UINT) return DepthPath::D24;
    return DepthPath::D32;  // D32_FLOAT, D32_FLOAT_S8X24_UINT: the float is in bytes 0..3
}

namespace {
float clampTo(float v, float lo, float hi) {
    if (!(v == v)) return 0.0f;  // NaN -> 0 (D3D11.3 §3.2.3.6: NaN converts to 0)
    return std::min(std::max(v, lo), hi);
}

// One blend factor for colour channel c (0..2) or alpha (c == 3).
float factor(Blend b, int c, const glm::vec4& s, const glm::vec4& d, const glm::vec4& k) {
    switch (b) {
    case Blend::Zero: return 0.0f;
    case Blend::One: return 1.0f;
    case Blend::SrcColor: return s[c];
    case Blend::InvSrcColor: return 1.0f - s[c];
    case Blend::SrcAlpha: return s.w;
    case Blend::InvSrcAlpha: return 1.0f - s.w;
    case Blend::DestAlpha: return d.w;
    case Blend::InvDestAlpha: return 1.0f - d.w;
    case Blend::DestColor: return d[c];
    case Blend::InvDestColor: return 1.0f - d[c];
    // D3D11_BLEND_SRC_ALPHA_SAT: (f, f, f, 1) with f = min(As, 1 - Ad).
    case Blend::SrcAlphaSat: return c == 3 ? 1.0f : std::min(s.w, 1.0f - d.w);
    case Blend::BlendFactor: return k[c];
    case Blend::InvBlendFactor: return 1.0f - k[c];
    default: return 0.0f;  // dual-source factors are rejected by validation before drawing
    }
}

float combine(BlendOp op, float s, float fs, float d, float fd) {
    switch (op) {
    case BlendOp::Add: return s * fs + d * fd;
    case BlendOp::Subtract: return s * fs - d * fd;
    case BlendOp::RevSubtract: return d * fd - s * fs;
    case BlendOp::Min: return std::min(s, d);  // factors are ignored for MIN and MAX
    case BlendOp::Max: return std::max(s, d);
    }
    return s;
}
} // namespace

void writeColorSample(Format format, std::byte* texel, const glm::vec4& srcIn, const RenderTargetBlendDesc& blend,
                      const glm::vec4& blendFactorIn) {
    const std::uint8_t mask = blend.renderTargetWriteMask & WriteAll;
    if (mask == 0) return;
    const FormatInfo& info = formatInfo(format);
    if (info.kind == FormatKind::Uint) {
        glm::uvec4 value = glm::floatBitsToUint(srcIn);
        if (mask != WriteAll) {
            const glm::uvec4 old = decodeTexelUint(format, texel);
            for (int c = 0; c < 4; ++c)
                if (!(mask & (1 << c))) value[c] = old[c];
        }
        encodeTexelUint(format, value, texel);
        return;
    }
    glm::vec4 src = srcIn, k = blendFactorIn;
    if (info.kind == FormatKind::Unorm || info.kind == FormatKind::Snorm) {
        const float lo = info.kind == FormatKind::Unorm ? 0.0f : -1.0f;
        for (int c = 0; c < 4; ++c) {
            src[c] = clampTo(src[c], lo, 1.0f);
            k[c] = clampTo(k[c], lo, 1.0f);
        }
    }
    if (!blend.blendEnable && mask == WriteAll) {
        encodeTexel(format, src, texel);
        return;
    }
    const glm::vec4 dst = decodeTexel(format, texel);
    glm::vec4 result = src;
    if (blend.blendEnable) {
        for (int c = 0; c < 3; ++c)
            result[c] = combine(blend.blendOp, src[c], factor(blend.srcBlend, c, src, dst, k), dst[c],
                                factor(blend.destBlend, c, src, dst, k));
        result.w = combine(blend.blendOpAlpha, src.w, factor(blend.srcBlendAlpha, 3, src, dst, k), dst.w,
                           factor(blend.destBlendAlpha, 3, src, dst, k));
    }
    for (int c = 0; c < 4; ++c)
        if (!(mask & (1 << c))) result[c] = dst[c];
    encodeTexel(format, result, texel);
}

} // namespace tessera

namespace tessera {

bool isRgba8UnormOverwrite(Format format, const RenderTargetBlendDesc& blend) {
    return format == Format::R8G8B8A8_UNORM && !blend.blendEnable && (blend.renderTargetWriteMask & WriteAll) == WriteAll;
}

} // namespace tessera
