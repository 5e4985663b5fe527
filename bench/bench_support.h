// Command-line and statistics helpers shared by the scene benchmarks (technique_bench,
// culling_bench): comma lists, counts with a named error, the median of the measured frames,
// and the allocator setting that makes every configuration of a run measure the steady state.
#pragma once

#include <malloc.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace tessera::bench {

// glibc serves blocks above M_MMAP_THRESHOLD (128 KiB, raised dynamically as mmapped blocks are
// freed) with fresh mmaps and returns heap tops above M_TRIM_THRESHOLD to the kernel; each frame
// allocates its buffers anew (a new BufferRegistry), so until the thresholds settle every frame
// page-faults its multi-MiB surfaces again. On this VM that made the first configuration of a
// run up to 2.7x slower than the same configuration measured second (forward-plus culling, 8 px
// tiles, 16384 lights: 155 vs 57 ms). Fixed thresholds keep freed pages in the heap for the
// next frame: the steady state of a renderer that draws frame after frame.
inline void useSteadyStateAllocator() {
    mallopt(M_MMAP_THRESHOLD, 1 << 30);  // bytes: blocks up to 1 GiB come from the heap
    mallopt(M_TRIM_THRESHOLD, 1 << 30);  // bytes: keep up to 1 GiB of free heap top
}

// "a,b,,c" -> {"a", "b", "c"} (empty items dropped).
inline std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= s.size()) {
        const std::size_t end = std::min(s.find(sep, start), s.size());
        if (end > start) out.push_back(s.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

// A comma list of counts in 0..1000000; anything else exits 2 naming `flag` and the item.
inline std::vector<std::uint32_t> splitUints(const std::string& flag, const std::string& s) {
    std::vector<std::uint32_t> out;
    for (const std::string& item : split(s, ',')) {
        char* tail = nullptr;
        const unsigned long v = std::strtoul(item.c_str(), &tail, 10);
        if (item.empty() || *tail != '\0' || v > 1000000) {
            std::fprintf(stderr, "%s: '%s' is not a count in 0..1000000\n", flag.c_str(), item.c_str());
            std::exit(2);
        }
        out.push_back(std::uint32_t(v));
    }
    return out;
}

inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

} // namespace tessera::bench
