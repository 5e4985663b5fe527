// `tessera serve`'s renders as child processes (serve_jobs.h): spawning and cancelling them, the
// worker that runs one at a time, and what a finished render publishes (manifest, pass times,
// the files it may serve, the deferred light whose stencil shows the trick).
#include "serve_jobs.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>
#include <system_error>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#ifndef TESSERA_NO_OIIO
#include <OpenImageIO/imageio.h>
#endif

extern char** environ;

namespace tessera::cli {

namespace fs = std::filesystem;

std::string readText(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

namespace {

// The child's error lines ("tessera: ..."), without the progress bar's carriage-return frames.
std::string errorLines(const std::string& err) {
    std::string lines;
    std::istringstream in(err);
    for (std::string line; std::getline(in, line);) {
        if (const std::size_t cr = line.rfind('\r'); cr != std::string::npos) line = line.substr(cr + 1);
        if (line.rfind("\033[K", 0) == 0) line = line.substr(3);
        if (!line.empty()) lines += (lines.empty() ? "" : "\n") + line;
    }
    return lines;
}

// The last progress frame the child drew on stderr ("\r\033[Klabel [###   ] 3/10").
std::string lastProgress(const fs::path& errFile) {
    std::ifstream in(errFile, std::ios::binary | std::ios::ate);
    if (!in) return "";
    constexpr std::streamoff kTail = 512;  // bytes: longer than one progress frame
    const std::streamoff size = in.tellg();
    in.seekg(std::max<std::streamoff>(0, size - kTail));
    std::string tail(std::size_t(size - in.tellg()), '\0');
    in.read(tail.data(), std::streamsize(tail.size()));
    const std::size_t cr = tail.rfind("\r\033[K");
    if (cr == std::string::npos) return "";
    std::string frame = tail.substr(cr + 4);
    if (const std::size_t nl = frame.find('\n'); nl != std::string::npos) frame.resize(nl);
    return frame;
}

// "pass <name> <median> ms  (<min>..<max>)" and "frame ..." lines of --stats over the two runs
// (pass names may hold spaces): the minimum, the run that wrote no dumps.
void parseTimes(const std::string& out, ServeRender& r) {
    static const std::regex passLine(R"(^pass (.+?) +([0-9.]+) ms(?: +\(([0-9.]+)\.\.)?)"),
        frameLine(R"(^frame +([0-9.]+) ms(?: +\(([0-9.]+)\.\.)?)");
    std::istringstream in(out);
    std::smatch m;
    for (std::string line; std::getline(in, line);) {
        if (std::regex_search(line, m, passLine)) r.passMs[m[1].str()] = std::stod(m[m[3].matched ? 3 : 2].str());
        else if (std::regex_search(line, m, frameLine)) r.frameMs = std::stod(m[m[2].matched ? 2 : 1].str());
    }
}

// The number of pixels of a stencil picture (8-bit codes) that differ from its most common value:
// 0 when the whole stencil holds one value (a light volume around the eye marks everything).
std::uint64_t stencilContrast([[maybe_unused]] const fs::path& png) {
#ifdef TESSERA_NO_OIIO
    return 0;
#else
    auto in = OIIO::ImageInput::open(png.string());
    if (!in) return 0;
    const OIIO::ImageSpec spec = in->spec();
    std::vector<unsigned char> codes(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
    const bool ok = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, codes.data());
    in->close();
    if (!ok) return 0;
    std::uint64_t histogram[256] = {};
    for (std::size_t i = 0; i < codes.size(); i += std::size_t(spec.nchannels)) ++histogram[codes[i]];
    return codes.size() / std::size_t(spec.nchannels) - *std::max_element(std::begin(histogram), std::end(histogram));
#endif
}

// Among the lights whose steps the render dumped, the one whose stencil (after the step that
// decides which pixels it shades: Killzone's "count", else "unmark") varies the most.
std::optional<std::uint32_t> pickDefaultLight(const ServeRender& r) {
    if (!r.manifest.contains("lightSteps")) return std::nullopt;
    std::optional<std::uint32_t> best;
    std::uint64_t bestContrast = 0;
    for (const auto& [light, steps] : r.manifest["lightSteps"].items()) {
        const char* step = steps.contains("count") ? "count" : "unmark";
        if (!steps.contains(step)) continue;
        const std::string folder = steps[step].value("folder", "");
        for (const auto& b : steps[step]["buffers"])
            if (b.contains("stencilFile")) {
                const std::uint64_t contrast = stencilContrast(r.folder / "dump" / folder / b["stencilFile"].get<std::string>());
                const auto index = std::uint32_t(std::stoul(light));
                if (!best || contrast > bestContrast || (contrast == bestContrast && index < *best)) {
                    best = index;
                    bestContrast = contrast;
                }
            }
    }
    return best;
}

nlohmann::json summary(const ServeRender& r) {
    nlohmann::json j{{"id", r.id}, {"status", r.status}, {"args", r.args}};
    if (!r.message.empty()) j["message"] = r.message;
    if (r.status == "done") {
        j["wallMs"] = r.wallMs;
        j["frameMs"] = r.frameMs;
    }
    return j;
}

} // namespace

ChildResult runChild(const fs::path& exe, const std::vector<std::string>& argv, const fs::path& outFile, const fs::path& errFile,
                     const std::atomic<bool>* cancel) {
    ChildResult result;
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, outFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, errFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<std::string> all{exe.string()};
    all.insert(all.end(), argv.begin(), argv.end());
    std::vector<char*> cargv;
    for (std::string& a : all) cargv.push_back(a.data());
    cargv.push_back(nullptr);
    // The server blocks SIGINT and SIGTERM (one thread takes them) and ignores SIGPIPE: the child
    // starts with no signal blocked and every default action, so cancelling and Ctrl-C end it.
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    sigset_t none, defaults;
    sigemptyset(&none);
    sigemptyset(&defaults);
    for (const int sig : {SIGINT, SIGTERM, SIGPIPE}) sigaddset(&defaults, sig);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setsigdefault(&attr, &defaults);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, exe.c_str(), &actions, &attr, cargv.data(), environ);
    posix_spawnattr_destroy(&attr);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) {
        result.err = "cannot start " + exe.string() + ": " + std::strerror(spawned);
        return result;
    }
    using namespace std::chrono_literals;
    std::optional<std::chrono::steady_clock::time_point> termSent;
    int status = 0;
    for (;;) {
        const pid_t done = waitpid(pid, &status, WNOHANG);
        if (done == pid) break;
        if (done < 0 && errno != EINTR) break;
        if (cancel && cancel->load() && !termSent) {
            kill(pid, SIGTERM);
            termSent = std::chrono::steady_clock::now();
            result.cancelled = true;
        }
        if (termSent && std::chrono::steady_clock::now() - *termSent > 2s) kill(pid, SIGKILL);
        std::this_thread::sleep_for(10ms);
    }
    if (WIFEXITED(status)) result.exitCode = WEXITSTATUS(status);
    result.out = readText(outFile);
    result.err = readText(errFile);
    return result;
}

ServeJobs::ServeJobs(fs::path exe, fs::path work, std::uint32_t lightSteps) : mExe(std::move(exe)), mWork(std::move(work)), mLightSteps(lightSteps) {
    mThread = std::thread([this] { worker(); });
}

ServeJobs::~ServeJobs() {
    stop();
    std::error_code ec;
    fs::remove_all(mWork, ec);
}

void ServeJobs::stop() {
    {
        const std::lock_guard<std::mutex> lock(mMutex);
        mStopping = true;
        mCancelRunning = true;
    }
    mWake.notify_all();
    if (mThread.joinable()) mThread.join();
}

std::uint64_t ServeJobs::submit(std::vector<std::string> args) {
    std::uint64_t id = 0;
    {
        const std::lock_guard<std::mutex> lock(mMutex);
        if (mPending) {  // replaced before it started
            auto dropped = std::make_shared<ServeRender>(*mPending);
            dropped->status = "cancelled";
            mRenders[dropped->id] = dropped;
        }
        auto r = std::make_shared<ServeRender>();
        r->id = id = mNextId++;
        r->status = "queued";
        r->args = std::move(args);
        r->folder = mWork / ("render-" + std::to_string(r->id));
        mRenders[r->id] = std::make_shared<ServeRender>(*r);
        mPending = std::move(r);
        if (mRunningId != 0) mCancelRunning = true;
    }
    mWake.notify_all();
    return id;
}

bool ServeJobs::cancel() {
    const std::lock_guard<std::mutex> lock(mMutex);
    bool any = false;
    if (mPending) {
        auto dropped = std::make_shared<ServeRender>(*mPending);
        dropped->status = "cancelled";
        mRenders[dropped->id] = dropped;
        mPending.reset();
        any = true;
    }
    if (mRunningId != 0) {
        mCancelRunning = true;
        any = true;
    }
    return any;
}

void ServeJobs::worker() {
    for (;;) {
        std::shared_ptr<ServeRender> r;
        {
            std::unique_lock<std::mutex> lock(mMutex);
            mWake.wait(lock, [this] { return mStopping || mPending; });
            if (mStopping) return;
            r = std::move(mPending);
            mPending.reset();
            r->status = "running";
            mRunningId = r->id;
            mCancelRunning = false;
            mRenders[r->id] = std::make_shared<ServeRender>(*r);
        }
        std::error_code ec;
        fs::create_directories(r->folder, ec);
        // Every buffer after every pass, the first lights' steps (techniques without them: none),
        // the pass times (--stats) of two runs, of which only the second writes the dumps (the
        // page shows the first's), and a progress bar to read (--progress).
        std::vector<std::string> argv{"render"};
        argv.insert(argv.end(), r->args.begin(), r->args.end());
        for (const std::string& a : {std::string("--dump"), (r->folder / "dump").string(), std::string("--out"), (r->folder / "image.png").string(),
                                     std::string("--dump-after"), std::string("all"), std::string("--stats"), std::string("--progress"),
                                     std::string("--warmup"), std::string("0"), std::string("--repeat"), std::string("2")})
            argv.push_back(a);
        if (mLightSteps > 0) {
            argv.emplace_back("--dump-lights");
            argv.push_back("0-" + std::to_string(mLightSteps - 1));
        }
        const auto t0 = std::chrono::steady_clock::now();
        const ChildResult result = runChild(mExe, argv, r->folder / "stdout.txt", r->folder / "stderr.txt", &mCancelRunning);
        r->wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        finish(r, result);
    }
}

void ServeJobs::finish(const std::shared_ptr<ServeRender>& r, const ChildResult& result) {
    std::error_code ec;
    if (result.cancelled) {
        r->status = "cancelled";
    } else if (result.exitCode != 0) {
        r->status = "failed";
        r->message = errorLines(result.err);
        if (r->message.empty()) r->message = "the render ended with exit code " + std::to_string(result.exitCode);
    } else {
        r->status = "done";
        parseTimes(result.out, *r);
        try {
            r->manifest = nlohmann::json::parse(readText(r->folder / "dump" / "manifest.json"));
        } catch (const nlohmann::json::exception& e) {
            r->status = "failed";
            r->message = std::string("the render's manifest did not parse: ") + e.what();
        }
        const fs::path dump = r->folder / "dump";
        for (auto it = fs::recursive_directory_iterator(dump, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
            if (it->is_regular_file(ec)) r->files.insert(fs::relative(it->path(), dump, ec).generic_string());
        r->defaultLight = pickDefaultLight(*r);
    }
    const std::lock_guard<std::mutex> lock(mMutex);
    mRenders[r->id] = r;
    mRunningId = 0;
    if (r->status == "done") {
        // Keep the newest two good renders' folders (a page may still be reading the previous one).
        if (mLatestDoneId != 0) {
            for (auto& [id, old] : mRenders)
                if (id < mLatestDoneId && old->status == "done") {
                    fs::remove_all(old->folder, ec);
                    auto gone = std::make_shared<ServeRender>(*old);
                    gone->status = "removed";
                    gone->files.clear();
                    old = gone;
                }
        }
        mLatestDoneId = r->id;
    } else {
        fs::remove_all(r->folder, ec);
    }
}

nlohmann::json ServeJobs::status() const {
    const std::lock_guard<std::mutex> lock(mMutex);
    nlohmann::json renders = nlohmann::json::array();
    for (const auto& [id, r] : mRenders) renders.push_back(summary(*r));
    nlohmann::json j{{"renders", renders}, {"latestDone", mLatestDoneId}, {"running", mRunningId}};
    if (mRunningId != 0) j["progress"] = lastProgress(mWork / ("render-" + std::to_string(mRunningId)) / "stderr.txt");
    return j;
}

std::shared_ptr<const ServeRender> ServeJobs::find(std::uint64_t id) const {
    const std::lock_guard<std::mutex> lock(mMutex);
    const auto it = mRenders.find(id);
    return it == mRenders.end() ? nullptr : it->second;
}

std::shared_ptr<const ServeRender> ServeJobs::latestDone() const {
    const std::lock_guard<std::mutex> lock(mMutex);
    const auto it = mRenders.find(mLatestDoneId);
    return it == mRenders.end() ? nullptr : it->second;
}

ChildResult ServeJobs::runTool(const std::vector<std::string>& argv, const std::string& base) {
    const fs::path out = mWork / (base + ".out"), err = mWork / (base + ".err");
    ChildResult result = runChild(mExe, argv, out, err, nullptr);
    std::error_code ec;
    fs::remove(out, ec);
    fs::remove(err, ec);
    result.err = errorLines(result.err);
    return result;
}

ChildResult ServeJobs::probe(const ServeRender& render, std::uint32_t x, std::uint32_t y) {
    const std::lock_guard<std::mutex> lock(mProbeMutex);
    std::vector<std::string> argv{"probe", render.args.at(0), std::to_string(x), std::to_string(y)};
    argv.insert(argv.end(), render.args.begin() + 1, render.args.end());
    argv.emplace_back("--json");
    return runTool(argv, "probe-" + std::to_string(++mProbeCount));
}

fs::path ServeJobs::diffHeatmap(std::uint64_t a, std::uint64_t b) const {
    return mWork / ("diff-" + std::to_string(a) + "-" + std::to_string(b) + ".png");
}

ChildResult ServeJobs::diff(const ServeRender& a, const ServeRender& b) {
    const std::lock_guard<std::mutex> lock(mDiffMutex);
    return runTool({"diff", (a.folder / "dump" / "backbuffer.png").string(), (b.folder / "dump" / "backbuffer.png").string(), "--json",
                    "--heatmap", diffHeatmap(a.id, b.id).string()},
                   "diff");
}

} // namespace tessera::cli
