// maskedFill (buffers/fill.h): texel patterns of 1, 2, 4, 8 or 16 bytes are widened to a
// 16-byte period and applied as (old & keep) | set on 32-bit lanes, compiled once per SIMD
// target by Highway's foreach_target and chosen at run time; other texel sizes run the scalar
// loop. Blocks of 64 KiB (a multiple of 16 bytes, so every block starts on a period) run in parallel.
#include <tessera/buffers/fill.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "buffers/fill.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace tessera::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// words: 32-bit words to fill at `bytes` (a multiple of 4, 4-byte aligned: a Surface's
// storage); keep4/set4: one 16-byte period. Loads and stores go through Highway's unaligned
// intrinsics and memcpy, never a plain uint32_t access, so the byte buffer is not aliased.
void MaskedFillWords(std::byte* HWY_RESTRICT bytes, std::size_t words, const std::uint32_t* keep4,
                     const std::uint32_t* set4) {
    auto* data = reinterpret_cast<std::uint32_t*>(bytes);
    const hn::ScalableTag<std::uint32_t> d;
    const std::size_t lanes = hn::Lanes(d);
    std::size_t i = 0;
    if (lanes % 4 == 0) {
        HWY_ALIGN std::uint32_t keepLanes[hn::MaxLanes(d)];
        HWY_ALIGN std::uint32_t setLanes[hn::MaxLanes(d)];
        for (std::size_t k = 0; k < lanes; ++k) {
            keepLanes[k] = keep4[k % 4];
            setLanes[k] = set4[k % 4];
        }
        const auto keep = hn::Load(d, keepLanes);
        const auto set = hn::Load(d, setLanes);
        const bool overwrite = std::all_of(keep4, keep4 + 4, [](std::uint32_t w) { return w == 0; });
        if (overwrite) {
            for (; i + lanes <= words; i += lanes) hn::StoreU(set, d, data + i);
        } else {
            for (; i + lanes <= words; i += lanes) hn::StoreU(hn::Or(hn::And(hn::LoadU(d, data + i), keep), set), d, data + i);
        }
    }
    for (; i < words; ++i) {
        std::uint32_t w;
        std::memcpy(&w, bytes + 4 * i, 4);
        w = (w & keep4[i % 4]) | set4[i % 4];
        std::memcpy(bytes + 4 * i, &w, 4);
    }
}

} // namespace tessera::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace tessera {

HWY_EXPORT(MaskedFillWords);

namespace {
constexpr std::size_t kPeriodBytes = 16;
constexpr std::size_t kBlockBytes = 64 * 1024;  // per parallel task; a multiple of kPeriodBytes

void checkSize(std::span<std::byte> bytes, std::uint32_t texelBytes) {
    if (texelBytes == 0 || texelBytes > 16 || bytes.size() % texelBytes != 0)
        throw std::invalid_argument("maskedFill: " + std::to_string(bytes.size()) + " bytes are not whole texels of " +
                                    std::to_string(texelBytes) + " bytes");
}
} // namespace

void maskedFillScalar(std::span<std::byte> bytes, const std::byte* keep, const std::byte* set, std::uint32_t texelBytes) {
    checkSize(bytes, texelBytes);
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        const std::size_t k = i % texelBytes;
        bytes[i] = (bytes[i] & keep[k]) | set[k];
    }
}

void maskedFill(std::span<std::byte> bytes, const std::byte* keep, const std::byte* set, std::uint32_t texelBytes) {
    checkSize(bytes, texelBytes);
    if (kPeriodBytes % texelBytes != 0) {
        maskedFillScalar(bytes, keep, set, texelBytes);
        return;
    }
    std::uint32_t keep4[4], set4[4];
    std::byte keepPeriod[kPeriodBytes], setPeriod[kPeriodBytes];
    for (std::size_t k = 0; k < kPeriodBytes; ++k) {
        keepPeriod[k] = keep[k % texelBytes];
        setPeriod[k] = set[k % texelBytes];
    }
    std::memcpy(keep4, keepPeriod, sizeof(keep4));
    std::memcpy(set4, setPeriod, sizeof(set4));
    const std::size_t whole = bytes.size() / kPeriodBytes * kPeriodBytes;
    if (whole <= kBlockBytes) {  // one block (a row of a rectangle clear): no task to spawn
        HWY_DYNAMIC_DISPATCH(MaskedFillWords)(bytes.data(), whole / 4, keep4, set4);
    } else {
        const std::size_t blocks = (whole + kBlockBytes - 1) / kBlockBytes;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t b = r.begin(); b != r.end(); ++b) {
                const std::size_t begin = b * kBlockBytes, end = std::min(whole, begin + kBlockBytes);
                HWY_DYNAMIC_DISPATCH(MaskedFillWords)(bytes.data() + begin, (end - begin) / 4, keep4, set4);
            }
        });
    }
    if (whole < bytes.size()) maskedFillScalar(bytes.subspan(whole), keepPeriod, setPeriod, texelBytes);
}

} // namespace tessera
#endif  // HWY_ONCE
