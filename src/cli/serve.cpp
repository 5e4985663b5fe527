// `tessera serve [SCENE] [--port N] [--bind ADDR] [render options]`: the frame inspector as a local
// web page. An HTTP server (cpp-httplib) answers the page embedded in the binary, the renders it
// made (serve_jobs.h: each a child `tessera render --dump`), their buffers as raw texels, and a
// pixel's history (a child `tessera probe --json`). Nothing else on disk is reachable.
#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <pthread.h>
#include <unistd.h>

#include <httplib.h>

#ifndef TESSERA_NO_OIIO
#include <OpenImageIO/imageio.h>
#endif

#include <tessera/state/viewport.h>  // kMaxSurfaceDimension
#include <tessera/techniques/technique.h>

#include "commands.h"
#include "render_args.h"
#include "serve_assets.h"
#include "serve_jobs.h"

namespace tessera::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kServeUsage = R"(usage: tessera serve [SCENE] [--port N] [--bind ADDR] [render options]

Serves the frame inspector on http://127.0.0.1:N/ (printed at start): the technique's passes with
their times and buffers, a buffer viewer (zoom, pan, the hovered texel decoded), a pixel's history
on click, the deferred light steps, and re-rendering with other techniques and options.
  --port N      the TCP port (default 8470; 0: any free port)
  --bind ADDR   the address to listen on (default 127.0.0.1, this machine only); anything else
                lets other machines read the page and start renders
  --max-rate N  requests per second served, all clients together (default 200; more get 429)
  --light-steps N  the lights (from 0) whose deferred steps each render keeps (default 16; 0 none)
Every option of `tessera render` that chooses what to draw applies (technique, --option, size,
MSAA, precision, lights, camera); serve owns --out, --dump, --dump-after, --dump-lights, --probe,
--repeat and --warmup (each render runs the frame twice: the first is timed, the second dumped).
Ctrl-C stops the server and removes its renders.
)";

constexpr int kDefaultPort = 8470;
constexpr std::size_t kMaxRequestBytes = 64 * 1024;  // a render request is a few hundred bytes
constexpr std::uint32_t kDefaultRate = 200;          // requests per second, all clients together
constexpr std::uint32_t kDefaultLightSteps = 16;     // lights whose deferred steps are dumped (each: every buffer, twice)
constexpr std::size_t kThreads = 16;                  // connections served at once (a probe holds one)
constexpr time_t kKeepAliveSeconds = 2;               // an idle kept-alive connection holds a thread this long

// Requests per second, all clients together: a token bucket holding two seconds' worth (a page
// makes a few requests per click; a burst after a pause is fine, a flood is not).
class RateLimit {
public:
    explicit RateLimit(double perSecond) : mPerSecond(perSecond), mTokens(2.0 * perSecond) {}
    bool admit() {
        const std::lock_guard<std::mutex> lock(mMutex);
        const auto now = std::chrono::steady_clock::now();
        mTokens = std::min(2.0 * mPerSecond, mTokens + mPerSecond * std::chrono::duration<double>(now - mLast).count());
        mLast = now;
        if (mTokens < 1.0) return false;
        mTokens -= 1.0;
        return true;
    }
    double perSecond() const { return mPerSecond; }

private:
    std::mutex mMutex;
    double mPerSecond;
    double mTokens;
    std::chrono::steady_clock::time_point mLast = std::chrono::steady_clock::now();
};

void sendError(httplib::Response& res, int status, const std::string& message) {
    res.status = status;
    res.set_content(nlohmann::json{{"error", message}}.dump(), "application/json");
}

void sendJson(httplib::Response& res, const nlohmann::json& j) {
    res.set_content(j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), "application/json");
}

std::string contentType(const std::string& name) {
    const std::string ext = fs::path(name).extension().string();
    if (ext == ".html") return "text/html; charset=utf-8";
    if (ext == ".js") return "text/javascript; charset=utf-8";
    if (ext == ".css") return "text/css; charset=utf-8";
    if (ext == ".png") return "image/png";
    if (ext == ".json") return "application/json";
    if (ext == ".md" || ext == ".txt") return "text/plain; charset=utf-8";
    return "application/octet-stream";
}

// A decimal in [lo, hi] from a path or query part, else nullopt.
std::optional<std::uint64_t> parseId(const std::string& text, std::uint64_t hi) {
    std::uint64_t v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || v > hi) return std::nullopt;
    return v;
}

// The render a request names (/api/.../<id>/...), finished well, else an error response.
std::shared_ptr<const ServeRender> requireRender(const ServeJobs& jobs, const std::string& idText, httplib::Response& res) {
    const auto id = parseId(idText, ~std::uint64_t(0));
    const auto r = id ? jobs.find(*id) : nullptr;
    if (!r) {
        sendError(res, 404, "no render " + idText);
        return nullptr;
    }
    if (r->status != "done") {
        sendError(res, 409, "render " + idText + " is " + r->status + (r->message.empty() ? "" : ": " + r->message));
        return nullptr;
    }
    return r;
}

// A dumped file as raw little-endian texels: PNG codes as uint8, TIFF as uint32, EXR as float32.
bool sendTexels([[maybe_unused]] const fs::path& file, httplib::Response& res) {
#ifdef TESSERA_NO_OIIO
    sendError(res, 501, "this tessera was built without OpenImageIO: texels cannot be read");
    return false;
#else
    auto in = OIIO::ImageInput::open(file.string());
    if (!in) {
        sendError(res, 500, "cannot read " + file.filename().string());
        return false;
    }
    const OIIO::ImageSpec spec = in->spec();
    const std::string ext = file.extension().string();
    const OIIO::TypeDesc type = ext == ".png" ? OIIO::TypeDesc::UINT8 : ext == ".tif" ? OIIO::TypeDesc::UINT32 : OIIO::TypeDesc::FLOAT;
    std::string bytes(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels) * type.size(), '\0');
    const bool ok = in->read_image(0, 0, 0, spec.nchannels, type, bytes.data());
    in->close();
    if (!ok) {
        sendError(res, 500, "cannot decode " + file.filename().string());
        return false;
    }
    res.set_header("X-Width", std::to_string(spec.width));
    res.set_header("X-Height", std::to_string(spec.height));
    res.set_header("X-Channels", std::to_string(spec.nchannels));
    res.set_header("X-Type", ext == ".png" ? "uint8" : ext == ".tif" ? "uint32" : "float32");
    res.set_header("Cache-Control", "max-age=3600");
    res.set_content(bytes, "application/octet-stream");
    return true;
#endif
}

// A render request from the page (JSON): each key becomes the render flag of the same meaning,
// after the server's own arguments (later flags win). Throws UsageError for a bad key or value.
std::vector<std::string> requestArgs(const std::vector<std::string>& base, const nlohmann::json& body) {
    if (!body.is_object()) throw UsageError("the request is not a JSON object");
    std::vector<std::string> args = base;
    for (auto it = body.begin(); it != body.end(); ++it) {
        const std::string& key = it.key();  // not a structured binding: clang 14's lambdas cannot capture those
        const nlohmann::json& value = it.value();
        const auto flagValue = [&](const char* flag) {
            if (!value.is_string() && !value.is_number_unsigned())
                throw UsageError("'" + key + "' must be a string or a non-negative integer (got " + value.dump() + ")");
            args.emplace_back(flag);
            args.push_back(value.is_string() ? value.get<std::string>() : std::to_string(value.get<std::uint64_t>()));
        };
        if (key == "technique") flagValue("--technique");
        else if (key == "width") flagValue("--width");
        else if (key == "height") flagValue("--height");
        else if (key == "msaa") flagValue("--msaa");
        else if (key == "precision") flagValue("--precision");
        else if (key == "lights") flagValue("--lights");
        else if (key == "options") {
            if (!value.is_object()) throw UsageError("'options' must be an object of KEY: VALUE (got " + value.dump() + ")");
            for (const auto& [optionKey, optionValue] : value.items()) {
                args.emplace_back("--option");
                args.push_back(optionKey + "=" + (optionValue.is_string() ? optionValue.get<std::string>() : optionValue.dump()));
            }
        } else throw UsageError("unknown key '" + key + "' (technique, width, height, msaa, precision, lights, options)");
    }
    bool help = false;
    std::vector<std::string_view> views(args.begin(), args.end());
    std::vector<std::string> warnings;
    (void)parseRenderArgs(views, help, &warnings);
    return args;
}

nlohmann::json renderJson(const ServeRender& r) {
    nlohmann::json j{{"id", r.id}, {"status", r.status}, {"args", r.args}, {"wallMs", r.wallMs}, {"frameMs", r.frameMs},
                     {"passMs", r.passMs}, {"manifest", r.manifest}, {"files", r.files}};
    if (!r.message.empty()) j["message"] = r.message;
    if (r.defaultLight) j["defaultLight"] = *r.defaultLight;
    return j;
}

void addRoutes(httplib::Server& server, ServeJobs& jobs, const std::vector<std::string>& base) {
    server.Get("/", [](const httplib::Request&, httplib::Response& res) { res.set_redirect("/index.html"); });
    server.Get(R"(/([A-Za-z0-9_.-]+))", [](const httplib::Request& req, httplib::Response& res) {
        const std::string name = req.matches[1];
        for (const EmbeddedFile& f : serveAssets())
            if (f.name == name) {
                res.set_content(f.bytes.data(), f.bytes.size(), contentType(name));
                return;
            }
        sendError(res, 404, "no page file '" + name + "'");
    });
    server.Get("/api/status", [&jobs](const httplib::Request&, httplib::Response& res) { sendJson(res, jobs.status()); });
    server.Get("/api/techniques", [](const httplib::Request&, httplib::Response& res) { sendJson(res, tessera::techniqueRegistryJson()); });
    server.Get(R"(/api/render/([^/]+))", [&jobs](const httplib::Request& req, httplib::Response& res) {
        const auto id = parseId(req.matches[1], ~std::uint64_t(0));
        const auto r = id ? jobs.find(*id) : nullptr;
        if (!r) return sendError(res, 404, "no render " + std::string(req.matches[1]));
        sendJson(res, renderJson(*r));
    });
    server.Post("/api/render", [&jobs, &base](const httplib::Request& req, httplib::Response& res) {
        const nlohmann::json body = nlohmann::json::parse(req.body, nullptr, false);
        if (body.is_discarded()) return sendError(res, 400, "the request body is not JSON");
        try {
            const std::uint64_t id = jobs.submit(requestArgs(base, body));
            res.status = 202;
            sendJson(res, {{"id", id}});
        } catch (const UsageError& e) {
            sendError(res, 400, e.what());
        }
    });
    server.Post("/api/cancel", [&jobs](const httplib::Request&, httplib::Response& res) { sendJson(res, {{"cancelled", jobs.cancel()}}); });
    server.Get(R"(/api/files/([^/]+)/(.+))", [&jobs](const httplib::Request& req, httplib::Response& res) {
        const auto r = requireRender(jobs, req.matches[1], res);
        if (!r) return;
        const std::string file = req.matches[2];
        if (!r->files.count(file)) return sendError(res, 404, "render " + std::to_string(r->id) + " wrote no file '" + file + "'");
        res.set_header("Cache-Control", "max-age=3600");
        res.set_content(readText(r->folder / "dump" / file), contentType(file));
    });
    server.Get(R"(/api/texels/([^/]+)/(.+))", [&jobs](const httplib::Request& req, httplib::Response& res) {
        const auto r = requireRender(jobs, req.matches[1], res);
        if (!r) return;
        const std::string file = req.matches[2];
        if (!r->files.count(file)) return sendError(res, 404, "render " + std::to_string(r->id) + " wrote no file '" + file + "'");
        sendTexels(r->folder / "dump" / file, res);
    });
    // Two renders' back buffers compared: tessera diff's statistics, and its heat map beside.
    server.Get(R"(/api/diff/([^/]+)/([^/]+))", [&jobs](const httplib::Request& req, httplib::Response& res) {
        const auto a = requireRender(jobs, req.matches[1], res);
        if (!a) return;
        const auto b = requireRender(jobs, req.matches[2], res);
        if (!b) return;
        const ChildResult diff = jobs.diff(*a, *b);
        if (diff.exitCode != 0) return sendError(res, diff.exitCode == 2 ? 400 : 500, diff.err);
        nlohmann::json j = nlohmann::json::parse(diff.out, nullptr, false);
        if (j.is_discarded()) return sendError(res, 500, "tessera diff printed no JSON");
        j["heatmap"] = "/api/diffmap/" + std::to_string(a->id) + "/" + std::to_string(b->id);
        j.erase("a");  // the server's own paths
        j.erase("b");
        sendJson(res, j);
    });
    server.Get(R"(/api/diffmap/([0-9]+)/([0-9]+))", [&jobs](const httplib::Request& req, httplib::Response& res) {
        const auto a = parseId(req.matches[1], ~std::uint64_t(0)), b = parseId(req.matches[2], ~std::uint64_t(0));
        if (!a || !b || !fs::is_regular_file(jobs.diffHeatmap(*a, *b)))
            return sendError(res, 404, "no comparison of renders " + std::string(req.matches[1]) + " and " + std::string(req.matches[2]) +
                                           " (GET /api/diff/A/B first)");
        res.set_content(readText(jobs.diffHeatmap(*a, *b)), "image/png");
    });
    server.Get(R"(/api/probe/([^/]+))", [&jobs](const httplib::Request& req, httplib::Response& res) {
        const auto r = requireRender(jobs, req.matches[1], res);
        if (!r) return;
        const auto x = parseId(req.get_param_value("x"), kMaxSurfaceDimension - 1);
        const auto y = parseId(req.get_param_value("y"), kMaxSurfaceDimension - 1);
        if (!x || !y) return sendError(res, 400, "probe needs x and y, window pixels (got x='" + req.get_param_value("x") +
                                                     "', y='" + req.get_param_value("y") + "')");
        const ChildResult probe = jobs.probe(*r, std::uint32_t(*x), std::uint32_t(*y));
        if (probe.exitCode != 0) return sendError(res, probe.exitCode == 2 ? 400 : 500, probe.err);
        res.set_content(probe.out, "application/json");
    });
}

} // namespace

int serveCommand(const std::vector<std::string_view>& args) {
    int port = kDefaultPort;
    std::uint32_t maxRate = kDefaultRate;
    std::uint32_t lightSteps = kDefaultLightSteps;
    std::string bindAddress = "127.0.0.1";
    // The scene first (as `tessera probe` takes it), then render's flags, forwarded as typed.
    std::vector<std::string> base{"default"};
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string_view a = args[i];
        const std::string_view name = a.substr(0, a.rfind("--", 0) == 0 ? a.find('=') : std::string_view::npos);
        const auto value = [&]() -> std::string_view {
            if (name.size() < a.size()) return a.substr(name.size() + 1);
            if (i + 1 >= args.size()) throw UsageError(std::string(name) + " needs a value");
            return args[++i];
        };
        if (a == "--help" || a == "-h") {
            std::fputs(kServeUsage, stdout);
            return 0;
        }
        if (name == "--port") port = int(parseUint("--port", value(), 0, 65535));
        else if (name == "--max-rate") maxRate = parseUint("--max-rate", value(), 1, 1000000);
        else if (name == "--light-steps") lightSteps = parseUint("--light-steps", value(), 0, 1000000);
        else if (name == "--bind") bindAddress = std::string(value());
        else if (name == "--out" || name == "-o" || name == "--dump" || name == "--dump-after" || name == "--dump-lights" ||
                 name == "--probe" || name == "--json" || name == "--no-output" || name == "--stats" || name == "--progress" ||
                 name == "--repeat" || name == "--warmup")
            throw UsageError(std::string(name) + ": serve chooses this itself (every render is dumped whole)");
        else if (i == 0 && !a.empty() && a[0] != '-') base[0] = std::string(a);
        else base.emplace_back(a);
    }
    {  // every render flag checked before anything starts
        bool help = false;
        std::vector<std::string_view> views(base.begin(), base.end());
        (void)parseRenderArgs(views, help, nullptr);
    }

    char exe[4096] = {};
    const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0) throw std::runtime_error("serve: cannot find this program's path (/proc/self/exe)");
    std::string workTemplate = (fs::temp_directory_path() / "tessera-serve-XXXXXX").string();
    if (!mkdtemp(workTemplate.data())) throw std::runtime_error("serve: cannot create a folder in " + fs::temp_directory_path().string());

    // Ctrl-C and SIGTERM are taken by one thread (sigwait), which stops the server: the other
    // threads, render children included, start with them blocked (children reset their mask).
    sigset_t stopSignals;
    sigemptyset(&stopSignals);
    sigaddset(&stopSignals, SIGINT);
    sigaddset(&stopSignals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stopSignals, nullptr);
    std::signal(SIGPIPE, SIG_IGN);

    ServeJobs jobs(fs::path(std::string(exe, std::size_t(n))), fs::path(workTemplate), lightSteps);
    // The first render before the URL: a scene that cannot render is said now, with its exit code.
    std::fprintf(stderr, "tessera serve: rendering %s\n", base[0].c_str());
    const std::uint64_t first = jobs.submit(base);
    for (;;) {
        const auto r = jobs.find(first);
        if (r->status == "done") break;
        if (r->status == "failed" || r->status == "cancelled") {
            std::fprintf(stderr, "%s\n", r->message.c_str());
            return 2;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }

    httplib::Server server;
    server.set_payload_max_length(kMaxRequestBytes);
    server.set_read_timeout(10, 0);
    server.set_keep_alive_timeout(kKeepAliveSeconds);
    server.new_task_queue = [] { return new httplib::ThreadPool(kThreads); };
    RateLimit rate(maxRate);
    server.set_pre_routing_handler([&rate](const httplib::Request&, httplib::Response& res) {
        if (rate.admit()) return httplib::Server::HandlerResponse::Unhandled;
        sendError(res, 429, "too many requests: at most " + std::to_string(int(rate.perSecond())) + " per second (--max-rate)");
        return httplib::Server::HandlerResponse::Handled;
    });
    server.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
        std::string what = "internal error";
        try {
            std::rethrow_exception(ep);
        } catch (const std::exception& e) {
            what = e.what();
        } catch (...) {
        }
        sendError(res, 500, what);
    });
    addRoutes(server, jobs, base);
    const int bound = port == 0 ? server.bind_to_any_port(bindAddress) : (server.bind_to_port(bindAddress, port) ? port : -1);
    if (bound < 0) throw UsageError("--port " + std::to_string(port) + ": cannot listen on " + bindAddress + ":" + std::to_string(port) +
                                    " (in use, or not this machine's address)");
    if (bindAddress != "127.0.0.1" && bindAddress != "localhost" && bindAddress != "::1")
        std::fprintf(stderr, "tessera serve: warning: listening on %s: other machines can read the page and start renders\n",
                     bindAddress.c_str());
    std::printf("tessera serve: http://%s:%d/ (Ctrl-C stops)\n", bindAddress.c_str(), bound);
    std::fflush(stdout);

    std::atomic<bool> signalled{false};
    std::thread signalThread([&] {
        int sig = 0;
        sigwait(&stopSignals, &sig);
        signalled = true;
        server.stop();
    });
    server.listen_after_bind();
    if (!signalled) pthread_kill(signalThread.native_handle(), SIGTERM);  // wakes its sigwait
    signalThread.join();
    jobs.stop();
    std::fprintf(stderr, "tessera serve: stopped\n");
    return 0;
}

} // namespace tessera::cli
