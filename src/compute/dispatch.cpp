// The non-template half of compute dispatch: D3D11 limit validation, the group schedulers
// (serial row-major, tbb::parallel_for, ascending-grab for ordered counters) and the
// OrderedCounter turn-passing. The per-thread loops live in the header (dispatch.h).
#include <tessera/compute/dispatch.h>
#include <tessera/compute/ordered_counter.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <stdexcept>
#include <string>
#include <thread>

namespace tessera::compute {

namespace {

[[noreturn]] void throwRange(const char* what, char axis, std::uint32_t value, std::uint32_t lo,
                             std::uint32_t hi, const char* limitName) {
    throw std::invalid_argument(std::string("tessera::compute::dispatch: ") + what + " " + axis +
                                " = " + std::to_string(value) + " is out of range [" +
                                std::to_string(lo) + ", " + std::to_string(hi) + "] (" +
                                limitName + ")");
}

} // namespace

void validateGroupSize(glm::uvec3 groupSize) {
    if (groupSize.x < 1 || groupSize.x > kMaxGroupSizeX)
        throwRange("group size", 'x', groupSize.x, 1, kMaxGroupSizeX, "D3D11_CS_THREAD_GROUP_MAX_X");
    if (groupSize.y < 1 || groupSize.y > kMaxGroupSizeY)
        throwRange("group size", 'y', groupSize.y, 1, kMaxGroupSizeY, "D3D11_CS_THREAD_GROUP_MAX_Y");
    if (groupSize.z < 1 || groupSize.z > kMaxGroupSizeZ)
        throwRange("group size", 'z', groupSize.z, 1, kMaxGroupSizeZ, "D3D11_CS_THREAD_GROUP_MAX_Z");
    const std::uint64_t threads = std::uint64_t{groupSize.x} * groupSize.y * groupSize.z;
    if (threads > kMaxThreadsPerGroup) {
        throw std::invalid_argument(
            "tessera::compute::dispatch: group size " + std::to_string(groupSize.x) + "x" +
            std::to_string(groupSize.y) + "x" + std::to_string(groupSize.z) + " = " +
            std::to_string(threads) + " threads exceeds " + std::to_string(kMaxThreadsPerGroup) +
            " (D3D11_CS_THREAD_GROUP_MAX_THREADS_PER_GROUP)");
    }
}

void validateGroupCount(glm::uvec3 groupCount) {
    const char* limit = "D3D11_CS_DISPATCH_MAX_THREAD_GROUPS_PER_DIMENSION";
    if (groupCount.x > kMaxGroupsPerDimension)
        throwRange("group count", 'x', groupCount.x, 0, kMaxGroupsPerDimension, limit);
    if (groupCount.y > kMaxGroupsPerDimension)
        throwRange("group count", 'y', groupCount.y, 0, kMaxGroupsPerDimension, limit);
    if (groupCount.z > kMaxGroupsPerDimension)
        throwRange("group count", 'z', groupCount.z, 0, kMaxGroupsPerDimension, limit);
}

namespace detail {

void runGroups(std::uint64_t groupTotal, const DispatchDesc& desc, GroupRangeFn fn, void* context) {
    const std::span<OrderedCounter* const> counters = desc.orderedCounters;
    for (OrderedCounter* counter : counters) {
        if (counter == nullptr)
            throw std::invalid_argument("tessera::compute::dispatch: null OrderedCounter");
        if (counter->mArmed.exchange(true))
            throw std::logic_error("tessera::compute::dispatch: an OrderedCounter is listed twice "
                                   "or used by two dispatches at once");
        counter->mTicket.store(0, std::memory_order_relaxed);
    }
    struct Disarm {
        std::span<OrderedCounter* const> list;
        ~Disarm() {
            for (OrderedCounter* counter : list) counter->mArmed.store(false);
        }
    } disarm{counters};

    if (desc.order == GroupOrder::Serial) {
        fn(context, 0, groupTotal); // row-major: rank 0, 1, 2, ...
        return;
    }
    if (counters.empty()) {
        tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, groupTotal),
                          [&](const tbb::blocked_range<std::uint64_t>& range) {
                              fn(context, range.begin(), range.end());
                          });
        return;
    }
    // Ascending-grab scheduling: every worker takes the lowest group not yet taken and runs it
    // to its end before taking another (the no-deadlock argument in ordered_counter.h).
    std::atomic<std::uint64_t> next{0};
    const int workers = tbb::this_task_arena::max_concurrency();
    tbb::parallel_for(
        0, workers,
        [&](int) {
            for (;;) {
                const std::uint64_t group = next.fetch_add(1, std::memory_order_relaxed);
                if (group >= groupTotal) return;
                fn(context, group, group + 1);
            }
        },
        tbb::simple_partitioner());
}

void finishGroup(std::span<OrderedCounter* const> counters, std::uint64_t group) {
    for (OrderedCounter* counter : counters) {
        if (counter->mTicket.load(std::memory_order_acquire) > group) continue; // reserved already
        counter->waitForTurn(group);
        counter->passTurn(group); // reserves 0
    }
}

void abandonCounters(std::span<OrderedCounter* const> counters) noexcept {
    for (OrderedCounter* counter : counters) {
        counter->mTicket.store(OrderedCounter::kAbandoned, std::memory_order_release);
        counter->mTicket.notify_all();
    }
}

} // namespace detail

void OrderedCounter::waitForTurn(std::uint64_t group) {
    // Spin first: the group before us is usually about to pass the turn, and a futex sleep and
    // wake costs more than the wait. Then yield, then sleep on the ticket.
    constexpr int kSpins = 4096;  // busy polls (~a few microseconds)
    constexpr int kYields = 64;   // sched_yield()s before sleeping
    for (int attempt = 0;; ++attempt) {
        const std::uint64_t ticket = mTicket.load(std::memory_order_acquire);
        if (ticket == group) return;
        if (ticket == kAbandoned)
            throw DispatchAbandoned("tessera::compute::OrderedCounter: dispatch abandoned after "
                                    "an exception in another group");
        if (attempt < kSpins) continue;
        if (attempt < kSpins + kYields) {
            std::this_thread::yield();
            continue;
        }
        // seq_cst pairs with passTurn: either it sees mSleepers > 0 and notifies, or this
        // thread's wait() sees the new ticket and returns at once.
        mSleepers.fetch_add(1, std::memory_order_seq_cst);
        mTicket.wait(ticket, std::memory_order_seq_cst);
        mSleepers.fetch_sub(1, std::memory_order_relaxed);
    }
}

void OrderedCounter::passTurn(std::uint64_t group) noexcept {
    mTicket.store(group + 1, std::memory_order_seq_cst);
    if (mSleepers.load(std::memory_order_seq_cst) != 0) mTicket.notify_all();
}

std::uint32_t OrderedCounter::reserveForGroup(std::uint64_t group, std::uint32_t count) {
    if (!mArmed.load(std::memory_order_relaxed))
        throw std::logic_error("tessera::compute::OrderedCounter::reserve: the counter is not "
                               "listed in this dispatch's DispatchDesc::orderedCounters");
    const std::uint64_t ticket = mTicket.load(std::memory_order_acquire);
    if (ticket != kAbandoned && ticket > group)
        throw std::logic_error("tessera::compute::OrderedCounter::reserve: group " +
                               std::to_string(group) + " reserved twice in one dispatch");
    waitForTurn(group);
    const std::uint32_t original = mValue;
    mValue = original + count; // uint32 wrap, as InterlockedAdd
    passTurn(group);
    return original;
}

} // namespace tessera::compute
