// Selectivity harness: which pixels one light's shading pass runs on (Device::setShadeCounts, the
// frame with the light minus the same frame without it) against geometric truth, each pixel's
// surface rebuilt in double from the stored D24 depth through the D3D (RH_ZO) projection.
// Image comparisons cannot see a light shaded where it adds 0; these counts can.
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "support/room_scene.h"

namespace tessera::test::selectivity {

constexpr std::uint32_t kW = 96, kH = 72;  // px: small frames, every light rendered twice

// One frame's per-pixel shader invocations and its depth buffer.
struct ShadeFrame {
    ShadeCounts counts;
    Rendered rendered;
};

inline ShadeFrame renderCounted(const TestScene& t, const std::string& technique, const nlohmann::json& options,
                                std::uint32_t samples = 1) {
    ShadeFrame f;
    f.counts = ShadeCounts(kW, kH);
    const SceneResources resources(t.scene, {}, TexturePolicy::AllLinear);
    Device device(DeviceConfig{32, 2});
    device.setShadeCounts(&f.counts);
    TechniqueContext ctx;
    ctx.device = &device;
    ctx.resources = &resources;
    ctx.camera = t.camera;
    ctx.width = kW;
    ctx.height = kH;
    ctx.sampleCount = samples;
    ctx.options = options;
    ctx.sceneFile = "memory.json";
    buildTechnique(technique, ctx, ctx.sceneFile).run(f.rendered.registry);
    return f;
}

// Invocations of `light`'s passes per pixel: the frame with only that light minus the frame
// without lights (every other pass, the G-buffer's included, is the same draw in both).
struct LightShading {
    std::vector<std::uint32_t> invocations;  // per pixel, row-major kW x kH
    ShadeFrame lit;                          // the lit frame (its depth buffer is the truth's input)
};

inline LightShading shadeOneLight(TestScene t, const Light& light, const std::string& technique, const nlohmann::json& options,
                                  std::uint32_t samples = 1) {
    t.scene.lights = {};
    const ShadeFrame dark = renderCounted(t, technique, options, samples);
    t.scene.lights = {light};
    LightShading s{{}, renderCounted(t, technique, options, samples)};
    s.invocations.resize(std::size_t(kW) * kH);
    for (std::size_t i = 0; i < s.invocations.size(); ++i) {
        REQUIRE(s.lit.counts.invocations[i] >= dark.counts.invocations[i]);
        s.invocations[i] = s.lit.counts.invocations[i] - dark.counts.invocations[i];
    }
    return s;
}

// A pixel's surface: the eye ray through its centre and, where the depth buffer holds a surface
// (depth < 1), the point the stored depth puts on it, in double.
struct PixelSurface {
    std::uint32_t xPx = 0, yPx = 0;  // window px
    bool surface = false;
    glm::dvec3 eyeWorld{0.0}, rayWorld{0.0};  // ray origin (the eye) and unit direction
    double tSurface = 0.0;                    // world distance from the eye to the surface
    glm::dvec3 posWorld{0.0};
};

// D3D projection (perspectiveRH_ZO, the techniques' "projection": "d3d"), inverted in double:
// NDC (x, y) = (2 (px + 0.5) / W - 1, 1 - 2 (py + 0.5) / H), z = the stored depth (sample `s`).
inline std::vector<PixelSurface> surfaces(const Surface& depth, const Camera& camera, std::uint32_t sample = 0) {
    const double aspect = double(kW) / double(kH);
    const glm::dmat4 clipFromView = glm::perspectiveRH_ZO(glm::radians(double(camera.fovYDeg)), aspect, double(camera.nearZ),
                                                          double(camera.farZ));
    const glm::dmat4 worldFromClip = glm::inverse(clipFromView * glm::dmat4(camera.viewFromWorld()));
    const glm::dmat4 worldFromView = glm::inverse(glm::dmat4(camera.viewFromWorld()));
    const glm::dvec3 eye = glm::dvec3(worldFromView * glm::dvec4(0, 0, 0, 1));
    std::vector<PixelSurface> out(std::size_t(kW) * kH);
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x) {
            PixelSurface& p = out[std::size_t(y) * kW + x];
            p.xPx = x;
            p.yPx = y;
            const double ndcX = 2.0 * (x + 0.5) / kW - 1.0, ndcY = 1.0 - 2.0 * (y + 0.5) / kH;
            const glm::dvec4 farH = worldFromClip * glm::dvec4(ndcX, ndcY, 1.0, 1.0);
            p.eyeWorld = eye;
            p.rayWorld = glm::normalize(glm::dvec3(farH) / farH.w - eye);
            const double d = double(depth.loadDepth(x, y, sample));
            if (!(d < 1.0)) continue;
            const glm::dvec4 h = worldFromClip * glm::dvec4(ndcX, ndcY, d, 1.0);
            p.surface = true;
            p.posWorld = glm::dvec3(h) / h.w;
            p.tSurface = glm::length(p.posWorld - eye);
        }
    return out;
}

// Signed "distance" to a light volume scaled by `scale` about the light: < 0 inside. For a point
// the sphere |p - c| - scale R; for a spot the capped cone the 3dgep and PR&C meshes draw (apex at
// the light, axis along its direction, length R, radius R tan(angle) at the base), measured as
// the larger of the axial excess and the radial excess (not a Euclidean distance, but 0 exactly
// on the surface, and at most the Euclidean distance from outside: margins are conservative).
// sphereCap: the spot's cone ends on the sphere of radius lengthScale R (forward's range test,
// the Cookbook's rounded base) instead of the flat base at lengthScale R along the axis.
inline double volumeExcess(const Light& l, const glm::dvec3& p, double radialScale, double lengthScale, bool sphereCap = false) {
    const glm::dvec3 c(l.positionWorld);
    const double r = double(l.range);
    if (l.type == LightType::Point) return glm::length(p - c) - radialScale * r;
    const glm::dvec3 axis = glm::normalize(glm::dvec3(l.directionWorld));
    const double along = glm::dot(p - c, axis);
    const double radial = glm::length((p - c) - along * axis);
    const double tanHalf = std::tan(glm::radians(double(l.spotHalfAngleDeg)));
    const double cosHalf = 1.0 / std::sqrt(1.0 + tanHalf * tanHalf * radialScale * radialScale);
    // radial excess measured perpendicular to the slanted side: (radial - along tan) cos
    const double side = (radial - along * tanHalf * radialScale) * cosHalf;
    const double cap = sphereCap ? glm::length(p - c) - lengthScale * r : along - lengthScale * r;
    return std::max({side, cap, -along});
}

// What a light's shaded pixel set was found to be against truth.
struct Tally {
    std::uint64_t truth = 0;     // surface pixels certainly inside the inner volume (must be shaded)
    std::uint64_t shaded = 0;    // pixels the light's passes ran on
    std::uint64_t missing = 0;   // truth pixels not shaded
    std::uint64_t extra = 0;     // shaded pixels certainly outside the allowed outer set
    std::uint64_t conservative = 0;  // shaded pixels outside the true volume but inside the outer bound
    std::uint64_t band = 0;      // pixels within the margin of a bound: not asserted
    std::uint64_t maxPerPixel = 0;
};

inline std::ostream& operator<<(std::ostream& os, const Tally& t) {
    return os << "truth " << t.truth << ", shaded " << t.shaded << ", missing " << t.missing << ", extra " << t.extra
              << ", conservative extra " << t.conservative << ", in margin bands " << t.band << ", max per pixel " << t.maxPerPixel;
}

// inner(p): < 0 where the light must reach (excess, world units); outer(p): > 0 where the
// technique may not shade. `margin` (world units) absorbs the D24 reconstruction and the 1/256 px
// vertex snapping: pixels within it of either bound are counted in `band` and not asserted.
// `exact` (excess of the true volume) splits the allowed extras off for the report.
inline Tally tally(const std::vector<std::uint32_t>& invocations, const std::vector<PixelSurface>& px,
                   const std::function<double(const PixelSurface&)>& inner, const std::function<double(const PixelSurface&)>& outer,
                   const std::function<double(const PixelSurface&)>& exact, double margin) {
    Tally t;
    for (std::size_t i = 0; i < px.size(); ++i) {
        const bool shaded = invocations[i] > 0;
        t.shaded += shaded;
        t.maxPerPixel = std::max<std::uint64_t>(t.maxPerPixel, invocations[i]);
        const double in = inner(px[i]), out = outer(px[i]);
        const bool mustShade = in < -margin, mayNotShade = out > margin;
        if (std::abs(in) <= margin || std::abs(out) <= margin) ++t.band;
        if (mustShade) {
            ++t.truth;
            if (!shaded && ++t.missing <= 3) MESSAGE("not shaded: pixel " << i % kW << ", " << i / kW << ", excess " << in);
        }
        if (shaded && mayNotShade) {
            ++t.extra;
            if (t.extra <= 3) MESSAGE("shaded outside the bound: pixel " << i % kW << ", " << i / kW << ", excess " << out);
        }
        if (shaded && !mayNotShade && exact(px[i]) > margin) ++t.conservative;
    }
    return t;
}

// Excess of a surface pixel against a light volume (no surface: +inf, never inside).
inline std::function<double(const PixelSurface&)> surfaceIn(const Light& l, double radialScale, double lengthScale,
                                                            bool sphereCap = false) {
    return [l, radialScale, lengthScale, sphereCap](const PixelSurface& p) {
        return p.surface ? volumeExcess(l, p.posWorld, radialScale, lengthScale, sphereCap) : HUGE_VAL;
    };
}

// The pixels a single-face volume test may shade: the pixel's ray enters the sphere of radius
// `radius` about the light and the surface (or the far plane) lies no farther than where the
// ray leaves it: everything in front of the volume's far side. < 0 inside; world units.
inline std::function<double(const PixelSurface&)> frontOfSphereFarSide(const Light& l, double radius) {
    return [c = glm::dvec3(l.positionWorld), radius](const PixelSurface& p) {
        const glm::dvec3 oc = p.eyeWorld - c;
        const double b = glm::dot(oc, p.rayWorld), cc = glm::dot(oc, oc) - radius * radius;
        const double disc = b * b - cc;
        if (disc < 0.0) return std::sqrt(std::max(0.0, glm::dot(oc, oc) - b * b)) - radius;  // miss: ray's distance - radius
        const double tFar = -b + std::sqrt(disc);
        if (tFar < 0.0) return -tFar;  // the sphere lies behind the eye
        return p.surface ? p.tSurface - tFar : HUGE_VAL;
    };
}

} // namespace tessera::test::selectivity
