// The small opaque room the technique unit tests render in memory (a floor and a wall, two
// glTF materials, point + spot + directional lights, 128x96 unless a test asks for another
// size), the render call they share, and byte / RGBA8-code comparisons of surfaces.
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include <tessera/techniques/technique.h>

#include "support/surface_compare.h"

namespace tessera::test {

constexpr std::uint32_t kWidth = 128, kHeight = 96;  // px

inline MeshPrimitive quad(glm::vec3 origin, glm::vec3 edgeU, glm::vec3 edgeV, int material) {
    MeshPrimitive p;
    const glm::vec3 n = glm::normalize(glm::cross(edgeU, edgeV));
    p.positionsObject = {origin, origin + edgeU, origin + edgeU + edgeV, origin + edgeV};
    p.normalsObject = {n, n, n, n};
    const glm::vec4 t(glm::normalize(edgeU), 1.0f);
    p.tangentsObject = {t, t, t, t};
    p.texCoords0 = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    p.indices = {0, 1, 2, 0, 2, 3};  // counter-clockwise seen from the side n points to
    p.material = material;
    return p;
}

// One triangle at view z = `zView` facing +Z (towards a camera at the origin looking down -Z),
// glTF default material: the smallest scene a technique can render.
inline Scene oneTriangle(float zView) {
    Scene scene;
    MeshPrimitive prim;
    prim.positionsObject = {{-1.0f, -1.0f, zView}, {1.0f, -1.0f, zView}, {0.0f, 1.0f, zView}};
    prim.normalsObject = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    prim.tangentsObject = {{1, 0, 0, 1}, {1, 0, 0, 1}, {1, 0, 0, 1}};
    prim.texCoords0 = {{0, 0}, {1, 0}, {0.5f, 1}};
    prim.indices = {0, 1, 2};
    Mesh mesh;
    mesh.primitives.push_back(prim);
    scene.meshes.push_back(mesh);
    scene.instances.push_back(MeshInstance{0, glm::mat4(1.0f), "triangle"});
    return scene;
}

struct LightSpec {
    LightType type;
    glm::vec3 position, direction;
    float range, angleDeg;
};

// Floor y = 0 (20 x 20 around the origin) and a wall z = -6 from y = wallBaseY up, opaque glTF
// materials with specular power 30 (roughness 0.5) and 245 (roughness 0.3, metallic 0.5);
// camera at `eye` looking at (0, 0.5, 0), 45 degrees, near 0.1, far 100. wallBaseY 0.05: the
// wall and the floor do not touch, so no two surfaces share a depth value and forward's LESS and
// a depth pre-pass's LESS_EQUAL pick the same fragments.
struct TestScene {
    Scene scene;
    Camera camera;
};

inline TestScene makeScene(const std::vector<Light>& lights, glm::vec3 eye = {0.0f, 3.0f, 8.0f}, float wallBaseY = 0.0f) {
    TestScene t;
    Material floor;
    floor.baseColorFactor = {0.8f, 0.7f, 0.6f, 1.0f};
    floor.roughnessFactor = 0.5f;
    floor.metallicFactor = 0.0f;
    Material wall;
    wall.baseColorFactor = {0.5f, 0.6f, 0.9f, 1.0f};
    wall.roughnessFactor = 0.3f;
    wall.metallicFactor = 0.5f;
    t.scene.materials = {floor, wall};
    Mesh mesh;
    mesh.primitives.push_back(quad({-10.0f, 0.0f, 10.0f}, {20.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -20.0f}, 0));
    mesh.primitives.push_back(quad({-10.0f, wallBaseY, -6.0f}, {20.0f, 0.0f, 0.0f}, {0.0f, 10.0f, 0.0f}, 1));
    t.scene.meshes.push_back(mesh);
    t.scene.instances.push_back(MeshInstance{0, glm::mat4(1.0f), "room"});
    t.scene.lights = lights;
    t.camera.positionWorld = eye;
    t.camera.orientationWorld = glm::quatLookAtRH(glm::normalize(glm::vec3(0.0f, 0.5f, 0.0f) - eye), glm::vec3(0, 1, 0));
    t.camera.nearZ = 0.1f;
    t.camera.farZ = 100.0f;
    return t;
}

inline Light makeLight(LightType type, glm::vec3 position, glm::vec3 direction, float range, glm::vec3 color, float angleDeg = 30.0f) {
    Light l;
    l.type = type;
    l.positionWorld = position;
    l.directionWorld = glm::normalize(direction);
    l.range = range;
    l.color = color;
    l.spotHalfAngleDeg = angleDeg;
    return l;
}

// Point and spot volumes well inside the view, away from the near plane; a dim directional.
inline std::vector<Light> defaultLights() {
    return {makeLight(LightType::Point, {-2.0f, 1.5f, 0.0f}, {0, 0, -1}, 5.0f, {1.0f, 0.8f, 0.6f}),
            makeLight(LightType::Spot, {2.0f, 4.0f, -1.0f}, {-0.2f, -1.0f, -0.3f}, 8.0f, {0.6f, 0.8f, 1.0f}, 35.0f),
            makeLight(LightType::Directional, {0, 0, 0}, {-0.3f, -1.0f, -0.5f}, 1.0f, {0.2f, 0.2f, 0.25f}),
            makeLight(LightType::Point, {1.5f, 2.0f, -4.0f}, {0, 0, -1}, 4.0f, {0.9f, 0.3f, 0.3f})};
}

struct Rendered {
    BufferRegistry registry;
    std::map<std::string, std::uint64_t> variants;
    const Surface& back() { return registry.get(kBackBufferName); }
    const Surface& get(std::string_view name) { return registry.get(name); }
};

inline void render(const TestScene& t, const std::string& technique, const nlohmann::json& options, Rendered& out,
                   Precision precision = Precision::Exact, std::uint32_t threads = 2, glm::uvec2 sizePx = {kWidth, kHeight},
                   decltype(TechniqueContext::afterLightStep) afterLightStep = {}, std::uint32_t samples = 1,
                   DrawStats* stats = nullptr) {
    const SceneResources resources(t.scene, {}, TexturePolicy::AllLinear);
    Device device(DeviceConfig{32, threads});
    TechniqueContext ctx;
    ctx.device = &device;
    ctx.resources = &resources;
    ctx.camera = t.camera;
    ctx.width = sizePx.x;
    ctx.height = sizePx.y;
    ctx.sampleCount = samples;
    ctx.stats = stats;
    ctx.options = options;
    ctx.precision = precision;
    ctx.variantCounts = &out.variants;
    ctx.sceneFile = "memory.json";
    ctx.afterLightStep = std::move(afterLightStep);
    buildTechnique(technique, ctx, ctx.sceneFile).run(out.registry);
}

// The draw statistics of one frame of `technique` (2 threads), e.g. pixel-shader invocations.
inline DrawStats renderStats(const TestScene& t, const std::string& technique, const nlohmann::json& options) {
    const SceneResources resources(t.scene, {}, TexturePolicy::AllLinear);
    Device device(DeviceConfig{32, 2});
    DrawStats stats;
    TechniqueContext ctx;
    ctx.device = &device;
    ctx.resources = &resources;
    ctx.camera = t.camera;
    ctx.width = kWidth;
    ctx.height = kHeight;
    ctx.options = options;
    ctx.stats = &stats;
    ctx.sceneFile = "memory.json";
    BufferRegistry registry;
    buildTechnique(technique, ctx, ctx.sceneFile).run(registry);
    return stats;
}

} // namespace tessera::test
