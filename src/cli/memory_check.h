// Memory a render needs, estimated and refused before anything large is allocated
// (frame/memory_limit.h): the limit from --memory-limit or the process's share, the scene's
// geometry and decoded images, and a quick bound that spares the probe frames when far below.
// Used by render (refusals, exit 2) and info (the estimate it prints).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include <tessera/scene/scene.h>

#include "render_args.h"

namespace tessera::cli {

std::uint64_t memoryLimitBytes(const RenderOptions& o);
// The limit in words: "3.0 GiB (--memory-limit)" or "... (3/4 of the ... this process may use; ...)".
std::string memoryLimitText(const RenderOptions& o);

// Throws MemoryLimitError when `bytes` pass the limit: "FILE: WHAT needs about X, past the
// memory limit of Y (...)".
void checkMemory(const RenderOptions& o, const std::string& file, const std::string& what, double bytes);

struct SceneBytes {
    double geometry = 0.0, images = 0.0;
};
// The loaded scene's vertex and index bytes (as SceneResources lays them out) and its decoded
// images' (RGBA8; from the headers when the images were not decoded).
SceneBytes sceneBytes(const Scene& scene);

// A bound on the frame's buffers that needs no probe frames: 512 B per sample (the largest
// technique holds 84 B per pixel per sample), 16 B per light per 8 x 8 tile (two unbounded
// lists of 4 B indices, twice over) and 4 KiB per light. True when far below the limit (then no
// probe frames are needed).
bool frameSurelyFits(const RenderOptions& o, std::uint32_t width, std::uint32_t height, std::size_t lights);

} // namespace tessera::cli
