// `tessera serve`'s renders: each one is this same program run as a child process (`tessera render
// ... --dump`, `tessera probe ... --json`) into a folder of its own, so a page never sees two frames
// mixed, a render can be cancelled by ending its process, and a failing render cannot take the
// server down. One render runs at a time; a newer request cancels it and waits in its place.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

namespace tessera::cli {

// One render: queued, running, then done, failed or cancelled. Published renders never change.
struct ServeRender {
    std::uint64_t id = 0;
    std::string status;                  // "queued", "running", "done", "failed", "cancelled"
    std::string message;                 // failed: the child's error lines
    std::vector<std::string> args;       // `tessera render` arguments (the scene first), as requested
    std::filesystem::path folder;        // <work>/render-<id>/: image.png, dump/, stdout.txt, stderr.txt
    nlohmann::json manifest;             // dump/manifest.json
    nlohmann::json passMs = nlohmann::json::object();  // pass name -> ms (the child's --stats lines)
    double frameMs = 0.0;
    std::set<std::string> files;         // every file under folder/dump/ (relative paths): all it serves
    std::optional<std::uint32_t> defaultLight;  // per-light steps: the light whose stencil shows the trick
    double wallMs = 0.0;                 // the child's whole run: loading, rendering, writing
};

// The outcome of running a child program to its end.
struct ChildResult {
    bool cancelled = false;
    int exitCode = -1;  // -1: ended by a signal
    std::string out, err;
};

// A file's bytes ("" when it cannot be read).
std::string readText(const std::filesystem::path& file);

// Runs `exe` with `argv` (argv[0] excluded), stdout and stderr into the two files; polls `cancel`
// and ends the child (SIGTERM, then SIGKILL after 2 s) when it becomes true.
ChildResult runChild(const std::filesystem::path& exe, const std::vector<std::string>& argv, const std::filesystem::path& outFile,
                     const std::filesystem::path& errFile, const std::atomic<bool>* cancel);

class ServeJobs {
public:
    // `exe`: this program; `work`: the server's folder, emptied and removed by the destructor.
    // `lightSteps`: the lights (from 0) whose deferred steps each render dumps.
    ServeJobs(std::filesystem::path exe, std::filesystem::path work, std::uint32_t lightSteps);
    ~ServeJobs();
    ServeJobs(const ServeJobs&) = delete;
    ServeJobs& operator=(const ServeJobs&) = delete;

    // Queues a render with `args` (scene first); a render still running is cancelled, one still
    // queued is replaced (reported cancelled). Returns the new render's id.
    std::uint64_t submit(std::vector<std::string> args);
    // Cancels the running or queued render, if any; true if there was one.
    bool cancel();
    // Every render's id and status, the running one's progress line, the latest finished id.
    nlohmann::json status() const;
    // A render by id (finished or not), or the latest that finished well.
    std::shared_ptr<const ServeRender> find(std::uint64_t id) const;
    std::shared_ptr<const ServeRender> latestDone() const;
    // `tessera probe SCENE X Y ... --json` with the render's arguments: the history's JSON text,
    // or the child's error (ChildResult::exitCode != 0). Probes run one at a time.
    ChildResult probe(const ServeRender& render, std::uint32_t x, std::uint32_t y);
    // `tessera diff A B --json --heatmap FILE` of two renders' back buffers (diffs run one at a
    // time, beside the probes): the statistics' JSON text; the heat map is diffHeatmap(a, b).
    ChildResult diff(const ServeRender& a, const ServeRender& b);
    std::filesystem::path diffHeatmap(std::uint64_t a, std::uint64_t b) const;
    // Ends the running child and the worker thread (no new renders start).
    void stop();

private:
    void worker();
    // A short child of this program (probe, diff): its output files under `base` in the work
    // folder, removed after reading; the error text reduced to its lines.
    ChildResult runTool(const std::vector<std::string>& argv, const std::string& base);
    void finish(const std::shared_ptr<ServeRender>& render, const ChildResult& result);

    std::filesystem::path mExe, mWork;
    std::uint32_t mLightSteps;
    mutable std::mutex mMutex;
    std::condition_variable mWake;
    std::map<std::uint64_t, std::shared_ptr<const ServeRender>> mRenders;  // published states, by id
    std::shared_ptr<ServeRender> mPending;  // queued, not started
    std::uint64_t mRunningId = 0, mLatestDoneId = 0, mNextId = 1;
    std::atomic<bool> mCancelRunning{false};
    bool mStopping = false;
    std::mutex mProbeMutex, mDiffMutex;
    std::uint64_t mProbeCount = 0;
    std::thread mThread;
};

} // namespace tessera::cli
