// Occlusion queries for shadow rays (GPU Pro 4 ch. 5 §5.6.2): the world-space triangles of a
// scene's opaque draw items in an Intel Embree 3 BVH, traversed in Embree's robust (watertight)
// mode so that a ray's answer does not depend on the BVH a build happened to make. Built once per
// SceneResources (shadowRaySceneOf) and shared by every frame; Embree stays private.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace tessera {

class SceneResources;

class ShadowRayScene {
public:
    // Three vertices per triangle, world space. Throws std::runtime_error when Embree fails
    // (no device, out of memory) with Embree's own message.
    explicit ShadowRayScene(std::span<const glm::vec3> trianglesWorld);
    ~ShadowRayScene();
    ShadowRayScene(const ShadowRayScene&) = delete;
    ShadowRayScene& operator=(const ShadowRayScene&) = delete;

    // For each segment originWorld + t * directionWorld, t in [0, tFar]: whether a triangle
    // meets it (both faces), hit[i] = 1 or 0. Embree's stream API (rtcOccluded1M) in robust mode;
    // thread safe.
    struct Segment {
        glm::vec3 originWorld;
        glm::vec3 directionWorld;
        float tFar;
    };
    void occluded(std::span<const Segment> segments, std::span<std::uint8_t> hit) const;
    std::size_t triangleCount() const { return mTriangleCount; }

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
    std::size_t mTriangleCount = 0;
};

// The occluders of `resources`: every triangle of every draw item whose material is not
// transparent (alpha blended), transformed by its worldFromObject in float, in draw-item order.
// Alpha-tested (MASK) materials occlude as opaque triangles: no alpha test on shadow rays.
std::vector<glm::vec3> occluderTrianglesWorld(const SceneResources& resources);

// The BVH of occluderTrianglesWorld(resources), built on the first call for these resources
// (thread safe, SceneResources::derived) and the same object for every frame of the scene.
const ShadowRayScene& shadowRaySceneOf(const SceneResources& resources);

} // namespace tessera
