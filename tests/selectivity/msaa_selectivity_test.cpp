// MSAA deferred shading's per-sample set against geometric truth: a pixel is shaded once per
// sample exactly where its samples hold different surfaces (each sample's surface rebuilt in double
// from its stored depth at the sample's position and named floor, wall or none), and once per
// pixel elsewhere; counted per pixel by the rasterizer (ShadeCounts::perSample).
#include "selectivity/selectivity.h"

#include <array>

#include <tessera/raster/sample_pattern.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera::test::selectivity::msaa_selectivity_test {
namespace {

enum class Hit { None, Floor, Wall };

// The surface of each sample of each pixel (room_scene.h: floor y = 0, wall z = -6 from y = 0).
std::vector<std::array<Hit, 8>> sampleHits(const Surface& depth, const Camera& camera, std::uint32_t samples) {
    const double aspect = double(kW) / double(kH);
    const glm::dmat4 clipFromView = glm::perspectiveRH_ZO(glm::radians(double(camera.fovYDeg)), aspect, double(camera.nearZ),
                                                          double(camera.farZ));
    const glm::dmat4 worldFromClip = glm::inverse(clipFromView * glm::dmat4(camera.viewFromWorld()));
    const std::span<const SampleOffset> pattern = standardSamplePattern(samples);
    std::vector<std::array<Hit, 8>> out(std::size_t(kW) * kH);
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x)
            for (std::uint32_t s = 0; s < samples; ++s) {
                Hit& h = out[std::size_t(y) * kW + x][s];
                h = Hit::None;
                const double d = double(depth.loadDepth(x, y, s));
                if (!(d < 1.0)) continue;
                // Sample offsets are in 1/16 px from the pixel centre (D3D11 standard patterns).
                const double xPx = x + 0.5 + pattern[s].x / 16.0, yPx = y + 0.5 + pattern[s].y / 16.0;
                const glm::dvec4 hw = worldFromClip * glm::dvec4(2.0 * xPx / kW - 1.0, 1.0 - 2.0 * yPx / kH, d, 1.0);
                const glm::dvec3 p = glm::dvec3(hw) / hw.w;
                // 0.01 world units: a hundred times the D24 reconstruction error at these depths
                // (1.3e-4), far below the 0.05+ separating the floor from the wall's plane elsewhere.
                if (std::abs(p.y) < 0.01) h = Hit::Floor;
                else if (std::abs(p.z + 6.0) < 0.01) h = Hit::Wall;
                else FAIL("sample on no known surface at (" << x << ", " << y << ") sample " << s);
            }
    return out;
}

struct EdgeTally {
    std::uint64_t edges = 0, perSamplePixels = 0, missedEdges = 0, extraPerSample = 0, wrongCounts = 0;
};

EdgeTally checkEdges(const std::string& technique, const nlohmann::json& options, std::uint32_t samples) {
    // A directional light: the far-plane quad (deferred) or full-screen quad (classic) over every
    // pixel, so each surface sample is the light's to shade.
    const TestScene t = makeScene({}, {0.0f, 3.0f, 8.0f}, 0.05f);
    const Light light = makeLight(LightType::Directional, {0, 0, 0}, {-0.3f, -1.0f, -0.5f}, 1.0f, {1, 1, 1});
    LightShading s = shadeOneLight(t, light, technique, options, samples);
    // The dark frame's per-sample counts are the G-buffer's (none) and the light passes' (none).
    const std::vector<std::array<Hit, 8>> hits = sampleHits(s.lit.rendered.get("depth"), t.camera, samples);
    EdgeTally e;
    for (std::size_t i = 0; i < hits.size(); ++i) {
        std::uint32_t surfaceSamples = 0;
        bool edge = false;
        for (std::uint32_t k = 0; k < samples; ++k) {
            surfaceSamples += hits[i][k] != Hit::None;
            edge = edge || hits[i][k] != hits[i][0];
        }
        const std::uint32_t perSample = s.lit.counts.perSample[i], total = s.invocations[i];
        e.edges += edge;
        e.perSamplePixels += perSample > 0;
        if (edge && surfaceSamples > 0) {
            if (perSample == 0) ++e.missedEdges;
            // shaded once per surface sample, and not per pixel besides
            else if (perSample != surfaceSamples || total != perSample) ++e.wrongCounts;
        } else if (!edge) {
            if (perSample > 0) ++e.extraPerSample;
            // one per pixel; two where the quad's diagonal splits the pixel's samples
            else if (surfaceSamples > 0 && (total < 1 || total > 2)) ++e.wrongCounts;
        }
    }
    MESSAGE(technique << " " << samples << "x " << options.dump() << ": " << e.edges << " edge pixels, " << e.perSamplePixels
                      << " shaded per sample, " << e.missedEdges << " edges missed, " << e.extraPerSample
                      << " one-surface pixels shaded per sample, " << e.wrongCounts << " with wrong counts");
    return e;
}

} // namespace

TEST_CASE("selectivity msaa deferred: Intel's depth/normal test shades per sample exactly the pixels whose samples hold two surfaces") {
    for (const std::uint32_t samples : {2u, 4u, 8u}) {
        CAPTURE(samples);
        const EdgeTally e = checkEdges("deferred", {{"projection", "d3d"}, {"msaaEdges", "depthNormal"}}, samples);
        CHECK(e.edges > 50);
        CHECK(e.missedEdges == 0);
        CHECK(e.extraPerSample == 0);
        CHECK(e.wrongCounts == 0);
    }
}

TEST_CASE("selectivity msaa deferred-classic: PR&C's coverage flag shades every two-surface pixel per sample (a conservative superset)") {
    // Listing 11.17's flag marks every pixel a triangle covered partly: the floor's and the wall's
    // own diagonals too, so one-surface pixels along them are shaded per sample (reported).
    for (const std::uint32_t samples : {2u, 4u, 8u}) {
        CAPTURE(samples);
        const EdgeTally e = checkEdges("deferred-classic", {{"msaaEdges", "coverage"}}, samples);
        CHECK(e.edges > 50);
        CHECK(e.missedEdges == 0);
        CHECK(e.wrongCounts == 0);
    }
}

} // namespace tessera::test::selectivity::msaa_selectivity_test
