// The memory a render may take and the error when it would take more. The limit is the CLI's
// --memory-limit, else three quarters of what this process may use (the least of physical
// memory, the cgroup's memory.max and RLIMIT_AS); estimates are checked against it before
// anything large is allocated, and BufferRegistry refuses a buffer that would pass it.
#pragma once

#include <cstdint>
#include <string>

#include <tessera/errors/input_error.h>

namespace tessera {

// Bad input in the sense of the CLI (exit code 2): the request itself is too large.
struct MemoryLimitError : InputError {
    using InputError::InputError;
};

// Bytes this process may use: min(physical memory, cgroup v2 memory.max, RLIMIT_AS).
std::uint64_t availableMemoryBytes();
// The default limit: 3/4 of availableMemoryBytes() (room for the program, the scene's files and
// the allocator's slack).
std::uint64_t defaultMemoryLimitBytes();
// "11.2 GiB", "640.0 MiB", "512 B".
std::string formatBytes(double bytes);

} // namespace tessera
