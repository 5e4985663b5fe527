// Shader-visible resources for compute kernels: (RW)StructuredBuffer and (RW)Texture2D views
// over caller-owned memory, with Direct3D 11 out-of-bounds rules and global Interlocked* ops.
// Views are shallow (like D3D views): copying one aliases the same memory, and the const member
// functions of an RW view may write, so a const kernel functor can hold them by value.
//
// Out-of-bounds rules (D3D11.3 functional spec, §22 "Shader Instruction Reference"; the same
// text is in the SM5 assembly reference pages for ld, ld_structured, store_structured,
// store_uav_typed and imm_atomic_*):
//  - reads (ld / ld_structured / ld_uav_typed) out of bounds return 0 in every component:
//    here a value-initialised T;
//  - writes (store_structured / store_uav_typed) out of bounds write nothing;
//  - atomics out of bounds on a u# write nothing; the value returned to the shader is
//    *undefined* in D3D11 (imm_atomic_*: "Out of bounds addressing on u# or g# causes an
//    undefined result to be returned"). tessera fixes that undefined value to 0.
// The D3D11 case "structured byte offset past the stride makes the whole UAV undefined" cannot
// arise: a view is indexed by whole elements of T.
#pragma once

#include <tessera/compute/interlocked.h>

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>

namespace tessera::compute {

// D3D11_REQ_TEXTURE2D_U_OR_V_DIMENSION: largest width or height of a Texture2D, in texels.
inline constexpr std::uint32_t kMaxTexture2DDimension = 16384;

namespace detail {

// An out-of-bounds atomic does nothing and returns 0 (tessera's choice for D3D11's undefined).
template<InterlockedScalar T>
T uavRmw(T* element, AtomicOp op, T value, T* original) noexcept {
    const T old = element != nullptr ? atomicRmw(*element, op, value) : T{};
    storeOriginal(original, old);
    return old;
}

template<InterlockedScalar T>
T uavCompareExchange(T* element, T compare, T value, T* original) noexcept {
    const T old = element != nullptr ? atomicCompareExchange(*element, compare, value) : T{};
    storeOriginal(original, old);
    return old;
}

inline std::uint32_t checkedElementCount(std::size_t size, const char* what) {
    if (size > std::numeric_limits<std::uint32_t>::max()) {
        throw std::invalid_argument(std::string(what) + ": " + std::to_string(size) +
                                    " elements exceed the 32-bit element address range");
    }
    return static_cast<std::uint32_t>(size);
}

inline void checkTexture2D(std::size_t dataSize, std::uint32_t width, std::uint32_t height,
                           const char* what) {
    if (width > kMaxTexture2DDimension || height > kMaxTexture2DDimension) {
        throw std::invalid_argument(std::string(what) + ": size " + std::to_string(width) + "x" +
                                    std::to_string(height) +
                                    " exceeds D3D11_REQ_TEXTURE2D_U_OR_V_DIMENSION (16384)");
    }
    const std::size_t needed = std::size_t{width} * height;
    if (dataSize < needed) {
        throw std::invalid_argument(std::string(what) + ": " + std::to_string(dataSize) +
                                    " texels given, " + std::to_string(needed) + " needed for " +
                                    std::to_string(width) + "x" + std::to_string(height));
    }
}

// The global Interlocked* members of an RW view, written once for both views. Derived
// provides `T* elementAt(Address) const noexcept` (nullptr out of bounds); each op returns the
// original value (0 out of bounds). The requires-clauses keep them off non-atomic T.
template<class Derived, class T, class Address>
class UavAtomics {
public:
    T interlockedAdd(Address at, T value, T* original = nullptr) const noexcept
        requires InterlockedScalar<T> { return rmw(at, AtomicOp::Add, value, original); }
    T interlockedMin(Address at, T value, T* original = nullptr) const noexcept
        requires InterlockedScalar<T> { return rmw(at, AtomicOp::Min, value, original); }
    T interlockedMax(Address at, T value, T* original = nullptr) const noexcept
        requires InterlockedScalar<T> { return rmw(at, AtomicOp::Max, value, original); }
    T interlockedAnd(Address at, T value, T* original = nullptr) const noexcept
        requires InterlockedScalar<T> { return rmw(at, AtomicOp::And, value, original); }
    T interlockedOr(Address at, T value, T* original = nullptr) const noexcept
        requires InterlockedScalar<T> { return rmw(at, AtomicOp::Or, value, original); }
    T interlockedXor(Address at, T value, T* original = nullptr) const noexcept
        requires InterlockedScalar<T> { return rmw(at, AtomicOp::Xor, value, original); }
    T interlockedExchange(Address at, T value, T* original = nullptr) const noexcept
        requires InterlockedScalar<T> { return rmw(at, AtomicOp::Exchange, value, original); }
    T interlockedCompareExchange(Address at, T compare, T value, T* original = nullptr) const noexcept
        requires InterlockedScalar<T> { return uavCompareExchange(element(at), compare, value, original); }
    void interlockedCompareStore(Address at, T compare, T value) const noexcept
        requires InterlockedScalar<T> { uavCompareExchange(element(at), compare, value, static_cast<T*>(nullptr)); }

private:
    T* element(Address at) const noexcept { return static_cast<const Derived&>(*this).elementAt(at); }
    T rmw(Address at, AtomicOp op, T value, T* original) const noexcept {
        return uavRmw(element(at), op, value, original);
    }
};

} // namespace detail

// StructuredBuffer<T> (SRV t#): read-only array of T.
template<class T>
class StructuredBuffer {
public:
    StructuredBuffer() = default;
    explicit StructuredBuffer(std::span<const T> data)
        : mData(data.data()), mSize(detail::checkedElementCount(data.size(), "StructuredBuffer")) {}

    std::uint32_t size() const noexcept { return mSize; } // elements
    std::span<const T> data() const noexcept { return {mData, mSize}; }

    // Out of bounds: T{} (all zero for the plain structs shaders use).
    T load(std::uint32_t index) const noexcept { return index < mSize ? mData[index] : T{}; }
    T operator[](std::uint32_t index) const noexcept { return load(index); }

private:
    const T* mData = nullptr;
    std::uint32_t mSize = 0;
};

// RWStructuredBuffer<T> (UAV u#): read/write array of T; atomics when T is int32/uint32.
// Non-atomic writes to one element from two groups that may run concurrently are a data race,
// exactly as on a GPU: a kernel run with GroupOrder::Parallel must not do that.
template<class T>
class RWStructuredBuffer : public detail::UavAtomics<RWStructuredBuffer<T>, T, std::uint32_t> {
public:
    RWStructuredBuffer() = default;
    explicit RWStructuredBuffer(std::span<T> data)
        : mData(data.data()), mSize(detail::checkedElementCount(data.size(), "RWStructuredBuffer")) {}

    std::uint32_t size() const noexcept { return mSize; } // elements
    std::span<T> data() const noexcept { return {mData, mSize}; }

    T load(std::uint32_t index) const noexcept { return index < mSize ? mData[index] : T{}; }
    T operator[](std::uint32_t index) const noexcept { return load(index); }
    // Out of bounds: discarded.
    void store(std::uint32_t index, const T& value) const noexcept {
        if (index < mSize) mData[index] = value;
    }

    // Global Interlocked*: interlockedAdd(index, value) etc., from detail::UavAtomics.

private:
    friend class detail::UavAtomics<RWStructuredBuffer<T>, T, std::uint32_t>;
    T* elementAt(std::uint32_t index) const noexcept { return index < mSize ? mData + index : nullptr; }

    T* mData = nullptr;
    std::uint32_t mSize = 0;
};

// Texture2D<T> (SRV t#, mip 0 only): row-major, row 0 at the top, `Load` semantics (no sampler).
// Coordinates are unsigned as in ld; a negative int converts to a huge value and so reads 0.
template<class T>
class Texture2D {
public:
    Texture2D() = default;
    Texture2D(std::span<const T> data, std::uint32_t width, std::uint32_t height)
        : mData(data.data()), mWidth(width), mHeight(height) {
        detail::checkTexture2D(data.size(), width, height, "Texture2D");
    }

    std::uint32_t width() const noexcept { return mWidth; }
    std::uint32_t height() const noexcept { return mHeight; }

    T load(std::uint32_t x, std::uint32_t y) const noexcept {
        return x < mWidth && y < mHeight ? mData[std::size_t{y} * mWidth + x] : T{};
    }
    T load(glm::uvec2 xy) const noexcept { return load(xy.x, xy.y); }
    T load(glm::ivec2 xy) const noexcept {
        return load(static_cast<std::uint32_t>(xy.x), static_cast<std::uint32_t>(xy.y));
    }

private:
    const T* mData = nullptr;
    std::uint32_t mWidth = 0;
    std::uint32_t mHeight = 0;
};

// RWTexture2D<T> (UAV u#): row-major, row 0 at the top; atomics when T is int32/uint32
// (typed UAV with R32_UINT / R32_SINT).
template<class T>
class RWTexture2D : public detail::UavAtomics<RWTexture2D<T>, T, glm::uvec2> {
public:
    RWTexture2D() = default;
    RWTexture2D(std::span<T> data, std::uint32_t width, std::uint32_t height)
        : mData(data.data()), mWidth(width), mHeight(height) {
        detail::checkTexture2D(data.size(), width, height, "RWTexture2D");
    }

    std::uint32_t width() const noexcept { return mWidth; }
    std::uint32_t height() const noexcept { return mHeight; }

    T load(std::uint32_t x, std::uint32_t y) const noexcept {
        const T* p = elementAt({x, y});
        return p != nullptr ? *p : T{};
    }
    T load(glm::uvec2 xy) const noexcept { return load(xy.x, xy.y); }
    void store(std::uint32_t x, std::uint32_t y, const T& value) const noexcept {
        if (T* p = elementAt({x, y})) *p = value;
    }
    void store(glm::uvec2 xy, const T& value) const noexcept { store(xy.x, xy.y, value); }

    // Global Interlocked*: interlockedAdd(xy, value) etc., from detail::UavAtomics.

private:
    friend class detail::UavAtomics<RWTexture2D<T>, T, glm::uvec2>;
    T* elementAt(glm::uvec2 xy) const noexcept {
        return xy.x < mWidth && xy.y < mHeight ? mData + (std::size_t{xy.y} * mWidth + xy.x) : nullptr;
    }

    T* mData = nullptr;
    std::uint32_t mWidth = 0;
    std::uint32_t mHeight = 0;
};

} // namespace tessera::compute
