// requireOutputFile / requireOutputFolder (output_check.h): a probe file created and removed in
// the folder that will hold the output.
#include "output_check.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include <stdlib.h>  // mkstemp (POSIX)
#include <unistd.h>  // close, unlink

#include "render_args.h"  // UsageError

namespace tessera::cli {
namespace {

namespace fs = std::filesystem;

// Empty when a new file can be created in `folder` (it is created and removed), else why not.
std::string whyNoNewFile(const fs::path& folder) {
    std::string pattern = (folder / ".tessera-write-check-XXXXXX").string();
    std::vector<char> name(pattern.begin(), pattern.end());
    name.push_back('\0');
    const int fd = mkstemp(name.data());
    if (fd < 0) return std::strerror(errno);
    close(fd);
    unlink(name.data());
    return {};
}

std::string quoted(const fs::path& p) {
    std::string text = p.string();
    text.insert(text.begin(), '\'');
    text.push_back('\'');
    return text;
}

} // namespace

void requireOutputFile(std::string_view flag, const std::string& path) {
    std::error_code ec;
    const fs::path out(path);
    const fs::path folder = out.has_parent_path() ? out.parent_path() : fs::path(".");
    const std::string head = std::string(flag) + ": " + quoted(out) + ": ";
    if (!fs::is_directory(folder, ec)) throw UsageError(head + "the folder " + quoted(folder) + " does not exist");
    if (fs::is_directory(out, ec)) throw UsageError(std::string(flag) + ": " + quoted(out) + " is a folder");
    if (const std::string why = whyNoNewFile(folder); !why.empty())
        throw UsageError(head + "cannot create a file in " + quoted(folder) + " (" + why + ")");
}

void requireOutputFolder(std::string_view flag, const std::string& path) {
    std::error_code ec;
    const fs::path dir(path);
    const std::string head = std::string(flag) + ": " + quoted(dir) + ": ";
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw UsageError(std::string(flag) + ": " + quoted(dir) + " exists and is not a folder");
    fs::path existing = dir;  // the deepest existing ancestor: where the first new entry goes
    while (!existing.empty() && !fs::exists(existing, ec)) existing = existing.parent_path();
    if (existing.empty()) existing = ".";
    if (!fs::is_directory(existing, ec)) throw UsageError(head + quoted(existing) + " is not a folder");
    if (const std::string why = whyNoNewFile(existing); !why.empty())
        throw UsageError(head + "cannot create anything in " + quoted(existing) + " (" + why + ")");
}

} // namespace tessera::cli
