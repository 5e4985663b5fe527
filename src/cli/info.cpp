// `tessera info SCENE`: loads a scene without decoding images and prints its triangles,
// materials, textures, cameras, lights by type, bounds, and the memory a render of it needs.
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <tbb/task_arena.h>

#include <tessera/frame/memory_limit.h>
#include <tessera/scene/scene_resources.h>
#include <tessera/techniques/builtin_scene.h>
#include <tessera/techniques/technique.h>

#include "commands.h"
#include "memory_check.h"
#include "scene_args.h"

namespace tessera::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kInfoUsage = R"(usage: tessera info SCENE

Loads SCENE without decoding images and prints its triangles, meshes, instances, materials,
textures, cameras, lights by type, world bounds and an estimate of the memory a render needs.
)";

// `tessera info builtin`: the generated scene's facts without a file.
int infoBuiltin() {
    const tessera::BuiltinSceneOptions opt;
    std::printf("scene       builtin (generated, no files)\n");
    std::printf("technique   its own Lambert-shaded draws (no scene-file technique), %ux%u by default, precision exact "
                "unless --precision; --msaa 1, 2, 4 or 8\n",
                opt.width, opt.height);
    std::printf("contents    generated cubes and a blended pane; no textures, no technique options\n");
    return 0;
}

} // namespace

int infoCommand(const std::vector<std::string_view>& args) {
    std::string sceneArg;
    for (const std::string_view a : args) {
        if (a == "--help" || a == "-h") {
            std::fputs(kInfoUsage, stdout);
            return 0;
        }
        if (!a.empty() && a[0] == '-') throw UsageError("unknown option '" + std::string(a) + "' (see tessera info --help)");
        if (!sceneArg.empty()) throw UsageError("one scene only");
        sceneArg = std::string(a);
    }
    if (sceneArg.empty()) throw UsageError("info needs a SCENE");
    if (sceneArg == "builtin") return infoBuiltin();
    const fs::path file = resolveScene(sceneArg);
    const tessera::SceneDescription desc = describe(file);
    tessera::Camera camera;
    const tessera::Scene scene = tessera::loadScene(desc, false, &camera);
    std::size_t primitives = 0;
    for (const tessera::Mesh& m : scene.meshes) primitives += m.primitives.size();
    const SceneBytes loaded = sceneBytes(scene);  // images: from their headers (not decoded here)
    const tessera::TechniqueInfo& technique = tessera::requireTechnique(desc.technique, file.string());
    const tessera::TextureMemoryEstimate textures = tessera::SceneResources::estimateTextureMemory(
        scene, technique.textures, std::size_t(tbb::this_task_arena::max_concurrency()));
    std::size_t lightsByType[3] = {0, 0, 0};
    for (const tessera::Light& l : scene.lights) ++lightsByType[int(l.type)];
    const tessera::Bounds b = scene.bounds();
    std::printf("scene       %s\n", file.string().c_str());
    std::printf("technique   %s (precision %s), %ux%u\n", desc.technique.c_str(), std::string(tessera::precisionName(desc.precision)).c_str(),
                desc.width, desc.height);
    std::printf("triangles   %llu (in %zu instances of %zu meshes, %zu primitives)\n", (unsigned long long)scene.triangleCount(),
                scene.instances.size(), scene.meshes.size(), primitives);
    std::printf("materials   %zu; textures %zu; images %zu\n", scene.materials.size(), scene.textures.size(), scene.images.size());
    std::printf("cameras     %zu in the glTF files; render camera at (%g, %g, %g), fovY %g deg, near %g, far %g\n",
                scene.cameras.size(), camera.positionWorld.x, camera.positionWorld.y, camera.positionWorld.z, camera.fovYDeg,
                camera.nearZ, camera.farZ);
    std::printf("lights      %zu (point %zu, spot %zu, directional %zu)", scene.lights.size(), lightsByType[0], lightsByType[1],
                lightsByType[2]);
    if (scene.gltfLightsNotUsed > 0)
        std::printf("; %zu more placed by the glTF files, left out (\"gltfLights\" uses them)", scene.gltfLightsNotUsed);
    std::printf("\n");
    if (b.empty()) std::printf("bounds      empty\n");
    else
        std::printf("bounds      (%g, %g, %g) .. (%g, %g, %g)\n", b.minWorld.x, b.minWorld.y, b.minWorld.z, b.maxWorld.x,
                    b.maxWorld.y, b.maxWorld.z);
    // Frame buffers: the technique's probe frames (estimateFrameMemory), untextured (no images here).
    double frameBytes = 0.0, perPixel = 0.0;
    if (technique.build) {
        const tessera::SceneResources resources(scene, {}, technique.textures);
        tessera::Device device(tessera::DeviceConfig{});
        const tessera::TechniqueContext ctx = frameContext(device, resources, camera, desc, file);
        const tessera::FrameMemoryEstimate e = tessera::estimateFrameMemory(desc.technique, ctx, file.string());
        frameBytes = e.bytes;
        perPixel = e.bytesPerPixel;
    }
    const double resident = loaded.geometry + loaded.images + textures.textureBytes + frameBytes;
    std::printf("memory      about %s besides the program, peak %s while textures decode: geometry %s, decoded images %s, "
                "textures with mips %s (+ %s of mip filter rows while decoding), frame buffers %s (%.0f B per pixel, 1 sample)\n",
                tessera::formatBytes(resident).c_str(),
                tessera::formatBytes(loaded.geometry + loaded.images + textures.textureBytes + textures.transientBytes).c_str(),
                tessera::formatBytes(loaded.geometry).c_str(), tessera::formatBytes(loaded.images).c_str(),
                tessera::formatBytes(textures.textureBytes).c_str(), tessera::formatBytes(textures.transientBytes).c_str(),
                tessera::formatBytes(frameBytes).c_str(), perPixel);
    std::printf("limit       renders are refused past %s (3/4 of the %s this process may use; tessera render --memory-limit)\n",
                tessera::formatBytes(double(tessera::defaultMemoryLimitBytes())).c_str(),
                tessera::formatBytes(double(tessera::availableMemoryBytes())).c_str());
    return 0;
}

} // namespace tessera::cli
