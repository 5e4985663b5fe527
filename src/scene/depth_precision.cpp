// Depth-buffer resolution of a camera and the scene-level warning (scene/depth_precision.h), in
// double: the quantities describe binary32 and D24 depth, they are not computed with them.
#include <tessera/scene/depth_precision.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace tessera {

double DepthResolution::stepAt(double distance) const {
    if (!std::isfinite(farZ)) return kDepthStepNearOne * distance * distance / nearZ;
    return kDepthStepNearOne * distance * distance * (farZ - nearZ) / (farZ * nearZ);
}

DepthResolution depthResolution(const Camera& camera) {
    DepthResolution r;
    r.nearZ = camera.nearZ;
    r.farZ = camera.farZ;
    const double ratio = std::isfinite(r.farZ) ? (r.farZ - r.nearZ) / r.farZ : 1.0;  // (f - n) / f
    r.collapseDistance = r.nearZ / (0.5 * kDepthStepNearOne * ratio + (std::isfinite(r.farZ) ? r.nearZ / r.farZ : 0.0));
    return r;
}

namespace {
std::string distance(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    return text;
}
} // namespace

std::optional<std::string> depthPrecisionWarning(const Camera& camera, const Bounds& sceneWorld) {
    if (camera.projection != ProjectionKind::Perspective || sceneWorld.empty()) return std::nullopt;
    const glm::dmat4 viewFromWorld(camera.viewFromWorld());
    double farthest = 0.0;
    for (int i = 0; i < 8; ++i) {
        const glm::dvec3 cornerWorld((i & 1) ? sceneWorld.maxWorld.x : sceneWorld.minWorld.x,
                                     (i & 2) ? sceneWorld.maxWorld.y : sceneWorld.minWorld.y,
                                     (i & 4) ? sceneWorld.maxWorld.z : sceneWorld.minWorld.z);
        farthest = std::max(farthest, -(viewFromWorld * glm::dvec4(cornerWorld, 1.0)).z);
    }
    const DepthResolution r = depthResolution(camera);
    farthest = std::min(farthest, r.farZ);
    if (!(farthest > r.nearZ)) return std::nullopt;
    // The near plane at which the farthest point gets a 1% step: step z^2 / n = 0.01 z (f >> n).
    const std::string advice = "a near plane of at least " + distance(kDepthStepNearOne * farthest / kDepthWarnRelativeStep) +
                               " resolves the scene to 1% (near " + distance(r.nearZ) + ", far " + distance(r.farZ) + ")";
    // Depth reaches 1.0 at the far plane by construction; only a collapse well inside the frustum
    // (before half the far distance) is the precision problem.
    if (farthest > r.collapseDistance && r.collapseDistance < 0.5 * r.farZ)
        return "the depth range collapses: surfaces farther than " + distance(r.collapseDistance) +
               " from the eye (the scene reaches " + distance(farthest) +
               ") get depth 1.0, the cleared value, so a LESS depth test (forward) discards them and a depth pre-pass "
               "cannot order them; " + advice;
    const double relative = r.stepAt(farthest) / farthest;
    if (relative > kDepthWarnRelativeStep)
        return "the depth buffer resolves only " + distance(r.stepAt(farthest)) + " view units at distance " + distance(farthest) +
               " (" + distance(relative * 100.0) +
               "% of it): depth tests, tile depth bounds and stencil light volumes are no finer than that; " + advice;
    return std::nullopt;
}

} // namespace tessera
