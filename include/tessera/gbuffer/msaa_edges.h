// Edge pixels of a multisampled G-buffer: the pixels whose samples hold different surfaces, which
// the deferred techniques shade once per sample (every other pixel once, from sample 0). Two
// detectors: the G-buffer pass's coverage (PR&C D3D11 §11.5, Listing 11.17) and Intel's depth and
// normal comparison (Lauritzen 2010 sample, GBuffer.hlsl RequiresPerSampleShading).
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include <glm/glm.hpp>

namespace tessera {

// What the G-buffer pass stores per sample for the detectors (beside each technique's own
// layout, so that the test does not depend on its encoding). viewZ = 0 is the cleared value:
// no surface at this sample (view depth is > 0 in front of the eye).
struct EdgeSample {
    glm::vec3 normalView{0.0f};  // the shading normal, normalized
    float viewZ = 0.0f;          // distance along the view axis, > 0
    float viewZSlope = 0.0f;     // |d viewZ/dx| + |d viewZ/dy| over the 2x2 quad, per px
    bool partial = false;        // the triangle that wrote the sample did not cover every sample
};

enum class EdgeDetector : std::uint8_t {
    Coverage,     // PR&C Listing 11.17: edgePixel = coverageMask != FullMask
    DepthNormal,  // Intel: |z_i - z_0| > |dz/dx| + |dz/dy| or dot(n_i, n_0) < 0.99
    All,          // every pixel per sample (the per-sample-frequency shader of PR&C §11.5)
};

// "coverage", "depthNormal", "all" (the option values), and back.
std::string_view edgeDetectorName(EdgeDetector detector);

// Listing 11.17's flag for a triangle's pixel: its rasterizer coverage is not the full mask.
constexpr bool partialCoverage(std::uint32_t coverage, std::uint32_t sampleCount) {
    return coverage != (sampleCount >= 32 ? ~0u : (1u << sampleCount) - 1u);
}

// Intel's minimum dot product of two samples' normals on one surface.
inline constexpr float kEdgeMinNormalDot = 0.99f;

// Intel's RequiresPerSampleShading over a pixel's samples: every sample i > 0 against sample 0.
// Samples without a surface (viewZ == 0) equal each other and differ from any surface.
bool depthNormalEdge(std::span<const EdgeSample> samples);

// Whether `detector` shades this pixel's samples one by one. Coverage: any sample was written by
// a triangle that covered the pixel partly (a later triangle that covers it fully overwrites the
// flag with its own, so only surfaces that still show count).
bool isEdgePixel(EdgeDetector detector, std::span<const EdgeSample> samples);

} // namespace tessera
