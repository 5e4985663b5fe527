// glTF accessor data (glTF 2.0 §3.6.2, "§" below cites that specification): the layout of an
// accessor in its bufferView, the per-file limits on decoded data, and the decoding of one
// component or one index. The checks against the file's buffers live in the reader
// (reader_accessors.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

namespace tessera::gltf_detail {

inline constexpr std::uint64_t MAX_ACCESSOR_ELEMENTS = std::uint64_t(1) << 28;
// The accessor data one file may decode, in bytes of 32-bit values: 256 MiB plus 256 bytes per
// byte of its buffers. Data decoded from a buffer is at most 4 bytes per byte, but an accessor
// without a bufferView (zeros plus sparse values) is as large as its count says, and every
// primitive that uses an accessor decodes it again: without a budget, a 400-byte file asked for
// 3 GiB. Real files stay far below (256x covers one vertex buffer shared by 64 primitives).
inline constexpr std::uint64_t DECODE_BUDGET_BASE = std::uint64_t(256) << 20;
inline constexpr std::uint64_t DECODE_BUDGET_PER_BUFFER_BYTE = 256;

struct AccessorLayout {
    const unsigned char* first = nullptr;  // element 0; null: no bufferView (all zeros, §3.6.2.3)
    std::size_t stride = 0, count = 0, components = 0, componentBytes = 0;
    int componentType = 0;
    bool normalized = false;
};

// Names of a componentType / an accessor type, for messages ("UNSIGNED_SHORT", "VEC3").
const char* componentTypeName(int componentType);
const char* accessorTypeName(int type);
// Bytes per component (0 for types glTF does not allow) and components per element (0: unknown).
std::size_t componentSize(int componentType);
std::size_t componentCount(int type);
// One component as float (normalized integers decoded as §3.11 says; accessors.cpp).
float decodeComponent(const unsigned char* p, int componentType, bool normalized);
// One index of UNSIGNED_BYTE, UNSIGNED_SHORT or (any other type) UNSIGNED_INT.
std::uint32_t decodeIndex(const unsigned char* p, int componentType);

} // namespace tessera::gltf_detail
