// What one light added at the watched pixel (`tessera probe`): the record the light loops of
// every lighting model leave while a pixel watch (raster/pixel_watch.h) has the watched pixel's
// shader running. Kept here, below the rasterizer, so that the lighting code records it without
// depending on the rasterizer.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include <glm/vec4.hpp>
#include <glm/ext/vector_double4.hpp>

namespace tessera {

// One light as the watched pixel's shader evaluated it. The light loops leave these while
// watchedLightTerms() is set, which the rasterizer (and the tiled compute passes) do only around
// the watched pixel's shader: elsewhere the loops pay one thread-local load per pixel.
struct LightTerm {
    // Why the loop added nothing without evaluating the light (None: it was evaluated).
    enum class Skip : std::uint8_t { None, Disabled, OutOfRange, OutsideCone };
    std::uint32_t light = 0;  // scene light index
    Skip skip = Skip::None;
    float distance = 0.0f;    // surface to light, in the shading space's units (0: directional)
    float range = std::numeric_limits<float>::infinity();  // where the light's falloff ends
    float nDotL = 0.0f;       // dot(N, L) before clamping: <= 0 means the surface faces away
    float falloff = 1.0f;     // distance attenuation (1 where the model has none)
    float cone = 1.0f;        // spot cone factor (1 for other lights)
    glm::vec4 diffuse{0.0f}, specular{0.0f};  // what the light added (combined: all of it in diffuse)
    bool combined = false;    // the model adds one colour per light (Intel's AccumulateBRDF)
};

// LightTerm::light of a pass that is no scene light (the Cookbook's ambient-only quad).
inline constexpr std::uint32_t kAmbientLightTerm = 0xFFFFFFFFu;

// The material the watched pixel's shader gathered before lighting (textures sampled, each
// texture's rule applied): what the light terms are multiplied by, so that the shader's output can
// be rebuilt from the probe's numbers. Recorded by the Phong surface gather (shading/phong_surface.h).
struct WatchedSurface {
    bool recorded = false;
    glm::dvec4 diffuse{0.0}, ambient{0.0}, emissive{0.0}, specular{0.0};  // ambient includes GlobalAmbient
    double alpha = 1.0, specularPower = 0.0;
};

namespace detail {
inline thread_local std::vector<LightTerm>* tWatchedLightTerms = nullptr;
inline thread_local WatchedSurface* tWatchedSurface = nullptr;
} // namespace detail

// Where the light loops record LightTerms now: non-null only while the watched pixel shades.
inline std::vector<LightTerm>* watchedLightTerms() { return detail::tWatchedLightTerms; }
inline void setWatchedLightTerms(std::vector<LightTerm>* terms) { detail::tWatchedLightTerms = terms; }
// Where the surface gather records the watched pixel's material: non-null only while it shades.
inline WatchedSurface* watchedSurface() { return detail::tWatchedSurface; }
inline void setWatchedSurface(WatchedSurface* surface) { detail::tWatchedSurface = surface; }

} // namespace tessera
