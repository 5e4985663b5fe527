// MSAA in the deferred techniques against geometric truth: three flat quads under one directional
// light (no specular), so every surface has one colour wherever it is shaded. At every edge pixel
// each sample must hold the colour of the surface a ray through that sample's position hits; every
// pixel whose samples see different surfaces must be an edge pixel; a pixel inside one triangle is
// shaded once per light; results do not depend on the thread count. Plus the edge detectors' math.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include <tessera/gbuffer/msaa_edges.h>
#include <tessera/raster/sample_pattern.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/technique.h>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_msaa_deferred_test {

using namespace tessera;
using namespace tessera::test;

namespace {

constexpr std::uint32_t kW = 96, kH = 72;  // px

// The quads (world space; corners origin, +u, +u+v, +v) and their materials.
struct FlatQuad {
    glm::dvec3 origin, u, v;
};
const std::array<FlatQuad, 3> kQuads{{
    {{-5.0, -4.0, -6.0}, {10.0, 0.0, 0.0}, {0.0, 8.0, 0.0}},   // back wall, facing +z
    {{-2.3, -1.6, -2.0}, {3.0, 0.0, -1.5}, {0.0, 3.1, 0.0}},   // tilted about y
    {{0.4, -2.1, 1.0}, {2.6, 0.0, 0.0}, {0.0, 2.1, -1.1}},     // tilted about x
}};

TestScene flatScene() {
    TestScene t;
    const glm::vec4 colours[3] = {{0.8f, 0.3f, 0.2f, 1.0f}, {0.2f, 0.7f, 0.3f, 1.0f}, {0.25f, 0.35f, 0.9f, 1.0f}};
    Mesh mesh;
    for (int k = 0; k < 3; ++k) {
        Material m;
        m.baseColorFactor = colours[k];
        m.roughnessFactor = 1.0f;  // specular power 0: no specular term, lighting independent of position
        m.metallicFactor = 0.0f;
        t.scene.materials.push_back(m);
        mesh.primitives.push_back(quad(glm::vec3(kQuads[std::size_t(k)].origin), glm::vec3(kQuads[std::size_t(k)].u),
                                       glm::vec3(kQuads[std::size_t(k)].v), k));
    }
    t.scene.meshes.push_back(mesh);
    t.scene.instances.push_back(MeshInstance{0, glm::mat4(1.0f), "quads"});
    t.scene.lights = {makeLight(LightType::Directional, {0, 0, 0}, {-0.3f, -0.5f, -1.0f}, 1.0f, {1.0f, 0.95f, 0.9f})};
    t.camera.positionWorld = {0.3f, 0.2f, 8.0f};
    t.camera.orientationWorld = glm::quatLookAtRH(glm::normalize(glm::vec3(0.0f, -0.3f, 0.0f) - t.camera.positionWorld), glm::vec3(0, 1, 0));
    t.camera.nearZ = 0.1f;
    t.camera.farZ = 100.0f;
    return t;
}

// Which quad a ray through window point (wx, wy) hits first (-1: none), and whether the point
// lies within `margin` px of a projected quad edge (where the rasterizer's snapping may decide
// otherwise than exact arithmetic).
struct Owner {
    int quad = -1;
    bool nearEdge = false;
};

class RayCaster {
public:
    explicit RayCaster(const Camera& camera) {
        const glm::mat4 proj = projection3dgep(camera, float(kW) / float(kH), ProjectionConvention::D3d);
        mP00 = proj[0][0];
        mP11 = proj[1][1];
        mWorldFromView = glm::inverse(glm::dmat4(camera.viewFromWorld()));
        mClipFromWorld = glm::dmat4(proj) * glm::dmat4(camera.viewFromWorld());
        for (const FlatQuad& q : kQuads) {
            std::array<glm::dvec2, 4> w;
            const glm::dvec3 corners[4] = {q.origin, q.origin + q.u, q.origin + q.u + q.v, q.origin + q.v};
            for (int i = 0; i < 4; ++i) {
                const glm::dvec4 c = mClipFromWorld * glm::dvec4(corners[i], 1.0);
                w[std::size_t(i)] = {(c.x / c.w + 1.0) * 0.5 * kW, (1.0 - c.y / c.w) * 0.5 * kH};
            }
            mWindowCorners.push_back(w);
        }
    }
    Owner owner(double wx, double wy, double margin) const {
        const glm::dvec3 dirView((2.0 * wx / kW - 1.0) / mP00, (1.0 - 2.0 * wy / kH) / mP11, -1.0);
        const glm::dvec3 origin(mWorldFromView[3]);
        const glm::dvec3 dir = glm::dmat3(mWorldFromView) * dirView;
        Owner o;
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < kQuads.size(); ++k) {
            const FlatQuad& q = kQuads[k];
            const glm::dvec3 n = glm::cross(q.u, q.v);
            const double t = glm::dot(q.origin - origin, n) / glm::dot(dir, n);
            const glm::dvec3 p = origin + t * dir - q.origin;
            const double a = glm::dot(p, q.u) / glm::dot(q.u, q.u), b = glm::dot(p, q.v) / glm::dot(q.v, q.v);
            if (t > 0.0 && a >= 0.0 && a <= 1.0 && b >= 0.0 && b <= 1.0 && t < best) {
                best = t;
                o.quad = int(k);
            }
            for (int i = 0; i < 4; ++i)
                o.nearEdge = o.nearEdge || segmentDistance({wx, wy}, mWindowCorners[k][std::size_t(i)],
                                                           mWindowCorners[k][std::size_t((i + 1) % 4)]) < margin;
        }
        return o;
    }

private:
    static double segmentDistance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
        const glm::dvec2 ab = b - a;
        const double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
        return glm::length(p - (a + t * ab));
    }
    double mP00 = 1.0, mP11 = 1.0;
    glm::dmat4 mWorldFromView{1.0}, mClipFromWorld{1.0};
    std::vector<std::array<glm::dvec2, 4>> mWindowCorners;
};

std::array<std::uint8_t, 4> texelBytes(const Surface& s, std::uint32_t x, std::uint32_t y, std::uint32_t i) {
    std::array<std::uint8_t, 4> b{};
    std::memcpy(b.data(), s.texel(x, y, i), 4);
    return b;
}

// The per-sample checks of one MSAA render: edge-pixel samples compared, those with another
// surface's colour, and pixels whose samples see different surfaces but are not marked.
struct RayCheck {
    std::size_t compared = 0, wrong = 0, notMarked = 0;
};
RayCheck checkAgainstRays(Rendered& r, std::uint32_t samples, const RayCaster& rays, bool everyPixelEdge) {
    const Surface& back = r.get(backBufferTarget(samples));
    const Surface& edges = r.get("edges");
    const std::span<const SampleOffset> pattern = standardSamplePattern(samples);
    constexpr double kMarginPx = 0.01;  // > the 1/512 px vertex snapping, with room for float setup
    std::vector<std::vector<Owner>> owners(std::size_t(kW) * kH);
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x)
            for (std::uint32_t i = 0; i < samples; ++i)
                owners[y * kW + x].push_back(rays.owner(x + 0.5 + pattern[i].x / 16.0, y + 0.5 + pattern[i].y / 16.0, kMarginPx));
    // Each surface's colour (and the background's, index 3) from pixels that lie wholly on it:
    // one value per surface wherever it is shaded (the premise of the scene).
    std::map<int, std::array<std::uint8_t, 4>> colourOf;
    std::size_t premiseFailures = 0;
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x) {
            const auto& o = owners[y * kW + x];
            bool whole = true;
            for (const Owner& s : o) whole = whole && !s.nearEdge && s.quad == o[0].quad;
            if (!whole) continue;
            const auto c = texelBytes(back, x, y, 0);
            const auto [it, inserted] = colourOf.emplace(o[0].quad, c);
            if (!inserted && it->second != c) ++premiseFailures;
        }
    CHECK(premiseFailures == 0);
    REQUIRE(colourOf.size() == 4);  // three quads and the background are each visible somewhere
    for (const auto& [a, ca] : colourOf)
        for (const auto& [b, cb] : colourOf)
            if (a != b) CHECK(ca != cb);  // so that a sample shaded from the wrong surface shows
    std::size_t compared = 0, notMarked = 0, wrong = 0;
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x) {
            const auto& o = owners[y * kW + x];
            const bool edge = edges.load(x, y, 0).x != 0.0f;
            if (everyPixelEdge) CHECK(edge);
            bool mixed = false;
            for (const Owner& s : o) mixed = mixed || (!s.nearEdge && !o[0].nearEdge && s.quad != o[0].quad);
            if (mixed && !edge) ++notMarked;
            if (!edge) continue;
            for (std::uint32_t i = 0; i < samples; ++i) {
                if (o[i].nearEdge) continue;
                ++compared;
                if (texelBytes(back, x, y, i) != colourOf[o[i].quad]) ++wrong;
            }
        }
    return {compared, wrong, notMarked};
}

} // namespace

TEST_CASE("msaa edges: Listing 11.17's coverage flag and Intel's depth/normal test on worked samples") {
    // PR&C §11.5 worked values: 4x, coverage 0xF -> 0 (not an edge), 0x7 -> 1.
    CHECK_FALSE(partialCoverage(0xFu, 4));
    CHECK(partialCoverage(0x7u, 4));
    CHECK_FALSE(partialCoverage(0xFFu, 8));
    CHECK(partialCoverage(0x1u, 2));
    const glm::vec3 up(0.0f, 0.0f, 1.0f);
    // One plane: z within the sample-0 slope (|dz/dx| + |dz/dy| = 0.5) -> one surface.
    std::array<EdgeSample, 4> s{{{up, 10.0f, 0.5f, false}, {up, 10.4f, 0.5f, false}, {up, 9.6f, 0.5f, false}, {up, 10.0f, 0.5f, false}}};
    CHECK_FALSE(depthNormalEdge(s));
    s[2].viewZ = 10.6f;  // 0.6 > 0.5: a depth discontinuity
    CHECK(depthNormalEdge(s));
    s[2].viewZ = 10.0f;
    // cos 8.11 deg = 0.99: a normal 9 deg away fails, 7 deg away passes.
    s[1].normalView = glm::vec3(std::sin(glm::radians(9.0f)), 0.0f, std::cos(glm::radians(9.0f)));
    CHECK(depthNormalEdge(s));
    s[1].normalView = glm::vec3(std::sin(glm::radians(7.0f)), 0.0f, std::cos(glm::radians(7.0f)));
    CHECK_FALSE(depthNormalEdge(s));
    // No surface (viewZ 0, the clear value) next to a surface: an edge; all empty: not one.
    s[3] = EdgeSample{};
    CHECK(depthNormalEdge(s));
    const std::array<EdgeSample, 4> empty{};
    CHECK_FALSE(depthNormalEdge(empty));
    CHECK_FALSE(isEdgePixel(EdgeDetector::Coverage, empty));
    CHECK(isEdgePixel(EdgeDetector::All, empty));
    std::array<EdgeSample, 2> partial{{{up, 5.0f, 0.0f, false}, {up, 5.0f, 0.0f, true}}};
    CHECK(isEdgePixel(EdgeDetector::Coverage, partial));
    CHECK_FALSE(isEdgePixel(EdgeDetector::DepthNormal, partial));  // one surface, split over two triangles
}

TEST_CASE("msaa deferred: every edge sample holds the colour of the surface at its sample position") {
    const TestScene t = flatScene();
    const RayCaster rays(t.camera);
    const std::vector<std::pair<std::string, nlohmann::json>> runs{
        {"deferred", {{"projection", "d3d"}}},
        {"deferred", {{"projection", "d3d"}, {"gbuffer", "float"}, {"accumulate", "lighting"}}},
        {"deferred-killzone", {{"projection", "d3d"}}},
        {"deferred-classic", nlohmann::json::object()},
        {"deferred-classic", {{"gbuffer", "optimized"}, {"normalEncoding", "safe"}, {"lightGeometry", "scissor"}}},
        {"deferred-classic", {{"stencil", true}, {"lightGeometry", "volumes"}}},
        {"light-prepass", {{"msaaFinal", "perSample"}}},
        {"deferred-cookbook", nlohmann::json::object()},
        {"deferred-cookbook", {{"lightGeometry", "quads"}, {"background", "stencil"}}},
        {"tiled-deferred", {{"shading", "3dgep"}}},
        {"tiled-deferred", {{"shading", "3dgep"}, {"gbuffer", "float"}, {"position", "gbuffer"}}},
    };
    for (const auto& run : runs)
        for (const char* detector : {"coverage", "depthNormal", "all"})
            for (const std::uint32_t samples : {2u, 4u, 8u}) {
                // Named copies: clang 14 cannot capture structured bindings in CAPTURE's lambda.
                const std::string& technique = run.first;
                const std::string optionsText = run.second.dump();
                CAPTURE(technique);
                CAPTURE(optionsText);
                CAPTURE(detector);
                CAPTURE(samples);
                nlohmann::json o = run.second;
                o["msaaEdges"] = detector;
                Rendered r;
                DrawStats stats;
                render(t, technique, o, r, Precision::Exact, 2, {kW, kH}, {}, samples, &stats);
                const RayCheck c = checkAgainstRays(r, samples, rays, std::string(detector) == "all");
                CHECK(c.compared > 100);  // the scene has edges to check
                CHECK(c.notMarked == 0);  // the detector misses no pixel whose samples see different surfaces
                CHECK(c.wrong == 0);      // every edge sample holds its own surface's colour
                CHECK(stats.edgePixels > 0);
                CHECK(stats.edgeTestedPixels == std::uint64_t(kW) * kH);
            }
}

TEST_CASE("msaa light-prepass: Listing 11.19's coverage loop averages light-buffer samples of surfaces in front (ERRATA #30)") {
    // D3D11's SV_Coverage input is the rasterizer's coverage, taken before the depth test: a
    // triangle that covers a pixel wholly but shows in only some samples (another surface in
    // front of the rest) averages the light buffer over every sample, the front surface's too,
    // and writes that to its own samples. msaaFinal perSample shades edge pixels per sample.
    const TestScene t = flatScene();
    const RayCaster rays(t.camera);
    for (const std::uint32_t samples : {2u, 4u, 8u}) {
        CAPTURE(samples);
        Rendered faithful, corrected;
        render(t, "light-prepass", nlohmann::json::object(), faithful, Precision::Exact, 2, {kW, kH}, {}, samples);
        render(t, "light-prepass", {{"msaaFinal", "perSample"}}, corrected, Precision::Exact, 2, {kW, kH}, {}, samples);
        const RayCheck f = checkAgainstRays(faithful, samples, rays, false);
        const RayCheck c = checkAgainstRays(corrected, samples, rays, false);
        MESSAGE(samples << "x: coverage loop " << f.wrong << " of " << f.compared << " edge samples wrong, per sample " << c.wrong);
        CHECK(f.wrong > 0);
        CHECK(c.wrong == 0);
    }
}

TEST_CASE("msaa deferred: a pixel inside one surface is shaded once per light, an edge pixel once per sample") {
    // deferred-classic with full-screen quads and no stencil mask: each light covers every pixel.
    // Pixel-shader calls of a frame = G-buffer + edge pass (one per pixel) + lights, and the lights'
    // are (pixels - edge pixels) x lights per pixel plus edge pixels x samples x lights per sample.
    // The same frame without lights gives the first two (the same G-buffer and edges).
    TestScene t = flatScene();
    t.scene.lights.push_back(makeLight(LightType::Point, {0.5f, 0.5f, 2.0f}, {0, 0, -1}, 50.0f, {0.3f, 0.3f, 0.3f}));
    const std::uint64_t lights = t.scene.lights.size();
    TestScene dark = t;
    dark.scene.lights.clear();
    const std::uint64_t pixels = std::uint64_t(kW) * kH;
    const nlohmann::json quads = {{"lightGeometry", "quads"}};
    for (const std::uint32_t samples : {2u, 4u, 8u}) {
        CAPTURE(samples);
        Rendered r, r0;
        DrawStats lit, unlit;
        render(t, "deferred-classic", quads, r, Precision::Exact, 2, {kW, kH}, {}, samples, &lit);
        render(dark, "deferred-classic", quads, r0, Precision::Exact, 2, {kW, kH}, {}, samples, &unlit);
        const std::uint64_t edges = lit.edgePixels;
        REQUIRE(edges > 0);
        CHECK(edges < pixels / 4);
        CHECK(unlit.edgePixels == edges);
        CHECK(lit.psPerSample == edges * samples * lights);
        CHECK(unlit.psPerSample == 0);
        // The lights' full-screen quads are two triangles each: a non-edge pixel whose samples lie
        // on both sides of the quad's diagonal (window (W, 0) to (0, H)) is shaded once by each.
        // Samples exactly on the diagonal go to one side by the fill rule: bounds for those.
        const Surface& edgeBuffer = r.get("edges");
        const std::span<const SampleOffset> pattern = standardSamplePattern(samples);
        std::uint64_t splitMin = 0, splitMax = 0;
        for (std::uint32_t y = 0; y < kH; ++y)
            for (std::uint32_t x = 0; x < kW; ++x) {
                if (edgeBuffer.load(x, y, 0).x != 0.0f) continue;
                int below = 0, above = 0, on = 0;  // sign of H x + W y - W H, in 1/16 px units
                for (std::uint32_t i = 0; i < samples; ++i) {
                    const std::int64_t X = 16 * std::int64_t(x) + 8 + pattern[i].x, Y = 16 * std::int64_t(y) + 8 + pattern[i].y;
                    const std::int64_t side = std::int64_t(kH) * X + std::int64_t(kW) * Y - 16 * std::int64_t(kW) * kH;
                    (side < 0 ? below : side > 0 ? above : on) += 1;
                }
                if (below > 0 && above > 0) ++splitMin;
                if (below + above > 0 && (below > 0 || on > 0) && (above > 0 || on > 0) && !(on > 0 && below + above == 0)) ++splitMax;
            }
        const std::uint64_t lightCalls = lit.psInvocations - unlit.psInvocations;
        const std::uint64_t expected = (pixels - edges) * lights + edges * samples * lights;
        MESSAGE(samples << "x: " << edges << " edge pixels; light calls " << lightCalls << ", once per pixel/sample "
                        << expected << ", diagonal pixels " << splitMin << ".." << splitMax);
        CHECK(lightCalls >= expected + splitMin * lights);
        CHECK(lightCalls <= expected + splitMax * lights);
    }
    Rendered single;
    DrawStats stats1;
    render(t, "deferred-classic", quads, single, Precision::Exact, 2, {kW, kH}, {}, 1, &stats1);
    CHECK(stats1.psPerSample == 0);
    CHECK(stats1.edgeTestedPixels == 0);
}

TEST_CASE("msaa deferred: with every correction, non-edge pixels equal forward's bit for bit at 4x") {
    // At 1x corrected deferred equals forward (deferred_test.cpp). With MSAA, forward shades each
    // pixel once at its centre; deferred does the same where the coverage detector sees one
    // triangle, and shades per sample elsewhere (where the two legitimately differ).
    // Two directional lights (full-screen quads): a light volume's own silhouette cuts samples
    // out of a pixel's shading, which forward's per-pixel range test does not.
    const TestScene t = makeScene({makeLight(LightType::Directional, {0, 0, 0}, {-0.3f, -1.0f, -0.5f}, 1.0f, {0.7f, 0.6f, 0.5f}),
                                   makeLight(LightType::Directional, {0, 0, 0}, {0.6f, -0.4f, -0.7f}, 1.0f, {0.2f, 0.3f, 0.6f})});
    const nlohmann::json corrected = {{"projection", "d3d"},     {"reconstruct", "centre"},     {"gbuffer", "float"},
                                      {"position", "gbuffer"},   {"accumulate", "lighting"},    {"lightVolumes", "circumscribed"},
                                      {"volumeRotation", "robust"}, {"msaaEdges", "coverage"}};
    Rendered forward, deferred;
    render(t, "forward", {{"projection", "d3d"}}, forward, Precision::Exact, 2, {kWidth, kHeight}, {}, 4);
    render(t, "deferred", corrected, deferred, Precision::Exact, 2, {kWidth, kHeight}, {}, 4);
    const Surface& f = forward.get(backBufferTarget(4));
    const Surface& d = deferred.get(backBufferTarget(4));
    const Surface& edges = deferred.get("edges");
    std::size_t inner = 0, differ = 0, edgeDiffer = 0;
    for (std::uint32_t y = 0; y < kHeight; ++y)
        for (std::uint32_t x = 0; x < kWidth; ++x) {
            const bool edge = edges.load(x, y, 0).x != 0.0f;
            for (std::uint32_t i = 0; i < 4; ++i) {
                const bool same = std::memcmp(f.texel(x, y, i), d.texel(x, y, i), 4) == 0;
                if (edge) edgeDiffer += same ? 0 : 1;
                else {
                    ++inner;
                    differ += same ? 0 : 1;
                }
            }
        }
    MESSAGE("non-edge samples " << inner << ", differing " << differ << "; edge samples differing " << edgeDiffer);
    CHECK(inner > 4 * kWidth * kHeight / 2);
    CHECK(differ == 0);
}

TEST_CASE("msaa deferred: the same bytes at 1, 2 and 7 threads") {
    const TestScene t = makeScene(defaultLights());
    for (const char* technique : {"deferred", "deferred-killzone", "deferred-classic", "light-prepass", "forward",
                                  "deferred-cookbook", "tiled-deferred"}) {
        CAPTURE(technique);
        Rendered a, b, c;
        render(t, technique, nlohmann::json::object(), a, Precision::Exact, 1, {kWidth, kHeight}, {}, 4);
        render(t, technique, nlohmann::json::object(), b, Precision::Exact, 2, {kWidth, kHeight}, {}, 4);
        render(t, technique, nlohmann::json::object(), c, Precision::Exact, 7, {kWidth, kHeight}, {}, 4);
        CHECK(sameBytes(a.back(), b.back()));
        CHECK(sameBytes(a.back(), c.back()));
        CHECK(sameBytes(a.get(backBufferTarget(4)), c.get(backBufferTarget(4))));
        CHECK(a.back().sampleCount() == 1);
    }
}

TEST_CASE("msaa forward+: with every sample in the tile bounds, forward-plus and forward-plus-amd equal forward at every sample") {
    // 300 small point lights scattered over the quads: a light that lights some sample of a tile
    // must be in the tile's list, so the tiled techniques' samples equal forward's bit for bit
    // (the 1x property of forward_plus_test.cpp and the AMD scene tests). Bounds taken from
    // sample 0 alone miss lights that only other samples' surfaces reach.
    TestScene t = flatScene();
    t.scene.lights.clear();
    std::uint32_t seed = 12345u;
    const auto uniform = [&seed](float lo, float hi) {
        seed = seed * 1664525u + 1013904223u;  // Numerical Recipes' LCG: the same lights everywhere
        return lo + (hi - lo) * float(seed >> 8) / float(1u << 24);
    };
    for (int i = 0; i < 300; ++i)
        t.scene.lights.push_back(makeLight(LightType::Point, {uniform(-5.0f, 5.0f), uniform(-4.0f, 4.0f), uniform(-6.0f, 2.0f)},
                                           {0, 0, -1}, uniform(0.3f, 1.2f), {uniform(0.2f, 1.0f), uniform(0.2f, 1.0f), uniform(0.2f, 1.0f)}));
    for (const std::uint32_t samples : {2u, 4u, 8u}) {
        CAPTURE(samples);
        Rendered forward, plus, amd;
        render(t, "forward", {{"projection", "d3d"}}, forward, Precision::Exact, 2, {kW, kH}, {}, samples);
        render(t, "forward-plus", {{"projection", "d3d"}, {"lightLists", "unbounded"}, {"tileSize", 8}}, plus, Precision::Exact, 2,
               {kW, kH}, {}, samples);
        render(t, "forward-plus-amd", {{"projection", "d3d"}, {"shading", "3dgep"}}, amd, Precision::Exact, 2, {kW, kH}, {}, samples);
        CHECK(sameBytes(forward.get(backBufferTarget(samples)), plus.get(backBufferTarget(samples))));
        CHECK(sameBytes(forward.get(backBufferTarget(samples)), amd.get(backBufferTarget(samples))));
    }
}

} // namespace tessera_test::techniques_msaa_deferred_test
