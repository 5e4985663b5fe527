// Determinism of the compute-shader emulation: GroupOrder::Parallel kernels (order-independent
// by contract) and ordered appends give byte-identical outputs under 1, 2, 7 and 16 oneTBB threads
// and equal the GroupOrder::Serial result. Each count runs in a task_arena of that many slots with
// the process-wide worker limit raised to match (global_control alone only lowers the limit, so on
// a 2-core machine 7 and 16 would silently mean 2); the test asserts the concurrency dispatch sees.
#include <tessera/compute/dispatch.h>
#include <tessera/compute/interlocked.h>
#include <tessera/compute/ordered_counter.h>
#include <tessera/compute/resources.h>

#include <doctest/doctest.h>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cstdint>
#include <cstring>
#include <vector>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::determinism_compute_determinism_test {

namespace tc = tessera::compute;
using tc::ThreadIds;

namespace {

constexpr std::uint32_t kWidth = 301;  // not a multiple of the group size: partial groups
constexpr std::uint32_t kHeight = 187;
constexpr std::uint32_t kBins = 64;

std::uint32_t valueAt(std::uint32_t x, std::uint32_t y) {
    std::uint32_t h = (x + 1) * 0x9E3779B1u ^ (y + 7) * 0x85EBCA77u;
    h ^= h >> 15;
    h *= 0x2C1B3C6Du;
    h ^= h >> 12;
    return h;
}

// Every kind of commutative global atomic, results used only as final memory values, plus a
// group-local reduction through shared memory: a Parallel-mode kernel by contract.
struct HistogramKernel {
    static constexpr glm::uvec3 groupSize{8, 8, 1};
    struct Shared {
        std::uint32_t localBins[kBins];
        std::int32_t localMin;
    };
    tc::Texture2D<std::uint32_t> input;
    tc::RWStructuredBuffer<std::uint32_t> bins;      // kBins: global InterlockedAdd
    tc::RWStructuredBuffer<std::int32_t> extremes;   // [0] min, [1] max (signed)
    tc::RWTexture2D<std::uint32_t> bitsPerColumn;    // kBins x 3: Or, And, Xor per bin
    tc::RWStructuredBuffer<float> groupMeans;        // per group, non-atomic, own element

    void operator()(tc::GroupContext<Shared>& g) const {
        Shared& s = g.shared();
        g.forOneThread(0, [&](const ThreadIds&) { s.localMin = 0x7FFFFFFF; });
        g.forEachThread([&](const ThreadIds& t) {
            const glm::uvec3 p = t.dispatchThreadId;
            if (p.x >= kWidth || p.y >= kHeight) return;
            const std::uint32_t v = input.load(p.x, p.y);
            tc::interlockedAdd(s.localBins[v % kBins], 1u);
            tc::interlockedMin(s.localMin, static_cast<std::int32_t>(v));
            extremes.interlockedMax(1, static_cast<std::int32_t>(v));
            bitsPerColumn.interlockedOr(glm::uvec2(v % kBins, 0), v);
            bitsPerColumn.interlockedAnd(glm::uvec2(v % kBins, 1), v);
            bitsPerColumn.interlockedXor(glm::uvec2(v % kBins, 2), v);
        });
        g.forEachStrided(kBins, [&](const ThreadIds&, std::uint32_t bin) {
            if (s.localBins[bin] != 0) bins.interlockedAdd(bin, s.localBins[bin]);
        });
        g.forOneThread(0, [&](const ThreadIds&) {
            extremes.interlockedMin(0, s.localMin);
            std::uint32_t total = 0;
            for (std::uint32_t c : s.localBins) total += c;
            // Float math on group-private data: deterministic, since the order is fixed in-group.
            float mean = 0.0f;
            for (std::uint32_t bin = 0; bin < kBins; ++bin)
                mean += static_cast<float>(bin) * static_cast<float>(s.localBins[bin]);
            groupMeans.store(static_cast<std::uint32_t>(g.groupFlatIndex()),
                             total != 0 ? mean / static_cast<float>(total) : -1.0f);
        });
    }
};

// Variable-length per-group append through an OrderedCounter (order rule 5).
struct AppendKernel {
    static constexpr glm::uvec3 groupSize{16, 16, 1};
    struct Shared {
        std::uint32_t count;
        std::uint32_t start;
        std::uint32_t items[256];
    };
    tc::Texture2D<std::uint32_t> input;
    tc::OrderedCounter* counter;
    tc::RWStructuredBuffer<std::uint32_t> list;
    tc::RWStructuredBuffer<glm::uvec2> ranges; // per group: (start, count)

    void operator()(tc::GroupContext<Shared>& g) const {
        Shared& s = g.shared();
        g.forEachThread([&](const ThreadIds& t) {
            const std::uint32_t v = input.load(t.dispatchThreadId.x, t.dispatchThreadId.y);
            if (v % 5 == 0) { // OOB threads load 0, which also passes: they append too
                std::uint32_t slot = 0;
                tc::interlockedAdd(s.count, 1u, &slot);
                s.items[slot] = v ^ t.groupIndex;
            }
        });
        g.forOneThread(0, [&](const ThreadIds&) {
            s.start = counter->reserve(g, s.count);
            ranges.store(static_cast<std::uint32_t>(g.groupFlatIndex()), glm::uvec2(s.start, s.count));
        });
        g.forEachStrided(s.count, [&](const ThreadIds&, std::uint32_t i) { list.store(s.start + i, s.items[i]); });
    }
};

struct Outputs {
    std::vector<std::uint32_t> bins = std::vector<std::uint32_t>(kBins, 0);
    std::vector<std::int32_t> extremes = std::vector<std::int32_t>{0x7FFFFFFF, -0x7FFFFFFF - 1};
    std::vector<std::uint32_t> bits = std::vector<std::uint32_t>(kBins * 3, 0);
    std::vector<float> means;
    std::vector<std::uint32_t> list;
    std::vector<glm::uvec2> ranges;
    std::uint32_t counterValue = 0;
};

template<class T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

Outputs runAll(tc::GroupOrder order) {
    std::vector<std::uint32_t> image(kWidth * kHeight);
    for (std::uint32_t y = 0; y < kHeight; ++y)
        for (std::uint32_t x = 0; x < kWidth; ++x) image[y * kWidth + x] = valueAt(x, y);
    const tc::Texture2D<std::uint32_t> input(image, kWidth, kHeight);

    Outputs o;
    for (std::uint32_t bin = 0; bin < kBins; ++bin) o.bits[kBins + bin] = 0xFFFFFFFFu; // And row
    const glm::uvec3 histGroups((kWidth + 7) / 8, (kHeight + 7) / 8, 1);
    o.means.assign(histGroups.x * histGroups.y, 0.0f);
    tc::dispatch(HistogramKernel{input, tc::RWStructuredBuffer<std::uint32_t>(o.bins),
                                 tc::RWStructuredBuffer<std::int32_t>(o.extremes),
                                 tc::RWTexture2D<std::uint32_t>(o.bits, kBins, 3),
                                 tc::RWStructuredBuffer<float>(o.means)},
                 histGroups, tc::DispatchDesc{order, {}});

    const glm::uvec3 appendGroups((kWidth + 15) / 16, (kHeight + 15) / 16, 1);
    o.list.assign(appendGroups.x * appendGroups.y * 256, 0xFFFFFFFFu);
    o.ranges.assign(appendGroups.x * appendGroups.y, glm::uvec2(0));
    tc::OrderedCounter counter(3); // a non-zero start, like a list shared by several passes
    tc::OrderedCounter* const counters[] = {&counter};
    tc::dispatch(AppendKernel{input, &counter, tc::RWStructuredBuffer<std::uint32_t>(o.list),
                              tc::RWStructuredBuffer<glm::uvec2>(o.ranges)},
                 appendGroups, tc::DispatchDesc{order, counters});
    o.counterValue = counter.value();
    return o;
}

} // namespace

TEST_CASE("compute determinism: Parallel dispatches are identical at 1, 2, 7 and 16 threads") {
    const Outputs serial = runAll(tc::GroupOrder::Serial);
    // The serial reference is itself right: the histogram counts every pixel once, and the
    // appended ranges are contiguous from the counter's start.
    std::uint64_t pixels = 0;
    for (std::uint32_t c : serial.bins) pixels += c;
    CHECK(pixels == std::uint64_t{kWidth} * kHeight);
    std::uint32_t next = 3;
    for (const glm::uvec2 r : serial.ranges) {
        CHECK(r.x == next);
        next += r.y;
    }
    CHECK(serial.counterValue == next);
    CHECK(next > 3 + 1000); // about a fifth of 56k pixels appended

    for (const int threads : {1, 2, 7, 16}) {
        CAPTURE(threads);
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(threads));
        tbb::task_arena arena(threads);
        arena.execute([&] {
            // dispatch partitions its groups over this many workers (compute/dispatch.cpp).
            REQUIRE(tbb::this_task_arena::max_concurrency() == threads);
            for (int repeat = 0; repeat < 3; ++repeat) {
                const Outputs parallel = runAll(tc::GroupOrder::Parallel);
                CHECK(sameBytes(parallel.bins, serial.bins));
                CHECK(sameBytes(parallel.extremes, serial.extremes));
                CHECK(sameBytes(parallel.bits, serial.bits));
                CHECK(sameBytes(parallel.means, serial.means));
                CHECK(sameBytes(parallel.list, serial.list));
                CHECK(sameBytes(parallel.ranges, serial.ranges));
                CHECK(parallel.counterValue == serial.counterValue);
            }
        });
    }
}

} // namespace tessera_test::determinism_compute_determinism_test
