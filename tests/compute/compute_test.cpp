// Unit tests of the compute-shader emulation (tessera/compute): barriers as phases, tree
// reduction, the tiled light-list append pattern with its exact row-major layout, tile depth
// min/max through asuint atomics, Interlocked* semantics tables, D3D11 out-of-bounds rules,
// ordered counters and D3D11 limit validation. Thread-count determinism: tests/determinism.
#include <tessera/compute/dispatch.h>
#include <tessera/compute/interlocked.h>
#include <tessera/compute/ordered_counter.h>
#include <tessera/compute/resources.h>

#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::compute_compute_test {

namespace tc = tessera::compute;
using tc::ThreadIds;

namespace {

// ----- barriers: a phase sees every write of the phase before it --------------------------------
struct RotateKernel {
    static constexpr glm::uvec3 groupSize{8, 4, 2};
    static constexpr std::uint32_t kThreads = tc::threadsPerGroup(groupSize);
    struct Shared {
        std::uint32_t values[kThreads];
    };
    tc::RWStructuredBuffer<std::uint32_t> out;
    tc::RWStructuredBuffer<std::uint32_t> idsOut; // 4 words per thread: gid.x, gtid packed, dtid packed, index

    void operator()(tc::GroupContext<Shared>& g) const {
        g.forEachThread([&](const ThreadIds& t) { g.shared().values[t.groupIndex] = t.groupIndex * 10 + 1; });
        g.forEachThread([&](const ThreadIds& t) {
            const std::uint32_t flat = static_cast<std::uint32_t>(g.groupFlatIndex()) * kThreads + t.groupIndex;
            // Reads the *next* thread's value: only correct if the previous phase completed for all.
            out.store(flat, g.shared().values[(t.groupIndex + 1) % kThreads]);
            idsOut.store(flat * 4 + 0, t.groupId.x + 100 * t.groupId.y + 10000 * t.groupId.z);
            idsOut.store(flat * 4 + 1, t.groupThreadId.x + 100 * t.groupThreadId.y + 10000 * t.groupThreadId.z);
            idsOut.store(flat * 4 + 2,
                         t.dispatchThreadId.x + 100 * t.dispatchThreadId.y + 10000 * t.dispatchThreadId.z);
            idsOut.store(flat * 4 + 3, t.groupIndex);
        });
    }
};

// ----- tree reduction over a 16x16 group ---------------------------------------------------------
struct ReduceKernel {
    static constexpr glm::uvec3 groupSize{16, 16, 1};
    static constexpr std::uint32_t kThreads = tc::threadsPerGroup(groupSize);
    struct Shared {
        std::uint32_t partial[kThreads];
    };
    tc::Texture2D<std::uint32_t> input;
    tc::RWStructuredBuffer<std::uint32_t> groupSums; // one per group, row-major
    tc::RWStructuredBuffer<std::uint32_t> total;     // [0]: global InterlockedAdd of group sums

    void operator()(tc::GroupContext<Shared>& g) const {
        Shared& s = g.shared();
        g.forEachThread([&](const ThreadIds& t) {
            s.partial[t.groupIndex] = input.load(t.dispatchThreadId.x, t.dispatchThreadId.y);
        });
        for (std::uint32_t stride = kThreads / 2; stride > 0; stride /= 2) { // log2(256) = 8 phases
            g.forEachThread([&](const ThreadIds& t) {
                if (t.groupIndex < stride) s.partial[t.groupIndex] += s.partial[t.groupIndex + stride];
            });
        }
        g.forOneThread(0, [&](const ThreadIds&) {
            groupSums.store(static_cast<std::uint32_t>(g.groupFlatIndex()), s.partial[0]);
            total.interlockedAdd(0, s.partial[0]); // commutative, original ignored: Parallel-safe
        });
    }
};

std::uint32_t hashValue(std::uint32_t x, std::uint32_t y) {
    std::uint32_t h = x * 0x9E3779B1u ^ (y + 0x7F4A7C15u) * 0x85EBCA77u;
    h ^= h >> 13;
    return h % 1000u;
}

// ----- tiled light list (3dgep / AMD Forward+ pattern) ----------------------------------------
constexpr std::uint32_t kLightCount = 700;
constexpr std::uint32_t kLocalCapacity = 256; // like AMD's LIGHT_CAPACITY
constexpr std::uint32_t kTilesX = 5;
constexpr std::uint32_t kTilesY = 3;

// "Light l overlaps tile (x, y)": a deterministic predicate; tile (1, 1) takes every light to
// overflow the local list (700 > 256).
bool lightHitsTile(std::uint32_t light, std::uint32_t tileX, std::uint32_t tileY) {
    if (tileX == 1 && tileY == 1) return true;
    if (tileX == 3 && tileY == 2) return false; // an empty tile
    return (light * 7u + tileX * 3u + tileY * 5u) % 11u < 3u;
}

struct LightListKernel {
    static constexpr glm::uvec3 groupSize{16, 16, 1};
    struct Shared {
        std::uint32_t count;      // unclamped, as the sources do
        std::uint32_t startOffset;
        std::uint32_t list[kLocalCapacity];
    };
    tc::RWStructuredBuffer<std::uint32_t> globalCounter; // [0]
    tc::RWStructuredBuffer<std::uint32_t> globalList;
    tc::RWTexture2D<glm::uvec2> grid;                  // (offset, stored count) per tile
    tc::RWTexture2D<std::uint32_t> rawCounts;          // unclamped count per tile
    tc::OrderedCounter* ordered = nullptr;             // when set: reserve through it instead

    void operator()(tc::GroupContext<Shared>& g) const {
        Shared& s = g.shared();
        const glm::uvec3 tile = g.groupId();
        g.forOneThread(0, [&](const ThreadIds&) { s.count = 0; });
        g.forEachStrided(kLightCount, [&](const ThreadIds&, std::uint32_t light) {
            if (!lightHitsTile(light, tile.x, tile.y)) return;
            std::uint32_t index = 0;
            tc::interlockedAdd(s.count, 1u, &index);
            if (index < kLocalCapacity) s.list[index] = light;
        });
        g.forOneThread(0, [&](const ThreadIds&) {
            const std::uint32_t stored = std::min(s.count, kLocalCapacity);
            if (ordered != nullptr) {
                s.startOffset = ordered->reserve(g, stored);
            } else {
                globalCounter.interlockedAdd(0, stored, &s.startOffset);
            }
            grid.store(tile.x, tile.y, glm::uvec2(s.startOffset, stored));
            rawCounts.store(tile.x, tile.y, s.count);
        });
        g.forEachStrided(std::min(s.count, kLocalCapacity), [&](const ThreadIds&, std::uint32_t i) {
            globalList.store(s.startOffset + i, s.list[i]);
        });
    }
};

struct LightListResult {
    std::uint32_t counter = 0;
    std::vector<std::uint32_t> list;
    std::vector<glm::uvec2> grid;
    std::vector<std::uint32_t> rawCounts;
    tc::DispatchStats stats;
};

LightListResult runLightList(tc::GroupOrder order, bool useOrderedCounter) {
    LightListResult r;
    r.list.assign(kTilesX * kTilesY * kLocalCapacity, 0xFFFFFFFFu);
    r.grid.assign(kTilesX * kTilesY, glm::uvec2(0));
    r.rawCounts.assign(kTilesX * kTilesY, 0);
    std::vector<std::uint32_t> counter(1, 0);
    tc::OrderedCounter ordered(0);
    LightListKernel kernel{tc::RWStructuredBuffer<std::uint32_t>(counter),
                           tc::RWStructuredBuffer<std::uint32_t>(r.list),
                           tc::RWTexture2D<glm::uvec2>(r.grid, kTilesX, kTilesY),
                           tc::RWTexture2D<std::uint32_t>(r.rawCounts, kTilesX, kTilesY),
                           useOrderedCounter ? &ordered : nullptr};
    tc::OrderedCounter* const counters[] = {&ordered};
    tc::DispatchDesc desc{order, {}};
    if (useOrderedCounter) desc.orderedCounters = counters;
    r.stats = tc::dispatch(kernel, glm::uvec3(kTilesX, kTilesY, 1), desc);
    r.counter = useOrderedCounter ? ordered.value() : counter[0];
    return r;
}

// The layout GroupOrder::Serial must give: tiles in row-major order, ascending light index in a
// tile, each tile truncated to the local capacity.
std::vector<std::uint32_t> expectedLightList() {
    std::vector<std::uint32_t> expected;
    for (std::uint32_t ty = 0; ty < kTilesY; ++ty) {
        for (std::uint32_t tx = 0; tx < kTilesX; ++tx) {
            std::uint32_t stored = 0;
            for (std::uint32_t l = 0; l < kLightCount && stored < kLocalCapacity; ++l) {
                if (lightHitsTile(l, tx, ty)) {
                    expected.push_back(l);
                    ++stored;
                }
            }
        }
    }
    return expected;
}

// ----- tile depth min/max via asuint -------------------------------------------------------------
struct DepthBoundsKernel {
    static constexpr glm::uvec3 groupSize{16, 16, 1};
    struct Shared {
        std::uint32_t minDepth;
        std::uint32_t maxDepth;
    };
    tc::Texture2D<float> depth;
    tc::RWTexture2D<std::uint32_t> minOut; // asuint bits per tile
    tc::RWTexture2D<std::uint32_t> maxOut;

    void operator()(tc::GroupContext<Shared>& g) const {
        Shared& s = g.shared();
        g.forOneThread(0, [&](const ThreadIds&) {
            s.minDepth = 0xFFFFFFFFu; // as 3dgep: uMinDepth = 0xffffffff, uMaxDepth = 0
            s.maxDepth = 0;
        });
        g.forEachThread([&](const ThreadIds& t) {
            // Out-of-bounds loads (partial edge tiles) return 0, as on D3D11.
            const std::uint32_t bits =
                std::bit_cast<std::uint32_t>(depth.load(t.dispatchThreadId.x, t.dispatchThreadId.y));
            tc::interlockedMin(s.minDepth, bits);
            tc::interlockedMax(s.maxDepth, bits);
        });
        g.forOneThread(0, [&](const ThreadIds&) {
            const glm::uvec2 tile(g.groupId().x, g.groupId().y);
            minOut.store(tile, s.minDepth);
            maxOut.store(tile, s.maxDepth);
        });
    }
};

float depthValue(std::uint32_t x, std::uint32_t y) {
    // Positive floats over many binades, including denormal-free small values and 1.0.
    const std::uint32_t h = hashValue(x, y);
    if (h == 7) return 1.0f;
    return static_cast<float>(h + 1) / 997.0f * (h % 3 == 0 ? 1.0e-3f : 1.0f);
}

// ----- validation helpers ---------------------------------------------------------------------------
template<std::uint32_t X, std::uint32_t Y, std::uint32_t Z>
struct SizedKernel {
    static constexpr glm::uvec3 groupSize{X, Y, Z};
    using Shared = tc::NoShared;
    std::uint32_t* calls = nullptr;
    void operator()(tc::GroupContext<Shared>& g) const {
        g.forEachThread([&](const ThreadIds&) { ++*calls; });
    }
};

template<class K>
std::string dispatchError(glm::uvec3 groupCount) {
    std::uint32_t calls = 0;
    try {
        tc::dispatch(K{&calls}, groupCount);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no exception";
}

// ----- kernels of the smaller cases ------------------------------------------------------------
struct TwiceKernel {
    static constexpr glm::uvec3 groupSize{1, 1, 1};
    using Shared = tc::NoShared;
    tc::OrderedCounter* counter;
    void operator()(tc::GroupContext<Shared>& g) const {
        counter->reserve(g, 1);
        counter->reserve(g, 1);
    }
};

struct OnceKernel {
    static constexpr glm::uvec3 groupSize{2, 1, 1};
    using Shared = tc::NoShared;
    tc::OrderedCounter* counter;
    tc::RWStructuredBuffer<std::uint32_t> offsets;
    void operator()(tc::GroupContext<Shared>& g) const {
        const auto rank = static_cast<std::uint32_t>(g.groupFlatIndex());
        if (rank % 2 == 1) return; // odd groups do not reserve: they count as 0
        offsets.store(rank, counter->reserve(g, rank + 1));
    }
};

struct StridedKernel {
    static constexpr glm::uvec3 groupSize{4, 2, 1};
    using Shared = tc::NoShared;
    tc::RWStructuredBuffer<std::uint32_t> threadOf; // per item: which thread ran it
    tc::RWStructuredBuffer<std::uint32_t> order;    // the order items ran in
    void operator()(tc::GroupContext<Shared>& g) const {
        std::uint32_t step = 0;
        g.forEachStrided(19, [&](const ThreadIds& t, std::uint32_t i) {
            threadOf.store(i, t.groupIndex + 100 * t.groupThreadId.y);
            order.store(step++, i);
        });
    }
};

struct DirtyKernel {
    static constexpr glm::uvec3 groupSize{2, 1, 1};
    struct Shared {
        std::uint32_t words[8];
        std::uint32_t marker = 7; // default member initialiser runs too
    };
    tc::RWStructuredBuffer<std::uint32_t> seen;
    void operator()(tc::GroupContext<Shared>& g) const {
        g.forOneThread(1, [&](const ThreadIds&) {
            std::uint32_t sum = g.shared().marker;
            for (std::uint32_t& w : g.shared().words) {
                sum += w;
                w = 0xDEADu; // must not leak into the next group
            }
            seen.store(static_cast<std::uint32_t>(g.groupFlatIndex()), sum);
            g.shared().marker = 1000;
        });
    }
};

} // namespace

TEST_CASE("compute: a barrier separates phases, system values follow HLSL") {
    constexpr glm::uvec3 groups(3, 2, 2);
    constexpr std::uint32_t kGroups = 12;
    std::vector<std::uint32_t> out(kGroups * RotateKernel::kThreads, 0);
    std::vector<std::uint32_t> ids(out.size() * 4, 0);
    const tc::DispatchStats stats =
        tc::dispatch(RotateKernel{tc::RWStructuredBuffer<std::uint32_t>(out),
                                  tc::RWStructuredBuffer<std::uint32_t>(ids)},
                     groups);
    CHECK(stats.groups == 12);
    CHECK(stats.threads == 12 * 64);
    CHECK(stats.phases == 12 * 2);
    for (std::uint32_t g = 0; g < kGroups; ++g) {
        const glm::uvec3 gid(g % 3, (g / 3) % 2, g / 6);
        for (std::uint32_t i = 0; i < RotateKernel::kThreads; ++i) {
            const std::uint32_t flat = g * RotateKernel::kThreads + i;
            CHECK(out[flat] == ((i + 1) % RotateKernel::kThreads) * 10 + 1);
            const glm::uvec3 gtid(i % 8, (i / 8) % 4, i / 32);
            const glm::uvec3 dtid = gid * RotateKernel::groupSize + gtid;
            CHECK(ids[flat * 4 + 0] == gid.x + 100 * gid.y + 10000 * gid.z);
            CHECK(ids[flat * 4 + 1] == gtid.x + 100 * gtid.y + 10000 * gtid.z);
            CHECK(ids[flat * 4 + 2] == dtid.x + 100 * dtid.y + 10000 * dtid.z);
            CHECK(ids[flat * 4 + 3] == i);
        }
    }
}

TEST_CASE("compute: 16x16 tree reduction with shared memory equals the serial sum") {
    // 7x5 groups over a 100x70 input: the right and bottom groups are partial (OOB loads read 0).
    constexpr std::uint32_t kW = 100, kH = 70, kGx = 7, kGy = 5;
    std::vector<std::uint32_t> input(kW * kH);
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x) input[y * kW + x] = hashValue(x, y);

    for (const tc::GroupOrder order : {tc::GroupOrder::Serial, tc::GroupOrder::Parallel}) {
        CAPTURE(static_cast<int>(order));
        std::vector<std::uint32_t> sums(kGx * kGy, 0), total(1, 0);
        const tc::DispatchStats stats = tc::dispatch(
            ReduceKernel{tc::Texture2D<std::uint32_t>(input, kW, kH),
                         tc::RWStructuredBuffer<std::uint32_t>(sums),
                         tc::RWStructuredBuffer<std::uint32_t>(total)},
            glm::uvec3(kGx, kGy, 1), tc::DispatchDesc{order, {}});
        CHECK(stats.groups == kGx * kGy);
        CHECK(stats.threads == kGx * kGy * 256);
        CHECK(stats.phases == kGx * kGy * (1 + 8 + 1)); // load, log2(256) steps, write-out
        std::uint32_t serialTotal = 0;
        for (std::uint32_t gy = 0; gy < kGy; ++gy) {
            for (std::uint32_t gx = 0; gx < kGx; ++gx) {
                std::uint32_t serial = 0;
                for (std::uint32_t y = gy * 16; y < std::min(kH, gy * 16 + 16); ++y)
                    for (std::uint32_t x = gx * 16; x < std::min(kW, gx * 16 + 16); ++x)
                        serial += input[y * kW + x];
                CHECK(sums[gy * kGx + gx] == serial);
                serialTotal += serial;
            }
        }
        CHECK(total[0] == serialTotal);
        CHECK(total[0] == std::accumulate(input.begin(), input.end(), 0u));
    }
}

TEST_CASE("compute: tiled light list, Serial order lays tiles out row-major") {
    const LightListResult r = runLightList(tc::GroupOrder::Serial, false);
    const std::vector<std::uint32_t> expected = expectedLightList();
    CHECK(r.stats.groups == kTilesX * kTilesY);
    CHECK(r.stats.phases == kTilesX * kTilesY * 4);
    REQUIRE(r.counter == expected.size());
    // The exact global layout: row-major tiles, ascending light index inside each tile.
    CHECK(std::equal(expected.begin(), expected.end(), r.list.begin()));
    CHECK(r.list[expected.size()] == 0xFFFFFFFFu); // nothing written past the end

    std::uint32_t offset = 0;
    for (std::uint32_t ty = 0; ty < kTilesY; ++ty) {
        for (std::uint32_t tx = 0; tx < kTilesX; ++tx) {
            std::uint32_t matching = 0;
            for (std::uint32_t l = 0; l < kLightCount; ++l) matching += lightHitsTile(l, tx, ty) ? 1u : 0u;
            const glm::uvec2 cell = r.grid[ty * kTilesX + tx];
            CAPTURE(tx);
            CAPTURE(ty);
            CHECK(cell.x == offset);
            CHECK(cell.y == std::min(matching, kLocalCapacity));
            CHECK(r.rawCounts[ty * kTilesX + tx] == matching); // the count runs past the capacity
            offset += cell.y;
        }
    }
    // The overflowing tile stored lights 0..255 and counted all 700; the empty tile has nothing.
    const glm::uvec2 full = r.grid[1 * kTilesX + 1];
    CHECK(full.y == kLocalCapacity);
    CHECK(r.rawCounts[1 * kTilesX + 1] == kLightCount);
    for (std::uint32_t i = 0; i < kLocalCapacity; ++i) CHECK(r.list[full.x + i] == i);
    CHECK(r.grid[2 * kTilesX + 3].y == 0);
    CHECK(r.rawCounts[2 * kTilesX + 3] == 0);
    // First tile (0,0) by hand: lights l with 7l mod 11 in {0, 1, 2} -> l = 0, 5, 8, 11, 16, ...
    CHECK(r.list[0] == 0);
    CHECK(r.list[1] == 5);
    CHECK(r.list[2] == 8);
    CHECK(r.list[3] == 11);
    CHECK(r.list[4] == 16);
}

TEST_CASE("compute: light list with an OrderedCounter gives the Serial layout in parallel") {
    const LightListResult serial = runLightList(tc::GroupOrder::Serial, false);
    for (const int threads : {1, 2, 7}) {
        CAPTURE(threads);
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(threads));
        for (const tc::GroupOrder order : {tc::GroupOrder::Serial, tc::GroupOrder::Parallel}) {
            const LightListResult r = runLightList(order, true);
            CHECK(r.counter == serial.counter);
            CHECK(r.list == serial.list);
            CHECK(std::equal(r.grid.begin(), r.grid.end(), serial.grid.begin()));
            CHECK(r.rawCounts == serial.rawCounts);
        }
    }
}

TEST_CASE("compute: light list in Parallel without ordering keeps each tile's list intact") {
    // Unordered parallel append: tile offsets may differ from Serial, tile contents may not.
    const LightListResult serial = runLightList(tc::GroupOrder::Serial, false);
    const LightListResult r = runLightList(tc::GroupOrder::Parallel, false);
    REQUIRE(r.counter == serial.counter);
    for (std::size_t t = 0; t < r.grid.size(); ++t) {
        const glm::uvec2 a = r.grid[t], b = serial.grid[t];
        REQUIRE(a.y == b.y);
        CHECK(std::equal(r.list.begin() + a.x, r.list.begin() + a.x + a.y, serial.list.begin() + b.x));
    }
}

TEST_CASE("compute: OrderedCounter misuse throws") {
    tc::OrderedCounter counter(5);
    tc::OrderedCounter* const list[] = {&counter};
    CHECK_THROWS_AS(tc::dispatch(TwiceKernel{&counter}, glm::uvec3(3, 1, 1)), std::logic_error); // not listed
    for (const tc::GroupOrder order : {tc::GroupOrder::Serial, tc::GroupOrder::Parallel}) {
        CHECK_THROWS_AS(tc::dispatch(TwiceKernel{&counter}, glm::uvec3(4, 1, 1), tc::DispatchDesc{order, list}),
                        std::logic_error);
    }
    // The counter is usable again afterwards; odd groups do not reserve and count as 0.
    counter.reset(10);
    std::vector<std::uint32_t> offsets(6, 0);
    tc::dispatch(OnceKernel{&counter, tc::RWStructuredBuffer<std::uint32_t>(offsets)}, glm::uvec3(3, 2, 1),
                 tc::DispatchDesc{tc::GroupOrder::Parallel, list});
    CHECK(offsets == std::vector<std::uint32_t>{10, 0, 11, 0, 14, 0});
    CHECK(counter.value() == 19);
}

TEST_CASE("compute: tile min/max depth through asuint InterlockedMin/Max") {
    constexpr std::uint32_t kW = 70, kH = 40; // 5x3 tiles of 16x16; right column and bottom row partial
    std::vector<float> depth(kW * kH);
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x) depth[y * kW + x] = depthValue(x, y);
    std::vector<std::uint32_t> minBits(15, 0), maxBits(15, 0);
    tc::dispatch(DepthBoundsKernel{tc::Texture2D<float>(depth, kW, kH),
                                   tc::RWTexture2D<std::uint32_t>(minBits, 5, 3),
                                   tc::RWTexture2D<std::uint32_t>(maxBits, 5, 3)},
                 glm::uvec3(5, 3, 1), tc::DispatchDesc{tc::GroupOrder::Parallel, {}});
    for (std::uint32_t ty = 0; ty < 3; ++ty) {
        for (std::uint32_t tx = 0; tx < 5; ++tx) {
            float lo = std::numeric_limits<float>::infinity(), hi = 0.0f;
            for (std::uint32_t y = ty * 16; y < std::min(kH, ty * 16 + 16); ++y) {
                for (std::uint32_t x = tx * 16; x < std::min(kW, tx * 16 + 16); ++x) {
                    lo = std::min(lo, depth[y * kW + x]);
                    hi = std::max(hi, depth[y * kW + x]);
                }
            }
            const bool partial = tx == 4 || ty == 2;
            if (partial) lo = 0.0f; // out-of-bounds threads load 0 (3dgep's edge-tile behaviour)
            CAPTURE(tx);
            CAPTURE(ty);
            CHECK(std::bit_cast<float>(minBits[ty * 5 + tx]) == lo);
            CHECK(std::bit_cast<float>(maxBits[ty * 5 + tx]) == hi);
        }
    }
    CHECK(std::bit_cast<float>(maxBits[0]) > 0.5f); // sanity: real data, not zeros
}

TEST_CASE("compute: Interlocked* semantics table (group-shared and global agree)") {
    struct Row {
        const char* op;
        std::uint32_t initial, a, b; // b: CompareExchange's value
        std::uint32_t final, original;
    };
    constexpr std::uint32_t kMax = 0xFFFFFFFFu;
    const Row rows[] = {
        {"cmpxchg equal", 5, 5, 9, 9, 5},
        {"cmpxchg differ", 5, 4, 9, 5, 5},
        {"cmpxchg zero", 0, 0, kMax, kMax, 0},
        {"cmpxchg same value", 7, 7, 7, 7, 7},
        {"add", 40, 2, 0, 42, 40},
        {"add wraps", kMax, 1, 0, 0, kMax},
        {"min", 10, 3, 0, 3, 10},
        {"min keeps", 3, 10, 0, 3, 3},
        {"min unsigned", 1, kMax, 0, 1, 1},
        {"max", 10, 30, 0, 30, 10},
        {"max unsigned", 1, 0x80000000u, 0, 0x80000000u, 1},
        {"and", 0xF0F0u, 0xFF00u, 0, 0xF000u, 0xF0F0u},
        {"or", 0xF0F0u, 0x0F0Fu, 0, 0xFFFFu, 0xF0F0u},
        {"xor", 0xFFFFu, 0x0FF0u, 0, 0xF00Fu, 0xFFFFu},
        {"exchange", 11, 22, 0, 22, 11},
    };
    for (const Row& row : rows) {
        CAPTURE(std::string(row.op));
        const std::string op = row.op;
        std::uint32_t shared = row.initial;
        std::vector<std::uint32_t> buffer{0, row.initial};
        std::vector<std::uint32_t> texels{0, 0, 0, row.initial};
        const tc::RWStructuredBuffer<std::uint32_t> uav(buffer);
        const tc::RWTexture2D<std::uint32_t> tex(texels, 2, 2);
        const glm::uvec2 at(1, 1);
        std::uint32_t o1 = 0, o2 = 0, o3 = 0, r1 = 0, r2 = 0, r3 = 0;
        if (op.starts_with("cmpxchg")) {
            r1 = tc::interlockedCompareExchange(shared, row.a, row.b, &o1);
            r2 = uav.interlockedCompareExchange(1, row.a, row.b, &o2);
            r3 = tex.interlockedCompareExchange(at, row.a, row.b, &o3);
        } else if (op.starts_with("add")) {
            r1 = tc::interlockedAdd(shared, row.a, &o1);
            r2 = uav.interlockedAdd(1, row.a, &o2);
            r3 = tex.interlockedAdd(at, row.a, &o3);
        } else if (op.starts_with("min")) {
            r1 = tc::interlockedMin(shared, row.a, &o1);
            r2 = uav.interlockedMin(1, row.a, &o2);
            r3 = tex.interlockedMin(at, row.a, &o3);
        } else if (op.starts_with("max")) {
            r1 = tc::interlockedMax(shared, row.a, &o1);
            r2 = uav.interlockedMax(1, row.a, &o2);
            r3 = tex.interlockedMax(at, row.a, &o3);
        } else if (op == "and") {
            r1 = tc::interlockedAnd(shared, row.a, &o1);
            r2 = uav.interlockedAnd(1, row.a, &o2);
            r3 = tex.interlockedAnd(at, row.a, &o3);
        } else if (op == "or") {
            r1 = tc::interlockedOr(shared, row.a, &o1);
            r2 = uav.interlockedOr(1, row.a, &o2);
            r3 = tex.interlockedOr(at, row.a, &o3);
        } else if (op == "xor") {
            r1 = tc::interlockedXor(shared, row.a, &o1);
            r2 = uav.interlockedXor(1, row.a, &o2);
            r3 = tex.interlockedXor(at, row.a, &o3);
        } else if (op == "exchange") {
            r1 = tc::interlockedExchange(shared, row.a, &o1);
            r2 = uav.interlockedExchange(1, row.a, &o2);
            r3 = tex.interlockedExchange(at, row.a, &o3);
        } else {
            FAIL("unknown op");
        }
        CHECK(shared == row.final);
        CHECK(buffer[1] == row.final);
        CHECK(texels[3] == row.final);
        CHECK(buffer[0] == 0); // neighbours untouched
        CHECK(texels[2] == 0);
        CHECK(r1 == row.original);
        CHECK(r2 == row.original);
        CHECK(r3 == row.original);
        CHECK(o1 == row.original);
        CHECK(o2 == row.original);
        CHECK(o3 == row.original);
    }
}

TEST_CASE("compute: signed Interlocked* compare as int32 and wrap") {
    constexpr std::int32_t kMin = std::numeric_limits<std::int32_t>::min();
    constexpr std::int32_t kMax = std::numeric_limits<std::int32_t>::max();
    std::int32_t v = 5;
    CHECK(tc::interlockedMin(v, -3) == 5);
    CHECK(v == -3); // signed: -3 < 5 (as uint32 it would be larger)
    CHECK(tc::interlockedMax(v, -10) == -3);
    CHECK(v == -3);
    v = kMax;
    CHECK(tc::interlockedAdd(v, 1) == kMax);
    CHECK(v == kMin); // two's-complement wrap, no UB
    std::vector<std::int32_t> buffer{kMax, 5};
    const tc::RWStructuredBuffer<std::int32_t> uav(buffer);
    CHECK(uav.interlockedAdd(0, 1) == kMax);
    CHECK(buffer[0] == kMin);
    CHECK(uav.interlockedMin(1, -7) == 5);
    CHECK(buffer[1] == -7);
    CHECK(uav.interlockedMax(1, -8) == -7);
    CHECK(buffer[1] == -7);
    tc::interlockedCompareStore(v, kMin, 42);
    CHECK(v == 42);
    tc::interlockedCompareStore(v, 0, 43);
    CHECK(v == 42);
    uav.interlockedCompareStore(1, -7, 3);
    CHECK(buffer[1] == 3);
    uav.interlockedCompareStore(1, -7, 4);
    CHECK(buffer[1] == 3);
}

TEST_CASE("compute: D3D11 out-of-bounds rules") {
    struct Light {
        float position[3];
        float range;
    };
    // StructuredBuffer: OOB read returns zero.
    const std::vector<Light> lights{{{1, 2, 3}, 4}};
    const tc::StructuredBuffer<Light> srv(lights);
    CHECK(srv.size() == 1);
    CHECK(srv[0].range == 4.0f);
    CHECK(srv[1].range == 0.0f);
    CHECK(srv[1].position[2] == 0.0f);
    CHECK(srv[0xFFFFFFFFu].position[0] == 0.0f);

    // RWStructuredBuffer over the first 4 of 6 words: OOB writes and atomics leave word 4 alone.
    std::vector<std::uint32_t> backing{1, 2, 3, 4, 0xAAAAu, 0xBBBBu};
    const tc::RWStructuredBuffer<std::uint32_t> uav(std::span<std::uint32_t>(backing).first(4));
    CHECK(uav.load(3) == 4);
    CHECK(uav.load(4) == 0);
    uav.store(4, 99);
    uav.store(0xFFFFFFFFu, 99);
    std::uint32_t original = 12345;
    CHECK(uav.interlockedAdd(4, 10, &original) == 0);
    CHECK(original == 0); // D3D11: undefined; tessera: 0
    CHECK(uav.interlockedMax(5, 10) == 0);
    CHECK(uav.interlockedExchange(4, 7) == 0);
    original = 1;
    CHECK(uav.interlockedCompareExchange(4, 0, 7, &original) == 0);
    CHECK(original == 0);
    uav.interlockedCompareStore(4, 0, 7);
    CHECK(backing == std::vector<std::uint32_t>{1, 2, 3, 4, 0xAAAAu, 0xBBBBu});

    // RWTexture2D 3x2 inside a 4x2 allocation (the last word is outside the view).
    std::vector<std::uint32_t> texels{10, 11, 12, 20, 21, 22, 0xCCCCu, 0xDDDDu};
    const tc::RWTexture2D<std::uint32_t> tex(texels, 3, 2);
    CHECK(tex.load(2, 1) == 22);
    CHECK(tex.load(3, 0) == 0);  // x == width
    CHECK(tex.load(0, 2) == 0);  // y == height
    tex.store(3, 0, 1);          // would alias (0, 1) if the bounds check were on the linear index
    tex.store(0, 2, 1);
    tex.store(glm::uvec2(static_cast<std::uint32_t>(-1), 0), 1);
    CHECK(tex.interlockedOr(glm::uvec2(3, 1), 0xFF) == 0);
    CHECK(tex.interlockedMin(glm::uvec2(0, 5), 0) == 0);
    CHECK(texels == std::vector<std::uint32_t>{10, 11, 12, 20, 21, 22, 0xCCCCu, 0xDDDDu});

    // Texture2D: OOB loads, including a negative coordinate, return 0.
    const std::vector<float> image{0.5f, 0.25f, 0.125f, 2.0f};
    const tc::Texture2D<float> srvTex(image, 2, 2);
    CHECK(srvTex.load(1, 1) == 2.0f);
    CHECK(srvTex.load(glm::ivec2(-1, 0)) == 0.0f);
    CHECK(srvTex.load(glm::ivec2(0, 2)) == 0.0f);
    CHECK(srvTex.load(glm::uvec2(2, 0)) == 0.0f);

    // Too little data for the stated size, or a size over D3D11's limit, is an error.
    CHECK_THROWS_AS(tc::Texture2D<float>(image, 3, 2), std::invalid_argument);
    CHECK_THROWS_AS(tc::RWTexture2D<std::uint32_t>(texels, 16385, 0), std::invalid_argument);
}

TEST_CASE("compute: validation names the offending value") {
    std::string msg = dispatchError<SizedKernel<0, 1, 1>>(glm::uvec3(1));
    CHECK(msg.find("group size x = 0") != std::string::npos);
    CHECK(msg.find("D3D11_CS_THREAD_GROUP_MAX_X") != std::string::npos);
    msg = dispatchError<SizedKernel<1, 0, 1>>(glm::uvec3(1));
    CHECK(msg.find("group size y = 0") != std::string::npos);
    msg = dispatchError<SizedKernel<1, 1, 65>>(glm::uvec3(1));
    CHECK(msg.find("group size z = 65") != std::string::npos);
    CHECK(msg.find("D3D11_CS_THREAD_GROUP_MAX_Z") != std::string::npos);
    msg = dispatchError<SizedKernel<2048, 1, 1>>(glm::uvec3(1));
    CHECK(msg.find("group size x = 2048") != std::string::npos);
    msg = dispatchError<SizedKernel<32, 32, 2>>(glm::uvec3(1));
    CHECK(msg.find("2048 threads") != std::string::npos);
    CHECK(msg.find("D3D11_CS_THREAD_GROUP_MAX_THREADS_PER_GROUP") != std::string::npos);
    msg = dispatchError<SizedKernel<1, 1, 1>>(glm::uvec3(65536, 1, 1));
    CHECK(msg.find("group count x = 65536") != std::string::npos);
    CHECK(msg.find("D3D11_CS_DISPATCH_MAX_THREAD_GROUPS_PER_DIMENSION") != std::string::npos);
    msg = dispatchError<SizedKernel<1, 1, 1>>(glm::uvec3(1, 1, 70000));
    CHECK(msg.find("group count z = 70000") != std::string::npos);

    // The limits themselves are accepted.
    std::uint32_t calls = 0;
    CHECK(tc::dispatch(SizedKernel<1024, 1, 1>{&calls}, glm::uvec3(1)).threads == 1024);
    CHECK(tc::dispatch(SizedKernel<1, 16, 64>{&calls}, glm::uvec3(1)).threads == 1024);
    CHECK(tc::dispatch(SizedKernel<1, 1, 1>{&calls}, glm::uvec3(65535, 1, 1)).groups == 65535);
    CHECK(calls == 1024 + 1024 + 65535);

    // A zero group count is a no-op.
    calls = 0;
    const tc::DispatchStats none = tc::dispatch(SizedKernel<4, 4, 1>{&calls}, glm::uvec3(0, 5, 5));
    CHECK(none.groups == 0);
    CHECK(none.threads == 0);
    CHECK(calls == 0);
}

TEST_CASE("compute: forEachStrided runs the strided loop in ascending order") {
    std::vector<std::uint32_t> threadOf(19, 0), order(19, 0);
    tc::dispatch(StridedKernel{tc::RWStructuredBuffer<std::uint32_t>(threadOf),
                               tc::RWStructuredBuffer<std::uint32_t>(order)},
                 glm::uvec3(1));
    for (std::uint32_t i = 0; i < 19; ++i) {
        CHECK(order[i] == i);
        const std::uint32_t thread = i % 8;
        CHECK(threadOf[i] == thread + 100 * (thread / 4));
    }
}

TEST_CASE("compute: group-shared memory is value-initialised for every group") {
    std::vector<std::uint32_t> seen(40, 1);
    const tc::DispatchStats stats =
        tc::dispatch(DirtyKernel{tc::RWStructuredBuffer<std::uint32_t>(seen)}, glm::uvec3(5, 4, 2));
    CHECK(stats.phases == 40);
    CHECK(seen == std::vector<std::uint32_t>(40, 7));
}

} // namespace tessera_test::compute_compute_test
