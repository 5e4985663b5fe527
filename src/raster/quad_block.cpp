// quadBlockCoverage / quadBlockCentres (raster/quad_block.h): the scalar per-quad operations of
// draw_impl.h run over the 64 pixels of a block, compiled once per SIMD target by Highway's
// foreach_target and chosen at run time. Only IEEE-exact lane operations are used (int64 add and
// compare, int64 -> double conversion, multiply, add, divide, double -> float demotion), never
// MulAdd or an approximate reciprocal, so every lane rounds as the scalar code does.
#include <tessera/raster/quad_block.h>

#include <bit>
#include <cstring>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/quad_block.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>
#include <hwy/targets.h>

HWY_BEFORE_NAMESPACE();
namespace tessera::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace {
constexpr int kSide = QuadBlock::kSide;

// xOffset[i][x] = x * stepX[i]: E_i's change from the block's first column to column x.
struct ColumnOffsets {
    HWY_ALIGN std::int64_t x[3][kSide];
    explicit ColumnOffsets(const QuadBlock::Edges& e) {
        for (int i = 0; i < 3; ++i)
            for (int c = 0; c < kSide; ++c) x[i][c] = e.stepX[i] * c;
    }
};
} // namespace

std::uint64_t BlockCoverage(const SetupTriangle& t, const QuadBlock::Edges& e, std::uint8_t columns, std::uint8_t rows) {
    const hn::CappedTag<std::int64_t, kSide> d;
    const std::size_t n = hn::Lanes(d);
    const ColumnOffsets offsets(e);
    std::uint64_t covered = 0;
    for (int row = 0; row < kSide; ++row) {
        if (!((rows >> row) & 1u)) continue;
        for (std::size_t c = 0; c < std::size_t(kSide); c += n) {
            auto in = hn::FirstN(d, n);  // all lanes
            for (int i = 0; i < 3; ++i) {
                const auto edge = hn::Add(hn::Set(d, e.origin[i] + e.stepY[i] * row), hn::Load(d, offsets.x[i] + c));
                // E >= bias as E > bias - 1 (integers; Highway 1.0 has no int64 Ge on x86).
                in = hn::And(in, hn::Gt(edge, hn::Set(d, std::int64_t(t.bias[i]) - 1)));
            }
            std::uint8_t bits[8] = {};
            hn::StoreMaskBits(d, in, bits);
            covered |= std::uint64_t(bits[0] & ((1u << n) - 1u)) << (row * kSide + int(c));
        }
    }
    std::uint64_t columnMask = 0;
    for (int row = 0; row < kSide; ++row) columnMask |= std::uint64_t(columns) << (row * kSide);
    return covered & columnMask;
}

void BlockCentres(const SetupTriangle& t, const QuadBlock::Edges& e, const float* HWY_RESTRICT vertexVaryings,
                  std::uint32_t varyingCount, bool wantPosW, bool fastBarycentrics, QuadBlock& out) {
    // Barycentrics, one row of the block at a time: l_i = float(double(E_i) * invArea2), as
    // detail::baryFromEdges; fast: float(double(E_i)) * float(invArea2).
    const hn::CappedTag<std::int64_t, kSide> di;
    const hn::Rebind<double, decltype(di)> dd;
    const hn::Rebind<float, decltype(di)> dh;
    const std::size_t n64 = hn::Lanes(di);
    const ColumnOffsets offsets(e);
    const auto invArea2 = hn::Set(dd, t.invArea2);
    const auto invArea2Float = hn::Set(dh, float(t.invArea2));
    for (int row = 0; row < kSide; ++row) {
        for (std::size_t c = 0; c < std::size_t(kSide); c += n64) {
            for (int i = 0; i < 3; ++i) {
                const auto edge = hn::Add(hn::Set(di, e.origin[i] + e.stepY[i] * row), hn::Load(di, offsets.x[i] + c));
                const auto edgeDouble = hn::ConvertTo(dd, edge);
                const auto l = fastBarycentrics ? hn::Mul(hn::DemoteTo(dh, edgeDouble), invArea2Float)
                                                : hn::DemoteTo(dh, hn::Mul(edgeDouble, invArea2));
                hn::StoreU(l, dh, out.l[i] + row * kSide + c);
            }
        }
    }

    // Depth, clip w and varyings over all 64 lanes, in the operation order of quadCentres.
    const hn::CappedTag<float, QuadBlock::kPixels> df;
    const std::size_t nf = hn::Lanes(df);
    const auto z0 = hn::Set(df, t.zWindow[0]);
    const auto dz1 = hn::Set(df, t.zWindow[1] - t.zWindow[0]), dz2 = hn::Set(df, t.zWindow[2] - t.zWindow[0]);
    for (std::size_t p = 0; p < std::size_t(QuadBlock::kPixels); p += nf) {
        const auto l1 = hn::Load(df, out.l[1] + p), l2 = hn::Load(df, out.l[2] + p);
        hn::Store(hn::Add(hn::Add(z0, hn::Mul(l1, dz1)), hn::Mul(l2, dz2)), df, out.z + p);
    }
    if (varyingCount == 0 && !wantPosW) return;
    const auto invW0 = hn::Set(df, t.invW[0]), invW1 = hn::Set(df, t.invW[1]), invW2 = hn::Set(df, t.invW[2]);
    const auto one = hn::Set(df, 1.0f);
    for (std::size_t p = 0; p < std::size_t(QuadBlock::kPixels); p += nf) {
        const auto l0 = hn::Load(df, out.l[0] + p), l1 = hn::Load(df, out.l[1] + p), l2 = hn::Load(df, out.l[2] + p);
        const auto sum = hn::Add(hn::Add(hn::Mul(l0, invW0), hn::Mul(l1, invW1)), hn::Mul(l2, invW2));
        const auto invDenom = hn::Div(one, sum);
        hn::Store(invDenom, df, out.posW + p);
        for (std::uint32_t k = 0; k < varyingCount; ++k) {
            const auto v0 = hn::Set(df, vertexVaryings[k]);
            const auto v1 = hn::Set(df, vertexVaryings[varyingCount + k]);
            const auto v2 = hn::Set(df, vertexVaryings[2 * varyingCount + k]);
            const auto sumV = hn::Add(hn::Add(hn::Mul(l0, v0), hn::Mul(l1, v1)), hn::Mul(l2, v2));
            hn::Store(hn::Mul(sumV, invDenom), df, out.varyings + std::size_t(k) * QuadBlock::kPixels + p);
        }
    }
}

// R8G8B8A8_UNORM codes of 64 pixels (SoA floats in, packed RGBA8 out). Exact: round(x * 255)
// with halves up on the clamped x, as writeColorRgba8Unorm's double arithmetic rounds it, but in
// 32-bit integer lanes (twice as many per vector as doubles, and no float <-> double conversion).
// For x in (0, 1], x = m * 2^(e - 150) with m the 24-bit significand and e the biased exponent,
// so x * 255 = p / 2^s with p = m * 255 < 2^32 and s = 150 - e, exactly. Halves up:
// code = floor((p + 2^(s-1)) / 2^s) = floor((floor(p / 2) + 2^(s-2)) / 2^(s-1)): halving p first
// keeps every sum below 2^32, and drops only p's low bit, which cannot change the quotient (a
// sum on the boundary has p = 2^(s-1) mod 2^s, even for s >= 2). Where e < 118, x < 2^-9 and
// x * 255 < 0.5: code 0, as for 0, NaN and denormals (their e is 0).
void BlockEncodeRgba8(const float* HWY_RESTRICT rgba, bool fast, std::uint32_t* HWY_RESTRICT codes) {
    const hn::CappedTag<float, 2 * kSide> df;
    const hn::RebindToSigned<decltype(df)> di;
    const hn::RebindToUnsigned<decltype(df)> du;
    const std::size_t n = hn::Lanes(df);
    const auto zero = hn::Zero(df), one = hn::Set(df, 1.0f);
    for (std::size_t p = 0; p < std::size_t(QuadBlock::kPixels); p += n) {
        auto packed = hn::Zero(du);
        for (int c = 0; c < 4; ++c) {
            const auto src = hn::LoadU(df, rgba + c * QuadBlock::kPixels + p);
            // x > 0 ? (x < 1 ? x : 1) : 0, so NaN -> 0 as in the scalar clamp.
            const auto x = hn::IfThenElse(hn::Gt(src, zero), hn::IfThenElse(hn::Lt(src, one), src, one), zero);
            hn::Vec<decltype(du)> code;
            if (fast) {
                code = hn::BitCast(du, hn::ConvertTo(di, hn::Add(hn::Mul(x, hn::Set(df, 255.0f)), hn::Set(df, 0.5f))));
            } else {
                const auto bits = hn::BitCast(du, x);
                const auto exponent = hn::BitCast(di, hn::ShiftRight<23>(bits));  // 0..127: x is in [0, 1]
                const auto significand = hn::Or(hn::And(bits, hn::Set(du, 0x7FFFFFu)), hn::Set(du, 0x800000u));
                const auto product = hn::Mul(significand, hn::Set(du, 255u));  // p < 2^32
                const auto inRange = hn::RebindMask(du, hn::Gt(exponent, hn::Set(di, 117)));
                // s - 1 = 149 - e: 22..31 in range; capped at 31 elsewhere (those lanes are zeroed).
                const auto shift = hn::BitCast(du, hn::Min(hn::Sub(hn::Set(di, 149), exponent), hn::Set(di, 31)));
                const auto half = hn::Shl(hn::Set(du, 1u), hn::Sub(shift, hn::Set(du, 1u)));  // 2^(s-2)
                code = hn::IfThenElseZero(inRange, hn::Shr(hn::Add(hn::ShiftRight<1>(product), half), shift));
            }
            packed = hn::Or(packed, hn::ShiftLeftSame(code, 8 * c));
        }
        hn::StoreU(packed, du, codes + p);
    }
}

// One blend factor (output_merger.cpp's factor()) for channel c (0..2 colour, 3 alpha) of a
// vector of pixels: s, d, k are the clamped source, decoded destination and clamped constant.
template <class D, class V>
V BlendFactorOf(D df, Blend b, int c, const V* s, const V* dst, const V* k) {
    const auto one = hn::Set(df, 1.0f);
    switch (b) {
    case Blend::Zero: return hn::Zero(df);
    case Blend::One: return one;
    case Blend::SrcColor: return s[c];
    case Blend::InvSrcColor: return hn::Sub(one, s[c]);
    case Blend::SrcAlpha: return s[3];
    case Blend::InvSrcAlpha: return hn::Sub(one, s[3]);
    case Blend::DestAlpha: return dst[3];
    case Blend::InvDestAlpha: return hn::Sub(one, dst[3]);
    case Blend::DestColor: return dst[c];
    case Blend::InvDestColor: return hn::Sub(one, dst[c]);
    case Blend::SrcAlphaSat: {  // std::min(As, 1 - Ad): the second operand where it is smaller
        if (c == 3) return one;
        const auto invDstAlpha = hn::Sub(one, dst[3]);
        return hn::IfThenElse(hn::Lt(invDstAlpha, s[3]), invDstAlpha, s[3]);
    }
    case Blend::BlendFactor: return k[c];
    case Blend::InvBlendFactor: return hn::Sub(one, k[c]);
    default: return hn::Zero(df);  // dual-source: rejected by validation before drawing
    }
}

// output_merger.cpp's combine(): products and sums rounded one at a time (never fused); MIN and
// MAX as std::min / std::max, the first operand unless the second is strictly smaller / larger.
template <class V>
V BlendCombine(BlendOp op, V s, V fs, V d, V fd) {
    switch (op) {
    case BlendOp::Add: return hn::Add(hn::Mul(s, fs), hn::Mul(d, fd));
    case BlendOp::Subtract: return hn::Sub(hn::Mul(s, fs), hn::Mul(d, fd));
    case BlendOp::RevSubtract: return hn::Sub(hn::Mul(d, fd), hn::Mul(s, fs));
    case BlendOp::Min: return hn::IfThenElse(hn::Lt(d, s), d, s);
    case BlendOp::Max: return hn::IfThenElse(hn::Lt(s, d), d, s);
    }
    return s;
}

void BlockBlendRgba8(float* HWY_RESTRICT rgba, const std::uint32_t* HWY_RESTRICT dstCodes,
                     const RenderTargetBlendDesc& blend, const float* blendFactor) {
    const hn::CappedTag<float, kSide> df;
    const hn::RebindToUnsigned<decltype(df)> du;
    const hn::RebindToSigned<decltype(df)> di;
    const std::size_t n = hn::Lanes(df);
    using V = hn::Vec<decltype(df)>;
    const auto zero = hn::Zero(df), one = hn::Set(df, 1.0f), max8 = hn::Set(df, 255.0f);
    // clampTo(v, 0, 1): NaN -> 0, then std::min(std::max(v, 0), 1) (max keeps v unless 0 is larger).
    const auto clampUnorm = [&](V v) {
        const auto lo = hn::IfThenElse(hn::Lt(v, zero), zero, v);
        const auto clamped = hn::IfThenElse(hn::Lt(one, lo), one, lo);
        return hn::IfThenElse(hn::Eq(v, v), clamped, zero);
    };
    V k[4];
    for (int c = 0; c < 4; ++c) k[c] = clampUnorm(hn::Set(df, blendFactor[c]));
    const std::uint8_t mask = blend.renderTargetWriteMask & WriteAll;
    for (std::size_t p = 0; p < std::size_t(QuadBlock::kPixels); p += n) {
        const auto codes = hn::LoadU(du, dstCodes + p);
        V s[4], dst[4], result[4];
        for (int c = 0; c < 4; ++c) {
            s[c] = clampUnorm(hn::LoadU(df, rgba + c * QuadBlock::kPixels + p));
            // unormToFloat(code, 8): float(code) / 255, correctly rounded in every lane.
            const auto code = hn::BitCast(di, hn::And(hn::ShiftRightSame(codes, 8 * c), hn::Set(du, 0xFFu)));
            dst[c] = hn::Div(hn::ConvertTo(df, code), max8);
            result[c] = s[c];
        }
        if (blend.blendEnable) {
            for (int c = 0; c < 3; ++c)
                result[c] = BlendCombine(blend.blendOp, s[c], BlendFactorOf(df, blend.srcBlend, c, s, dst, k), dst[c],
                                         BlendFactorOf(df, blend.destBlend, c, s, dst, k));
            result[3] = BlendCombine(blend.blendOpAlpha, s[3], BlendFactorOf(df, blend.srcBlendAlpha, 3, s, dst, k), dst[3],
                                     BlendFactorOf(df, blend.destBlendAlpha, 3, s, dst, k));
        }
        for (int c = 0; c < 4; ++c)
            hn::StoreU((mask >> c) & 1u ? result[c] : dst[c], df, rgba + c * QuadBlock::kPixels + p);
    }
}

std::uint64_t BlockDepthTest(const float* HWY_RESTRICT z, const std::uint32_t* HWY_RESTRICT stored, std::uint64_t lanes,
                             bool d24, ComparisonFunc func, float minDepth, float maxDepth, float* HWY_RESTRICT zClamped,
                             std::uint32_t* HWY_RESTRICT incoming) {
    const hn::CappedTag<double, kSide> dd;
    const hn::Rebind<float, decltype(dd)> df;
    const hn::Rebind<std::int32_t, decltype(dd)> di;
    const hn::Rebind<std::uint32_t, decltype(dd)> du;
    const std::size_t n = hn::Lanes(dd);
    const auto lo = hn::Set(df, minDepth), hi = hn::Set(df, maxDepth);
    std::uint64_t pass = 0;
    for (std::size_t p = 0; p < std::size_t(QuadBlock::kPixels); p += n) {
        const auto raw = hn::LoadU(df, z + p);
        // clampDepth: !(z >= min) -> min, else z > max -> max.
        const auto zc = hn::IfThenElse(hn::Ge(raw, lo), hn::IfThenElse(hn::Gt(raw, hi), hi, raw), lo);
        hn::StoreU(zc, df, zClamped + p);
        hn::Mask<decltype(di)> ok;
        if (d24) {
            // depthToD24: z <= 0 -> 0, z >= 1 -> 2^24 - 1, else p = z * (2^24 - 1) in double,
            // truncated, plus 1 where the fraction is >= 0.5. z is clamped, so never NaN.
            const auto scaled = hn::Mul(hn::PromoteTo(dd, zc), hn::Set(dd, 16777215.0));
            const auto truncated = hn::DemoteTo(di, scaled);
            const auto whole = hn::PromoteTo(dd, truncated);
            const auto roundUp = hn::Ge(hn::Sub(scaled, whole), hn::Set(dd, 0.5));
            auto code = hn::DemoteTo(di, hn::Add(whole, hn::IfThenElseZero(roundUp, hn::Set(dd, 1.0))));
            code = hn::IfThenElse(hn::RebindMask(di, hn::Gt(zc, hn::Zero(df))), code, hn::Zero(di));
            code = hn::IfThenElse(hn::RebindMask(di, hn::Ge(zc, hn::Set(df, 1.0f))), hn::Set(di, 0xFFFFFF), code);
            hn::StoreU(hn::BitCast(du, code), du, incoming + p);
            // Codes are below 2^24, so signed compares order them as unsigned ones.
            const auto dst = hn::BitCast(di, hn::And(hn::LoadU(du, stored + p), hn::Set(du, 0xFFFFFFu)));
            switch (func) {
            case ComparisonFunc::Never: ok = hn::FirstN(di, 0); break;
            case ComparisonFunc::Less: ok = hn::Lt(code, dst); break;
            case ComparisonFunc::Equal: ok = hn::Eq(code, dst); break;
            case ComparisonFunc::LessEqual: ok = hn::Not(hn::Gt(code, dst)); break;
            case ComparisonFunc::Greater: ok = hn::Gt(code, dst); break;
            case ComparisonFunc::NotEqual: ok = hn::Not(hn::Eq(code, dst)); break;
            case ComparisonFunc::GreaterEqual: ok = hn::Not(hn::Lt(code, dst)); break;
            default: ok = hn::FirstN(di, n); break;  // Always
            }
        } else {
            hn::StoreU(hn::BitCast(du, zc), du, incoming + p);
            const auto dst = hn::BitCast(df, hn::LoadU(du, stored + p));
            hn::Mask<decltype(df)> okf;
            // IEEE: NaN compares false except under NotEqual (spelled Not(Eq): Highway's != is
            // ordered on some targets) and Always, as compare() in state/comparison.h.
            switch (func) {
            case ComparisonFunc::Never: okf = hn::FirstN(df, 0); break;
            case ComparisonFunc::Less: okf = hn::Lt(zc, dst); break;
            case ComparisonFunc::Equal: okf = hn::Eq(zc, dst); break;
            case ComparisonFunc::LessEqual: okf = hn::Le(zc, dst); break;
            case ComparisonFunc::Greater: okf = hn::Gt(zc, dst); break;
            case ComparisonFunc::NotEqual: okf = hn::Not(hn::Eq(zc, dst)); break;
            case ComparisonFunc::GreaterEqual: okf = hn::Ge(zc, dst); break;
            default: okf = hn::FirstN(df, n); break;  // Always
            }
            ok = hn::RebindMask(di, okf);
        }
        std::uint8_t bits[8] = {};
        hn::StoreMaskBits(di, ok, bits);
        pass |= std::uint64_t(bits[0] & ((1u << n) - 1u)) << p;
    }
    return pass & lanes;
}

const char* BlockTarget() { return hwy::TargetName(HWY_TARGET); }

} // namespace tessera::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace tessera {

static_assert(std::endian::native == std::endian::little, "quadBlockEncodeRgba8 packs R into the low byte");
HWY_EXPORT(BlockCoverage);
HWY_EXPORT(BlockCentres);
HWY_EXPORT(BlockTarget);
HWY_EXPORT(BlockEncodeRgba8);
HWY_EXPORT(BlockDepthTest);
HWY_EXPORT(BlockBlendRgba8);

std::uint64_t quadBlockCoverage(const SetupTriangle& t, const QuadBlock::Edges& e, std::uint8_t columns,
                                std::uint8_t rows) {
    return HWY_DYNAMIC_DISPATCH(BlockCoverage)(t, e, columns, rows);
}

void quadBlockCentres(const SetupTriangle& t, const QuadBlock::Edges& e, const float* vertexVaryings,
                      std::uint32_t varyingCount, bool wantPosW, bool fastBarycentrics, QuadBlock& out) {
    HWY_DYNAMIC_DISPATCH(BlockCentres)(t, e, vertexVaryings, varyingCount, wantPosW, fastBarycentrics, out);
}

void quadBlockEncodeRgba8(const float* rgba, bool fast, std::uint32_t* codes) {
    HWY_DYNAMIC_DISPATCH(BlockEncodeRgba8)(rgba, fast, codes);
}

void quadBlockBlendRgba8(float* rgba, const std::uint32_t* dstCodes, const RenderTargetBlendDesc& blend,
                         const glm::vec4& blendFactor) {
    const float factor[4] = {blendFactor.x, blendFactor.y, blendFactor.z, blendFactor.w};
    HWY_DYNAMIC_DISPATCH(BlockBlendRgba8)(rgba, dstCodes, blend, factor);
}

std::uint64_t quadBlockDepthTest(const float* z, const std::uint32_t* stored, std::uint64_t lanes, bool d24,
                                 ComparisonFunc func, float minDepth, float maxDepth, float* zClamped,
                                 std::uint32_t* incoming) {
    return HWY_DYNAMIC_DISPATCH(BlockDepthTest)(z, stored, lanes, d24, func, minDepth, maxDepth, zClamped, incoming);
}

const char* quadBlockTarget() { return HWY_DYNAMIC_DISPATCH(BlockTarget)(); }

} // namespace tessera
#endif  // HWY_ONCE
