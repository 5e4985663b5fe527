// Output paths refused before any work: a command that would fail only when it writes its
// result (after loading and rendering) fails at once instead, with exit 2 and the path named.
// The check creates and removes a file where the output will go, because permission bits do
// not answer it (access(W_OK) says yes to root in /proc, on read-only mounts' mount points, ...).
#pragma once

#include <string>
#include <string_view>

namespace tessera::cli {

// `path` names a file the command will write (replacing it if it exists): its folder must exist
// and take a new file, and `path` must not be a folder. Throws UsageError naming `flag` and `path`.
void requireOutputFile(std::string_view flag, const std::string& path);

// `path` names a folder the command will create with its parents, or fill if it exists: it must
// be a folder if it exists, and its deepest existing ancestor must take a new file.
void requireOutputFolder(std::string_view flag, const std::string& path);

} // namespace tessera::cli
