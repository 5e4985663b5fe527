// Writing a whole file so that readers see either the previous file or the complete new one:
// the bytes go to a uniquely named temporary file beside the target (created with O_EXCL, so
// concurrent writers never share one), are flushed to the disk, and the temporary is renamed over
// the target. Every failed step (short write, full disk, fsync, close, rename) throws.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace tessera {

// Writes `bytes` to `target` atomically (write, fsync, close, rename; each return value checked,
// short writes continued, EINTR retried). On failure the temporary file is removed, an existing
// `target` is left as it was, and std::runtime_error is thrown naming `target` and the step,
// with strerror of the errno that step set (e.g. "x.png: cannot write: File too large").
// The temporary file is "<stem>.partial-<pid>-<8 hex digits><ext>" in target's folder.
void writeFileAtomically(const std::filesystem::path& target, std::span<const unsigned char> bytes);

// 64-bit FNV-1a (offset basis 0xcbf29ce484222325, prime 0x100000001b3; Fowler, Noll, Vo,
// "The FNV Non-Cryptographic Hash Algorithm", IETF draft-eastlake-fnv) of `bytes`.
std::uint64_t fnv1a64(std::span<const unsigned char> bytes);
// fnv1a64 as 16 lower-case hex digits.
std::string hashHex(std::uint64_t hash);

} // namespace tessera
