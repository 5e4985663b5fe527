// The `tessera` command as a user meets it: exit codes (0 ok, 1 render failure, 2 bad usage),
// messages that name the bad flag and value, and no partial output file after a failure.
#include <doctest/doctest.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/wait.h>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::cli_cli_test {

namespace {

struct Run {
    int exitCode;
    std::string output;  // stdout + stderr
};

Run run(const std::string& args) {
    std::string cmd = TESSERA_CLI;  // += rather than a + chain: GCC 12's -Warray-bounds misfires on the chain
    cmd += ' ';
    cmd += args;
    cmd += " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::string out;
    std::array<char, 4096> buf{};
    while (std::fgets(buf.data(), int(buf.size()), pipe)) out += buf.data();
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

std::filesystem::path scratch(const std::string& name) {
    const auto dir = std::filesystem::path(TESSERA_TEST_OUTPUT_DIR) / "cli-out";
    std::filesystem::create_directories(dir);
    return dir / name;
}

} // namespace

TEST_CASE("cli: render writes the image and exits 0, --dump writes every named buffer") {
    const auto out = scratch("ok.png");
    const auto dump = scratch("dump");
    std::filesystem::remove(out);
    std::filesystem::remove_all(dump);
    const Run r = run("render builtin --out " + out.string() + " --width 64 --height 48 --msaa 4 --quiet --dump " + dump.string());
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(r.output.empty());
    CHECK(std::filesystem::file_size(out) > 100);
    for (const char* f : {"backbuffer.png", "backbuffer.msaa.png", "depth.exr", "depth.stencil.png"})
        CHECK(std::filesystem::exists(dump / f));
}

TEST_CASE("cli: bytes that are not UTF-8 in a path reach the manifest as U+FFFD, and in --option they are bad usage") {
    const auto out = scratch("latin1-\xE9.png");
    const auto dump = scratch("latin1-dump");
    std::filesystem::remove_all(dump);
    const Run r = run("render builtin --width 16 --height 16 --quiet --out '" + out.string() + "' --dump " + dump.string());
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(std::filesystem::exists(out));
    const nlohmann::json manifest = nlohmann::json::parse(std::ifstream(dump / "manifest.json"));
    CHECK(manifest["image"].get<std::string>().find("latin1-\xEF\xBF\xBD.png") != std::string::npos);
    std::filesystem::remove(out);

    const Run option = run("render default --option \"$(printf 'tileSize=\\351')\"");  // 0xE9, through /bin/sh's printf
    CHECK(option.exitCode == 2);
    CHECK(option.output.find("--option: the argument is not valid UTF-8") != std::string::npos);
}

TEST_CASE("cli: --msaa renders a scene file through a deferred technique, dumps the multisampled buffers and counts edge pixels") {
    const auto out = scratch("msaa.png");
    const auto dump = scratch("msaa-dump");
    std::filesystem::remove(out);
    std::filesystem::remove_all(dump);
    const Run r = run("render --technique deferred-classic --width 64 --height 40 --msaa 4 --stats --out " + out.string() +
                      " --dump " + dump.string());
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(r.output.find("edges    ") != std::string::npos);
    CHECK(r.output.find("per sample") != std::string::npos);
    CHECK(std::filesystem::file_size(out) > 100);
    for (const char* f : {"backbuffer.png", "backbuffer.msaa.png", "edges.exr", "msaa.surface.exr", "gbuffer.normal.exr"})
        CHECK(std::filesystem::exists(dump / f));
    const Run bad = run("render --technique deferred-classic --msaa 4 --option msaaEdges=sobel --width 8 --height 8 --no-output");
    CHECK(bad.exitCode == 2);
    CHECK(bad.output.find("msaaEdges") != std::string::npos);
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
        {"render --width=0", "--width: '0'"},                          // GNU --flag=value: the same checks
        {"render --stats=yes", "--stats takes no value (got 'yes')"},  // a switch given a value
        {"report --width=abc --out x", "--width: 'abc'"},
        {"diff --threshold", "--threshold needs a value"},
        {"render --out noextension", "must end in .png or .exr"},
        {"render --out x.jpg", "must end in .png or .exr"},
        {"render --exr quarter", "--exr: 'quarter'"},
        {"render --precision sloppy", "--precision: 'sloppy'"},
        {"render --lights 1000001", "--lights: '1000001'"},
        {"render a.json b.json", "one scene only"},
        {"list extra", "list takes no arguments"},
        {"info", "info needs a SCENE"},
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

TEST_CASE("cli: an output that cannot be written is refused before rendering, names the path and leaves nothing behind") {
    const auto dir = scratch("no-such-dir") / "deeper";
    std::filesystem::remove_all(dir.parent_path());
    const auto out = dir / "x.png";
    // The Sponza scene would take seconds to load: the refusal comes before any loading.
    const Run r = run("render sponza-small-lights --out " + out.string());
    INFO(r.output);
    CHECK(r.exitCode == 2);
    CHECK(r.output.find("--out") != std::string::npos);
    CHECK(r.output.find(dir.string()) != std::string::npos);
    CHECK(r.output.find("loading") == std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir));
    // --dump onto an existing file.
    const auto file = scratch("a-file");
    { std::FILE* f = std::fopen(file.string().c_str(), "w"); REQUIRE(f); std::fclose(f); }
    const Run d = run("render builtin --out " + scratch("d.png").string() + " --dump " + file.string());
    CHECK(d.exitCode == 2);
    CHECK(d.output.find("--dump") != std::string::npos);
    CHECK(d.output.find("not a folder") != std::string::npos);
}

TEST_CASE("cli: --version, help COMMAND, info builtin, and warnings for flags a scene ignores") {
    const Run v = run("--version");
    CHECK(v.exitCode == 0);
    CHECK(v.output.rfind("tessera 0.", 0) == 0);
    const Run h = run("help render");
    CHECK(h.exitCode == 0);
    CHECK(h.output.find("usage: tessera render") != std::string::npos);
    CHECK(h.output.find("--option KEY=VALUE") != std::string::npos);
    const Run i = run("info builtin");
    INFO(i.output);
    CHECK(i.exitCode == 0);
    CHECK(i.output.find("builtin (generated, no files)") != std::string::npos);
    const Run w = run("render builtin --lights 5 --technique forward --exr half --width 16 --height 16 --out " +
                      scratch("w.png").string());
    INFO(w.output);
    CHECK(w.exitCode == 0);
    for (const char* flag : {"warning: --lights", "warning: --technique", "warning: --exr"})
        CHECK_MESSAGE(w.output.find(flag) != std::string::npos, flag);
}

TEST_CASE("cli: options lists every technique's options, and render --option is checked against the technique before loading") {
    const Run all = run("options");
    INFO(all.output);
    CHECK(all.exitCode == 0);
    for (const char* line : {"forward-plus\n", "  coneTest          demo | corrected", "ERRATA.md #10", "tileListCapacity",
                             "integer in 1..4294967294 | unbounded", "preview: no options", "light-prepass", "specPowerUnpack", "scissorRound"})
        CHECK_MESSAGE(all.output.find(line) != std::string::npos, line);
    const Run one = run("options deferred");
    CHECK(one.exitCode == 0);
    CHECK(one.output.find("lightVolumes") != std::string::npos);
    CHECK(one.output.find("coneTest") == std::string::npos);
    CHECK(run("options raytrace").exitCode == 2);

    struct Case { const char* args; const char* mentions; };
    const Case cases[] = {
        {"render sponza-small-lights --technique forward-plus --option coneTest=maybe",
         "--option coneTest=\"maybe\": \"maybe\" is not one of demo | corrected (technique forward-plus)"},
        {"render sponza-small-lights --technique forward --option coneTest=corrected", "forward has no option 'coneTest'"},
        {"render sponza-small-lights --technique forward-plus --option tileSize=12", "12 is not one of 16 | 8 | 32"},
        {"render sponza-small-lights --option noequals", "is not KEY=VALUE"},
        {"render builtin --option projection=d3d", "the builtin scene has no technique options"},
    };
    for (const Case& c : cases) {
        const Run r = run(c.args);
        INFO(c.args << " -> " << r.output);
        CHECK(r.exitCode == 2);
        CHECK(r.output.find(c.mentions) != std::string::npos);
        CHECK(r.output.find("loading") == std::string::npos);
    }
    // A valid option reaches the technique: deferred's centre reconstruction moves P by half a
    // pixel (ERRATA #3) and changes the lit image; the faithful value given explicitly does not.
    const auto a = scratch("opt-a.png"), b = scratch("opt-b.png"), c = scratch("opt-c.png");
    const std::string deferred = "render default --technique deferred --width 64 --height 36 --quiet";
    REQUIRE(run(deferred + " --out " + a.string()).exitCode == 0);
    REQUIRE(run(deferred + " --option reconstruct=\"centre\" --out " + b.string()).exitCode == 0);
    REQUIRE(run(deferred + " --option reconstruct=corner --out " + c.string()).exitCode == 0);
    CHECK(run("diff " + a.string() + " " + c.string()).output.find("differing  0 of") != std::string::npos);
    const Run diff = run("diff " + a.string() + " " + b.string());
    INFO(diff.output);
    CHECK(diff.output.find("differing  0 of") == std::string::npos);
}

TEST_CASE("cli: --help for every subcommand exits 0") {
    for (const char* args : {"--help", "help", "render --help", "list --help", "info --help", "list"}) {
        const Run r = run(args);
        INFO(args);
        CHECK(r.exitCode == 0);
        CHECK(!r.output.empty());
    }
}

TEST_CASE("cli: list names every technique with its state and the bundled scenes") {
    const Run r = run("list");
    CHECK(r.exitCode == 0);
    for (const char* id : {"preview ", "forward ", "deferred ", "forward-plus ", "deferred-classic ", "light-prepass ", "ready", "default ", "sponza-large-lights",
                           "sponza-small-lights", "builtin"})
        CHECK_MESSAGE(r.output.find(id) != std::string::npos, id);
    // Each scene's line says what sets it apart (size, technique, lights), and its description's
    // first sentence is not cut at an abbreviation ("GPU Pro 4 ch. 5's ...").
    const auto lineOf = [&r](const std::string& scene) {
        const std::size_t at = r.output.find("\n  " + scene + " ");
        return at == std::string::npos ? std::string() : r.output.substr(at + 1, r.output.find('\n', at + 1) - at - 1);
    };
    CHECK(lineOf("sponza-large-lights").find("1280x720, forward, 64 generated lights of range 35..40: Crytek Sponza") != std::string::npos);
    CHECK(lineOf("sponza-small-lights").find("64 generated lights of range 1..2: Crytek Sponza") != std::string::npos);
    CHECK(lineOf("sponza-sun").find("forward-plus-amd, 1 light, 64 generated lights") != std::string::npos);
    CHECK(lineOf("sponza-sun").find("GPU Pro 4 ch. 5's two Forward+ extensions") != std::string::npos);
    CHECK(lineOf("default").find("640x360, forward, 4 lights: The default scene") != std::string::npos);
    for (const char* scene : {"default", "sponza-large-lights", "sponza-small-lights", "sponza-sun"})
        CHECK_MESSAGE(lineOf(scene).size() < 2 + 22 + 1 + 80 + 2 + 160 + 4, scene);  // name, facts, summary cut at a word
}

TEST_CASE("cli: bad scene input exits 2, names the file and key, and writes nothing") {
    const auto dir = scratch("bad-scenes");
    std::filesystem::create_directories(dir);
    struct Case { const char* name; const char* json; const char* mentions; };
    // Every file names a valid model, so each error below is the one the case is about.
    const std::string box = std::string(TESSERA_SOURCE_DIR) + "/scenes/khronos/Box/glTF/Box.gltf";
    const std::string model = R"({"models": [{"path": ")" + box + R"("}], "technique": "preview", )";
    const Case cases[] = {
        {"wrongtype.json", R"("resolution": ["640", 360]})", "/resolution/0"},
        {"zero.json", R"("resolution": [0, 360]})", "/resolution/0"},
        {"huge.json", R"("resolution": [1000000000, 360]})", "/resolution/0"},
        {"range.json", R"("lights": [{"type": "point", "position": [0,0,0], "range": -1}]})", "/lights/0/range"},
        {"nan.json", R"("lights": [{"type": "point", "position": [0,1e39,0], "range": 1}]})", "/lights/0/position/1"},
        {"overflow.json", R"("lights": [{"type": "point", "position": [0,1e999,0], "range": 1}]})", "number overflow"},
        {"count.json", R"("generate": [{"count": 2000000, "seed": 1}]})", "/generate/0/count"},
        {"unknownkey.json", R"("resolutoin": [8, 8]})", "/resolutoin"},
        {"syntax.json", R"("resolution": [)", "invalid JSON"},
    };
    for (const Case& c : cases) {
        const auto file = dir / c.name;
        {
            FILE* f = std::fopen(file.string().c_str(), "w");
            REQUIRE(f != nullptr);
            std::fputs((model + c.json).c_str(), f);
            std::fclose(f);
        }
        const auto out = dir / (std::string(c.name) + ".png");
        std::filesystem::remove(out);
        const Run r = run("render " + file.string() + " --out " + out.string());
        INFO(c.name << " -> " << r.output);
        CHECK(r.exitCode == 2);
        CHECK(r.output.find(c.name) != std::string::npos);
        CHECK(r.output.find(c.mentions) != std::string::npos);
        CHECK_FALSE(std::filesystem::exists(out));
    }
    {
        std::FILE* f = std::fopen((dir / "missing-model.json").string().c_str(), "w");
        REQUIRE(f != nullptr);
        std::fputs(R"({"models": [{"path": "nope.gltf"}], "technique": "preview"})", f);
        std::fclose(f);
        const Run r = run("render " + (dir / "missing-model.json").string() + " --out " + (dir / "x.png").string());
        CHECK(r.exitCode == 2);
        CHECK(r.output.find("/models/0/path") != std::string::npos);
        const Run t = run("render " + (dir / "missing-model.json").string() + " --technique raytrace --out " + (dir / "x.png").string());
        CHECK(t.exitCode == 2);
        CHECK(t.output.find("unknown technique 'raytrace'") != std::string::npos);
    }
    const Run missing = run("render no-such-scene --out " + (dir / "x.png").string());
    CHECK(missing.exitCode == 2);
    CHECK(missing.output.find("no-such-scene: no such file") != std::string::npos);
    std::filesystem::remove(dir / "x.png");  // a previous run's, if any
    const Run badOption = run("render default --technique light-prepass --option lightGeometry=cones --out " + (dir / "x.png").string());
    CHECK(badOption.exitCode == 2);
    CHECK(badOption.output.find("lightGeometry") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir / "x.png"));
}

TEST_CASE("cli: the default scene renders with no arguments beyond render, and info describes it") {
    const auto out = scratch("default.png");
    std::filesystem::remove(out);
    const Run r = run("render --out " + out.string() + " --width 160 --height 90 --stats");
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(std::filesystem::file_size(out) > 1000);
    for (const char* line : {"load ", "textures ", "pass opaque", "pass transparent", "frame ", "triangles in"})
        CHECK_MESSAGE(r.output.find(line) != std::string::npos, line);
    const auto exr = scratch("default.exr");
    CHECK(run("render default --out " + exr.string() + " --exr half --width 32 --height 18 --quiet").exitCode == 0);
    CHECK(std::filesystem::exists(exr));

    const Run i = run("info default");
    INFO(i.output);
    CHECK(i.exitCode == 0);
    for (const char* line : {"triangles ", "materials ", "lights ", "bounds ", "memory "})
        CHECK_MESSAGE(i.output.find(line) != std::string::npos, line);
}

TEST_CASE("cli: a glTF file renders directly with the preview technique and a framing camera") {
    const auto out = scratch("box.png");
    std::filesystem::remove(out);
    const std::string box = std::string(TESSERA_SOURCE_DIR) + "/scenes/khronos/BoxTextured/glTF/BoxTextured.gltf";
    const Run r = run("render " + box + " --out " + out.string() + " --width 64 --height 64 --quiet");
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(std::filesystem::exists(out));
    const Run bad = run("render " + std::string(TESSERA_SOURCE_DIR) + "/README.md --out " + out.string());
    CHECK(bad.exitCode == 2);
    CHECK(bad.output.find("not a scene file") != std::string::npos);
}

TEST_CASE("cli: camera flags on a glTF give the bytes of a scene file with that camera, and bad values exit 2") {
    const std::string box = std::string(TESSERA_SOURCE_DIR) + "/scenes/khronos/BoxTextured/glTF/BoxTextured.gltf";
    const auto scene = scratch("camera-flags.json");
    {
        std::ofstream f(scene);
        f << R"({"models": [{"path": ")" << box
          << R"("}], "camera": {"position": [2, 1.5, 3], "target": [0, 0, 0], "fovYDeg": 30}, "resolution": [64, 36], "technique": "preview"})";
    }
    const auto bytesOf = [](const std::filesystem::path& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    const auto fromFile = scratch("camera-file.png"), fromFlags = scratch("camera-flags.png"), framing = scratch("camera-framing.png"),
               positionOnly = scratch("camera-position.png");
    REQUIRE(run("render " + scene.string() + " -o " + fromFile.string() + " --quiet").exitCode == 0);
    const std::string size = " --width 64 --height 36 --quiet";
    REQUIRE(run("render " + box + size + " --camera-position 2,1.5,3 --camera-target 0,0,0 --fov 30 -o " + fromFlags.string()).exitCode == 0);
    REQUIRE(run("render " + box + size + " -o " + framing.string()).exitCode == 0);
    // BoxTextured's bounds are centred on the origin: a position alone looks at (0, 0, 0) too.
    REQUIRE(run("render " + box + size + " --camera-position=2,1.5,3 --fov=30 -o " + positionOnly.string()).exitCode == 0);
    CHECK(!bytesOf(fromFile).empty());
    CHECK(bytesOf(fromFlags) == bytesOf(fromFile));
    CHECK(bytesOf(positionOnly) == bytesOf(fromFile));
    CHECK(bytesOf(framing) != bytesOf(fromFile));  // the flags did move the camera
    struct Case { std::string args, mentions; };
    const Case cases[] = {
        {"--camera-position 1,2", "--camera-position: '1,2' is not X,Y,Z"},
        {"--camera-target 1,x,3", "--camera-target: '1,x,3' is not X,Y,Z"},
        {"--camera-position 1,2,3 --camera-target 1,2,3", "--camera-target: the target equals the position"},
        {"--camera-position 0,5,0", "--camera-position: \"up\" is parallel to the view direction"},
        {"--fov 180", "--fov: '180' is not a vertical field of view"},
        {"--fov 0", "--fov: '0' is not a vertical field of view"},
        {"--orbit 10", "--orbit: '10' is not AZIMUTH,ELEVATION"},
        {"--orbit 0,90", "--orbit: '0,90' is not AZIMUTH,ELEVATION"},
        {"--orbit 0,0 --camera-position 1,2,3", "--orbit places the camera itself"},
    };
    // --orbit 0,0: on +Z from the bounds' centre (BoxTextured: the unit cube about the origin) at
    // 1.1 x the bounding radius / sin(fov / 2), the same float operations as render.cpp's:
    // radius = |(1, 1, 1)| / 2 = sqrt(3) / 2, fov 30: 1.1 * 0.8660254 / sin(15 deg) = 3.6807...
    const float radius = std::sqrt(3.0f) * 0.5f;
    const float distance = 1.1f * radius / std::sin(glm::radians(30.0f) * 0.5f);
    char position[64];
    std::snprintf(position, sizeof position, "0,0,%.9g", double(distance));
    const auto orbit = scratch("camera-orbit.png"), orbitAsFlags = scratch("camera-orbit-flags.png");
    REQUIRE(run("render " + box + size + " --orbit 0,0 --fov 30 -o " + orbit.string()).exitCode == 0);
    REQUIRE(run("render " + box + size + " --camera-position " + position + " --camera-target 0,0,0 --fov 30 -o " + orbitAsFlags.string()).exitCode == 0);
    CHECK(bytesOf(orbit) == bytesOf(orbitAsFlags));
    CHECK(bytesOf(orbit) != bytesOf(fromFile));
    for (const Case& c : cases) {
        const Run e = run("render " + box + size + " --no-output " + c.args);
        INFO(c.args << " -> " << e.output);
        CHECK(e.exitCode == 2);
        CHECK(e.output.find(c.mentions) != std::string::npos);
    }
}

TEST_CASE("cli: --precision reaches every technique and the builtin scene") {
    const auto dump = scratch("precision-dump");
    std::filesystem::remove_all(dump);
    // reference writes the float copy beside the back buffer; fast and exact do not.
    Run r = run("render builtin --precision reference --width 48 --height 32 --quiet --out " + scratch("ref.png").string() +
                " --dump " + dump.string());
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(std::filesystem::exists(dump / "backbuffer.reference.exr"));
    for (const char* technique : {"forward", "forward-plus", "deferred", "deferred-killzone"}) {
        r = run(std::string("render default --technique ") + technique + " --precision fast --width 32 --height 18 --quiet --out " +
                scratch("fast.png").string());
        INFO(technique << ": " << r.output);
        CHECK(r.exitCode == 0);
    }
    r = run("render default --technique tiled-deferred --precision reference --width 32 --height 18 --quiet --out " +
            scratch("tiled.png").string());
    CHECK(r.exitCode == 0);
}

TEST_CASE("cli: diff reports zero against itself, nonzero against another render, and refuses mismatched images") {
    const auto a = scratch("diff-a.png"), b = scratch("diff-b.png"), small = scratch("diff-small.png");
    const auto dump = scratch("diff-dump");
    std::filesystem::remove_all(dump);
    REQUIRE(run("render builtin --width 48 --height 32 --quiet --out " + a.string() + " --dump " + dump.string()).exitCode == 0);
    REQUIRE(run("render builtin --width 48 --height 32 --msaa 4 --quiet --out " + b.string()).exitCode == 0);
    REQUIRE(run("render builtin --width 24 --height 16 --quiet --out " + small.string()).exitCode == 0);

    Run r = run("diff " + a.string() + " " + a.string());
    INFO(r.output);
    CHECK(r.exitCode == 0);
    for (const char* line : {"max abs    0\n", "rmse       0\n", "psnr       inf", "differing  0 of 1536 pixels", "8-bit code units"})
        CHECK_MESSAGE(r.output.find(line) != std::string::npos, line);
    r = run("diff --json " + a.string() + " " + a.string());
    CHECK(r.exitCode == 0);
    CHECK(r.output.find("\"max_abs\":0.0") != std::string::npos);
    CHECK(r.output.find("\"psnr_db\":null") != std::string::npos);
    CHECK(r.output.find("\"differing_pixels\":0") != std::string::npos);

    // 4x MSAA smooths the edges of the same scene: some pixels differ, by a finite PSNR.
    r = run("diff --json " + a.string() + " " + b.string());
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(r.output.find("\"max_abs\":0.0") == std::string::npos);
    CHECK(r.output.find("\"differing_pixels\":0,") == std::string::npos);
    CHECK(r.output.find("\"psnr_db\":null") == std::string::npos);

    // Sizes, then channel counts (RGBA against the one-channel depth EXR): exit 2 naming both files.
    r = run("diff " + a.string() + " " + small.string());
    CHECK(r.exitCode == 2);
    CHECK(r.output.find(a.string()) != std::string::npos);
    CHECK(r.output.find(small.string()) != std::string::npos);
    CHECK(r.output.find("sizes differ") != std::string::npos);
    r = run("diff " + a.string() + " " + (dump / "depth.exr").string());
    CHECK(r.exitCode == 2);
    CHECK(r.output.find("channel counts differ") != std::string::npos);
    CHECK(r.output.find((dump / "depth.exr").string()) != std::string::npos);
    CHECK(run("diff " + a.string()).exitCode == 2);
    CHECK(run("diff " + a.string() + " " + scratch("diff-missing.png").string()).exitCode == 2);
}

TEST_CASE("cli: render --repeat N prints medians over N runs and the peak memory, and writes the same image") {
    const auto once = scratch("repeat-1.png"), thrice = scratch("repeat-3.png");
    Run r = run("render builtin --width 40 --height 24 --stats --quiet --out " + once.string());
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(r.output.find("repeat ") == std::string::npos);
    CHECK(r.output.find("peak memory  ") != std::string::npos);
    r = run("render builtin --width 40 --height 24 --stats --quiet --repeat 3 --warmup 1 --out " + thrice.string());
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(r.output.find("repeat   3 timed runs after 1 warm-up runs") != std::string::npos);
    CHECK(r.output.find("frame    ") != std::string::npos);
    CHECK(r.output.find("peak memory  ") != std::string::npos);
    CHECK(run("diff --json " + once.string() + " " + thrice.string()).output.find("\"differing_pixels\":0,") != std::string::npos);
    r = run("render builtin --repeat 0");
    CHECK(r.exitCode == 2);
    CHECK(r.output.find("--repeat: '0'") != std::string::npos);
}

TEST_CASE("cli: --draw-by-draw writes the same bytes as binned passes, and --stats counts the binned draws") {
    // forward-plus bins its depth pre-pass, opaque and transparent passes (raster/draw_batch.h).
    const auto binned = scratch("binned.png"), byDraw = scratch("by-draw.png");
    Run r = run("render default --technique forward-plus --width 160 --height 90 --threads 2 --stats --quiet --out " + binned.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(r.output.find("binned   0 draws") == std::string::npos);
    CHECK(r.output.find("binned   ") != std::string::npos);
    r = run("render default --technique forward-plus --width 160 --height 90 --threads 2 --stats --quiet --draw-by-draw --out " +
            byDraw.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(r.output.find("binned   0 draws in 0 runs") != std::string::npos);
    CHECK(run("diff --json " + binned.string() + " " + byDraw.string()).output.find("\"differing_pixels\":0,") != std::string::npos);
    // One thread draws draw by draw unless --binned asks for the shared lists; the bytes stay.
    const auto oneThread = scratch("one-thread.png"), oneBinned = scratch("one-thread-binned.png");
    r = run("render default --technique forward-plus --width 160 --height 90 --threads 1 --stats --quiet --out " + oneThread.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(r.output.find("binned   0 draws in 0 runs") != std::string::npos);
    r = run("render default --technique forward-plus --width 160 --height 90 --threads 1 --binned --stats --quiet --out " +
            oneBinned.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(r.output.find("binned   0 draws") == std::string::npos);
    CHECK(run("diff --json " + binned.string() + " " + oneThread.string()).output.find("\"differing_pixels\":0,") != std::string::npos);
    CHECK(run("diff --json " + binned.string() + " " + oneBinned.string()).output.find("\"differing_pixels\":0,") != std::string::npos);
    // Without --dump or --probe, forward-plus skips its heatmap pass (inspection only): same bytes.
    CHECK(r.output.find("pass heatmap") == std::string::npos);
    CHECK(r.output.find("skipped inspection-only passes: heatmap") != std::string::npos);
    CHECK(r.output.find("buffers  ") != std::string::npos);
    const auto dumped = scratch("dumped");
    r = run("render default --technique forward-plus --width 160 --height 90 --threads 2 --stats --quiet --dump " + dumped.string() +
            " --out " + scratch("dumped.png").string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(r.output.find("pass heatmap") != std::string::npos);
    CHECK(r.output.find("1 for inspection") != std::string::npos);
    CHECK(run("diff --json " + binned.string() + " " + scratch("dumped.png").string()).output.find("\"differing_pixels\":0,") !=
          std::string::npos);
    r = run("render builtin --binned --draw-by-draw");
    CHECK(r.exitCode == 2);
    CHECK(r.output.find("--draw-by-draw and --binned: choose one") != std::string::npos);
}

TEST_CASE("cli: --scalar-raster writes the same bytes as the SIMD blocks, --stats counts the blocks, --no-output writes nothing") {
    const auto simd = scratch("simd.png"), scalar = scratch("scalar.png"), none = scratch("none.png");
    Run r = run("render default --width 160 --height 90 --stats --quiet --out " + simd.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    // The default scene has triangles large enough for whole 8x8 blocks.
    CHECK(r.output.find("simd     0 blocks") == std::string::npos);
    CHECK(r.output.find("simd     ") != std::string::npos);
    r = run("render default --width 160 --height 90 --stats --quiet --scalar-raster --out " + scalar.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(r.output.find("simd     0 blocks") != std::string::npos);
    CHECK(run("diff --json " + simd.string() + " " + scalar.string()).output.find("\"differing_pixels\":0,") != std::string::npos);
    std::filesystem::remove(none);
    std::filesystem::remove("tessera.png");
    r = run("render builtin --width 40 --height 24 --no-output --stats");
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(r.output.find("nothing written (--no-output)") != std::string::npos);
    CHECK(r.output.find("hash ") == std::string::npos);
    CHECK(!std::filesystem::exists("tessera.png"));
    r = run("render builtin --no-output --out " + none.string());
    CHECK(r.exitCode == 2);
    CHECK(r.output.find("--no-output and --out") != std::string::npos);
    CHECK(!std::filesystem::exists(none));
}

TEST_CASE("cli: diff prints mean abs, the float32 ULP distance of float files, and writes a heat map of the difference") {
    const auto dir = scratch("diffulp");
    std::filesystem::remove_all(dir);
    const auto out = scratch("diffulp.exr");
    REQUIRE(run("render builtin --precision reference --width 64 --height 36 --quiet --dump " + dir.string() + " --out " +
                out.string()).exitCode == 0);
    const auto reference = dir / "backbuffer.reference.exr";
    // --precision reference --out writes the reference itself; exact's image comes from a render without it.
    const Run same = run("diff " + out.string() + " " + reference.string() + " --json");
    CHECK(nlohmann::json::parse(same.output)["max_ulp"] == 0);
    const auto exact = scratch("diffulp-exact.exr");
    REQUIRE(run("render builtin --width 64 --height 36 --quiet --out " + exact.string()).exitCode == 0);
    const auto heat = scratch("diffulp-heat.png");
    std::filesystem::remove(heat);
    const Run r = run("diff " + exact.string() + " " + reference.string() + " --ignore-alpha --json --heatmap " + heat.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    const nlohmann::json j = nlohmann::json::parse(r.output);
    // The exact back buffer is the shading rounded to 8-bit codes (<= 0.5 code from the float it
    // rounds), computed in float where the reference is double: the two stay within one code, and
    // no channel keeps the same float32 bits (a code / 255 is rarely the reference's value).
    CHECK(j["max_abs"].get<double>() > 0.0);
    CHECK(j["max_abs"].get<double>() < 1.0);
    CHECK(j["mean_abs"].get<double>() > 0.0);
    CHECK(j["mean_abs"].get<double>() <= j["max_abs"].get<double>());
    CHECK(j["max_ulp"].get<std::uint64_t>() > 0);
    CHECK(std::filesystem::file_size(heat) > 0);
    const Run self = run("diff " + reference.string() + " " + reference.string() + " --json");
    const nlohmann::json s = nlohmann::json::parse(self.output);
    CHECK(s["max_ulp"] == 0);
    CHECK(s["mean_abs"] == 0.0);
    // 8-bit files have no ULP figure.
    const Run png = run("diff " + (dir / "backbuffer.png").string() + " " + (dir / "backbuffer.png").string() + " --json");
    CHECK(nlohmann::json::parse(png.output)["max_ulp"].is_null());
    CHECK(run("diff a.png b.png --heatmap x.jpg").exitCode == 2);
}

TEST_CASE("cli: a glTF file without lights gets the default rig under a lighting technique, announced, and --no-default-lights keeps it dark") {
    const std::string gltf = std::string(TESSERA_SOURCE_DIR) + "/scenes/khronos/BoxTextured/glTF/BoxTextured.gltf";
    const auto lit = scratch("rig-lit.png"), dark = scratch("rig-dark.png");
    const Run a = run("render " + gltf + " --technique forward --width 64 --height 36 --out " + lit.string());
    INFO(a.output);
    REQUIRE(a.exitCode == 0);
    CHECK(a.output.find("has no lights; shading with the default rig") != std::string::npos);
    const Run b = run("render " + gltf + " --technique forward --width 64 --height 36 --no-default-lights --out " + dark.string());
    REQUIRE(b.exitCode == 0);
    CHECK(b.output.find("default rig") == std::string::npos);
    const nlohmann::json d = nlohmann::json::parse(run("diff " + lit.string() + " " + dark.string() + " --json").output);
    CHECK(d["differing_pixels"].get<std::uint64_t>() > 100);  // the box is lit, not ambient-only
    // The preview technique has its own head light: no rig, no note.
    CHECK(run("render " + gltf + " --width 32 --height 18 --out " + scratch("rig-preview.png").string()).output.find("default rig") ==
          std::string::npos);
}

TEST_CASE("cli: probe prints a pixel's history through the passes, the tile and its lights for tiled techniques, and --json") {
    const Run r = run("probe default 80 50 --technique forward-plus --width 160 --height 90 --json");  // on the wall
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    const nlohmann::json j = nlohmann::json::parse(r.output);
    CHECK(j["pixel"] == nlohmann::json::array({80, 50}));
    CHECK(j["events"].size() > 2);
    CHECK(j["events"][0]["pass"] == "clear");
    CHECK(j["final"].contains("backbuffer"));
    CHECK(j["tile"]["tile"] == nlohmann::json::array({80 / 16, 50 / 16}));
    CHECK(j["tile"]["lights"].size() == j["tile"]["listCount"].get<std::size_t>());
    CHECK(j["tile"].contains("frustumPlanes"));
    // Draw-level events: the last draw that wrote colour leaves the final back buffer's value.
    const nlohmann::json* lastColour = nullptr;
    int draws = 0;
    for (const auto& e : j["events"])
        if (e.contains("draw")) {
            ++draws;
            CHECK(e.contains("primitive"));
            CHECK(e.contains("depthStencil"));
            if (e.contains("color") && e["passed"].get<std::uint32_t>() != 0) lastColour = &e;
        }
    CHECK(draws > 0);
    REQUIRE(lastColour != nullptr);
    CHECK((*lastColour)["color"]["after"] == j["final"]["backbuffer"]);
    // The shading draw's inputs (SV_Position first, the varyings by name) and each listed light's term.
    REQUIRE((*lastColour).contains("inputs"));
    CHECK((*lastColour)["inputs"][0]["name"] == "SV_Position");
    CHECK((*lastColour)["inputs"][0]["value"][0] == 80.5);
    CHECK((*lastColour)["inputs"][0]["value"][1] == 50.5);
    CHECK((*lastColour)["inputs"][2]["name"] == "posView");
    REQUIRE((*lastColour).contains("lights"));
    CHECK((*lastColour)["lights"].size() == j["tile"]["listCount"].get<std::size_t>());  // one term per listed light
    for (const auto& l : (*lastColour)["lights"]) CHECK((l.contains("diffuse") || l.contains("none")));
    CHECK(j["tile"].contains("culled"));
    const Run text = run("probe default 10 10 --technique deferred --width 64 --height 36");
    INFO(text.output);
    CHECK(text.exitCode == 0);
    CHECK(text.output.find("pixel (10, 10)") != std::string::npos);
    CHECK(text.output.find("gbuffer: depth") != std::string::npos);
    CHECK(text.output.find("in  SV_Position [10.5,10.5,") != std::string::npos);
    CHECK(text.output.find("      light 0 'sun': ") != std::string::npos);  // by index and the scene's name
    CHECK(text.output.find("shade: draw") != std::string::npos);
    // Text rounds to 6 significant digits (--json keeps every digit): no decimal number with 7 or
    // more significant digits (0.17033250629901886 was printed as is; integers such as D24 codes
    // are exact and stay whole).
    std::size_t mostDigits = 0;
    std::string widest;
    for (std::size_t i = 0; i < text.output.size();) {
        const auto isNumberChar = [&](std::size_t k) {
            return std::isdigit(static_cast<unsigned char>(text.output[k])) || text.output[k] == '.';
        };
        if (!std::isdigit(static_cast<unsigned char>(text.output[i]))) { ++i; continue; }
        std::size_t end = i;
        while (end < text.output.size() && isNumberChar(end)) ++end;
        const std::string number = text.output.substr(i, end - i);
        if (number.find('.') != std::string::npos) {
            std::size_t significant = 0;
            for (const char c : number) significant += c != '.' && (significant > 0 || c != '0');
            if (significant > mostDigits) { mostDigits = significant; widest = number; }
        }
        i = end;
    }
    INFO("widest decimal: " << widest);
    CHECK(mostDigits <= 6);
    // Errors name the arguments as the user typed them (probe X Y), not render's --probe X,Y.
    const Run outside = run("probe default 64 0 --width 64 --height 36");
    CHECK(outside.exitCode == 2);
    CHECK(outside.output.find("probe 64 0: (64, 0) is outside the 64x36 frame") != std::string::npos);
    const Run notNumber = run("probe default x 5");
    CHECK(notNumber.exitCode == 2);
    CHECK(notNumber.output.find("probe X: 'x' is not an integer") != std::string::npos);
    CHECK(run("probe default 5 70000").output.find("probe Y: '70000' is not an integer") != std::string::npos);
    for (const char* args : {"probe default 64 0 --width 64 --height 36", "probe default x 5", "probe default 5 70000"})
        CHECK_MESSAGE(run(args).output.find("--probe") == std::string::npos, args);
    CHECK(run("probe default 5").exitCode == 2);
    CHECK(run("render default --json").exitCode == 2);
}

TEST_CASE("cli: probe prints the material the shader sampled, from which its output is rebuilt with the light terms") {
    // 3dgep's forward PS (demo ForwardRendering.hlsl): out = emissive + ambient + diffuse * sum of
    // the lights' diffuse + specular * sum of their specular, alpha = the diffuse alpha. The probe
    // prints every factor as the shader held it (binary32, every digit in --json); summing in
    // double instead of the shader's float order leaves differences below 1e-5 at these magnitudes
    // (values < 4, at most 5 additions of binary32 terms: each rounding <= 2^-24 * 4).
    const Run r = run("probe default 240 150 --technique forward --width 480 --height 270 --json");  // a textured wall
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    const nlohmann::json j = nlohmann::json::parse(r.output);
    const nlohmann::json* shaded = nullptr;
    for (const auto& e : j["events"])
        if (e.contains("draw") && e["shaded"].get<bool>() && e.contains("surface")) shaded = &e;
    REQUIRE(shaded != nullptr);
    const nlohmann::json& m = (*shaded)["surface"];
    double diffuseSum[3] = {}, specularSum[3] = {};
    for (const auto& l : (*shaded)["lights"])
        if (!l.contains("none"))
            for (int c = 0; c < 3; ++c) {
                diffuseSum[c] += l["diffuse"][c].get<double>();
                specularSum[c] += l["specular"][c].get<double>();
            }
    for (int c = 0; c < 3; ++c) {
        const double rebuilt = m["emissive"][c].get<double>() + m["ambient"][c].get<double>() + m["diffuse"][c].get<double>() * diffuseSum[c] +
                               m["specular"][c].get<double>() * specularSum[c];
        CHECK(std::abs(rebuilt - (*shaded)["output"][c].get<double>()) < 1e-5);
    }
    CHECK((*shaded)["output"][3].get<double>() == m["alpha"].get<double>());
    // The sampled albedo is the texture's (not the material's constant white): it differs per channel.
    CHECK(m["diffuse"][0].get<double>() != m["diffuse"][2].get<double>());
    const Run text = run("probe default 240 150 --technique forward --width 480 --height 270");
    CHECK(text.output.find("material diffuse [") != std::string::npos);
}

TEST_CASE("cli: --dump's lightExtents bound on screen every pixel each light lit, and are null where a light holds the eye") {
    // From z = 20 the default scene's point lights (range 6) lie in front of the near plane: each
    // gets a rectangle narrower than the frame; a pixel a light lit (its probe term is not 'none')
    // must lie inside that light's rectangle. From the scene's own camera the point and spot lights'
    // spheres hold the eye: null (they may cover the whole screen).
    const std::string camera = " --width 160 --height 90 --camera-position 0,2,20 --camera-target 0,0.8,0";
    const std::filesystem::path dir = scratch("extents");
    std::filesystem::remove_all(dir);
    REQUIRE(run("render default --quiet --dump " + dir.string() + " -o " + scratch("extents.png").string() + camera).exitCode == 0);
    std::ifstream in(dir / "manifest.json");
    const nlohmann::json extents = nlohmann::json::parse(in)["lightExtents"];
    REQUIRE(extents.size() == 4);
    CHECK(extents[0]["rectWindow"].is_null());  // directional: no range
    for (int l : {1, 2}) {
        REQUIRE(extents[l]["rectWindow"].is_array());
        CHECK(extents[l]["rectWindow"][2].get<double>() - extents[l]["rectWindow"][0].get<double>() < 160.0);
    }
    int checked = 0;
    for (int x : {60, 100}) {  // the two wall pixels of row 45 (the scene is small from z = 20)
        const Run r = run("probe default " + std::to_string(x) + " 45 --json" + camera);
        REQUIRE(r.exitCode == 0);
        const nlohmann::json history = nlohmann::json::parse(r.output);  // named: a temporary's ["events"] would dangle
        for (const auto& e : history["events"])
            for (const auto& t : e.value("lights", nlohmann::json::array())) {
                if (t.contains("none") || !t["light"].is_number()) continue;
                const nlohmann::json& rect = extents[t["light"].get<std::size_t>()]["rectWindow"];
                if (rect.is_null()) continue;
                CAPTURE(x);
                CAPTURE(t["light"]);
                CHECK(rect[0].get<double>() <= x + 0.5);
                CHECK(x + 0.5 <= rect[2].get<double>());
                CHECK(rect[1].get<double>() <= 45.5);
                CHECK(45.5 <= rect[3].get<double>());
                ++checked;
            }
    }
    CHECK(checked >= 3);  // lights 1 and 3 at x 60, light 2 at x 100
    const std::filesystem::path own = scratch("extents-own");
    std::filesystem::remove_all(own);
    REQUIRE(run("render default --quiet --width 64 --height 36 --dump " + own.string() + " -o " + scratch("extents-own.png").string()).exitCode == 0);
    std::ifstream ownIn(own / "manifest.json");
    const nlohmann::json ownManifest = nlohmann::json::parse(ownIn);
    for (const auto& e : ownManifest["lightExtents"]) CHECK(e["rectWindow"].is_null());
}

TEST_CASE("cli: renders that would pass the memory limit are refused before allocating, with exit 2 and nothing written") {
    const auto out = scratch("too-big.png");
    std::filesystem::remove(out);
    // deferred, float G-buffer: 84 B per pixel (tests/frame/memory_limit_test.cpp) x 16384^2 = 21 GiB.
    const Run d = run("render default --technique deferred --option gbuffer=float --width 16384 --height 16384 --memory-limit 4 --out " +
                      out.string());
    INFO(d.output);
    CHECK(d.exitCode == 2);
    CHECK(d.output.find("rendering 16384x16384 with deferred (frame buffers 21.0 GiB, 84 B per pixel") != std::string::npos);
    CHECK(d.output.find("past the memory limit of 4.0 GiB (--memory-limit); nothing was allocated") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(out));
    // builtin at --msaa 8: colour + depth 8 B per sample x 8 samples + the resolved 4 B = 68 B per px = 17 GiB.
    const Run b = run("render builtin --width 16384 --height 16384 --msaa 8 --memory-limit 8 --out " + out.string());
    INFO(b.output);
    CHECK(b.exitCode == 2);
    CHECK(b.output.find("builtin: rendering 16384x16384 at --msaa 8 needs about 17.0 GiB") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(out));
    // A million large lights in forward-plus's unbounded lists: nearly every light in every tile's
    // two lists (920 tiles x 10^6 x 4 B x 2 = 7.4 GB), the light term of the estimate.
    const Run l = run("render sponza-large-lights --technique forward-plus --option lightLists=unbounded --lights 1000000 "
                      "--memory-limit 1 --no-output --width 640 --height 360");
    INFO(l.output);
    CHECK(l.exitCode == 2);
    CHECK(l.output.find("rendering 640x360 with forward-plus (frame buffers 6.") != std::string::npos);
    CHECK(l.output.find("past the memory limit of 1.0 GiB (--memory-limit)") != std::string::npos);
    // The same scene at 64 lights fits.
    CHECK(run("render sponza-large-lights --lights 64 --memory-limit 1 --no-output --width 64 --height 36").exitCode == 0);
    for (const char* bad : {"0", "-1", "abc", "1e9"}) {
        const Run u = run(std::string("render default --no-output --memory-limit ") + bad);
        CHECK(u.exitCode == 2);
        CHECK(u.output.find("--memory-limit: '" + std::string(bad) + "' is not a number of GiB") != std::string::npos);
    }
    const Run i = run("info default");
    CHECK(i.output.find("frame buffers 1.8 MiB (8 B per pixel, 1 sample)") != std::string::npos);  // RGBA8 + D24S8 at 640x360
    CHECK(i.output.find("limit       renders are refused past") != std::string::npos);
}

TEST_CASE("cli: a projection whose depth range collapses is rendered with a warning naming the distances") {
    const auto scene = scratch("collapsed.json");
    {
        std::ofstream f(scene);
        f << R"({"models": [{"path": ")" << TESSERA_SOURCE_DIR
          << R"(/scenes/khronos/BoxTextured/glTF/BoxTextured.gltf"}], "camera": {"position": [0, 0, 5], "target": [0, 0, 0], "near": 1e-7, "far": 1e9}, "resolution": [32, 32]})";
    }
    const Run r = run("render " + scene.string() + " --no-output");
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(r.output.find("warning: " + scene.string() + ": the depth range collapses: surfaces farther than 3.36 from the eye") !=
          std::string::npos);
}

TEST_CASE("cli: GNU long options: --flag=value and -o equal --flag value and --out, byte for byte") {
    const auto spaced = scratch("gnu-spaced.png"), joined = scratch("gnu-joined.png"), shortOut = scratch("gnu-short.png");
    const Run a = run("render builtin --quiet --width 40 --height 24 --msaa 2 --out " + spaced.string());
    const Run b = run("render builtin --quiet --width=40 --height=24 --msaa=2 --out=" + joined.string());
    const Run c = run("render builtin --quiet --width 40 --height 24 --msaa 2 -o " + shortOut.string());
    INFO(a.output << b.output << c.output);
    REQUIRE(a.exitCode == 0);
    REQUIRE(b.exitCode == 0);
    REQUIRE(c.exitCode == 0);
    const auto bytesOf = [](const std::filesystem::path& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    const std::string bytesA = bytesOf(spaced);
    CHECK(!bytesA.empty());
    CHECK(bytesA == bytesOf(joined));
    CHECK(bytesA == bytesOf(shortOut));
    // report takes -o too: refused here by the output check, which names the folder it was given.
    const Run r = run("report -o /proc/rep-short");
    CHECK(r.exitCode == 2);
    CHECK(r.output.find("--out: '/proc/rep-short'") != std::string::npos);
}

} // namespace tessera_test::cli_cli_test
