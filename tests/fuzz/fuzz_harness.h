// One harness per input the fuzz targets feed: scene files, glTF files and `tessera render`'s
// arguments. The libFuzzer drivers (*_fuzz.cpp) and the corpus replay test (tests_fuzz) call
// the same functions, so a saved crash reproduces in every build.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tessera::fuzz {

// Each returns 0 when the input was accepted, or refused with the error its loader documents
// (tessera::InputError; for the arguments, tessera::cli::UsageError). Any other exception
// escapes, and a crash, hang or sanitizer report is the caller's to see.

// The bytes as a scene file in an empty folder: parseSceneJson, then (when it passes and no
// model path names an existing file) loadScene without images, which refuses the missing
// models, and loadScene of the same description without its models: the light list, the
// generators, the shadow casters and the camera.
int fuzzSceneFile(const std::uint8_t* data, std::size_t size);

// The bytes as a .gltf or .glb (loadGltfFromMemory), images decoded, external uris resolved
// against an empty folder.
int fuzzGltf(const std::uint8_t* data, std::size_t size);

// The bytes as `tessera render`'s arguments, one per line (a final newline ends the last one):
// parseRenderArgs, then the --option values against the chosen technique, or every technique
// when none is chosen. Nothing is loaded, rendered or written.
int fuzzCli(const std::uint8_t* data, std::size_t size);

} // namespace tessera::fuzz
