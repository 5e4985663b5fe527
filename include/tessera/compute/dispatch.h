// Compute-shader emulation: dispatch(kernel, groupCount) runs a kernel functor over a grid of
// thread groups, with group-shared memory, barriers (phases) and a documented, deterministic
// order for everything whose result could depend on thread scheduling. Callers: the tiled
// light-culling passes (Forward+, AMD Forward+, Intel tiled deferred) and their tests.
//
// ===== Execution model =======================================================================
// A kernel is a functor with
//     static constexpr glm::uvec3 groupSize;      // [numthreads(x, y, z)]
//     using Shared = ...;                          // groupshared variables, one struct
//     void operator()(GroupContext<Shared>& g) const;
// operator() runs once per thread group. It describes the group's HLSL program as a sequence of
// *phases*: each g.forEachThread(f) call runs f once for every thread of the group, and the end
// of the call is a GroupMemoryBarrierWithGroupSync(). So
//     HLSL: A; GroupMemoryBarrierWithGroupSync(); B;
//     here: g.forEachThread([&](const ThreadIds& t) { A }); g.forEachThread([&](...) { B });
// Values a thread keeps across a barrier (its registers) live in PerThread<T, N> arrays indexed
// by the thread, declared in operator(). Code in operator() outside a phase is group-uniform
// (e.g. reading g.groupId()); it must not stand in for per-thread work.
//
// ===== Order rules (what makes results independent of the host's threads) ====================
// 1. Threads of a phase run one after another in ascending SV_GroupIndex
//    (groupIndex = x + y*sx + z*sx*sy), each to the end of the phase. This is one legal GPU
//    interleaving, so race-free HLSL gives the GPU's answer, and the racy parts get a fixed
//    one: group-shared InterlockedAdd hands out slots in thread order; a plain group-shared
//    store to one address by several threads of a phase leaves the highest groupIndex's value.
// 2. g.forEachStrided(n, f) runs the HLSL loop `for (i = groupIndex; i < n; i += threads)` in
//    lockstep, i.e. f(thread i % threads, i) for i = 0, 1, ..., n-1 in ascending i. Appending
//    inside it gives "ascending light index inside a tile", tessera's fixed order for GPU atomics.
// 3. GroupOrder::Serial (the default): groups run one at a time in row-major order of SV_GroupID
//    (x fastest, then y, then z) on the calling thread. Global atomics, and the originals they
//    return, happen in that order: an append to a global list lays tiles out in row-major order.
// 4. GroupOrder::Parallel: groups run concurrently on oneTBB workers, in no fixed order. The
//    kernel author promises the result does not depend on group order: groups never write the
//    same non-atomic global element, never read what another group writes, and use global
//    atomics only as commutative updates (Add/Min/Max/And/Or/Xor) whose returned originals are
//    ignored. Such a kernel gives the same bytes as Serial at any thread count.
// 5. Ordered appends in parallel: an OrderedCounter (ordered_counter.h) registered in
//    DispatchDesc::orderedCounters gives each group the offset it would get under rule 3
//    (row-major prefix sum of the groups' reservations) even with GroupOrder::Parallel.
#pragma once

#include <tessera/compute/interlocked.h>

#include <glm/glm.hpp>

#include <array>
#include <atomic>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace tessera::compute {

// ----- Direct3D 11 compute limits -----------------------------------------------------------
inline constexpr std::uint32_t kMaxGroupSizeX = 1024;         // D3D11_CS_THREAD_GROUP_MAX_X
inline constexpr std::uint32_t kMaxGroupSizeY = 1024;         // D3D11_CS_THREAD_GROUP_MAX_Y
inline constexpr std::uint32_t kMaxGroupSizeZ = 64;           // D3D11_CS_THREAD_GROUP_MAX_Z
inline constexpr std::uint32_t kMaxThreadsPerGroup = 1024;    // D3D11_CS_THREAD_GROUP_MAX_THREADS_PER_GROUP
inline constexpr std::uint32_t kMaxGroupsPerDimension = 65535; // D3D11_CS_DISPATCH_MAX_THREAD_GROUPS_PER_DIMENSION
inline constexpr std::size_t kMaxGroupSharedBytes = 32768;    // D3D11_CS_TGSM_REGISTER_COUNT (8192) x 4 bytes

// System values of one thread, named after their HLSL semantics.
struct ThreadIds {
    glm::uvec3 groupId;          // SV_GroupID
    glm::uvec3 groupThreadId;    // SV_GroupThreadID
    glm::uvec3 dispatchThreadId; // SV_DispatchThreadID = groupId * groupSize + groupThreadId
    std::uint32_t groupIndex;    // SV_GroupIndex = x + y*sx + z*sx*sy of groupThreadId
};

// Threads in a group of the given size (no validation; see validateGroupSize).
constexpr std::uint32_t threadsPerGroup(glm::uvec3 groupSize) noexcept {
    return groupSize.x * groupSize.y * groupSize.z;
}

// Throw std::invalid_argument, naming the offending value and the D3D11 limit, unless
// 1 <= x <= 1024, 1 <= y <= 1024, 1 <= z <= 64 and x*y*z <= 1024.
void validateGroupSize(glm::uvec3 groupSize);
// Throw std::invalid_argument unless every component is <= 65535 (0 is valid: a no-op dispatch).
void validateGroupCount(glm::uvec3 groupCount);

enum class GroupOrder : std::uint8_t {
    Serial,   // row-major, one group at a time, on the calling thread (order rule 3)
    Parallel, // concurrent, the kernel promises order independence (order rule 4)
};

class OrderedCounter;

// Thrown by OrderedCounter in groups that were waiting for their turn when another group of the
// same dispatch threw; dispatch() rethrows the other group's exception, not this one.
class DispatchAbandoned : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct DispatchDesc {
    GroupOrder order = GroupOrder::Serial;
    // Counters whose reserve() the kernel calls (order rule 5). Each is reset to "no group has
    // reserved yet" (its value is kept) at the start of the dispatch.
    std::span<OrderedCounter* const> orderedCounters{};
};

// What a dispatch ran; deterministic (independent of the order and the thread count).
struct DispatchStats {
    std::uint64_t groups = 0;  // thread groups run
    std::uint64_t threads = 0; // thread invocations: groups * threads per group
    std::uint64_t phases = 0;  // phases (barrier-separated steps) summed over groups
};

// An empty group-shared block, for kernels that use no groupshared memory.
struct NoShared {};

// Per-thread values that live across barriers (a thread's registers): one T per thread of a
// group of `Threads` threads, value-initialised, indexed by the thread's SV_GroupIndex.
template<class T, std::uint32_t Threads>
class PerThread {
    static_assert(Threads >= 1 && Threads <= kMaxThreadsPerGroup,
                  "PerThread: thread count must be in [1, D3D11_CS_THREAD_GROUP_MAX_THREADS_PER_GROUP]");

public:
    T& operator[](const ThreadIds& t) noexcept { return mValues[t.groupIndex]; }
    const T& operator[](const ThreadIds& t) const noexcept { return mValues[t.groupIndex]; }
    T& operator[](std::uint32_t groupIndex) noexcept { return mValues[groupIndex]; }
    const T& operator[](std::uint32_t groupIndex) const noexcept { return mValues[groupIndex]; }
    static constexpr std::uint32_t size() noexcept { return Threads; }

private:
    std::array<T, Threads> mValues{};
};

// One thread group's view of the dispatch: its ids, its group-shared memory, and the phase
// runners. Created by dispatch() for each group; kernels only receive it.
template<class Shared>
class GroupContext {
public:
    GroupContext(Shared& shared, glm::uvec3 groupId, glm::uvec3 groupSize, glm::uvec3 groupCount,
                 std::uint64_t groupFlatIndex) noexcept
        : mShared(shared), mGroupId(groupId), mGroupSize(groupSize), mGroupCount(groupCount),
          mGroupBase(groupId * groupSize), mGroupFlatIndex(groupFlatIndex),
          mThreadCount(threadsPerGroup(groupSize)) {}

    Shared& shared() noexcept { return mShared; } // groupshared memory, value-initialised
    glm::uvec3 groupId() const noexcept { return mGroupId; }       // SV_GroupID
    glm::uvec3 groupSize() const noexcept { return mGroupSize; }   // numthreads
    glm::uvec3 groupCount() const noexcept { return mGroupCount; } // Dispatch(x, y, z)
    std::uint32_t threadCount() const noexcept { return mThreadCount; }
    // Row-major rank of this group: x + y*cx + z*cx*cy (its place in GroupOrder::Serial).
    std::uint64_t groupFlatIndex() const noexcept { return mGroupFlatIndex; }
    std::uint64_t phaseCount() const noexcept { return mPhases; }

    // The ids of the thread with the given SV_GroupIndex (< threadCount()).
    ThreadIds threadIds(std::uint32_t groupIndex) const noexcept {
        const std::uint32_t sx = mGroupSize.x;
        const std::uint32_t sxy = mGroupSize.x * mGroupSize.y;
        const glm::uvec3 local(groupIndex % sx, (groupIndex % sxy) / sx, groupIndex / sxy);
        return ThreadIds{mGroupId, local, mGroupBase + local, groupIndex};
    }

    // One phase: f(ids) for every thread in ascending SV_GroupIndex, then a barrier.
    template<std::invocable<const ThreadIds&> F>
    void forEachThread(F&& f) {
        ThreadIds t{mGroupId, glm::uvec3(0), mGroupBase, 0};
        for (std::uint32_t z = 0; z < mGroupSize.z; ++z) {
            for (std::uint32_t y = 0; y < mGroupSize.y; ++y) {
                for (std::uint32_t x = 0; x < mGroupSize.x; ++x) {
                    t.groupThreadId = glm::uvec3(x, y, z);
                    t.dispatchThreadId = mGroupBase + t.groupThreadId;
                    f(std::as_const(t));
                    ++t.groupIndex;
                }
            }
        }
        ++mPhases;
    }

    // One phase in which only the thread with SV_GroupIndex `groupIndex` does work (the HLSL
    // `if (groupIndex == 0) { ... }` block), then a barrier.
    template<std::invocable<const ThreadIds&> F>
    void forOneThread(std::uint32_t groupIndex, F&& f) {
        if (groupIndex < mThreadCount) {
            const ThreadIds t = threadIds(groupIndex);
            f(t);
        }
        ++mPhases;
    }

    // One phase running `for (i = groupIndex; i < count; i += threadCount) f(ids, i)` for every
    // thread, in lockstep: ascending i (order rule 2). Then a barrier.
    template<std::invocable<const ThreadIds&, std::uint32_t> F>
    void forEachStrided(std::uint32_t count, F&& f) {
        std::uint32_t thread = 0;
        for (std::uint32_t i = 0; i < count; ++i) {
            const ThreadIds t = threadIds(thread);
            f(t, i);
            thread = thread + 1 == mThreadCount ? 0 : thread + 1;
        }
        ++mPhases;
    }

private:
    Shared& mShared;
    glm::uvec3 mGroupId;
    glm::uvec3 mGroupSize;
    glm::uvec3 mGroupCount;
    glm::uvec3 mGroupBase; // groupId * groupSize: SV_DispatchThreadID of thread 0
    std::uint64_t mGroupFlatIndex;
    std::uint32_t mThreadCount;
    std::uint64_t mPhases = 0;
};

// A kernel: group size, group-shared type (trivially destructible and default-constructible,
// like HLSL groupshared data) and a const call operator taking the group context.
template<class K>
concept ComputeKernel = requires {
    typename K::Shared;
    { K::groupSize } -> std::convertible_to<glm::uvec3>;
} && std::default_initializable<typename K::Shared> &&
    std::is_trivially_destructible_v<typename K::Shared> &&
    std::invocable<const K&, GroupContext<typename K::Shared>&>;

namespace detail {

// Runs fn(context, first, last) over group ranges [first, last) covering [0, groupTotal):
// Serial: one call on this thread; Parallel: tbb::parallel_for (ascending-grab scheduling when
// ordered counters are registered). Also resets/arms/disarms the ordered counters.
using GroupRangeFn = void (*)(void* context, std::uint64_t first, std::uint64_t last);
void runGroups(std::uint64_t groupTotal, const DispatchDesc& desc, GroupRangeFn fn, void* context);
// After each group: groups that did not reserve on a counter reserve 0 (keeps the row-major chain).
void finishGroup(std::span<OrderedCounter* const> counters, std::uint64_t group);
// On an exception in a group: wake every group waiting on these counters so they fail too.
void abandonCounters(std::span<OrderedCounter* const> counters) noexcept;

} // namespace detail

// Run `kernel` over groupCount.x * .y * .z thread groups (Direct3D 11 Dispatch). Throws
// std::invalid_argument for an invalid group size or count; a zero group count runs nothing.
// Exceptions thrown by the kernel propagate to the caller (remaining groups may not run).
template<ComputeKernel K>
DispatchStats dispatch(const K& kernel, glm::uvec3 groupCount, const DispatchDesc& desc = {}) {
    using Shared = typename K::Shared;
    static_assert(sizeof(Shared) <= kMaxGroupSharedBytes,
                  "group-shared memory exceeds D3D11's 32 KiB (D3D11_CS_TGSM_REGISTER_COUNT * 4)");
    const glm::uvec3 groupSize = K::groupSize;
    validateGroupSize(groupSize);
    validateGroupCount(groupCount);
    const std::uint64_t groupTotal =
        std::uint64_t{groupCount.x} * groupCount.y * std::uint64_t{groupCount.z};
    if (groupTotal == 0) return {};

    struct Run {
        const K* kernel;
        glm::uvec3 groupSize;
        glm::uvec3 groupCount;
        std::span<OrderedCounter* const> counters;
        std::atomic<std::uint64_t> phases{0};
        std::atomic<bool> failed{false};
        std::exception_ptr firstError{}; // written once, by the group that set `failed`
    } run{&kernel, groupSize, groupCount, desc.orderedCounters};

    const detail::GroupRangeFn runRange = [](void* runPtr, std::uint64_t first, std::uint64_t last) {
        Run& r = *static_cast<Run*>(runPtr);
        const std::uint64_t cx = r.groupCount.x;
        const std::uint64_t cxy = cx * r.groupCount.y;
        const auto shared = std::make_unique<Shared>(); // value-initialised; reused per group
        std::uint64_t phases = 0;
        for (std::uint64_t g = first; g < last; ++g) {
            if (g != first) std::construct_at(shared.get()); // fresh value-initialised block
            const glm::uvec3 groupId(static_cast<std::uint32_t>(g % cx),
                                     static_cast<std::uint32_t>((g % cxy) / cx),
                                     static_cast<std::uint32_t>(g / cxy));
            GroupContext<Shared> group(*shared, groupId, r.groupSize, r.groupCount, g);
            if (r.counters.empty()) {
                (*r.kernel)(group);
            } else {
                try {
                    (*r.kernel)(group);
                    detail::finishGroup(r.counters, g);
                } catch (const DispatchAbandoned&) {
                    throw; // a consequence of another group's exception
                } catch (...) {
                    if (!r.failed.exchange(true)) r.firstError = std::current_exception();
                    detail::abandonCounters(r.counters);
                    throw;
                }
            }
            phases += group.phaseCount();
        }
        r.phases.fetch_add(phases, std::memory_order_relaxed);
    };
    try {
        detail::runGroups(groupTotal, desc, runRange, &run);
    } catch (...) {
        if (run.failed.load()) std::rethrow_exception(run.firstError); // the root cause
        throw;
    }

    return DispatchStats{groupTotal, groupTotal * threadsPerGroup(groupSize),
                         run.phases.load(std::memory_order_relaxed)};
}

} // namespace tessera::compute
