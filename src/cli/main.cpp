// The `tessera` command: the first argument names the command, which gets the rest (one file per
// command under src/cli/: render, probe, list, options, info, report, diff, serve; commands.h). `help
// COMMAND` is `COMMAND --help`. Exit codes: 0 success, 1 failure while rendering, 2 bad usage or
// bad input (UsageError: the message and a pointer to the command's help; InputError: the message).
#include <cstdio>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <tessera/errors/input_error.h>

#include "commands.h"
#include "render_args.h"

namespace tessera::cli {
namespace {
std::string gCommandLine;  // "tessera render ...", for --dump's manifest
} // namespace

const std::string& commandLine() { return gCommandLine; }
void setCommandLine(std::string line) { gCommandLine = std::move(line); }

} // namespace tessera::cli

namespace {

constexpr const char* kUsage = R"(usage: tessera <command> [options]

commands:
  render [SCENE]  render a scene and write the back buffer (default: the bundled scene 'default')
  list            list techniques and bundled scenes
  options [TECH]  list the options of every technique (or of TECH): values, faithful default,
                  correction, erratum
  probe SCENE X Y the history of one pixel through the frame (render's flags apply; --json)
  info SCENE      describe a scene: triangles, materials, lights, bounds, memory
  report [SCENE] --out DIR  an HTML page walking through every technique's passes and buffers
  diff A B        compare two images: max abs difference, RMSE, PSNR, differing pixels
  serve [SCENE]   the frame inspector in a web browser: passes, buffers, a pixel's history
  help [COMMAND]  show this text, or the command's options
  --version       print the version

SCENE is a scene file (.json), a glTF file (.gltf/.glb), the name of a bundled scene
(see `tessera list`), or `builtin` (a generated scene that needs no files).
`tessera <command> --help` lists the command's options.
)";

using Command = int (*)(const std::vector<std::string_view>&);

// The commands by name, each in its own file (commands.h).
const std::map<std::string_view, Command>& commands() {
    static const std::map<std::string_view, Command> table{
        {"render", tessera::cli::renderCommand}, {"probe", tessera::cli::probeCommand},
        {"list", tessera::cli::listCommand},     {"options", tessera::cli::optionsCommand},
        {"info", tessera::cli::infoCommand},     {"report", tessera::cli::reportCommand},
        {"diff", tessera::cli::diffCommand},     {"serve", tessera::cli::serveCommand}};
    return table;
}

} // namespace

int main(int argc, char** argv) {
    std::vector<std::string_view> args(argv + 1, argv + argc);
    std::string line = "tessera";
    for (const std::string_view a : args) {
        line += ' ';
        line.append(a);
    }
    tessera::cli::setCommandLine(line);
    try {
        if (args.empty() || args[0] == "--help" || args[0] == "-h" || (args[0] == "help" && args.size() == 1)) {
            std::fputs(kUsage, args.empty() ? stderr : stdout);
            return args.empty() ? 2 : 0;
        }
        if (args[0] == "--version" || args[0] == "version") {
            std::printf("tessera %s\n", TESSERA_VERSION);
            return 0;
        }
        if (args[0] == "help") {  // help COMMAND = COMMAND --help
            if (args.size() > 2) throw tessera::cli::UsageError("help takes one COMMAND");
            args = {args[1], "--help"};
        }
        const auto command = commands().find(args[0]);
        if (command == commands().end()) {
            std::fprintf(stderr, "tessera: unknown command '%s'\n%s", std::string(args[0]).c_str(), kUsage);
            return 2;
        }
        return command->second(std::vector<std::string_view>(args.begin() + 1, args.end()));
    } catch (const tessera::cli::UsageError& e) {
        // The command's own help names its options; the top-level usage would bury the message.
        if (!args.empty() && commands().count(args[0]))
            std::fprintf(stderr, "tessera: %s\n(see `tessera help %s`)\n", e.what(), std::string(args[0]).c_str());
        else std::fprintf(stderr, "tessera: %s\n%s", e.what(), kUsage);
        return 2;
    } catch (const tessera::InputError& e) {
        std::fprintf(stderr, "tessera: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "tessera: %s\n", e.what());
        return 1;
    }
}
