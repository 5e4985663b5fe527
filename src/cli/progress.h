// A one-line progress bar on stderr for long work (loading a scene, decoding textures, running
// passes). Shown only when stderr is a terminal, unless forced with --progress; --quiet hides
// it. In pipes and CI it prints nothing, so logs stay clean.
#pragma once

#include <cstddef>
#include <cstdio>
#include <mutex>
#include <string>

#include <unistd.h>

namespace tessera::cli {

class Progress {
public:
    enum class Mode { Auto, On, Off };
    explicit Progress(Mode mode) : mEnabled(mode == Mode::On || (mode == Mode::Auto && isatty(STDERR_FILENO))) {}
    ~Progress() { finish(); }

    bool enabled() const { return mEnabled; }
    // Shows "label [#####     ] done/total" (total 0: just the label).
    void update(const std::string& label, std::size_t done, std::size_t total) {
        if (!mEnabled) return;
        const std::lock_guard<std::mutex> lock(mMutex);
        constexpr int kBarWidth = 30;  // characters
        std::string line = label;
        if (total > 0) {
            const int filled = int(double(done) / double(total) * kBarWidth);
            line += " [" + std::string(std::size_t(filled), '#') + std::string(std::size_t(kBarWidth - filled), ' ') + "] " +
                    std::to_string(done) + "/" + std::to_string(total);
        }
        std::fprintf(stderr, "\r\033[K%s", line.c_str());
        std::fflush(stderr);
        mOpen = true;
    }
    // Clears the line so that the next output starts clean.
    void finish() {
        if (!mEnabled || !mOpen) return;
        std::fprintf(stderr, "\r\033[K");
        std::fflush(stderr);
        mOpen = false;
    }

private:
    bool mEnabled;
    bool mOpen = false;
    std::mutex mMutex;
};

} // namespace tessera::cli
