// Arguments shared by the `tessera` commands: the usage error every command throws (exit 2),
// bounded integers, and scene arguments (bundled scene names, scene files, glTF files).
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include <tessera/scene/scene_file.h>

namespace tessera::cli {

// Bad usage: the command prints it with a pointer to its --help and exits 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// `text` as an integer in [lo, hi], else a UsageError naming `flag` and the range.
std::uint32_t parseUint(std::string_view flag, std::string_view text, std::uint32_t lo, std::uint32_t hi);

// Where bundled scenes live: $TESSERA_SCENES, else <prefix>/share/tessera/scenes beside an
// installed binary, else the source tree's scenes/ folder this binary was built from.
std::filesystem::path bundledScenesDir();
// A scene argument as a file: an existing path, else a bundled scene name (InputError if neither).
std::filesystem::path resolveScene(const std::string& arg);
// The scene description of a scene file, or of a glTF file drawn with the preview technique.
SceneDescription describe(const std::filesystem::path& file);

} // namespace tessera::cli
