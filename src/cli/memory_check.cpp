// Memory checks of the command (memory_check.h).
#include "memory_check.h"

#include <tessera/frame/memory_limit.h>
#include <tessera/scene/scene_resources.h>

namespace tessera::cli {

std::uint64_t memoryLimitBytes(const RenderOptions& o) {
    return o.memoryLimitGiB ? std::uint64_t(*o.memoryLimitGiB * 1073741824.0) : tessera::defaultMemoryLimitBytes();
}

std::string memoryLimitText(const RenderOptions& o) {
    const std::string limit = tessera::formatBytes(double(memoryLimitBytes(o)));
    if (o.memoryLimitGiB) return limit + " (--memory-limit)";
    return limit + " (3/4 of the " + tessera::formatBytes(double(tessera::availableMemoryBytes())) +
           " this process may use; --memory-limit GIB sets it)";
}

void checkMemory(const RenderOptions& o, const std::string& file, const std::string& what, double bytes) {
    if (bytes > double(memoryLimitBytes(o)))
        throw tessera::MemoryLimitError(file + ": " + what + " needs about " + tessera::formatBytes(bytes) +
                                        ", past the memory limit of " + memoryLimitText(o) + "; nothing was allocated");
}

SceneBytes sceneBytes(const tessera::Scene& scene) {
    SceneBytes b;
    for (const tessera::Mesh& m : scene.meshes)
        for (const tessera::MeshPrimitive& p : m.primitives)
            b.geometry += double(p.positionsObject.size()) * sizeof(tessera::SceneVertex) + double(p.indices.size()) * 4.0;
    for (const tessera::Image& img : scene.images) b.images += double(img.width) * img.height * 4.0;
    return b;
}

bool frameSurelyFits(const RenderOptions& o, std::uint32_t width, std::uint32_t height, std::size_t lights) {
    const double pixels = double(width) * height;
    const double bound = pixels * o.msaa * 512.0 + pixels / 64.0 * double(lights) * 16.0 + double(lights) * 4096.0;
    return bound < 0.5 * double(memoryLimitBytes(o));
}

} // namespace tessera::cli
