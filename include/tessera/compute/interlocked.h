// HLSL Interlocked* operations on 32-bit integers, in two flavours: plain sequential ops for
// group-shared memory (threads of a group run one after another, so no atomics are needed) and
// std::atomic_ref ops for global resources (groups may run on several CPU threads at once).
// Both return the value in memory before the operation (HLSL's `original_value` out-parameter).
#pragma once

#include <atomic>
#include <concepts>
#include <cstdint>
#include <type_traits>

namespace tessera::compute {

// The element types SM5 atomics accept: R32_UINT / R32_SINT (imm_atomic_* on u# and g#).
template<class T>
concept InterlockedScalar = std::same_as<T, std::uint32_t> || std::same_as<T, std::int32_t>;

namespace detail {

// Two's-complement wrap for both signednesses: arithmetic is done in uint32 (no signed overflow UB).
template<InterlockedScalar T>
constexpr T wrappingAdd(T a, T b) noexcept {
    return static_cast<T>(static_cast<std::uint32_t>(a) + static_cast<std::uint32_t>(b));
}

template<class T>
constexpr void storeOriginal(T* original, T value) noexcept {
    if (original != nullptr) *original = value;
}

} // namespace detail

// ---------------------------------------------------------------------------------------------
// Group-shared memory (HLSL `groupshared`). The emulator runs the threads of one group one at a
// time in ascending SV_GroupIndex order inside each phase, so these are ordinary read-modify-
// writes; their order is the thread order and therefore fully deterministic. Each returns the
// original value and also stores it to *original when given (HLSL's optional out-parameter).
// Do not use them on global (cross-group) memory: that is what the resource members are for.
// ---------------------------------------------------------------------------------------------

template<InterlockedScalar T>
constexpr T interlockedAdd(T& dest, std::type_identity_t<T> value, T* original = nullptr) noexcept {
    const T old = dest;
    dest = detail::wrappingAdd(old, value);
    detail::storeOriginal(original, old);
    return old;
}

// Signed compare for int32 (imm_atomic_imin), unsigned for uint32 (imm_atomic_umin).
template<InterlockedScalar T>
constexpr T interlockedMin(T& dest, std::type_identity_t<T> value, T* original = nullptr) noexcept {
    const T old = dest;
    if (value < old) dest = value;
    detail::storeOriginal(original, old);
    return old;
}

template<InterlockedScalar T>
constexpr T interlockedMax(T& dest, std::type_identity_t<T> value, T* original = nullptr) noexcept {
    const T old = dest;
    if (value > old) dest = value;
    detail::storeOriginal(original, old);
    return old;
}

template<InterlockedScalar T>
constexpr T interlockedAnd(T& dest, std::type_identity_t<T> value, T* original = nullptr) noexcept {
    const T old = dest;
    dest = static_cast<T>(old & value);
    detail::storeOriginal(original, old);
    return old;
}

template<InterlockedScalar T>
constexpr T interlockedOr(T& dest, std::type_identity_t<T> value, T* original = nullptr) noexcept {
    const T old = dest;
    dest = static_cast<T>(old | value);
    detail::storeOriginal(original, old);
    return old;
}

template<InterlockedScalar T>
constexpr T interlockedXor(T& dest, std::type_identity_t<T> value, T* original = nullptr) noexcept {
    const T old = dest;
    dest = static_cast<T>(old ^ value);
    detail::storeOriginal(original, old);
    return old;
}

template<InterlockedScalar T>
constexpr T interlockedExchange(T& dest, std::type_identity_t<T> value, T* original = nullptr) noexcept {
    const T old = dest;
    dest = value;
    detail::storeOriginal(original, old);
    return old;
}

// InterlockedCompareExchange: dest = (dest == compare) ? value : dest; the original is always
// returned (imm_atomic_cmp_exch), whether or not the store happened.
template<InterlockedScalar T>
constexpr T interlockedCompareExchange(T& dest, std::type_identity_t<T> compare,
                                       std::type_identity_t<T> value, T* original = nullptr) noexcept {
    const T old = dest;
    if (old == compare) dest = value;
    detail::storeOriginal(original, old);
    return old;
}

// InterlockedCompareStore (atomic_cmp_store): as CompareExchange, but returns nothing.
template<InterlockedScalar T>
constexpr void interlockedCompareStore(T& dest, std::type_identity_t<T> compare,
                                       std::type_identity_t<T> value) noexcept {
    if (dest == compare) dest = value;
}

// ---------------------------------------------------------------------------------------------
// Global memory (UAV elements): true atomics through std::atomic_ref, relaxed ordering. Relaxed
// is enough: within a dispatch only the atomic values themselves are shared between groups that
// may run concurrently, and the end of a dispatch (TBB join) orders everything before what
// follows. The resource classes (resources.h) wrap these with D3D11 bounds checks.
// ---------------------------------------------------------------------------------------------
namespace detail {

enum class AtomicOp : std::uint8_t { Add, Min, Max, And, Or, Xor, Exchange };

template<InterlockedScalar T>
T atomicRmw(T& dest, AtomicOp op, T value) noexcept {
    std::atomic_ref<T> ref(dest);
    constexpr auto order = std::memory_order_relaxed;
    switch (op) {
    case AtomicOp::Add: return ref.fetch_add(value, order); // atomic signed add wraps (no UB)
    case AtomicOp::And: return ref.fetch_and(value, order);
    case AtomicOp::Or: return ref.fetch_or(value, order);
    case AtomicOp::Xor: return ref.fetch_xor(value, order);
    case AtomicOp::Exchange: return ref.exchange(value, order);
    case AtomicOp::Min: {
        T old = ref.load(order);
        while (value < old && !ref.compare_exchange_weak(old, value, order)) {
        }
        return old;
    }
    case AtomicOp::Max: {
        T old = ref.load(order);
        while (value > old && !ref.compare_exchange_weak(old, value, order)) {
        }
        return old;
    }
    }
    return T{};
}

template<InterlockedScalar T>
T atomicCompareExchange(T& dest, T compare, T value) noexcept {
    std::atomic_ref<T> ref(dest);
    T expected = compare;
    ref.compare_exchange_strong(expected, value, std::memory_order_relaxed);
    return expected; // the original value, whether or not the exchange happened
}

} // namespace detail

} // namespace tessera::compute
