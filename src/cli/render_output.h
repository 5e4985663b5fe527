// What a render writes: the image --out names (the back buffer as stored, or with precision
// reference the double result), and with --dump every buffer of the registry (exact files, a
// viewable picture of each, manifest.json), staged out of sight and moved into place only when
// the render succeeded; the FNV-1a 64 hash of each written file for --stats.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <tessera/frame/buffer_registry.h>

#include "dump_staging.h"
#include "render_args.h"

namespace tessera::cli {

// One written file and the FNV-1a 64 hash of its bytes (io/atomic_file.h), for --stats.
struct WrittenFile {
    std::string path;
    std::uint64_t hash;
};

// How a dumped file of `format` decodes, for the manifest.
std::string decodeRule(Format format, const std::string& file);

// Writes every buffer of `registry` into `dir` (exact files, plus viewable pictures in
// `dir`/view/ when `views`) and describes them in `buffers` (the manifest's entries).
void dumpRegistry(const BufferRegistry& registry, const std::filesystem::path& dir, const RenderOptions& o, bool views,
                  std::vector<WrittenFile>& written, nlohmann::json& buffers);

// The image --out writes: the back buffer as stored (alpha included, as the goldens and --dump keep
// it, so a render of a golden's command line is that golden byte for byte). With precision
// reference, the double result instead: for PNG "backbuffer.reference" rounded once to the back
// buffer's 8-bit format (the UNORM clamp and encode of storeAsUnorm), for EXR the float values.
Surface outputImage(const BufferRegistry& registry, const std::string& out);

// What a render wrote: the image, then with --dump every buffer, their views and manifest.json
// (`manifest` holds the scene, technique, camera, options and command line; the passes and
// buffers are added here), the staged dump moved into place last (`staging`, may be null).
std::vector<WrittenFile> writeOutputs(const BufferRegistry& registry, const RenderOptions& o, nlohmann::json manifest,
                                      DumpStaging* staging);

// "hash     <16 hex digits>  <file>": FNV-1a 64 of each written file's bytes, in write order,
// with staged paths as they read after the move.
void printHashes(const std::vector<WrittenFile>& written, const DumpStaging* staging);

} // namespace tessera::cli
