// The scene file (JSON; schema in scenes/scene.schema.json): glTF files with transforms, the
// camera, the resolution, the technique and its options, the precision mode, and lights
// (explicit lists, the glTFs' own KHR_lights_punctual lights, and seeded generators).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <tessera/scene/light_generator.h>
#include <tessera/state/precision.h>
#include <tessera/scene/scene.h>

namespace tessera {

struct ModelRef {
    std::filesystem::path path;      // resolved against the scene file's folder
    glm::mat4 worldFromFile{1.0f};   // from "translation" / "rotation" (quat xyzw) / "scale" (number or vec3)
    std::uint8_t lightGroups = kDefaultGeometryLightGroups;  // "lightGroups": [0..7, ...] as a bit mask
};

// Where the camera comes from: "camera" absent (Auto: the first glTF camera, else Framing),
// {"position", "rotation"|"target"} (Explicit), {"gltf": N} (Gltf), or only fovYDeg/near/far
// (Framing: look at the bounds' centre from +Z, framing the bounding sphere).
enum class CameraSource { Auto, Explicit, Gltf, Framing };

struct SceneDescription {
    std::filesystem::path file;      // the scene file itself (for messages)
    std::vector<ModelRef> models;
    Camera camera;                   // "camera"; if absent: the first glTF camera, else a default framing
    bool cameraFromGltf = false;     // true when "camera" was {"gltf": N}
    int gltfCameraIndex = -1;
    CameraSource cameraSource = CameraSource::Auto;
    // "camera": {"fovYDeg", "near", "far"} as given; applied over a glTF or framing camera
    // (an Explicit camera holds them in `camera` directly).
    std::optional<float> cameraFovYDeg, cameraNearZ, cameraFarZ;
    std::uint32_t width = 1280, height = 720;   // "resolution": [W, H], 1..16384 each
    std::string technique = "forward";          // "technique": an id from the technique registry
    nlohmann::json techniqueOptions = nlohmann::json::object();  // "options": passed to the technique verbatim
    Precision precision = Precision::Exact;     // "precision"
    std::vector<Light> explicitLights;          // "lights": [...]
    bool useGltfLights = false;                 // "gltfLights": {"enabled": true, ...}
    // Handed to every model's GltfLoadOptions (ERRATA #33; the command line's --generated-bitangent).
    bool generatedBitangentUp = true;
    float gltfLightDefaultRange = 0.0f;         // "gltfLights": {"defaultRange": R}: replaces infinite KHR ranges (0: keep inf)
    std::vector<LightGeneratorSpec> generators; // "generate": [...]
    // "shadowCasters": "none" (default) | "all" | [light indices into the final list: explicit,
    // glTF, generated]; checked against the list's length by loadScene.
    enum class ShadowCasters { None, All, List } shadowCasters = ShadowCasters::None;
    std::vector<std::uint32_t> shadowCasterIndices;
};

// Parses and validates a scene file. Throws InputError naming the file and the key path
// ("/lights/2/range: -1 is negative", "/resolution/0: 0 is outside 1..16384").
SceneDescription parseSceneFile(const std::filesystem::path& file);
// Same, from JSON text; `file` is used for messages and to resolve relative model paths.
SceneDescription parseSceneJson(const std::string& text, const std::filesystem::path& file);

// The top-level keys a scene file may hold (the schema's "properties" list exactly these).
const std::vector<std::string>& sceneFileTopLevelKeys();

// The camera to render with, per description.cameraSource, against the loaded scene's cameras
// and bounds. Throws InputError for a glTF camera index the models do not have.
Camera resolveCamera(const SceneDescription& description, const Scene& scene);

// Loads the models and builds the light list: explicit lights, then the glTFs' lights (when
// enabled), then each generator's lights in order. Throws InputError on bad input (a missing
// model file names the scene file, "/models/N/path" and the resolved path). With cameraOut,
// also stores resolveCamera(description, scene) there.
Scene loadScene(const SceneDescription& description, bool loadImages = true, Camera* cameraOut = nullptr);

} // namespace tessera
