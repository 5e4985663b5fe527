// The `tessera` command's files: a full disk (RLIMIT_FSIZE in a forked child) exits 1 and keeps
// the previous image, concurrent renders to one --out never collide, the same command writes the
// same bytes, --stats prints each file's FNV-1a 64 hash, and hostile input exits 2, never crashes.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::cli_cli_output_test {

namespace fs = std::filesystem;

namespace {

struct Run {
    int exitCode;        // -1 when the process did not exit normally (a crash)
    std::string output;  // stdout + stderr
};

FILE* start(const std::string& args) {
    std::string cmd = TESSERA_CLI;  // += rather than a + chain: GCC 12's -Warray-bounds misfires on the chain (unity batch)
    cmd += ' ';
    cmd += args;
    cmd += " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    REQUIRE(pipe != nullptr);
    return pipe;
}

Run finish(FILE* pipe) {
    std::string out;
    std::array<char, 4096> buf{};
    while (std::fgets(buf.data(), int(buf.size()), pipe)) out += buf.data();
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

Run run(const std::string& args) { return finish(start(args)); }

// Runs the command in a forked child whose RLIMIT_FSIZE is `bytes`, with SIGXFSZ ignored: a
// write past the limit then fails with EFBIG, as a write to a full disk fails with ENOSPC.
Run runWithFileSizeLimit(const std::vector<std::string>& args, rlim_t bytes) {
    std::vector<std::string> words = {TESSERA_CLI};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    int fds[2];
    REQUIRE(pipe(fds) == 0);
    const pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        dup2(fds[1], 1);
        dup2(fds[1], 2);
        close(fds[0]);
        close(fds[1]);
        std::signal(SIGXFSZ, SIG_IGN);  // kept across exec
        const rlimit limit{bytes, bytes};
        if (setrlimit(RLIMIT_FSIZE, &limit) != 0) _exit(125);
        execv(argv[0], argv.data());
        _exit(127);
    }
    close(fds[1]);
    std::string out;
    std::array<char, 4096> buf{};
    for (ssize_t n; (n = read(fds[0], buf.data(), buf.size())) != 0;) {
        if (n < 0) {
            if (errno == EINTR) continue;
            break;
        }
        out.append(buf.data(), std::size_t(n));
    }
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

fs::path scratch(const std::string& name) {
    const fs::path dir = fs::path(TESSERA_TEST_OUTPUT_DIR) / "cli-output" / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string readText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void writeText(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    REQUIRE(out.good());
}

int partialFiles(const fs::path& dir) {
    int count = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir)) count += e.path().filename().string().find(".partial") != std::string::npos;
    return count;
}

// Every file under `dir` by its relative path, with its bytes.
std::map<std::string, std::string> directoryContents(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = readText(e.path());
    return files;
}

// 64-bit FNV-1a (Fowler, Noll, Vo): offset basis 0xcbf29ce484222325, prime 0x100000001b3.
std::string fnv1a64Hex(const std::string& bytes) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (const char c : bytes) {
        h ^= static_cast<unsigned char>(c);
        h *= 0x100000001b3ull;
    }
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
    return text;
}

// The "hash     <hex>  <file>" lines of --stats, as file -> hex.
std::map<std::string, std::string> printedHashes(const std::string& output) {
    std::map<std::string, std::string> hashes;
    std::istringstream lines(output);
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("hash     ", 0) != 0) continue;
        const std::string hex = line.substr(9, 16);
        REQUIRE(line.substr(25, 2) == "  ");
        hashes[line.substr(27)] = hex;
    }
    return hashes;
}

const std::string kBox = std::string(TESSERA_SOURCE_DIR) + "/scenes/khronos/Box/glTF/Box.gltf";

} // namespace

TEST_CASE("cli: a full disk exits 1, names the file and leaves the previous image byte for byte") {
    const fs::path dir = scratch("full-disk");
    const fs::path out = dir / "x.png";
    REQUIRE(run("render builtin --out " + out.string() + " --width 64 --height 48 --quiet").exitCode == 0);
    const std::string before = readText(out);
    constexpr rlim_t kLimitBytes = 256;  // bytes; below either image
    REQUIRE(before.size() > kLimitBytes);
    const Run r = runWithFileSizeLimit({"render", "builtin", "--out", out.string(), "--width", "96", "--height", "64"}, kLimitBytes);
    INFO(r.output);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find(out.string()) != std::string::npos);
    CHECK(r.output.find("File too large") != std::string::npos);
    CHECK(r.output.find("wrote") == std::string::npos);
    CHECK(readText(out) == before);
    CHECK(partialFiles(dir) == 0);
}

TEST_CASE("cli: concurrent renders to one --out all exit 0 and leave one complete image of one of them") {
    const fs::path dir = scratch("concurrent");
    const int widths[] = {480, 481, 482, 483, 484, 485};  // px; large enough that the writes overlap
    std::vector<std::string> expected;
    for (const int w : widths) {
        const fs::path alone = dir / ("alone" + std::to_string(w) + ".png");
        REQUIRE(run("render builtin --quiet --width " + std::to_string(w) + " --height 320 --out " + alone.string()).exitCode == 0);
        expected.push_back(readText(alone));
    }
    const fs::path shared = dir / "shared.png";
    constexpr int kRounds = 2;  // repetitions, to give the race a chance
    for (int round = 0; round < kRounds; ++round) {
        std::vector<FILE*> pipes;
        for (const int w : widths)
            pipes.push_back(start("render builtin --quiet --width " + std::to_string(w) + " --height 320 --out " + shared.string()));
        for (FILE* p : pipes) {
            const Run r = finish(p);
            INFO(r.output);
            CHECK(r.exitCode == 0);
        }
        CHECK(std::find(expected.begin(), expected.end(), readText(shared)) != expected.end());
        CHECK(partialFiles(dir) == 0);
    }
}

TEST_CASE("cli: --out naming an existing directory is refused before rendering with the real cause, not 'Success'") {
    // (The write path's own refusal, "cannot rename into place", is tests/io's atomic_file_test.)
    const fs::path dir = scratch("rename");
    const fs::path out = dir / "taken.png";
    fs::create_directories(out / "inside");
    const Run r = run("render builtin --width 16 --height 16 --out " + out.string());
    INFO(r.output);
    CHECK(r.exitCode == 2);
    CHECK(r.output.find("--out: '" + out.string() + "' is a folder") != std::string::npos);
    CHECK(r.output.find("Success") == std::string::npos);
    CHECK(partialFiles(dir) == 0);
}

TEST_CASE("cli: output paths that cannot take a file are refused with exit 2 before the scene loads (render, report)") {
    // /proc takes no new file even for root, whose access(W_OK) says yes to it. The scene named
    // does not exist: a message about the path (not the scene) shows the check ran first.
    const fs::path dir = scratch("refused");
    fs::create_directories(dir);
    const fs::path file = dir / "plain.txt";
    writeText(file, "x");
    struct Case { std::string args, mentions; };
    const Case cases[] = {
        {"render no-such-scene.json --out /proc/x.png", "--out: '/proc/x.png': cannot create a file in '/proc'"},
        {"render no-such-scene.json --out " + (dir / "missing" / "x.png").string(), "the folder '" + (dir / "missing").string() + "' does not exist"},
        {"render no-such-scene.json --out " + (dir / "x.png").string() + " --dump /proc/dump", "--dump: '/proc/dump': cannot create anything in '/proc'"},
        {"render no-such-scene.json --out " + (dir / "x.png").string() + " --dump " + file.string(), "--dump: '" + file.string() + "' exists and is not a folder"},
        {"report no-such-scene.json --out /proc/rep", "--out: '/proc/rep': cannot create anything in '/proc'"},
        {"report no-such-scene.json --out /proc/a/b", "--out: '/proc/a/b': cannot create anything in '/proc'"},
        {"report no-such-scene.json --out " + file.string(), "--out: '" + file.string() + "' exists and is not a folder"},
    };
    for (const Case& c : cases) {
        const Run r = run(c.args);
        INFO(c.args << " -> " << r.output);
        CHECK(r.exitCode == 2);
        CHECK(r.output.find(c.mentions) != std::string::npos);
        CHECK(r.output.find("no-such-scene") == std::string::npos);
        CHECK(r.output.find("filesystem error") == std::string::npos);
    }
    // Nothing left behind: the probe file the check creates is removed, and nothing was written.
    CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator()) == 1);
}

TEST_CASE("cli: the same render --dump twice, a second apart, writes byte-identical files (PNG, EXR, TIFF)") {
    const fs::path dir = scratch("reproducible");
    const std::string builtin = "render builtin --quiet --width 48 --height 32 --msaa 4";
    const std::string tiled = "render default --quiet --technique forward-plus --width 64 --height 36";
    for (const char* run1 : {"1", "2"}) {
        const fs::path d = dir / run1;
        fs::create_directories(d);
        REQUIRE(run(builtin + " --out " + (d / "builtin.exr").string() + " --dump " + (d / "builtin").string()).exitCode == 0);
        REQUIRE(run(tiled + " --out " + (d / "tiled.png").string() + " --dump " + (d / "tiled").string()).exitCode == 0);
        std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // past the next second of any timestamp
    }
    const auto first = directoryContents(dir / "1"), second = directoryContents(dir / "2");
    std::size_t tifs = 0, exrs = 0;
    for (const auto& entry : first) {
        const std::string& name = entry.first;
        const std::string& bytes = entry.second;
        CAPTURE(name);
        tifs += fs::path(name).extension() == ".tif";
        exrs += fs::path(name).extension() == ".exr";
        REQUIRE(second.count(name) == 1);
        if (fs::path(name).filename() == "manifest.json") {  // equal but for the paths on the command line
            nlohmann::json a = nlohmann::json::parse(bytes), b = nlohmann::json::parse(second.at(name));
            for (nlohmann::json* m : {&a, &b}) {
                CHECK(m->erase("command") == 1);
                CHECK(m->erase("image") == 1);
            }
            CHECK(a == b);
            continue;
        }
        CHECK(second.at(name) == bytes);
    }
    CHECK(first.size() == second.size());
    CHECK(tifs > 0);
    CHECK(exrs > 0);
}

TEST_CASE("cli: --stats prints the FNV-1a 64 hash of every written file, equal to the file's and stable across runs") {
    const fs::path dir = scratch("stats");
    const fs::path out = dir / "x.png", dump = dir / "dump";
    const std::string args = "render builtin --width 40 --height 24 --msaa 2 --stats --out " + out.string() + " --dump " + dump.string();
    const Run r = run(args);
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    const auto hashes = printedHashes(r.output);
    std::size_t dumped = 0;
    for (const auto& e : fs::recursive_directory_iterator(dump)) dumped += e.is_regular_file();  // views and manifest too
    CHECK(hashes.size() == 1 + dumped);
    REQUIRE(hashes.count(out.string()) == 1);
    for (const auto& entry : hashes) {
        const std::string& file = entry.first;
        CAPTURE(file);
        CHECK(entry.second == fnv1a64Hex(readText(file)));
    }
    const Run again = run(args);
    CHECK(printedHashes(again.output) == hashes);
}

TEST_CASE("cli: info refuses a scene file's unknown technique with exit 2, naming the file, /technique and the id") {
    const fs::path dir = scratch("info");
    const fs::path file = dir / "unknown-technique.json";
    writeText(file, R"({"models": [{"path": ")" + kBox + R"("}], "technique": "raytrace"})");
    const Run r = run("info " + file.string());
    INFO(r.output);
    CHECK(r.exitCode == 2);
    CHECK(r.output.find(file.string() + ": /technique: unknown technique 'raytrace'") != std::string::npos);
}

TEST_CASE("cli: deeply nested scene and glTF files and duplicate keys exit 2 instead of crashing or guessing") {
    const fs::path dir = scratch("hostile");
    constexpr std::size_t kSceneLevels = 1000000;  // nested arrays in "options"
    const fs::path deepScene = dir / "deep-options.json";
    writeText(deepScene, R"({"models": [{"path": ")" + kBox + R"("}], "technique": "preview", "options": {"x": )" +
                             std::string(kSceneLevels, '[') + std::string(kSceneLevels, ']') + "}}");
    constexpr std::size_t kGltfLevels = 15000;  // nested arrays in "extras"
    const fs::path deepGltf = dir / "deep-extras.gltf";
    writeText(deepGltf, R"({"asset": {"version": "2.0"}, "extras": )" + std::string(kGltfLevels, '[') +
                            std::string(kGltfLevels, ']') + "}");
    const fs::path duplicate = dir / "duplicate.json";
    writeText(duplicate, R"({"models": [{"path": ")" + kBox + R"("}], "technique": "preview", "technique": "forward"})");
    const fs::path out = dir / "x.png";
    struct Case { fs::path file; std::string mentions; };
    const Case cases[] = {{deepScene, "nested deeper than 256 levels"},
                          {deepGltf, "nested deeper than 256 levels"},
                          {duplicate, "/technique: duplicate key \"technique\""}};
    for (const Case& c : cases)
        for (const std::string command : {"render", "info"}) {
            const Run r = run(command + " " + c.file.string() + (command == "render" ? " --out " + out.string() : std::string()));
            INFO(command << " " << c.file.string() << " -> " << r.output.substr(0, 400));
            CHECK(r.exitCode == 2);
            CHECK(r.output.find(c.file.string() + ": ") != std::string::npos);
            CHECK(r.output.find(c.mentions) != std::string::npos);
        }
    CHECK_FALSE(fs::exists(out));
}

TEST_CASE("cli: --dump writes manifest.json (passes in order, every buffer with format, decode rule and file), viewable pictures, and --dump-after snapshots") {
    const fs::path dir = scratch("manifest");
    fs::remove_all(dir);
    const Run r = run("render builtin --quiet --width 48 --height 32 --stats --dump " + dir.string() + " --dump-after clear --out " +
                      (dir.parent_path() / "manifest.png").string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    std::ifstream in(dir / "manifest.json");
    REQUIRE(in);
    const nlohmann::json m = nlohmann::json::parse(in);
    CHECK(m["scene"] == "builtin");
    CHECK(m["command"].get<std::string>().find("render builtin") != std::string::npos);
    // Passes in the order --stats prints them.
    std::size_t at = 0;
    for (const auto& p : m["passes"]) {
        const std::size_t found = r.output.find("pass " + p["name"].get<std::string>(), at);
        CHECK_MESSAGE(found != std::string::npos, p["name"]);
        at = found;
    }
    int views = 0;
    for (const auto& b : m["buffers"]) {
        CAPTURE(b.dump());
        CHECK(fs::exists(dir / b["file"].get<std::string>()));
        CHECK(!b["decode"].get<std::string>().empty());
        if (b.contains("stencilFile")) CHECK(fs::exists(dir / b["stencilFile"].get<std::string>()));
        if (b.contains("views"))
            for (const auto& v : b["views"]) {
                CHECK(fs::exists(dir / v["file"].get<std::string>()));
                ++views;
            }
    }
    CHECK(views >= 2);  // depth and stencil at least
    REQUIRE(m["after"].contains("clear"));
    for (const auto& b : m["after"]["clear"]["buffers"]) CHECK(fs::exists(dir / "after-clear" / b["file"].get<std::string>()));
    const Run bad = run("render builtin --width 16 --height 16 --dump " + dir.string() + " --dump-after nosuchpass --out " +
                        (dir.parent_path() / "manifest.png").string());
    CHECK(bad.exitCode == 2);
    CHECK(bad.output.find("no pass 'nosuchpass' (its passes: ") != std::string::npos);
    CHECK(run("render builtin --dump-after clear").exitCode == 2);
}

TEST_CASE("cli: --dump-lights writes deferred's buffers after each step of the chosen lights, and refuses what cannot work") {
    const fs::path dir = scratch("lights");
    fs::remove_all(dir);
    const std::string out = " --out " + (dir.parent_path() / "lights.png").string();
    const Run r = run("render default --technique deferred --width 64 --height 36 --quiet --dump " + dir.string() +
                      " --dump-lights 3,0" + out);
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    // Light 3 is a point light (unmark + shade), light 0 the directional one (shade only).
    for (const char* folder : {"light-3-unmark", "light-3-shade", "light-0-shade"}) {
        CAPTURE(folder);
        CHECK(fs::exists(dir / folder / "depth.stencil.png"));
        CHECK(fs::exists(dir / folder / "view" / "depth.stencil.png"));
    }
    CHECK_FALSE(fs::exists(dir / "light-0-unmark"));
    CHECK_FALSE(fs::exists(dir / "light-1-shade"));
    std::ifstream in(dir / "manifest.json");
    const nlohmann::json m = nlohmann::json::parse(in);
    CHECK(m["lightSteps"]["3"]["unmark"]["folder"] == "light-3-unmark");
    // A range keeps the lights of it the scene has (4: 0..3); `all`, every light; a technique
    // without light steps takes either without complaint and dumps none (tessera serve asks so).
    const auto stepsOf = [&](const std::string& technique, const std::string& lights) {
        const fs::path d = scratch("lights-range");
        fs::remove_all(d);
        const Run rr = run("render default --technique " + technique + " --width 32 --height 18 --quiet --dump " + d.string() +
                           " --dump-lights " + lights + out);
        INFO(rr.output);
        REQUIRE(rr.exitCode == 0);
        std::ifstream f(d / "manifest.json");
        const nlohmann::json manifest = nlohmann::json::parse(f);
        std::vector<std::string> keys;
        if (manifest.contains("lightSteps"))
            for (const auto& [key, value] : manifest["lightSteps"].items()) keys.push_back(key);
        return keys;
    };
    CHECK(stepsOf("deferred", "2-9") == std::vector<std::string>{"2", "3"});
    CHECK(stepsOf("deferred", "all") == std::vector<std::string>{"0", "1", "2", "3"});
    CHECK(stepsOf("forward", "all").empty());
    struct Case { std::string args, mentions; };
    const Case cases[] = {
        {"render default --technique deferred --dump " + dir.string() + " --dump-lights 99" + out, "light 99 does not exist"},
        {"render default --technique forward --dump " + dir.string() + " --dump-lights 0" + out, "does not shade light by light"},
        {"render default --technique deferred --dump-lights 0" + out, "--dump-lights needs --dump DIR"},
        {"render default --technique deferred --dump " + dir.string() + " --dump-lights 1,x" + out, "--dump-lights: 'x'"},
        {"render default --technique deferred --dump " + dir.string() + " --dump-lights 3-1" + out, "'3-1' is an empty range"},
    };
    for (const Case& c : cases) {
        const Run e = run(c.args);
        INFO(c.args << " -> " << e.output);
        CHECK(e.exitCode == 2);
        CHECK(e.output.find(c.mentions) != std::string::npos);
    }
}

} // namespace tessera_test::cli_cli_output_test
