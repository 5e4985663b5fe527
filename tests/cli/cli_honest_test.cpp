// Nothing dropped in silence: what a technique skips or clamps is warned on with its count, erratum
// and remedy; one note names what visibly changes the image; the report's "why" comes from the same
// records; --out writes what was asked for (the reference result, the stored alpha); unknown ids are
// errors; every accepted size renders through every technique; a failed render leaves no dump.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <type_traits>
#include <vector>
#include <sys/wait.h>

#include <OpenImageIO/imageio.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::cli_cli_honest_test {

namespace {

namespace fs = std::filesystem;

struct Run {
    int exitCode;
    std::string output;  // stdout + stderr
};

Run run(const std::string& args) {
    std::string cmd = TESSERA_CLI;
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

fs::path scratch(const std::string& name) {
    const fs::path dir = fs::path(TESSERA_TEST_OUTPUT_DIR) / "cli-honest-out";
    fs::create_directories(dir);
    return dir / name;
}

std::size_t occurrences(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
    return n;
}

// The pixels of an image file as stored (alpha unassociated), as float or 8-bit values.
template <class T>
std::vector<T> readPixels(const fs::path& file, int& width, int& height) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(file.string(), &config);
    REQUIRE_MESSAGE(in, "cannot open " << file.string());
    const OIIO::ImageSpec& spec = in->spec();
    width = spec.width;
    height = spec.height;
    REQUIRE(spec.nchannels == 4);
    std::vector<T> pixels(std::size_t(width) * std::size_t(height) * 4);
    REQUIRE(in->read_image(0, 0, 0, 4, std::is_same_v<T, float> ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8, pixels.data()));
    return pixels;
}

std::string fileBytes(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The technique ids `tessera list` prints as ready.
std::vector<std::string> readyTechniques() {
    const Run r = run("list");
    REQUIRE(r.exitCode == 0);
    std::vector<std::string> ids;
    std::size_t at = r.output.find("techniques:\n");
    REQUIRE(at != std::string::npos);
    at += 12;
    while (at < r.output.size() && r.output.compare(at, 2, "  ") == 0) {
        const std::size_t end = r.output.find('\n', at);
        const std::string line = r.output.substr(at + 2, end - at - 2);
        const std::string id = line.substr(0, line.find(' '));
        const std::size_t status = line.find_first_not_of(' ', id.size());
        if (status != std::string::npos && line.compare(status, 5, "ready") == 0) ids.push_back(id);
        at = end + 1;
    }
    REQUIRE(ids.size() >= 9);
    return ids;
}

} // namespace

TEST_CASE("cli honest: deferred-killzone warns once that it skipped the 2 lights whose volume holds the eye (ERRATA #6)") {
    const fs::path out = scratch("killzone.png");
    const Run r = run("render default --technique deferred-killzone --width 64 --height 36 --out " + out.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    const std::string warning = "tessera: warning: deferred-killzone: 2 lights skipped: the eye is inside their volume";
    CHECK(occurrences(r.output, warning) == 1);
    CHECK(r.output.find("(ERRATA.md #6; --technique deferred changes it)") != std::string::npos);
    // The 3dgep method lights them: nothing skipped.
    const Run d = run("render default --technique deferred --width 64 --height 36 --out " + out.string());
    INFO(d.output);
    REQUIRE(d.exitCode == 0);
    CHECK(d.output.find("lights skipped") == std::string::npos);
    // --quiet prints nothing, the notes included; --dump's manifest keeps them.
    const fs::path dump = scratch("killzone-dump");
    fs::remove_all(dump);
    const Run q = run("render default --technique deferred-killzone --width 64 --height 36 --quiet --out " + out.string() +
                      " --dump " + dump.string());
    CHECK(q.exitCode == 0);
    CHECK(q.output.empty());
    const std::string manifest = fileBytes(dump / "manifest.json");
    CHECK(manifest.find("\"kind\": \"eye-inside-volume\"") != std::string::npos);
    // A threshold above a light's query count skips it too (the option's doing, not an erratum):
    // counted and warned with the option that restores it. At 160x90 threshold 12000 is above the
    // query count of one of the default scene's two lit lights (measured; killzone.samples in --dump
    // holds the counts), and the 2 eye-inside lights stay counted apart. Threshold 0 (the default)
    // skips nothing more.
    const Run t = run("render default --technique deferred-killzone --option threshold=12000 --width 160 --height 90 --out " +
                      out.string());
    INFO(t.output);
    CHECK(occurrences(t.output, "deferred-killzone: 1 lights skipped: their occlusion query passed samples, but not more than "
                                "\"threshold\" (--option threshold=0 changes it)") == 1);
    CHECK(occurrences(t.output, warning) == 1);
    CHECK(r.output.find("occlusion query passed samples") == std::string::npos);
}

TEST_CASE("cli honest: the forward pass without alpha test is counted per draw of a MASK material, alphaTest=true silences it") {
    const fs::path out = scratch("forward.png");
    const Run r = run("render default --width 64 --height 36 --out " + out.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(occurrences(r.output, "tessera: warning: forward: ") == 1);
    CHECK(r.output.find("draws of alpha-masked materials shaded without the alpha test") != std::string::npos);
    CHECK(r.output.find("(ERRATA.md #2; --option alphaTest=true changes it)") != std::string::npos);
    const Run fixed = run("render default --option alphaTest=true --width 64 --height 36 --out " + out.string());
    INFO(fixed.output);
    REQUIRE(fixed.exitCode == 0);
    CHECK(fixed.output.find("alpha-masked") == std::string::npos);
}

TEST_CASE("cli honest: tiled-deferred counts the list entries a small tileListCapacity drops (ERRATA #16)") {
    const fs::path out = scratch("tiled.png");
    const Run r = run("render default --technique tiled-deferred --option tileListCapacity=1 --width 64 --height 36 --out " + out.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(r.output.find("tessera: warning: tiled-deferred: ") != std::string::npos);
    CHECK(r.output.find("tile light-list entries past the tile list's capacity dropped (ERRATA.md #16; --option "
                        "tileListCapacity=unbounded changes it)") != std::string::npos);
    const Run unbounded = run("render default --technique tiled-deferred --width 64 --height 36 --out " + out.string());
    CHECK(unbounded.output.find("capacity dropped") == std::string::npos);
}

TEST_CASE("cli honest: one note per render names what visibly changes the image: MASK draws (#2) and the saturated pixels, counted") {
    const fs::path out = scratch("note.png");
    const Run r = run("render default --width 160 --height 90 --out " + out.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(occurrences(r.output, "tessera: note: what changes this image visibly: ") == 1);
    CHECK(r.output.find("(#2)") != std::string::npos);
    CHECK(r.output.find("Corrected: --option alphaTest=true") != std::string::npos);
    // The saturated count is the image's own: pixels with R = G = B = 255.
    int w = 0, h = 0;
    const std::vector<unsigned char> px = readPixels<unsigned char>(out, w, h);
    std::size_t saturated = 0;
    for (std::size_t i = 0; i < px.size(); i += 4) saturated += (px[i] == 255 && px[i + 1] == 255 && px[i + 2] == 255) ? 1u : 0u;
    if (saturated > 0) CHECK(r.output.find(std::to_string(saturated) + " pixels saturated to white") != std::string::npos);
    else CHECK(r.output.find("saturated") == std::string::npos);
    // With the alpha test on, alpha test is no longer named.
    const Run fixed = run("render default --option alphaTest=true --width 160 --height 90 --out " + out.string());
    CHECK(fixed.output.find("alphaTest") == std::string::npos);
}

// A technique that counts nothing still names its faithful choices: deferred-cookbook's defaults
// include the chapter's directional quad over the background (#26) and the table's cull mode (#23),
// which change two thirds and a third of the default scene's pixels (measured with tessera diff).
// Each erratum option at its faithful value is named once, with its correction; a corrected one is not.
TEST_CASE("cli honest: the note names every technique's faithful erratum choices in effect, from its option table") {
    const fs::path out = scratch("note-cookbook.png");
    const Run r = run("render default --technique deferred-cookbook --width 64 --height 36 --out " + out.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(occurrences(r.output, "tessera: note: ") == 1);
    for (const char* named : {"background=book (#26)", "volumeCull=table (#23)", "specPowerUnpack=printed (#22)",
                              "--option background=stencil", "--option volumeCull=front"})
        CHECK_MESSAGE(occurrences(r.output, named) == 1, named);
    const Run corrected = run("render default --technique deferred-cookbook --option background=stencil --width 64 --height 36 --out " +
                              out.string());
    CHECK(corrected.output.find("background=book") == std::string::npos);
    CHECK(corrected.output.find("--option background=stencil") == std::string::npos);
    CHECK(corrected.output.find("volumeCull=table (#23)") != std::string::npos);
    // Every technique with an erratum option gets the note (preview has none).
    for (const std::string technique : {"forward", "deferred", "deferred-killzone", "forward-plus", "tiled-deferred",
                                        "deferred-classic", "light-prepass", "forward-plus-amd"}) {
        CAPTURE(technique);
        const Run t = run("render default --technique " + technique + " --width 32 --height 18 --out " + out.string());
        CHECK(t.exitCode == 0);
        CHECK(occurrences(t.output, "tessera: note: ") == 1);
        CHECK(t.output.find("Corrected: ") != std::string::npos);
        CHECK(t.output.find(" --option ") != std::string::npos);
    }
}

TEST_CASE("cli honest: the report's why column comes from each run's counts and faithful options: killzone #6, deferred #2") {
    const fs::path dir = scratch("report");
    fs::remove_all(dir);
    const Run r = run("report default --width 64 --height 36 --out " + dir.string());
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    const std::string page = fileBytes(dir / "index.html");
    const auto rowOf = [&page](const std::string& id) {
        const std::size_t table = page.find("<h2>Difference from forward</h2>");
        REQUIRE(table != std::string::npos);
        const std::size_t at = page.find("<td>" + id + "</td>", table);
        REQUIRE_MESSAGE(at != std::string::npos, id);
        return page.substr(at, page.find("</tr>", at) - at);
    };
    const std::string killzone = rowOf("deferred-killzone");
    CHECK(killzone.find("2 lights skipped: the eye is inside their volume") != std::string::npos);
    CHECK(killzone.find("ERRATA.md #6") != std::string::npos);
    const std::string deferred = rowOf("deferred");
    CHECK(deferred.find("alphaTest=false (#2)") != std::string::npos);
    CHECK(deferred.find("lights skipped") == std::string::npos);
    // Stencil pictures only where the stencil holds more than one value: forward never touches it
    // (a flat picture taught nothing), Killzone 2's marking does.
    const auto sectionOf = [&page](const std::string& id) {
        const std::size_t at = page.find("<h2 id=\"" + id + "\">");
        REQUIRE_MESSAGE(at != std::string::npos, id);
        return page.substr(at, page.find("<h2 id=", at + 1) - at);
    };
    const std::string forward = sectionOf("forward");
    CHECK(forward.find(".stencil.png") == std::string::npos);
    CHECK(forward.find("its stencil is 0 everywhere (no picture)") != std::string::npos);
    CHECK(sectionOf("deferred-killzone").find(".stencil.png") != std::string::npos);
    // Forward+'s light grid as counts over the final image, beside the culling pass (it was missing).
    const std::string forwardPlus = sectionOf("forward-plus");
    const std::size_t overlay = forwardPlus.find("lightgrid.opaque.overlay.png");
    REQUIRE(overlay != std::string::npos);
    const std::size_t src = forwardPlus.rfind("src=\"", overlay);
    REQUIRE(src != std::string::npos);
    CHECK(fs::exists(dir / forwardPlus.substr(src + 5, overlay + std::string("lightgrid.opaque.overlay.png").size() - src - 5)));
    // The deferred light shown step by step leaves the eye outside its volume: light 3 'key' (the
    // default scene's lights 1 and 2 hold the eye, which Killzone's row above counts as skipped),
    // so its stencil after unmark is a picture (not one flat value).
    const std::string deferredSection = sectionOf("deferred");
    CHECK(deferredSection.find("light 3, step by step") != std::string::npos);
    CHECK(deferredSection.find("light-3-unmark/depth.stencil.png") != std::string::npos);
    CHECK(fs::exists(dir / "deferred/light-3-unmark/depth.stencil.png"));
}

TEST_CASE("cli honest: --precision reference --out writes the double result: PNG rounded once from it, EXR its floats") {
    const fs::path exact = scratch("exact.png"), ref = scratch("ref.png"), refExr = scratch("ref.exr");
    // tiled-deferred: its 8-bit G-buffer moves many codes (forward differs in 3 pixels of 320x180).
    const std::string command = "render default --technique tiled-deferred --quiet --width 96 --height 54";
    REQUIRE(run(command + " --out " + exact.string()).exitCode == 0);
    REQUIRE(run(command + " --precision reference --out " + ref.string()).exitCode == 0);
    REQUIRE(run(command + " --precision reference --out " + refExr.string()).exitCode == 0);
    int w = 0, h = 0;
    const std::vector<unsigned char> e = readPixels<unsigned char>(exact, w, h);
    const std::vector<unsigned char> p = readPixels<unsigned char>(ref, w, h);
    const std::vector<float> f = readPixels<float>(refExr, w, h);
    REQUIRE(e.size() == p.size());
    REQUIRE(f.size() == p.size());
    std::size_t differFromExact = 0, wrongRounding = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const float v = f[i];
        // The UNORM encode: NaN and <= 0 -> 0, >= 1 -> 255, else round half up of v x 255 (in double).
        const unsigned expected = !(v > 0.0f) ? 0u : v >= 1.0f ? 255u : unsigned(std::floor(double(v) * 255.0 + 0.5));
        wrongRounding += p[i] != expected ? 1u : 0u;
        differFromExact += p[i] != e[i] ? 1u : 0u;
    }
    CHECK(wrongRounding == 0);
    CHECK(differFromExact > 0);
}

TEST_CASE("cli honest: render with a golden's command line writes that golden byte for byte, and diff reports it identical") {
    const fs::path goldens = fs::path(TESSERA_SOURCE_DIR) / "golden";
    std::vector<std::pair<std::string, fs::path>> cases{
        {"render builtin", goldens / "builtin" / "forward.png"},
        {"render builtin --msaa 4", goldens / "builtin" / "forward-msaa4.png"}};
    for (const char* id : {"forward", "deferred", "deferred-killzone", "forward-plus", "tiled-deferred", "light-prepass"})
        cases.push_back({std::string("render default --width 320 --height 180 --technique ") + id, goldens / "default" / (std::string(id) + ".png")});
    cases.push_back({"render default --width 320 --height 180 --msaa 4 --technique forward", goldens / "default" / "msaa4-forward.png"});
    for (const auto& c : cases) {
        const std::string& command = c.first;
        const fs::path& golden = c.second;
        CAPTURE(command);
        const fs::path mine = scratch("golden-mine.png");
        fs::remove(mine);
        REQUIRE(run(command + " --quiet --out " + mine.string()).exitCode == 0);
        CHECK(fileBytes(mine) == fileBytes(golden));
        const Run d = run("diff " + mine.string() + " " + golden.string());
        INFO(d.output);
        CHECK(d.exitCode == 0);
        CHECK(d.output.find("max abs    0\n") != std::string::npos);
        CHECK(d.output.find("psnr       inf dB (equal)") != std::string::npos);
    }
}

TEST_CASE("cli honest: an unknown technique is an error everywhere (render, builtin included, probe, options), naming the known ones") {
    for (const char* text : {"render builtin --technique nope", "render --technique nope", "render default --technique nope --quiet",
                             "probe default 1 1 --technique nope", "options nope"}) {
        const std::string command(text);
        CAPTURE(command);
        const Run plain = run(command);
        INFO(plain.output);
        CHECK(plain.exitCode == 2);
        CHECK(plain.output.find("unknown technique 'nope'") != std::string::npos);
        CHECK(plain.output.find("forward, ") != std::string::npos);
        CHECK(plain.output.find("deferred-killzone") != std::string::npos);
    }
    const Run option = run("render default --option nope=1");
    CHECK(option.exitCode == 2);
    CHECK(option.output.find("has no option 'nope'") != std::string::npos);
    const Run report = run("report --technique forward --out " + scratch("r").string());
    CHECK(report.exitCode == 2);
    const Run diff = run("diff --nope a.png b.png");
    CHECK(diff.exitCode == 2);
}

TEST_CASE("cli honest: every accepted size renders through every technique: 1x1, 1x16384 and 16384x1, with dumps") {
    // The default scene's lights and camera over one textured box (BoxTextured, a 256^2 texture):
    // the sizes are the subject, and 30 renders of the default scene would spend their time
    // decoding its three 2048^2 textures.
    const fs::path sceneFile = scratch("extreme-sizes.json");
    {
        const fs::path box = fs::path(TESSERA_SOURCE_DIR) / "scenes/khronos/BoxTextured/glTF/BoxTextured.gltf";
        std::ofstream(sceneFile) << R"({"models": [{"path": ")" << box.string() << R"("}],
            "camera": {"position": [0.0, 2.2, 7.5], "target": [0.0, 0.8, 0.0], "up": [0.0, 1.0, 0.0],
                       "fovYDeg": 45, "near": 0.1, "far": 100},
            "lights": [
              {"type": "directional", "direction": [-0.4, -1.0, -0.6], "color": [1.0, 0.95, 0.85], "intensity": 0.35},
              {"type": "point", "position": [-2.5, 2.0, 2.5], "color": [1.0, 0.7, 0.4], "intensity": 1.0, "range": 6.0},
              {"type": "spot", "position": [0.0, 4.0, 4.0], "direction": [0.0, -0.7, -0.7], "color": [1.0, 1.0, 1.0],
               "intensity": 1.0, "range": 10.0, "spotAngleDeg": 35}]})";
    }
    const fs::path out = scratch("extreme.png");
    for (const std::string& id : readyTechniques()) {
        for (const char* size : {"--width 1 --height 1", "--width 1 --height 16384", "--width 16384 --height 1"}) {
            CAPTURE(id);
            CAPTURE(size);
            const fs::path dump = scratch("extreme-dump");
            fs::remove_all(dump);
            const Run r = run("render " + sceneFile.string() + " --quiet --threads 2 --technique " + id + " " + size + " --out " + out.string() +
                              " --dump " + dump.string());
            INFO(r.output);
            CHECK(r.exitCode == 0);
            CHECK(fs::exists(dump / "manifest.json"));
        }
    }
}

TEST_CASE("cli honest: a render that fails leaves nothing behind: no dump folder, no staging folder, an existing dump untouched") {
    const fs::path parent = scratch("fail");
    fs::remove_all(parent);
    fs::create_directories(parent);
    const fs::path dump = parent / "dump", out = parent / "image.png";
    // A file size limit (SIGXFSZ ignored, so writes fail with EFBIG) that the first large buffer passes.
    // += rather than a + chain: GCC 12's -Warray-bounds misfires on the chain (unity batch).
    std::string limited = "sh -c \"trap '' XFSZ; ulimit -f 64; exec ";
    limited += TESSERA_CLI;
    limited += " render default --technique deferred --width 320 --height 180 --quiet --out " + out.string();
    limited += " --dump " + dump.string() + " --dump-after gbuffer\" 2>&1";
    const auto runShell = [](const std::string& cmd) {
        FILE* pipe = popen(cmd.c_str(), "r");
        REQUIRE(pipe != nullptr);
        std::string text;
        std::array<char, 4096> buf{};
        while (std::fgets(buf.data(), int(buf.size()), pipe)) text += buf.data();
        const int status = pclose(pipe);
        return Run{WIFEXITED(status) ? WEXITSTATUS(status) : -1, text};
    };
    const Run r = runShell(limited);
    INFO(r.output);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find("File too large") != std::string::npos);
    CHECK(r.output.find(dump.string() + "/") != std::string::npos);  // the message names DIR, not the staging folder
    CHECK(r.output.find(".tessera-dump") == std::string::npos);
    CHECK_FALSE(fs::exists(dump));
    CHECK_FALSE(fs::exists(out));
    for (const fs::directory_entry& e : fs::directory_iterator(parent)) FAIL_CHECK("left behind: " << e.path().string());

    // An existing dump folder keeps exactly what it held.
    fs::create_directories(dump);
    std::ofstream(dump / "mine.txt") << "kept";
    const Run again = runShell(limited);
    CHECK(again.exitCode == 1);
    std::vector<std::string> entries;
    for (const fs::directory_entry& e : fs::directory_iterator(dump)) entries.push_back(e.path().filename().string());
    CHECK(entries == std::vector<std::string>{"mine.txt"});
    std::size_t inParent = 0;
    for (const fs::directory_entry& e : fs::directory_iterator(parent)) inParent += e.path() != dump ? 1u : 0u;
    CHECK(inParent == 0);

    // The same command without the limit succeeds and fills the folder (the staging folder renamed or merged in).
    const Run ok = run("render default --technique deferred --width 32 --height 18 --quiet --out " + out.string() + " --dump " +
                       dump.string() + " --dump-after gbuffer");
    CHECK(ok.exitCode == 0);
    CHECK(fs::exists(dump / "mine.txt"));
    CHECK(fs::exists(dump / "manifest.json"));
    CHECK(fs::exists(dump / "after-gbuffer" / "depth.exr"));
    for (const fs::directory_entry& e : fs::directory_iterator(parent))
        CHECK_MESSAGE(e.path().filename().string().rfind(".tessera-dump", 0) != 0, e.path().string());
}

TEST_CASE("cli honest: --generated-bitangent down changes a render whose normal maps lack TANGENT, and warns where no normal map reads a generated one") {
    // Sponza's normal-mapped primitives have no TANGENT (ERRATA #33): the generated bitangent's
    // direction decides the sign of every normal map's green channel, so the old generator's render
    // (down) differs wherever a light grazes a normal-mapped surface, while `up` is the default byte
    // for byte. Which of the two is glTF's truth is shown on a constructed quad in
    // scene/gltf_rules_test.cpp.
    const fs::path up = scratch("bitangent-default.png"), explicitUp = scratch("bitangent-up.png"),
                   down = scratch("bitangent-down.png");
    const std::string common = "render sponza-large-lights --technique forward --width 160 --height 90 --quiet --out ";
    REQUIRE(run(common + up.string()).exitCode == 0);
    REQUIRE(run(common + explicitUp.string() + " --generated-bitangent up").exitCode == 0);
    REQUIRE(run(common + down.string() + " --generated-bitangent=down").exitCode == 0);
    CHECK(fileBytes(up) == fileBytes(explicitUp));
    int w = 0, h = 0;
    const std::vector<std::uint8_t> a = readPixels<std::uint8_t>(down, w, h);
    const std::vector<std::uint8_t> b = readPixels<std::uint8_t>(up, w, h);
    std::size_t differing = 0;
    for (std::size_t i = 0; i < a.size(); i += 4)
        differing += (a[i] != b[i] || a[i + 1] != b[i + 1] || a[i + 2] != b[i + 2]) ? 1 : 0;
    INFO("pixels that differ: " << differing << " of " << a.size() / 4);
    CHECK(differing * 100 > a.size() / 4);  // more than 1% of the frame
    // The default scene's normal-mapped model (AlphaBlendModeTest) carries TANGENT, and the boxes
    // get generated tangents that no normal texture reads: the flag changes nothing there.
    const Run plain = run("render default --width 16 --height 16 --no-output --generated-bitangent down");
    INFO(plain.output);
    CHECK(plain.exitCode == 0);
    CHECK(plain.output.find("tessera: warning: --generated-bitangent: ") != std::string::npos);
    CHECK(plain.output.find("has no normal-mapped primitive without TANGENT; the flag changes nothing") != std::string::npos);
    const Run bad = run("render default --generated-bitangent sideways --no-output");
    CHECK(bad.exitCode == 2);
    CHECK(bad.output.find("--generated-bitangent: 'sideways' is not down or up") != std::string::npos);
}

// A glTF's own KHR_lights_punctual lights: a bare .gltf is lit by them (as a glTF viewer lights it,
// not by the default rig), and a scene file that leaves them out (no "gltfLights") says so in
// `render` and `info` instead of calling the scene unlit.
TEST_CASE("cli honest: a bare glTF's placed lights light it, and a scene file that leaves them out says how many") {
    // The Box with one point light placed 3 units in front of it.
    const fs::path box = fs::path(TESSERA_SOURCE_DIR) / "scenes" / "khronos" / "Box" / "glTF";
    nlohmann::json doc;
    std::ifstream(box / "Box.gltf") >> doc;
    doc["extensionsUsed"] = {"KHR_lights_punctual"};
    doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"color", {1, 1, 1}}, {"intensity", 5}, {"range", 20}}};
    doc["nodes"].push_back({{"translation", {0, 0, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    doc["scenes"][0]["nodes"].push_back(doc["nodes"].size() - 1);
    const fs::path dir = scratch("gltf-lights");
    fs::create_directories(dir);
    fs::copy_file(box / "Box0.bin", dir / "Box0.bin", fs::copy_options::overwrite_existing);
    std::ofstream(dir / "lit.gltf") << doc.dump();
    std::ofstream(dir / "scene.json") << R"({"models": [{"path": "lit.gltf"}], "technique": "forward"})";

    const Run bare = run("render " + (dir / "lit.gltf").string() + " --technique forward --width 32 --height 18 --out " +
                         (dir / "bare.png").string());
    INFO(bare.output);
    CHECK(bare.exitCode == 0);
    CHECK(bare.output.find("has no lights") == std::string::npos);
    CHECK(run("info " + (dir / "lit.gltf").string()).output.find("lights      1 (point 1,") != std::string::npos);

    const Run scene = run("render " + (dir / "scene.json").string() + " --width 32 --height 18 --out " + (dir / "scene.png").string());
    INFO(scene.output);
    CHECK(scene.exitCode == 0);
    CHECK(occurrences(scene.output, "place 1 KHR_lights_punctual light(s), which this scene file leaves out") == 1);
    const Run info = run("info " + (dir / "scene.json").string());
    CHECK(info.output.find("lights      0 (point 0, spot 0, directional 0); 1 more placed by the glTF files, left out") !=
          std::string::npos);
}

// COLOR_0 is not applied (README "glTF conformance"): a primitive with vertex colours other than
// white renders with its base colour alone, and `render` says so once; the Box without them says nothing.
TEST_CASE("cli honest: COLOR_0 vertex colours are warned, not applied") {
    const fs::path box = fs::path(TESSERA_SOURCE_DIR) / "scenes" / "khronos" / "Box" / "glTF";
    nlohmann::json doc;
    std::ifstream(box / "Box.gltf") >> doc;
    // A COLOR_0 accessor of 24 red VEC3 floats in a second buffer (the Box has 24 vertices).
    const std::size_t vertices = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>()]["count"];
    std::vector<std::uint8_t> bytes;
    for (std::size_t v = 0; v < vertices; ++v)
        for (const float c : {1.0f, 0.0f, 0.0f}) {
            const auto* b = reinterpret_cast<const std::uint8_t*>(&c);
            bytes.insert(bytes.end(), b, b + 4);
        }
    const fs::path dir = scratch("gltf-color");
    fs::create_directories(dir);
    fs::copy_file(box / "Box0.bin", dir / "Box0.bin", fs::copy_options::overwrite_existing);
    std::ofstream(dir / "red.bin", std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    doc["buffers"].push_back({{"uri", "red.bin"}, {"byteLength", bytes.size()}});
    doc["bufferViews"].push_back({{"buffer", doc["buffers"].size() - 1}, {"byteLength", bytes.size()}});
    doc["accessors"].push_back({{"bufferView", doc["bufferViews"].size() - 1}, {"componentType", 5126}, {"count", vertices}, {"type", "VEC3"}});
    doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = doc["accessors"].size() - 1;
    std::ofstream(dir / "red.gltf") << doc.dump();
    const Run red = run("render " + (dir / "red.gltf").string() + " --technique forward --width 32 --height 18 --out " +
                        (dir / "red.png").string());
    INFO(red.output);
    CHECK(red.exitCode == 0);
    CHECK(occurrences(red.output, "1 primitive(s) carry COLOR_0 vertex colours, which tessera does not apply") == 1);
    const Run plain = run("render " + (box / "Box.gltf").string() + " --technique forward --width 32 --height 18 --out " +
                          (dir / "plain.png").string());
    CHECK(plain.exitCode == 0);
    CHECK(plain.output.find("COLOR_0") == std::string::npos);
}

} // namespace tessera_test::cli_cli_honest_test
