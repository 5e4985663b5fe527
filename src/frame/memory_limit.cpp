// availableMemoryBytes reads sysconf, /sys/fs/cgroup/memory.max and getrlimit; formatBytes
// prints binary units.
#include <tessera/frame/memory_limit.h>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>

namespace tessera {

std::uint64_t availableMemoryBytes() {
    std::uint64_t bytes = std::numeric_limits<std::uint64_t>::max();
    const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
    if (pages > 0 && pageSize > 0) bytes = std::uint64_t(pages) * std::uint64_t(pageSize);
    std::ifstream cgroup("/sys/fs/cgroup/memory.max");  // "max" or a byte count (cgroup v2)
    std::string text;
    if (cgroup >> text && !text.empty() && text != "max") {
        try {
            bytes = std::min<std::uint64_t>(bytes, std::stoull(text));
        } catch (const std::exception&) {
        }
    }
    rlimit limit{};
    if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
        bytes = std::min<std::uint64_t>(bytes, std::uint64_t(limit.rlim_cur));
    return bytes;
}

std::uint64_t defaultMemoryLimitBytes() { return availableMemoryBytes() / 4 * 3; }

std::string formatBytes(double bytes) {
    char text[48];
    if (bytes >= 1024.0 * 1024.0 * 1024.0) std::snprintf(text, sizeof text, "%.1f GiB", bytes / (1024.0 * 1024.0 * 1024.0));
    else if (bytes >= 1024.0 * 1024.0) std::snprintf(text, sizeof text, "%.1f MiB", bytes / (1024.0 * 1024.0));
    else if (bytes >= 1024.0) std::snprintf(text, sizeof text, "%.1f KiB", bytes / 1024.0);
    else std::snprintf(text, sizeof text, "%.0f B", bytes);
    return text;
}

} // namespace tessera
