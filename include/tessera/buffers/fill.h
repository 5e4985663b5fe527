// Clears as one masked fill: every texel of a buffer becomes (old & keep) | set, with keep and
// set one texel's bytes. SIMD through Highway (runtime dispatch: SSE4, AVX2, AVX-512 from one
// source) and parallel over 64 KiB blocks with TBB; the bytes do not depend on either.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace tessera {

// texelBytes 1..16; keep and set hold texelBytes bytes each. Throws std::invalid_argument when
// bytes.size() is not a multiple of texelBytes.
void maskedFill(std::span<std::byte> bytes, const std::byte* keep, const std::byte* set, std::uint32_t texelBytes);

// The same result one texel at a time: the oracle of tests/buffers/fill_test.cpp.
void maskedFillScalar(std::span<std::byte> bytes, const std::byte* keep, const std::byte* set, std::uint32_t texelBytes);

} // namespace tessera
