// Atomic whole-file writes with POSIX calls, every return value checked: a unique O_EXCL
// temporary beside the target, a write loop that continues short writes and retries EINTR,
// fsync, close, rename; the temporary is unlinked on any failure. Also FNV-1a 64.
#include <tessera/io/atomic_file.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <stdexcept>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace tessera {
namespace {

constexpr int kMaxNameAttempts = 64;  // tries at a fresh random temporary name before giving up

[[noreturn]] void fail(const std::filesystem::path& target, const std::string& step, int error) {
    throw std::runtime_error(target.string() + ": " + step + ": " + std::strerror(error));
}

// A random 32-bit value per call; seeded once per process from std::random_device.
std::uint32_t randomSuffix() {
    thread_local std::mt19937 engine{std::random_device{}()};
    return std::uint32_t(engine());
}

} // namespace

std::uint64_t fnv1a64(std::span<const unsigned char> bytes) {
    std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-64 offset basis
    for (const unsigned char b : bytes) {
        h ^= b;
        h *= 0x100000001b3ull;  // FNV-64 prime
    }
    return h;
}

std::string hashHex(std::uint64_t hash) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
    return text;
}

void writeFileAtomically(const std::filesystem::path& target, std::span<const unsigned char> bytes) {
    const std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
    std::filesystem::path tmp;
    int fd = -1;
    for (int attempt = 0; attempt < kMaxNameAttempts && fd < 0; ++attempt) {
        char suffix[32];
        std::snprintf(suffix, sizeof suffix, ".partial-%ld-%08x", static_cast<long>(::getpid()), randomSuffix());
        tmp = dir / (target.stem().string() + suffix + target.extension().string());
        // 0666 before the umask, as fopen creates files: the image gets the user's usual mode.
        do {
            fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        } while (fd < 0 && errno == EINTR);
        if (fd < 0 && errno != EEXIST) fail(target, "cannot create a temporary file in '" + dir.string() + "'", errno);
    }
    if (fd < 0) fail(target, "cannot create a temporary file in '" + dir.string() + "'", EEXIST);

    // From here on: remember the first failure's errno, close and unlink, then throw.
    auto abandon = [&](const std::string& step, int error) {
        if (fd >= 0) ::close(fd);
        ::unlink(tmp.c_str());
        fail(target, step, error);
    };
    const unsigned char* p = bytes.data();
    std::size_t left = bytes.size();
    while (left > 0) {
        const ssize_t n = ::write(fd, p, left);
        if (n < 0) {
            if (errno == EINTR) continue;
            abandon("cannot write", errno);
        }
        if (n == 0) abandon("cannot write", ENOSPC);  // no progress and no errno: treat as a full disk
        p += n;
        left -= std::size_t(n);
    }
    if (::fsync(fd) != 0) abandon("cannot flush to disk", errno);
    const int closed = ::close(fd);
    fd = -1;
    if (closed != 0) abandon("cannot close", errno);
    if (::rename(tmp.c_str(), target.c_str()) != 0) abandon("cannot rename into place", errno);
    // Make the rename itself durable; the new file is already in place, so a failure to sync the
    // folder (some file systems refuse fsync on directories) is not reported.
    const int dirFd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dirFd >= 0) {
        (void)::fsync(dirFd);
        (void)::close(dirFd);
    }
}

} // namespace tessera
