// OrderedCounter: a global append counter whose reservations come out in row-major group order
// even when groups run in parallel (order rule 5 in dispatch.h). It replaces the light-list
// pattern's `if (groupIndex == 0) InterlockedAdd(gCounter[0], count, startOffset)` so that a
// GroupOrder::Parallel dispatch lays the global list out exactly as GroupOrder::Serial does.

// How: group g's reserve() waits until every group before it (row-major rank) has reserved or
// finished, then adds. A group that finishes without reserving passes its turn on (it counts as
// reserving 0). The dispatcher hands groups to workers in ascending rank and a worker runs a
// group to its end before taking another, so the lowest unfinished group never waits: no
// deadlock at any thread count. The wait costs little when, as in light culling, the
// reservation comes after the expensive part of the kernel.
#pragma once

#include <tessera/compute/dispatch.h>

#include <atomic>
#include <cstdint>

namespace tessera::compute {

class OrderedCounter {
public:
    explicit OrderedCounter(std::uint32_t initialValue = 0) noexcept : mValue(initialValue) {}
    OrderedCounter(const OrderedCounter&) = delete;
    OrderedCounter& operator=(const OrderedCounter&) = delete;

    // The counter value: the initial value plus every count reserved so far (wraps at 2^32
    // like InterlockedAdd). Read it between dispatches.
    std::uint32_t value() const noexcept { return mValue; }
    void reset(std::uint32_t value) noexcept { mValue = value; }

    // InterlockedAdd(counter, count, original) in row-major group order: returns the value
    // before adding. At most once per group per dispatch, and only from a dispatch that lists
    // this counter in DispatchDesc::orderedCounters; otherwise throws std::logic_error.
    template<class Shared>
    std::uint32_t reserve(const GroupContext<Shared>& group, std::uint32_t count) {
        return reserveForGroup(group.groupFlatIndex(), count);
    }

private:
    friend void detail::runGroups(std::uint64_t, const DispatchDesc&, detail::GroupRangeFn, void*);
    friend void detail::finishGroup(std::span<OrderedCounter* const>, std::uint64_t);
    friend void detail::abandonCounters(std::span<OrderedCounter* const>) noexcept;

    static constexpr std::uint64_t kAbandoned = ~std::uint64_t{0}; // ticket after a failed group

    std::uint32_t reserveForGroup(std::uint64_t group, std::uint32_t count);
    void waitForTurn(std::uint64_t group); // returns when mTicket == group; throws if abandoned
    void passTurn(std::uint64_t group) noexcept;

    std::uint32_t mValue;                     // touched only by the group holding the turn
    std::atomic<std::uint64_t> mTicket{0};    // rank of the group whose turn it is
    std::atomic<bool> mArmed{false};          // inside a dispatch that lists this counter
    std::atomic<std::uint32_t> mSleepers{0};  // threads blocked in mTicket.wait()
};

} // namespace tessera::compute
