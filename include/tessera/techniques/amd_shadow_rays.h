// GPU Pro 4 ch. 5 §5.6.2, shadows from many lights by ray casting, after the light culling:
// ray-cast job creation (one 32-bit job per pixel and overlapping light of its tile list), ray
// casting (one occlusion ray per job, Embree: raytrace/shadow_ray_scene.h) into a per-pixel int4
// mask of 128 light slots set by atomic OR, read by final shading (forward_plus_amd.h).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/techniques/amd_light_culling.h>

namespace tessera {

class ShadowRayScene;

// A job: pixel index (y * width + x) in the high 25 bits, the light's slot in its tile list in
// the low 7 (the chapter packs "pixel index + light index" into 32 bits without the split; a
// slot rather than the global light index fits beside any pixel index of a 5792 x 5792 frame).
// Limits: slots 0..127 (the int4 mask's 128 bits), frames of at most 2^25 = 33,554,432 pixels.
inline constexpr std::uint32_t kShadowSlotBits = 7;
inline constexpr std::uint32_t kShadowMaxSlots = 1u << kShadowSlotBits;           // 128 light slots per pixel
inline constexpr std::uint64_t kShadowMaxPixels = std::uint64_t{1} << (32 - kShadowSlotBits);  // 33,554,432 px
inline constexpr std::uint32_t kShadowMaskWords = kShadowMaxSlots / 32;          // 4: one int4 per pixel
// Rays stop this fraction of the way short of the light (t in [0, 1 - 2^-10] of origin -> light)
// so that a light lying on a surface is not shadowed by that surface.
inline constexpr float kShadowRayEndFraction = 1.0f / 1024.0f;

constexpr std::uint32_t packShadowJob(std::uint32_t pixelIndex, std::uint32_t slot) {
    return (pixelIndex << kShadowSlotBits) | slot;
}
constexpr std::uint32_t shadowJobPixel(std::uint32_t job) { return job >> kShadowSlotBits; }
constexpr std::uint32_t shadowJobSlot(std::uint32_t job) { return job & (kShadowMaxSlots - 1u); }
// §10 item 9: slot s of a pixel's mask is mask[s >> 5] & (1 << (s & 31)).
constexpr std::uint32_t shadowMaskWord(std::uint32_t slot) { return slot >> 5; }
constexpr std::uint32_t shadowMaskFlag(std::uint32_t slot) { return 1u << (slot & 31u); }
inline bool shadowMaskBit(std::span<const std::uint32_t, kShadowMaskWords> mask, std::uint32_t slot) {
    return (mask[shadowMaskWord(slot)] & shadowMaskFlag(slot)) != 0;
}

// What job creation does with a light behind the surface (dot(N, L) <= 0 for the G-pass normal):
//   Mask (default): no ray; its bit is set (the surface shadows it; AMD's specular lobe, which can
//         be non-zero there, is masked too);
//   Lit:  no ray, no bit (the light shades as without shadows);
//   Cast: a ray like any other.
enum class ShadowBackfaces : std::uint8_t { Mask, Lit, Cast };
// Lights past slot 127 of a tile list: Lit (default: shaded unshadowed) or Unlit (dropped).
enum class ShadowOverflow : std::uint8_t { Lit, Unlit };

struct ShadowRayOptions {
    float normalOffset = 0.01f;  // world units along the G-pass normal from the rebuilt position
    ShadowBackfaces backfaces = ShadowBackfaces::Mask;
    ShadowOverflow overflow = ShadowOverflow::Lit;
};

// A light as the job creation sees it (scene light index order; VPLs never cast).
struct ShadowCaster {
    glm::vec3 positionWorld{0.0f};   // point centre or spot apex
    glm::vec3 directionWorld{0.0f};  // spot axis (unit)
    float range = 0.0f;              // world units
    float cosCone = -2.0f;           // spot: cos(half angle); point: -2 (no cone)
    bool castsShadows = false;
};

// The per-pixel inputs: the pre-pass depth (window z, 1.0 where nothing was drawn), the G-pass
// normal, and the inverse of clipFromWorld for the rebuild.
struct ShadowPixels {
    std::uint32_t width = 0, height = 0;
    std::span<const float> depthWindow;       // width * height
    std::span<const glm::vec4> normalWorld;   // width * height, xyz unit
    glm::dmat4 worldFromClip{1.0};
};

// The surface point of a pixel, rebuilt from depth by inverse projection (§5.6.2 "primary-hit
// position"): NDC (2 (x + 0.5) / W - 1, 1 - 2 (y + 0.5) / H, depth), times worldFromClip in
// double, divided by w, rounded to float.
glm::vec3 shadowSurfacePoint(const ShadowPixels& pixels, std::uint32_t pixelIndex);
// The ray origin: the surface point plus normalOffset * normal (float).
glm::vec3 shadowRayOrigin(const ShadowPixels& pixels, std::uint32_t pixelIndex, float normalOffset);

struct ShadowJobStats {
    std::uint64_t jobs = 0;
    std::uint64_t occluded = 0;          // rays that hit something
    std::uint64_t backfaceMasked = 0;    // slots masked without a ray (ShadowBackfaces::Mask)
    std::uint64_t overflowPixels = 0;    // pixels whose tile lists more than 128 lights
    std::uint64_t overflowLights = 0;    // (pixel, light) pairs past slot 127 that overlap
};

struct ShadowJobs {
    std::vector<std::uint32_t> jobs;     // row-major pixel order, slots ascending
    std::vector<std::uint32_t> mask;     // kShadowMaskWords per pixel; job creation sets backface bits
    ShadowJobStats stats;
};

// Ray-cast job creation: for each drawn pixel, each slot s < 128 of its tile's list whose light
// casts shadows and overlaps the pixel (point: distance < range; spot: also cos angle to the axis
// > cosCone) makes a job, unless it is behind the surface (see ShadowBackfaces). Runs rows in
// parallel and concatenates them in row order: the same buffer at any thread count.
ShadowJobs createShadowJobs(const ShadowPixels& pixels, const AmdTileLightLists& lists, std::span<const ShadowCaster> lights,
                            const ShadowRayOptions& options);

// Ray casting: one occlusion ray per job from shadowRayOrigin to the light (t up to
// 1 - kShadowRayEndFraction), setting the job's bit with an atomic OR on a hit.
void castShadowJobs(const ShadowPixels& pixels, const AmdTileLightLists& lists, std::span<const ShadowCaster> lights,
                    const ShadowRayScene& occluders, const ShadowRayOptions& options, ShadowJobs& jobs);

} // namespace tessera
