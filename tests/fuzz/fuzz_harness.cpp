// The fuzz harnesses (fuzz_harness.h): each turns the bytes into one input, runs the code that
// reads it, and swallows only the documented error type. Files are never written; the empty
// folder the inputs pretend to live in is made once per process.
#include "fuzz_harness.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include <tessera/errors/input_error.h>
#include <tessera/scene/gltf_loader.h>
#include <tessera/scene/scene.h>
#include <tessera/scene/scene_file.h>
#include <tessera/techniques/technique.h>

#include "cli/render_args.h"

namespace tessera::fuzz {
namespace {

namespace fs = std::filesystem;

// An empty folder of this process's own (mkdtemp), removed at exit: relative paths in the
// inputs resolve there and find nothing.
const fs::path& emptyFolder() {
    static const fs::path folder = [] {
        std::string pattern = (fs::temp_directory_path() / "tessera-fuzz-XXXXXX").string();
        if (!mkdtemp(pattern.data())) throw std::runtime_error("fuzz harness: mkdtemp failed for " + pattern);
        return fs::path(pattern);
    }();
    static const struct Remover {
        ~Remover() {
            std::error_code ec;
            fs::remove(folder, ec);  // only if still empty: nothing is ever written there
        }
    } remover;
    return folder;
}

bool anyModelExists(const SceneDescription& description) {
    for (const ModelRef& model : description.models) {
        std::error_code ec;
        if (fs::exists(model.path, ec) || ec) return true;
    }
    return false;
}

} // namespace

int fuzzSceneFile(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const SceneDescription description = parseSceneJson(text, emptyFolder() / "scene.json");
        // A model path that names a real file (absolute, or ../ out of the folder) would load it:
        // the glTF target covers the loader, and a large model only slows the run down.
        if (anyModelExists(description)) return 0;
        Camera camera;
        try {
            (void)loadScene(description, false, &camera);  // refused: the first model is missing
        } catch (const InputError&) {
        }
        // The rest of loadScene without the models: the light list, the generators (in their
        // boxes; without one they need geometry), the shadow casters and the camera.
        SceneDescription withoutModels = description;
        withoutModels.models.clear();
        (void)loadScene(withoutModels, false, &camera);
    } catch (const InputError&) {
    }
    return 0;
}

int fuzzGltf(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    std::vector<std::string> warnings;
    GltfLoadOptions options;
    options.warnings = &warnings;
    Scene scene;
    try {
        loadGltfFromMemory(bytes, "fuzz.gltf", emptyFolder(), scene, options);
    } catch (const InputError&) {
    }
    return 0;
}

int fuzzCli(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    std::vector<std::string_view> args;
    for (std::size_t start = 0; start < text.size();) {
        const std::size_t newline = std::min(text.find('\n', start), text.size());
        args.push_back(std::string_view(text).substr(start, newline - start));
        start = newline + 1;
    }
    try {
        bool help = false;
        std::vector<std::string> warnings;
        const cli::RenderOptions options = cli::parseRenderArgs(args, help, &warnings);
        auto apply = [&](const std::string& technique) {
            nlohmann::json techniqueOptions = nlohmann::json::object();
            cli::applyOptionArgs(options, technique, techniqueOptions);
        };
        if (findTechnique(options.technique)) {
            apply(options.technique);
        } else {
            for (const TechniqueInfo& technique : techniques()) {
                try {
                    apply(std::string(technique.id));
                } catch (const cli::UsageError&) {
                }
            }
        }
    } catch (const cli::UsageError&) {
    }
    return 0;
}

} // namespace tessera::fuzz
