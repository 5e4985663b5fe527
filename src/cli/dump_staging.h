// --dump's staging folder (DumpStaging): a render's dump is written out of sight and appears
// under the name the user gave only when the whole render succeeded.
#pragma once

#include <chrono>
#include <filesystem>
#include <string>
#include <system_error>

#include <unistd.h>

#include "render_args.h"

namespace tessera::cli {

// --dump's folder, filled out of sight: every dump (the final buffers, --dump-after's and
// --dump-lights' folders, manifest.json) is written into a hidden staging folder inside the
// deepest existing ancestor of DIR, and moved into DIR only when the render succeeded (renamed
// when DIR does not exist, else merged into it entry by entry). A render that fails removes the
// staging folder: DIR stays absent or as it was.
class DumpStaging {
public:
    // Points o.dumpDir at the staging folder (nothing is created yet).
    explicit DumpStaging(RenderOptions& o) {
        if (o.dumpDir.empty()) return;
        mTarget = std::filesystem::path(o.dumpDir).lexically_normal();
        if (mTarget.filename().empty()) mTarget = mTarget.parent_path();
        std::error_code ec;
        std::filesystem::path existing = mTarget.has_parent_path() ? mTarget.parent_path() : std::filesystem::path(".");
        while (!existing.empty() && !std::filesystem::exists(existing, ec)) existing = existing.has_parent_path() ? existing.parent_path() : std::filesystem::path(".");
        if (existing.empty()) existing = ".";
        mStaging = existing / (".tessera-dump.partial-" + std::to_string(::getpid()) + "-" + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
        o.dumpDir = mStaging.string();
    }
    DumpStaging(const DumpStaging&) = delete;
    DumpStaging& operator=(const DumpStaging&) = delete;
    ~DumpStaging() {
        std::error_code ec;
        if (!mStaging.empty()) std::filesystem::remove_all(mStaging, ec);
    }
    // Moves the staged dump into place (after everything else was written).
    void commit() {
        if (mStaging.empty() || mCommitted) return;
        std::error_code ec;
        if (!std::filesystem::exists(mStaging, ec)) std::filesystem::create_directories(mStaging);
        if (mTarget.has_parent_path()) std::filesystem::create_directories(mTarget.parent_path());
        if (!std::filesystem::exists(mTarget, ec)) std::filesystem::rename(mStaging, mTarget);
        else moveInto(mStaging, mTarget);
        mCommitted = true;
    }
    // `text` (an error message) with the staging folder named as DIR, the folder the user gave.
    std::string named(std::string text) const {
        if (mStaging.empty()) return text;
        const std::string staging = mStaging.string(), target = mTarget.string();
        for (std::size_t at = text.find(staging); at != std::string::npos; at = text.find(staging, at + target.size()))
            text.replace(at, staging.size(), target);
        return text;
    }
    // A written path under the staging folder as it reads after commit.
    std::string finalPath(const std::string& path) const {
        if (mStaging.empty()) return path;
        const std::string staging = mStaging.string();
        if (path.compare(0, staging.size(), staging) != 0) return path;
        return mTarget.string() + path.substr(staging.size());
    }

private:
    static void moveInto(const std::filesystem::path& from, const std::filesystem::path& to) {
        for (const std::filesystem::directory_entry& e : std::filesystem::directory_iterator(from)) {
            const std::filesystem::path dest = to / e.path().filename();
            std::error_code ec;
            if (e.is_directory() && std::filesystem::is_directory(dest, ec)) {
                moveInto(e.path(), dest);
                continue;
            }
            if (std::filesystem::is_directory(dest, ec)) std::filesystem::remove_all(dest);
            std::filesystem::rename(e.path(), dest);
        }
    }
    std::filesystem::path mTarget, mStaging;
    bool mCommitted = false;
};

} // namespace tessera::cli
