// AMD Forward+ culling on the CPU (techniques/amd_light_culling.h): the two-level list against a
// per-tile recomputation from the tested building blocks, Serial = Parallel bytes, the 256 cap
// and its overflow count, and a brute-force conservativeness test on a depth buffer with partial
// edge tiles (GPU Pro 4 depth and ForwardPlus11's reversed depth, min/max and 2.5D): every light
// whose sphere contains a pixel's surface point is in that pixel's tile list. Prints the list
// sizes and false-positive rates of min/max and 2.5D culling.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <set>
#include <sstream>
#include <vector>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include <tessera/culling/depth_mask.h>
#include <tessera/scene/light_generator.h>
#include <tessera/techniques/amd_light_culling.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_amd_light_culling_test {

using namespace tessera;

namespace {

constexpr std::uint32_t kWidth = 70, kHeight = 45;  // 9 x 6 tiles of 8 px, the last column/row partial

struct TestScene {
    glm::mat4 projection{1.0f};
    glm::mat4 inverseProjection{1.0f};
    std::vector<float> depth;
    std::vector<float> viewZ;  // the depth's LH view z (0 where cleared)
    std::vector<glm::vec4> lights;
    bool reversed = false;
};

// LH perspective; reversed = ForwardPlus11's (near and far swapped: depth 1 at near, cleared 0).
// Background at view z 40, a cleared 10 x 10 corner, and 25 random rectangles at z in [2, 30]:
// many tiles hold a foreground and a background.
TestScene makeScene(bool reversed, std::uint64_t seed, std::uint32_t lightCount) {
    TestScene s;
    s.reversed = reversed;
    const float aspect = float(kWidth) / float(kHeight);
    s.projection = reversed ? glm::perspectiveLH_ZO(glm::radians(60.0f), aspect, 100.0f, 0.5f)
                            : glm::perspectiveLH_ZO(glm::radians(60.0f), aspect, 0.5f, 100.0f);
    s.inverseProjection = glm::inverse(s.projection);
    const float cleared = reversed ? 0.0f : 1.0f;
    s.viewZ.assign(std::size_t{kWidth} * kHeight, 40.0f);
    Pcg32 rng(seed);
    for (int r = 0; r < 25; ++r) {
        const std::uint32_t x0 = rng.next() % kWidth, y0 = rng.next() % kHeight;
        const std::uint32_t w = 1 + rng.next() % 20, h = 1 + rng.next() % 15;
        const float z = rng.uniform(2.0f, 30.0f);
        for (std::uint32_t y = y0; y < std::min(kHeight, y0 + h); ++y)
            for (std::uint32_t x = x0; x < std::min(kWidth, x0 + w); ++x) s.viewZ[y * kWidth + x] = z;
    }
    for (std::uint32_t y = 0; y < 10; ++y)
        for (std::uint32_t x = 0; x < 10; ++x) s.viewZ[y * kWidth + x] = 0.0f;
    s.depth.resize(s.viewZ.size());
    for (std::size_t i = 0; i < s.viewZ.size(); ++i)  // depth = P33 + P43 / z (D3D row-vector _33, _43)
        s.depth[i] = s.viewZ[i] == 0.0f ? cleared : s.projection[2][2] + s.projection[3][2] / s.viewZ[i];
    for (std::uint32_t i = 0; i < lightCount; ++i) {
        const float z = rng.uniform(0.5f, 60.0f);
        const float x = rng.uniform(-1.0f, 1.0f) * z * 0.6f * aspect;
        const float y = rng.uniform(-1.0f, 1.0f) * z * 0.6f;
        s.lights.emplace_back(x, y, z, rng.uniform(0.2f, 6.0f));
    }
    return s;
}

DepthImageView view(const TestScene& s) { return DepthImageView{s.depth, kWidth, kHeight}; }

AmdCullingOptions optionsFor(const TestScene& s, AmdDepthCulling culling, compute::GroupOrder order) {
    AmdCullingOptions o;
    o.depthConvention = s.reversed ? AmdDepthConvention::ForwardPlus11 : AmdDepthConvention::GpuPro4;
    o.depthCulling = culling;
    o.order = order;
    return o;
}

}  // namespace

TEST_CASE("cullTilesAmd: lists, offsets and depth data equal a per-tile recomputation from the building blocks") {
    for (bool reversed : {false, true}) {
        for (AmdDepthCulling culling : {AmdDepthCulling::MinMax, AmdDepthCulling::DepthMask25D}) {
            CAPTURE(reversed);
            const TestScene s = makeScene(reversed, 5, 300);
            const AmdTileLightLists lists =
                cullTilesAmd(view(s), s.lights, s.inverseProjection, optionsFor(s, culling, compute::GroupOrder::Serial));
            REQUIRE(lists.tileCount == glm::uvec2(9, 6));
            std::uint32_t expectedOffset = 0;
            for (std::uint32_t gy = 0; gy < 6; ++gy) {
                for (std::uint32_t gx = 0; gx < 9; ++gx) {
                    const std::uint32_t t = gx + gy * 9;
                    const TileDepthBits bits = reversed ? tileViewZBitsAmdForwardPlus11(view(s), {gx, gy}, 8, s.inverseProjection)
                                                        : tileViewZBitsAmdGpuPro4(view(s), {gx, gy}, 8, s.inverseProjection);
                    REQUIRE(lists.tileMinZBits[t] == bits.minBits);
                    REQUIRE(lists.tileMaxZBits[t] == bits.maxBits);
                    const float minZ = bits.minValue(), maxZ = bits.maxValue();
                    std::uint32_t mask = 0;
                    if (culling == AmdDepthCulling::DepthMask25D) {
                        if (reversed) {  // the ForwardPlus11 pixels: depth != 0, z = 1 / (d _34 + _44)
                            std::vector<float> zs;
                            for (std::uint32_t y = 0; y < 8; ++y)
                                for (std::uint32_t x = 0; x < 8; ++x) {
                                    const float d = view(s).load(gx * 8 + x, gy * 8 + y);
                                    if (d != 0.0f)
                                        zs.push_back(1.0f / (d * s.inverseProjection[2][3] + s.inverseProjection[3][3]));
                                }
                            mask = tileDepthMaskFromViewZ(zs, minZ, maxZ);
                        } else {
                            mask = tileDepthMaskAmdGpuPro4(view(s), {gx, gy}, 8, s.inverseProjection, minZ, maxZ);
                        }
                    }
                    REQUIRE(lists.tileDepthMask[t] == mask);
                    const auto eqn = tileSidePlanesAmd({gx, gy}, 8, {kWidth, kHeight}, s.inverseProjection, AmdTileCorners::Screen);
                    std::vector<std::uint32_t> expected;
                    for (std::uint32_t i = 0; i < s.lights.size(); ++i) {
                        const glm::vec3 c(s.lights[i]);
                        const float r = s.lights[i].w;
                        if (!sphereOverlapsTileAmd(c, r, eqn, minZ, maxZ)) continue;
                        if (culling == AmdDepthCulling::DepthMask25D &&
                            !depthMasksOverlap(lightDepthMask(c.z, r, minZ, depthMaskPitch(minZ, maxZ)), mask))
                            continue;
                        expected.push_back(i);  // ascending light index
                    }
                    REQUIRE(expected.size() <= kAmdLightCapacity);
                    const auto got = lists.tileLights(t);
                    REQUIRE(std::vector<std::uint32_t>(got.begin(), got.end()) == expected);
                    // Row-major pool: offset = sum of the earlier tiles' counts; empty tiles keep 0.
                    CHECK(lists.tileOffset[t] == (expected.empty() ? 0u : expectedOffset));
                    expectedOffset += static_cast<std::uint32_t>(expected.size());
                }
            }
            CHECK(lists.lightIndices.size() == expectedOffset);
            CHECK(lists.overflowTiles == 0);
        }
    }
}

TEST_CASE("cullTilesAmd: Parallel gives the same bytes as Serial") {
    const TestScene s = makeScene(false, 9, 1000);
    for (AmdDepthCulling culling : {AmdDepthCulling::MinMax, AmdDepthCulling::DepthMask25D}) {
        const AmdTileLightLists a =
            cullTilesAmd(view(s), s.lights, s.inverseProjection, optionsFor(s, culling, compute::GroupOrder::Serial));
        const AmdTileLightLists b =
            cullTilesAmd(view(s), s.lights, s.inverseProjection, optionsFor(s, culling, compute::GroupOrder::Parallel));
        CHECK(a.lightIndices == b.lightIndices);
        CHECK(a.tileOffset == b.tileOffset);
        CHECK(a.tileLightCount == b.tileLightCount);
        CHECK(a.tileDepthMask == b.tileDepthMask);
    }
}

TEST_CASE("cullTilesAmd: LIGHT_CAPACITY 256 keeps the first 256 lights and counts the overflow") {
    // One 8 x 8 tile at view z 10; 300 identical lights at the tile's centre ray, radius 5.
    const glm::mat4 projection = glm::perspectiveLH_ZO(glm::radians(60.0f), 1.0f, 0.5f, 100.0f);
    const std::vector<float> depth(64, projection[2][2] + projection[3][2] / 10.0f);
    const std::vector<glm::vec4> lights(300, glm::vec4(0.0f, 0.0f, 10.0f, 5.0f));
    const AmdTileLightLists lists = cullTilesAmd(DepthImageView{depth, 8, 8}, lights, glm::inverse(projection));
    CHECK(lists.tileFoundCount[0] == 300u);
    CHECK(lists.tileLightCount[0] == 256u);
    CHECK(lists.overflowTiles == 1u);
    CHECK(lists.droppedLights == 44u);
    REQUIRE(lists.lightIndices.size() == 256u);
    for (std::uint32_t i = 0; i < 256; ++i) CHECK(lists.lightIndices[i] == i);
    // Invalid input: an empty screen.
    CHECK_THROWS_AS(cullTilesAmd(DepthImageView{{}, 0, 0}, lights, glm::inverse(projection)), std::invalid_argument);
}

TEST_CASE("cullTilesAmd brute force: no light that contains a pixel's surface point is missing from its tile") {
    std::ostringstream report;
    for (bool reversed : {false, true}) {
        const TestScene s = makeScene(reversed, 2024, 600);
        const DepthImageView image = view(s);
        const glm::dmat4 inverseD = glm::inverse(glm::dmat4(s.projection));
        const AmdTileLightLists minMax = cullTilesAmd(image, s.lights, s.inverseProjection,
                                                      optionsFor(s, AmdDepthCulling::MinMax, compute::GroupOrder::Parallel));
        const AmdTileLightLists mask25 = cullTilesAmd(image, s.lights, s.inverseProjection,
                                                      optionsFor(s, AmdDepthCulling::DepthMask25D, compute::GroupOrder::Parallel));
        std::set<std::pair<std::uint32_t, std::uint32_t>> needed;  // (tile, light)
        std::uint64_t missingMinMax = 0, missing25 = 0;
        for (std::uint32_t py = 0; py < kHeight; ++py) {
            for (std::uint32_t px = 0; px < kWidth; ++px) {
                const float d = s.depth[py * kWidth + px];
                if (d == (reversed ? 0.0f : 1.0f)) continue;
                // The pixel's surface point: its centre at its stored depth, back through the
                // projection in double.
                const glm::dvec4 clip((px + 0.5) / kWidth * 2.0 - 1.0, 1.0 - (py + 0.5) / kHeight * 2.0, double(d), 1.0);
                const glm::dvec4 h = inverseD * clip;
                const glm::dvec3 posView = glm::dvec3(h) / h.w;
                const std::uint32_t tile = px / 8 + (py / 8) * minMax.tileCount.x;
                const auto inList = [&](const AmdTileLightLists& lists, std::uint32_t light) {
                    const auto l = lists.tileLights(tile);
                    return std::binary_search(l.begin(), l.end(), light);
                };
                for (std::uint32_t i = 0; i < s.lights.size(); ++i) {
                    const glm::dvec3 c(glm::vec3(s.lights[i]));
                    // Strictly inside by a relative 1e-4 of r: the kernel works on binary32 view
                    // positions, a few ulps from these double ones.
                    if (glm::length(posView - c) >= double(s.lights[i].w) * (1.0 - 1e-4)) continue;
                    needed.insert({tile, i});
                    if (!inList(minMax, i)) ++missingMinMax;
                    if (!inList(mask25, i)) ++missing25;
                }
            }
        }
        CHECK(missingMinMax == 0);
        CHECK(missing25 == 0);
        CHECK(mask25.lightIndices.size() <= minMax.lightIndices.size());
        const auto pct = [](double a, double b) { return b > 0 ? 100.0 * a / b : 0.0; };
        const double tiles = double(minMax.tileCount.x) * minMax.tileCount.y;
        report.precision(3);
        report << std::fixed << (reversed ? "ForwardPlus11 reversed depth" : "GPU Pro 4 depth") << ", " << s.lights.size()
               << " lights, " << kWidth << "x" << kHeight << " (" << tiles << " tiles): mean lights/tile min/max "
               << double(minMax.lightIndices.size()) / tiles << ", 2.5D " << double(mask25.lightIndices.size()) / tiles
               << ", needed " << double(needed.size()) / tiles << "; false positives min/max "
               << pct(double(minMax.lightIndices.size() - needed.size()), double(minMax.lightIndices.size())) << "%, 2.5D "
               << pct(double(mask25.lightIndices.size() - needed.size()), double(mask25.lightIndices.size())) << "%\n";
    }
    MESSAGE(report.str());
}

namespace {

// Every output of cullTilesAmd, for byte comparisons.
bool sameLists(const AmdTileLightLists& a, const AmdTileLightLists& b) {
    return a.tileCount == b.tileCount && a.lightIndices == b.lightIndices && a.tileOffset == b.tileOffset &&
           a.tileLightCount == b.tileLightCount && a.tileFoundCount == b.tileFoundCount && a.tileMinZBits == b.tileMinZBits &&
           a.tileMaxZBits == b.tileMaxZBits && a.tileDepthMask == b.tileDepthMask && a.tileOffsetFar == b.tileOffsetFar &&
           a.tileLightCountFar == b.tileLightCountFar && a.tileFoundCountFar == b.tileFoundCountFar &&
           a.overflowTiles == b.overflowTiles && a.droppedLights == b.droppedLights && a.overflowTilesFar == b.overflowTilesFar &&
           a.droppedLightsFar == b.droppedLightsFar;
}

}  // namespace

TEST_CASE("cullTilesAmd: binned and all-lights loops give the same bytes") {
    // The binned loop skips a light on a tile only where its padded sphere is outside the tile's
    // column or row planes (tile_binning.h); any light it wrongly skips changes the lists. Lights
    // here: the scene's (in front), plus ones around and behind the eye (the scanned case), huge
    // ones, ones at the frustum's edges, and a NaN radius. Projections: GPU Pro 4, ForwardPlus11
    // reversed, and a mirrored one (NDC x to view -x) that the binary searches must not be used on.
    std::uint64_t binnedSkips = 0;
    for (int projectionKind = 0; projectionKind < 3; ++projectionKind) {
        TestScene s = makeScene(projectionKind == 1, 77 + projectionKind, 1500);
        if (projectionKind == 2) {  // mirrored x: the same depth buffer seen through x -> -x
            s.projection = glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 1.0f, 1.0f)) * s.projection;
            s.inverseProjection = glm::inverse(s.projection);
        }
        Pcg32 rng(4242 + projectionKind);
        for (int i = 0; i < 400; ++i) {  // around the eye: z in [-8, 8], radii up to 10
            s.lights.emplace_back(rng.uniform(-10.0f, 10.0f), rng.uniform(-8.0f, 8.0f), rng.uniform(-8.0f, 8.0f),
                                  rng.uniform(0.01f, 10.0f));
        }
        s.lights.emplace_back(0.0f, 0.0f, 0.0f, 0.0f);
        s.lights.emplace_back(0.0f, 0.0f, 50.0f, 1000.0f);
        s.lights.emplace_back(0.0f, 0.0f, 50.0f, std::nanf(""));
        for (int i = 0; i < 200; ++i) {  // near the four frustum edges: x or y at the edge's slope
            const float z = rng.uniform(1.0f, 80.0f), t = rng.uniform(-1.0f, 1.0f);
            const float edge = (i % 2 ? 1.0f : -1.0f) * z * std::tan(glm::radians(30.0f));
            const float aspect = float(kWidth) / float(kHeight);
            const glm::vec3 c = i % 4 < 2 ? glm::vec3(edge * aspect, t * z * 0.5f, z) : glm::vec3(t * z * 0.5f * aspect, edge, z);
            s.lights.emplace_back(c, rng.uniform(0.001f, 2.0f));
        }
        const DepthImageView image = view(s);
        for (AmdDepthCulling culling : {AmdDepthCulling::MinMax, AmdDepthCulling::DepthMask25D})
            for (bool halfZ : {false, true})
                for (AmdDepthRange range : {AmdDepthRange::Opaque, AmdDepthRange::NearToMax})
                    for (AmdTileCorners corners : {AmdTileCorners::Screen, AmdTileCorners::PaddedGrid}) {
                        CAPTURE(projectionKind);
                        CAPTURE(halfZ);
                        AmdCullingOptions o = optionsFor(s, culling, compute::GroupOrder::Parallel);
                        o.halfZ = halfZ;
                        o.range = range;
                        o.corners = corners;
                        o.lightLoop = AmdLightLoop::AllLights;
                        const AmdTileLightLists all = cullTilesAmd(image, s.lights, s.inverseProjection, o);
                        o.lightLoop = AmdLightLoop::Binned;
                        const AmdTileLightLists binned = cullTilesAmd(image, s.lights, s.inverseProjection, o);
                        CHECK(sameLists(all, binned));
                        const double tiles = double(all.tileCount.x) * all.tileCount.y;
                        binnedSkips += static_cast<std::uint64_t>(tiles * double(s.lights.size())) - all.lightIndices.size();
                    }
    }
    CHECK(binnedSkips > 0);
}

TEST_CASE("cullTilesAmd: a sphere 0.1% of r outside the screen's left edge is in no list, 0.1% inside only in column 0's") {
    // 64 x 64 px (8 x 8 tiles), 60 deg vertical fov, a wall at view z 20. The left edge plane
    // through the eye has outward normal (-cos 30, 0, -sin 30) (60 deg horizontal fov too), so the
    // distance of (x, 0, 20) from it is -(x + 20 tan 30) cos 30: a sphere of radius r centred at
    // x = -20 tan 30 - k r / cos 30 lies k r beyond the edge (it intersects the screen iff k < 1).
    // Both loops must agree: the binned loop's padding may keep a candidate, never drop one.
    const glm::mat4 projection = glm::perspectiveLH_ZO(glm::radians(60.0f), 1.0f, 0.5f, 100.0f);
    const std::vector<float> depth(64 * 64, projection[2][2] + projection[3][2] / 20.0f);  // a wall at z 20
    const DepthImageView image{depth, 64, 64};
    const float r = 2.0f;
    const float xOutside = -20.0f * std::tan(glm::radians(30.0f)) - r / std::cos(glm::radians(30.0f)) * 1.001f;
    const float xInside = -20.0f * std::tan(glm::radians(30.0f)) - r / std::cos(glm::radians(30.0f)) * 0.999f;
    const std::vector<glm::vec4> lights{{xOutside, 0.0f, 20.0f, r}, {xInside, 0.0f, 20.0f, r}};
    for (AmdLightLoop loop : {AmdLightLoop::AllLights, AmdLightLoop::Binned}) {
        AmdCullingOptions o;
        o.lightLoop = loop;
        const AmdTileLightLists lists = cullTilesAmd(image, lights, glm::inverse(projection), o);
        std::vector<std::uint32_t> column0;
        for (std::uint32_t gy = 0; gy < lists.tileCount.y; ++gy)
            for (std::uint32_t light : lists.tileLights(gy * lists.tileCount.x)) column0.push_back(light);
        CHECK(std::count(column0.begin(), column0.end(), 0u) == 0);
        CHECK(std::count(column0.begin(), column0.end(), 1u) > 0);
        CHECK(lists.lightIndices.size() == column0.size());  // the inside light reaches column 0 only
    }
}

TEST_CASE("cullTilesAmd half-Z: a tile whose near list is empty keeps offset 0 and its far list follows the pool, in both loops") {
    // 16 x 8 px, two 8 x 8 tiles, LH 60 deg vertical fov, aspect 2. Tile 0 is a wall at view z 10;
    // tile 1 holds z 5 (top half) and z 40 (bottom half), so its half-Z split is 22.5. Light 0 sits
    // on tile 0's centre ray at z 10 (r 2); light 1 on tile 1's centre ray (NDC x 0.5: view x =
    // 0.5 z tan 30 * 2) at z 39 (r 1), inside [22.5, 40] only. Expected pool: tile 0's lists
    // (light 0), then tile 1's far list: offset(1) = 0 (its near list is empty, as the
    // document's write-back leaves it), offsetFar(1) = the entries before it.
    const glm::mat4 projection = glm::perspectiveLH_ZO(glm::radians(60.0f), 2.0f, 0.5f, 100.0f);
    const auto depthAt = [&](float z) { return projection[2][2] + projection[3][2] / z; };
    std::vector<float> depth(16 * 8);
    for (std::uint32_t y = 0; y < 8; ++y)
        for (std::uint32_t x = 0; x < 16; ++x) depth[y * 16 + x] = depthAt(x < 8 ? 10.0f : (y < 4 ? 5.0f : 40.0f));
    const float t30 = std::tan(glm::radians(30.0f));
    const std::vector<glm::vec4> lights{{-0.5f * 10.0f * t30 * 2.0f, 0.0f, 10.0f, 2.0f}, {0.5f * 39.0f * t30 * 2.0f, 0.0f, 39.0f, 1.0f}};
    for (AmdLightLoop loop : {AmdLightLoop::AllLights, AmdLightLoop::Binned}) {
        CAPTURE(loop == AmdLightLoop::Binned);
        AmdCullingOptions o;
        o.halfZ = true;
        o.lightLoop = loop;
        const AmdTileLightLists lists = cullTilesAmd(DepthImageView{depth, 16, 8}, lights, glm::inverse(projection), o);
        REQUIRE(lists.tileCount == glm::uvec2(2, 1));
        CHECK(lists.tileLightCount[1] == 0u);
        REQUIRE(lists.tileLightCountFar[1] == 1u);
        const std::uint32_t before = lists.tileLightCount[0] + lists.tileLightCountFar[0];
        CHECK(before >= 1u);  // light 0 is in tile 0
        CHECK(lists.tileOffset[1] == 0u);
        CHECK(lists.tileOffsetFar[1] == before);
        CHECK(lists.tileLightsFar(1)[0] == 1u);
        CHECK(lists.lightIndices.size() == before + 1u);
    }
}

TEST_CASE("cullTilesAmd over several passes: each result equals its own call (shared binning)") {
    const TestScene s = makeScene(false, 31, 800);
    std::vector<AmdCullingOptions> passes(5);
    passes[0].depthCulling = AmdDepthCulling::DepthMask25D;
    passes[0].halfZ = true;
    passes[1].range = AmdDepthRange::NearToMax;
    passes[2].corners = AmdTileCorners::PaddedGrid;
    passes[3].lightLoop = AmdLightLoop::AllLights;
    passes[4].corners = AmdTileCorners::PaddedGrid;
    passes[4].order = compute::GroupOrder::Serial;
    const std::vector<AmdTileLightLists> together = cullTilesAmd(view(s), s.lights, s.inverseProjection, passes);
    REQUIRE(together.size() == passes.size());
    for (std::size_t i = 0; i < passes.size(); ++i) {
        CAPTURE(i);
        CHECK(sameLists(together[i], cullTilesAmd(view(s), s.lights, s.inverseProjection, passes[i])));
        CHECK(!together[i].lightIndices.empty());
    }
    CHECK(cullTilesAmd(view(s), s.lights, s.inverseProjection, std::span<const AmdCullingOptions>{}).empty());
}

} // namespace tessera_test::techniques_amd_light_culling_test
