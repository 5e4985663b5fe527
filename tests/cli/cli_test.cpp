// The `tessera` command as a user meets it: exit codes (0 ok, 1 render failure, 2 bad usage),
// messages that name the bad flag and value, and no partial output file after a failure.
#include <doctest/doctest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <sys/wait.h>

namespace {

struct Run {
    int exitCode;
    std::string output;  // stdout + stderr
};

Run run(const std::string& args) {
    const std::string cmd = std::string(TESSERA_CLI) + " " + args + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::string out;
    std::array<char, 4096> buf{};
    while (std::fgets(buf.data(), int(buf.size()), pipe)) out += buf.data();
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

std::filesystem::path scratch(const std::string& name) {
    const auto dir = std::filesystem::current_path() / "cli-out";
    std::filesystem::create_directories(dir);
    return dir / name;
}

} // namespace

TEST_CASE("cli: render writes the image and exits 0; --dump writes every named buffer") {
    const auto out = scratch("ok.png");
    const auto dump = scratch("dump");
    std::filesystem::remove(out);
    std::filesystem::remove_all(dump);
    const Run r = run("render --out " + out.string() + " --width 64 --height 48 --msaa 4 --quiet --dump " + dump.string());
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(r.output.empty());
    CHECK(std::filesystem::file_size(out) > 100);
    for (const char* f : {"backbuffer.png", "backbuffer.msaa.png", "depth.exr", "depth.stencil.png"})
        CHECK(std::filesystem::exists(dump / f));
}

TEST_CASE("cli: bad usage exits 2 and names the flag and value") {
    struct Case { const char* args; const char* mentions; };
    const Case cases[] = {
        {"render --width 0", "--width: '0'"},
        {"render --height 1000000000", "--height: '1000000000'"},
        {"render --width abc", "--width: 'abc'"},
        {"render --msaa 3", "--msaa: 3"},
        {"render --tile 15", "--tile: 15"},
        {"render --threads -1", "--threads: '-1'"},
        {"render --frobnicate", "unknown option '--frobnicate'"},
        {"render --out", "--out needs a value"},
        {"render --out noextension", "has no extension"},
        {"explode", "unknown command 'explode'"},
        {"", "usage: tessera"},
    };
    for (const Case& c : cases) {
        const Run r = run(c.args);
        INFO(c.args << " -> " << r.output);
        CHECK(r.exitCode == 2);
        CHECK(r.output.find(c.mentions) != std::string::npos);
    }
}

TEST_CASE("cli: a failed write exits 1, names the file and leaves nothing behind") {
    const auto dir = scratch("no-such-dir") / "deeper";
    std::filesystem::remove_all(dir.parent_path());
    const auto out = dir / "x.png";
    const Run r = run("render --out " + out.string() + " --width 16 --height 16");
    INFO(r.output);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find(out.string()) != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir));
    const Run bad = run("render --out " + scratch("image.unknownext").string() + " --width 16 --height 16");
    CHECK(bad.exitCode == 1);
    CHECK_FALSE(std::filesystem::exists(scratch("image.unknownext")));
    CHECK_FALSE(std::filesystem::exists(scratch("image.partial.unknownext")));
}

TEST_CASE("cli: --help for every subcommand exits 0") {
    for (const char* args : {"--help", "help", "render --help", "list"}) {
        const Run r = run(args);
        INFO(args);
        CHECK(r.exitCode == 0);
        CHECK(!r.output.empty());
    }
}
