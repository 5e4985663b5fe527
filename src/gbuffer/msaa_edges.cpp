// The MSAA edge detectors (gbuffer/msaa_edges.h): PR&C D3D11 Listing 11.17's coverage flag and the
// Intel 2010 sample's RequiresPerSampleShading.
#include <tessera/gbuffer/msaa_edges.h>

#include <cmath>

namespace tessera {

std::string_view edgeDetectorName(EdgeDetector detector) {
    switch (detector) {
    case EdgeDetector::Coverage: return "coverage";
    case EdgeDetector::DepthNormal: return "depthNormal";
    case EdgeDetector::All: return "all";
    }
    return "?";
}

bool depthNormalEdge(std::span<const EdgeSample> samples) {
    if (samples.size() < 2) return false;
    const EdgeSample& s0 = samples[0];
    // GBuffer.hlsl: maxZDelta = abs(ddx(z_0)) + abs(ddy(z_0)), stored by the G-buffer pass.
    const float maxZDelta = s0.viewZSlope;
    for (std::size_t i = 1; i < samples.size(); ++i) {
        const EdgeSample& si = samples[i];
        const bool surface0 = s0.viewZ != 0.0f, surfaceI = si.viewZ != 0.0f;
        if (surface0 != surfaceI) return true;
        if (!surface0) continue;  // both empty: the same (cleared) background
        if (std::fabs(si.viewZ - s0.viewZ) > maxZDelta) return true;
        if (glm::dot(si.normalView, s0.normalView) < kEdgeMinNormalDot) return true;
    }
    return false;
}

bool isEdgePixel(EdgeDetector detector, std::span<const EdgeSample> samples) {
    switch (detector) {
    case EdgeDetector::Coverage:
        for (const EdgeSample& s : samples)
            if (s.partial) return true;
        return false;
    case EdgeDetector::DepthNormal: return depthNormalEdge(samples);
    case EdgeDetector::All: return samples.size() > 1;
    }
    return false;
}

} // namespace tessera
