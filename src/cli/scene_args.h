// Scene arguments shared by the `tessera` commands: bundled scene names, scene files, glTF
// files (the usage error and bounded integers every command uses are in render_args.h).
#pragma once

#include <filesystem>
#include <string>

#include <tessera/scene/scene_file.h>
#include <tessera/techniques/technique.h>

#include "render_args.h"

namespace tessera::cli {

// Where bundled scenes live: $TESSERA_SCENES, else <prefix>/share/tessera/scenes beside an
// installed binary, else the source tree's scenes/ folder this binary was built from.
std::filesystem::path bundledScenesDir();
// A scene argument as a file: an existing path, else a bundled scene name (InputError if neither).
std::filesystem::path resolveScene(const std::string& arg);
// The scene description of a scene file, or of a glTF file drawn with the preview technique.
SceneDescription describe(const std::filesystem::path& file);

// The frame a scene file describes: its camera, size, technique options and precision (render
// adds samples and statistics).
TechniqueContext frameContext(Device& device, const SceneResources& resources, const Camera& camera,
                              const SceneDescription& desc, const std::filesystem::path& sceneFile);

} // namespace tessera::cli
