// Shared scene arguments (scene_args.h): bundled names, scene and glTF files.
#include "scene_args.h"

#include <cstdlib>
#include <system_error>

#include <tessera/errors/input_error.h>

namespace tessera::cli {
namespace {
bool isGltf(const std::filesystem::path& p) {
    const std::string ext = p.extension().string();
    return ext == ".gltf" || ext == ".glb";
}
} // namespace

// Where bundled scenes live: $TESSERA_SCENES, else <prefix>/share/tessera/scenes beside an
// installed binary, else the source tree's scenes/ folder this binary was built from.
std::filesystem::path bundledScenesDir() {
    if (const char* env = std::getenv("TESSERA_SCENES"); env && *env) return env;
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const std::filesystem::path installed = exe.parent_path().parent_path() / "share" / "tessera" / "scenes";
        if (std::filesystem::is_directory(installed, ec)) return installed;
    }
    return TESSERA_SOURCE_SCENES;
}

// A scene argument as a file: an existing path, else a bundled scene name.
std::filesystem::path resolveScene(const std::string& arg) {
    std::error_code ec;
    if (std::filesystem::exists(arg, ec)) return arg;
    if (arg.find('/') == std::string::npos) {
        const std::filesystem::path bundled = bundledScenesDir() / (std::filesystem::path(arg).extension() == ".json" ? arg : arg + ".json");
        if (std::filesystem::exists(bundled, ec)) return bundled;
    }
    throw InputError(arg + ": no such file, and no bundled scene of that name (see `tessera list`)");
}

SceneDescription describe(const std::filesystem::path& file) {
    if (isGltf(file)) {
        SceneDescription d;
        d.file = file;
        d.models.push_back({file, glm::mat4(1.0f)});
        d.technique = "preview";
        // A bare glTF is lit by the KHR_lights_punctual lights its nodes place, as a glTF viewer
        // lights it (a scene file opts in with "gltfLights"); none: the default rig (render.cpp).
        d.useGltfLights = true;
        return d;
    }
    if (file.extension() != ".json")
        throw InputError(file.string() + ": not a scene file (.json) or glTF file (.gltf, .glb)");
    return parseSceneFile(file);
}

tessera::TechniqueContext frameContext(tessera::Device& device, const tessera::SceneResources& resources, const tessera::Camera& camera,
                                       const tessera::SceneDescription& desc, const std::filesystem::path& sceneFile) {
    tessera::TechniqueContext ctx;
    ctx.device = &device;
    ctx.resources = &resources;
    ctx.camera = camera;
    ctx.width = desc.width;
    ctx.height = desc.height;
    ctx.options = desc.techniqueOptions;
    ctx.precision = desc.precision;
    ctx.sceneFile = sceneFile.string();
    return ctx;
}

} // namespace tessera::cli
