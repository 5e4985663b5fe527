// `tessera probe SCENE X Y [render flags]`: the history of one pixel through the frame, which is
// `tessera render SCENE --probe X,Y` writing nothing unless --out or --dump is given.
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include <tessera/state/viewport.h>  // kMaxSurfaceDimension

#include "commands.h"
#include "render_args.h"

namespace tessera::cli {
namespace {

constexpr const char* kProbeUsage = R"(usage: tessera probe SCENE X Y [render options] [--json]

Renders SCENE as `tessera render` does and prints the history of window pixel (X, Y), in pass and
draw order: every primitive that covered it (coverage, depth and stencil outcome, the shader's
inputs and output, what each light added or why it added nothing, the texels before and after),
every buffer's value there after each pass and light step, and for the tiled techniques the
pixel's tile (depth range, frustum planes, light list, lights culled).
  --json        the same as one JSON object, for tools
Every option of `tessera render` applies (see `tessera help render`); nothing is written unless
--out or --dump is given.
)";

} // namespace

int probeCommand(const std::vector<std::string_view>& args) {
    if (args.size() == 1 && (args[0] == "--help" || args[0] == "-h")) {
        std::fputs(kProbeUsage, stdout);
        return 0;
    }
    if (args.size() < 3) throw UsageError("probe needs SCENE X Y (window pixels)");
    // X and Y are checked here, under the names the user typed, not as render's --probe X,Y.
    const std::uint32_t x = parseUint("probe X", args[1], 0, kMaxSurfaceDimension - 1);
    const std::uint32_t y = parseUint("probe Y", args[2], 0, kMaxSurfaceDimension - 1);
    const std::string xy = std::to_string(x) + "," + std::to_string(y);
    std::vector<std::string_view> renderArgs{args[0], "--probe", xy};
    bool writes = false;
    for (std::size_t i = 3; i < args.size(); ++i) {
        writes = writes || args[i] == "--out" || args[i] == "-o" || args[i] == "--dump" || args[i].substr(0, 6) == "--out=" ||
                 args[i].substr(0, 7) == "--dump=";
        renderArgs.push_back(args[i]);
    }
    if (!writes) renderArgs.push_back("--no-output");
    try {
        return renderCommand(renderArgs);
    } catch (const UsageError& e) {
        // A pixel outside the frame is known only once the scene has loaded: say it as "probe X Y".
        const std::string_view what = e.what();
        constexpr std::string_view kRenderFlag = "--probe: ";
        if (what.substr(0, kRenderFlag.size()) != kRenderFlag) throw;
        throw UsageError("probe " + std::string(args[1]) + " " + std::string(args[2]) + ": " +
                         std::string(what.substr(kRenderFlag.size())));
    }
}

} // namespace tessera::cli
