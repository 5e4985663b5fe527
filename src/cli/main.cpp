// The `tessera` command: `tessera render` draws the built-in scene (until the glTF scene
// loader lands) and writes the back buffer; `--dump DIR` writes every named buffer.
// Exit codes: 0 success, 1 failure while rendering, 2 bad usage or bad input.
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <tessera/state/viewport.h>

#include "builtin_scene.h"
#include <tessera/io/image_writer.h>

namespace {

constexpr const char* kUsage = R"(usage: tessera <command> [options]

commands:
  render     render the built-in scene and write the back buffer
  list       list techniques and bundled scenes
  help       show this text

`tessera render --help` lists the render options.
)";

constexpr const char* kRenderUsage = R"(usage: tessera render [options]

Renders the built-in scene (lit cubes on a plane, an alpha-blended pane) and writes the
back buffer as an image (PNG for .png, EXR for .exr).

options:
  --out FILE        output image (default: tessera.png)
  --width W         width in px, 1..16384 (default 640)
  --height H        height in px, 1..16384 (default 360)
  --threads N       worker threads, 0 = all cores (default 0)
  --tile T          tile size in px, even, 8..1024 (default 64)
  --msaa S          samples per pixel: 1, 2, 4 or 8 (default 1)
  --dump DIR        also write every named buffer into DIR (<name>.png/.exr, stencil as <name>.stencil.png)
  --stats           print per-pass times and draw counters
  --quiet           print nothing on success
  --help            show this text
)";

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

std::uint32_t parseUint(std::string_view flag, std::string_view text, std::uint32_t lo, std::uint32_t hi) {
    std::uint64_t v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || v < lo || v > hi)
        throw UsageError(std::string(flag) + ": '" + std::string(text) + "' is not an integer in " + std::to_string(lo) + ".." +
                         std::to_string(hi));
    return std::uint32_t(v);
}

int render(const std::vector<std::string_view>& args) {
    std::string out = "tessera.png", dumpDir;
    tessera::cli::BuiltinSceneOptions opt;
    tessera::DeviceConfig cfg;
    bool stats = false, quiet = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string_view a = args[i];
        auto value = [&]() -> std::string_view {
            if (i + 1 >= args.size()) throw UsageError(std::string(a) + " needs a value");
            return args[++i];
        };
        if (a == "--help" || a == "-h") {
            std::fputs(kRenderUsage, stdout);
            return 0;
        } else if (a == "--out") out = std::string(value());
        else if (a == "--width") opt.width = parseUint(a, value(), 1, tessera::kMaxSurfaceDimension);
        else if (a == "--height") opt.height = parseUint(a, value(), 1, tessera::kMaxSurfaceDimension);
        else if (a == "--threads") cfg.threads = parseUint(a, value(), 0, 256);
        else if (a == "--tile") {
            cfg.tileSize = parseUint(a, value(), 8, 1024);
            if (cfg.tileSize % 2) throw UsageError("--tile: " + std::to_string(cfg.tileSize) + " is odd; tiles hold whole 2x2 quads");
        } else if (a == "--msaa") {
            opt.sampleCount = parseUint(a, value(), 1, 8);
            if (opt.sampleCount != 1 && opt.sampleCount != 2 && opt.sampleCount != 4 && opt.sampleCount != 8)
                throw UsageError("--msaa: " + std::to_string(opt.sampleCount) + " is not 1, 2, 4 or 8");
        } else if (a == "--dump") dumpDir = std::string(value());
        else if (a == "--stats") stats = true;
        else if (a == "--quiet") quiet = true;
        else throw UsageError("unknown option '" + std::string(a) + "' (see tessera render --help)");
    }
    if (std::filesystem::path(out).extension().empty()) throw UsageError("--out: '" + out + "' has no extension (.png or .exr)");

    try {
        tessera::Device device(cfg);
        tessera::DrawStats drawStats;
        tessera::BufferRegistry registry;
        const tessera::Frame frame = tessera::cli::buildBuiltinScene(device, opt, drawStats);
        const auto timings = frame.run(registry);
        tessera::writeSurface(registry.get("backbuffer"), out);
        if (!dumpDir.empty()) {
            std::filesystem::create_directories(dumpDir);
            for (const std::string& name : registry.names()) {
                const tessera::Surface& s = registry.get(name);
                const tessera::FormatInfo& info = tessera::formatInfo(s.format());
                const bool png = s.format() == tessera::Format::R8G8B8A8_UNORM || s.format() == tessera::Format::R8G8B8A8_UNORM_SRGB;
                const std::string base = (std::filesystem::path(dumpDir) / name).string();
                tessera::writeSurface(s, base + (png ? ".png" : info.kind == tessera::FormatKind::Uint ? ".tif" : ".exr"));
                if (info.hasStencil) tessera::writeStencil(s, base + ".stencil.png");
            }
        }
        if (stats) {
            for (const auto& t : timings) std::printf("pass %-12s %9.3f ms\n", t.name.c_str(), t.milliseconds);
            std::printf("triangles in %llu, clipped %llu, culled %llu, rasterized %llu; quads %llu; ps invocations %llu; samples passed %llu\n",
                        (unsigned long long)drawStats.setup.trianglesIn, (unsigned long long)drawStats.setup.clipped,
                        (unsigned long long)(drawStats.setup.culledFacing + drawStats.setup.culledDegenerate + drawStats.setup.culledNonFinite),
                        (unsigned long long)drawStats.setup.trianglesOut, (unsigned long long)drawStats.quads,
                        (unsigned long long)drawStats.psInvocations, (unsigned long long)drawStats.samplesPassed);
        }
        if (!quiet) std::printf("wrote %s (%ux%u)\n", out.c_str(), opt.width, opt.height);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "tessera render: %s\n", e.what());
        return 1;
    }
}

} // namespace

int main(int argc, char** argv) {
    std::vector<std::string_view> args(argv + 1, argv + argc);
    try {
        if (args.empty() || args[0] == "help" || args[0] == "--help" || args[0] == "-h") {
            std::fputs(kUsage, args.empty() ? stderr : stdout);
            return args.empty() ? 2 : 0;
        }
        if (args[0] == "render") return render({args.begin() + 1, args.end()});
        if (args[0] == "list") {
            std::puts("techniques:\n  builtin   the built-in forward scene (lit opaque pass + alpha-blended pass)\n"
                      "bundled scenes:\n  (none yet: the glTF scene loader is a later issue)");
            return 0;
        }
        throw UsageError("unknown command '" + std::string(args[0]) + "'");
    } catch (const UsageError& e) {
        std::fprintf(stderr, "tessera: %s\n%s", e.what(), kUsage);
        return 2;
    }
}
