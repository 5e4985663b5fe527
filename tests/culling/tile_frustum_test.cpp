// Tile frustums built the three ways of culling/tile_frustum.h: one hand-derived tile through all
// three constructions, the tile-frustum note's 600x600 / 10-pixel-tile worked example, agreement
// of the three on every tile of a 1280x720 grid (after conversion to the common convention), and
// the two source errata: Intel's 2010 planes span 2x2 tiles, AMD's padded-grid corners miss pixel rows.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include <glm/ext/matrix_clip_space.hpp>

#include <tessera/culling/tile_frustum.h>

#include "support/unit_projections.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::culling_tile_frustum_test {

using namespace tessera;

namespace {

bool near3(const glm::vec3& a, const glm::vec3& b, float tol) {
    return std::fabs(a.x - b.x) <= tol && std::fabs(a.y - b.y) <= tol && std::fabs(a.z - b.z) <= tol;
}

using test::inverseGlFormUnit;

// AMD: a left-handed inverse with view = (X, Y, W, Z): ndc (x, y, 1, 1) maps to view (x, y, 1).
glm::mat4 inverseLhUnit() {
    glm::mat4 m(0.0f);
    m[0][0] = 1.0f;
    m[1][1] = 1.0f;
    m[3][2] = 1.0f;
    m[2][3] = 1.0f;
    return m;
}

constexpr float kInvSqrt2 = 0.70710678f;
constexpr float kTwoBySqrt5 = 0.89442719f;
constexpr float kOneBySqrt5 = 0.44721360f;

}  // namespace

TEST_CASE("one tile, three constructions, hand-derived (64x64 px, 16 px tiles, tile (0,0), P11 = P22 = 1)") {
    // Tile (0,0) spans px [0,16] x [0,16]: NDC x in [-1, -0.5] (x = px / 64 * 2 - 1), y in [0.5, 1]
    // (y = (1 - py / 64) * 2 - 1). With P11 = P22 = 1 a view point X projects to x/(-z), y/(-z) (RH).
    // Edges in RH view space and their inward normals:
    //   left   x = z         (x_ndc = -1):   N ~ (1, 0, -1)  -> (0.7071068, 0, -0.7071068)
    //   right  x = 0.5 z     (x_ndc = -0.5): N ~ (-2, 0, 1)  -> (-0.8944272, 0, 0.4472136)
    //   top    y = -z        (y_ndc = 1):    N ~ (0, -1, -1) -> (0, -0.7071068, -0.7071068)
    //   bottom y = -0.5 z    (y_ndc = 0.5):  N ~ (0, 2, 1)   -> (0, 0.8944272, 0.4472136)
    // and d = 0 (every plane passes through the eye).
    const glm::vec3 left(kInvSqrt2, 0, -kInvSqrt2), right(-kTwoBySqrt5, 0, kOneBySqrt5);
    const glm::vec3 top(0, -kInvSqrt2, -kInvSqrt2), bottom(0, kTwoBySqrt5, kOneBySqrt5);
    constexpr float tol = 2e-7f;

    SUBCASE("3dgep: corners (-1,1,-1), (-.5,1,-1), (-1,.5,-1), (-.5,.5,-1); Left = (eye, v2, v0) ...") {
        // cross(v2, v0) = (-1,.5,-1) x (-1,1,-1) = (.5*(-1) - (-1)*1, (-1)(-1) - (-1)(-1), (-1)*1 - .5*(-1))
        //               = (0.5, 0, -0.5) -> left. The others likewise (tile_frustum.h).
        const Frustum f = gridFrustum3dgep({0, 0}, 16, {64.0f, 64.0f}, inverseGlFormUnit());
        CHECK(near3(f.planes[0].N, left, tol));
        CHECK(near3(f.planes[1].N, right, tol));
        CHECK(near3(f.planes[2].N, top, tol));
        CHECK(near3(f.planes[3].N, bottom, tol));
        for (const Plane& p : f.planes) CHECK(p.d == 0.0f);
    }
    SUBCASE("AMD: corners (-1,1,1), (-.5,1,1), (-.5,.5,1), (-1,.5,1) clockwise; eqn_i = normalize(f_i x f_i+1)") {
        // eqn0 = (-1,1,1) x (-.5,1,1) = (0, .5, -.5) -> top, OUTWARD (+y) in LH view space;
        // eqn1 = (.5, 0, .25) -> right; eqn2 = (0, -.5, .25) -> bottom; eqn3 = (-.5, 0, -.5) -> left.
        const std::array<glm::vec3, 4> eqn =
            tileSidePlanesAmd({0, 0}, 16, {64, 64}, inverseLhUnit(), AmdTileCorners::PaddedGrid);
        CHECK(near3(eqn[0], glm::vec3(0, kInvSqrt2, -kInvSqrt2), tol));
        CHECK(near3(eqn[1], glm::vec3(kTwoBySqrt5, 0, kOneBySqrt5), tol));
        CHECK(near3(eqn[2], glm::vec3(0, -kTwoBySqrt5, kOneBySqrt5), tol));
        CHECK(near3(eqn[3], glm::vec3(-kInvSqrt2, 0, -kInvSqrt2), tol));
        // Common convention: N = (-x, -y, z), reordered left, right, top, bottom: the 3dgep planes.
        const TileSidePlanes common = commonSidePlanesFromAmd(eqn);
        CHECK(near3(common[0].N, left, tol));
        CHECK(near3(common[1].N, right, tol));
        CHECK(near3(common[2].N, top, tol));
        CHECK(near3(common[3].N, bottom, tol));
    }
    SUBCASE("Intel: tileScale = 64 * rcp(32) = 2, tileBias = 2; c1 = (2,0,2,0), c2 = (0,-2,2,0)") {
        // P0 = c4 - c1 = (-2,0,-1) -> (-.894,0,-.447); P1 = c1 = (2,0,2) -> (.707,0,.707);
        // P2 = c4 - c2 = (0,2,-1) -> (0,.894,-.447); P3 = c2 = (0,-2,2) -> (0,-.707,.707) (LH, inward).
        const glm::mat4 projection(1.0f);  // only _11 = m[0][0] and _22 = m[1][1] are read
        const IntelTileColumns cols = intelTileColumns({0, 0}, 16, {64, 64}, projection);
        CHECK(cols.tileScale == glm::vec2(2.0f));
        CHECK(cols.c1 == glm::vec4(2, 0, 2, 0));
        CHECK(cols.c2 == glm::vec4(0, -2, 2, 0));
        const std::array<glm::vec4, 6> planes =
            tileFrustumPlanesIntel({0, 0}, 16, {64, 64}, projection, 1.0f, 2.0f, IntelSidePlanes::TileBounds);
        CHECK(near3(glm::vec3(planes[0]), glm::vec3(-kTwoBySqrt5, 0, -kOneBySqrt5), tol));
        CHECK(near3(glm::vec3(planes[1]), glm::vec3(kInvSqrt2, 0, kInvSqrt2), tol));
        CHECK(near3(glm::vec3(planes[2]), glm::vec3(0, kTwoBySqrt5, -kOneBySqrt5), tol));
        CHECK(near3(glm::vec3(planes[3]), glm::vec3(0, -kInvSqrt2, kInvSqrt2), tol));
        CHECK(planes[4] == glm::vec4(0, 0, 1, -1));  // near: z - minTileZ >= 0
        CHECK(planes[5] == glm::vec4(0, 0, -1, 2));  // far: -z + maxTileZ >= 0
        // Common convention: N = (a, b, -c), d = -w, order P1, P0, P3, P2.
        const TileSidePlanes common = commonSidePlanesFromIntel(planes);
        CHECK(near3(common[0].N, left, tol));
        CHECK(near3(common[1].N, right, tol));
        CHECK(near3(common[2].N, top, tol));
        CHECK(near3(common[3].N, bottom, tol));
        for (const Plane& p : common) CHECK(p.d == 0.0f);
    }
}

TEST_CASE("tile-frustum note worked example: 600x600, COMPUTE_SHADER_TILE_GROUP_DIM 10, _11 = _22 = 1") {
    // tileScale = 600 * rcp(20) = 30 (rcp(20) = 0.0500000007f, 600 * that rounds to 30.0f exactly);
    // tileBias = 30 - g. Planes derived by hand from the note's code (raw, then normalized to 6 decimals).
    const glm::mat4 projection(1.0f);
    const glm::uvec2 fb(600, 600);
    struct Row {
        glm::uvec2 g;
        std::array<glm::vec4, 4> raw;
        std::array<glm::vec3, 4> unit;
    };
    const Row rows[] = {
        {{0, 0},
         {glm::vec4(-30, 0, -29, 0), glm::vec4(30, 0, 30, 0), glm::vec4(0, 30, -29, 0), glm::vec4(0, -30, 30, 0)},
         {glm::vec3(-.718988f, 0, -.695022f), glm::vec3(.707107f, 0, .707107f), glm::vec3(0, .718988f, -.695022f),
          glm::vec3(0, -.707107f, .707107f)}},
        {{1, 0},
         {glm::vec4(-30, 0, -28, 0), glm::vec4(30, 0, 29, 0), glm::vec4(0, 30, -29, 0), glm::vec4(0, -30, 30, 0)},
         {glm::vec3(-.731055f, 0, -.682318f), glm::vec3(.718988f, 0, .695022f), glm::vec3(0, .718988f, -.695022f),
          glm::vec3(0, -.707107f, .707107f)}},
        {{29, 29},
         {glm::vec4(-30, 0, 0, 0), glm::vec4(30, 0, 1, 0), glm::vec4(0, 30, 0, 0), glm::vec4(0, -30, 1, 0)},
         {glm::vec3(-1, 0, 0), glm::vec3(.999445f, 0, .033315f), glm::vec3(0, 1, 0), glm::vec3(0, -.999445f, .033315f)}},
        {{59, 59},
         {glm::vec4(-30, 0, 30, 0), glm::vec4(30, 0, -29, 0), glm::vec4(0, 30, 30, 0), glm::vec4(0, -30, -29, 0)},
         {glm::vec3(-.707107f, 0, .707107f), glm::vec3(.718988f, 0, -.695022f), glm::vec3(0, .707107f, .707107f),
          glm::vec3(0, -.718988f, -.695022f)}},
    };
    for (const Row& row : rows) {
        CAPTURE(row.g.x);
        CAPTURE(row.g.y);
        const IntelTileColumns cols = intelTileColumns(row.g, 10, fb, projection);
        CHECK(cols.tileScale == glm::vec2(30.0f));
        CHECK(cols.tileBias == glm::vec2(30.0f) - glm::vec2(row.g));  // +30 (g = 0) ... -29 (g = 59)
        const std::array<glm::vec4, 4> raw = intelSidePlanesRaw(cols, IntelSidePlanes::TileBounds);
        const std::array<glm::vec4, 6> planes = tileFrustumPlanesIntel(row.g, 10, fb, projection, 1.0f, 100.0f, IntelSidePlanes::TileBounds);
        for (std::size_t i = 0; i < 4; ++i) {
            CAPTURE(i);
            CHECK(raw[i] == row.raw[i]);  // small integers: exact
            CHECK(near3(glm::vec3(planes[i]), row.unit[i], 6e-7f));  // the table's 6 decimals
            CHECK(planes[i].w == 0.0f);
        }
    }
    // The note's check: light at view (0, 0, 10), r = 1, tile (29, 29): P0 d = 0, P1 d = .33315,
    // P2 d = 0, P3 d = .33315 (all >= -1). Near/far decide: with minTileZ = 5, maxTileZ = 20 the
    // near plane gives 10 - 5 = 5 and the far plane -10 + 20 = 10: kept. With maxTileZ = 8.5 the
    // far plane gives -1.5 < -1: culled; with maxTileZ = 9 it gives -1, not < -1: kept.
    const glm::vec3 light(0, 0, 10);
    const auto planes = tileFrustumPlanesIntel({29, 29}, 10, fb, projection, 5.0f, 20.0f, IntelSidePlanes::TileBounds);
    const auto d = [&](std::size_t i) { return glm::dot(planes[i], glm::vec4(light, 1.0f)); };
    CHECK(d(0) == 0.0f);
    CHECK(d(1) == doctest::Approx(0.33315).epsilon(1e-4));
    CHECK(d(2) == 0.0f);
    CHECK(d(3) == doctest::Approx(0.33315).epsilon(1e-4));
    CHECK(sphereInFrustumIntel(light, 1.0f, planes));
    CHECK_FALSE(sphereInFrustumIntel(light, 1.0f, tileFrustumPlanesIntel({29, 29}, 10, fb, projection, 5.0f, 8.5f, IntelSidePlanes::TileBounds)));
    CHECK(sphereInFrustumIntel(light, 1.0f, tileFrustumPlanesIntel({29, 29}, 10, fb, projection, 5.0f, 9.0f, IntelSidePlanes::TileBounds)));
}

TEST_CASE("Intel 2010 sample planes (c4 +- c1, c4 +- c2) span 2x2 tiles, while the note's (c1, c2) bound the tile") {
    // 600x600, 10 px tiles, _11 = _22 = 1, tile (29, 29) = px [290, 300] x [290, 300]. In tile
    // units tx = (x_ndc + 1) * 30 = px / 10: c4 - c1 >= 0 <=> tx <= 30, c1 >= 0 <=> tx >= 29, but
    // c4 + c1 >= 0 <=> tx >= 28. Test points on the rays through pixel centres at view z = 10.
    const glm::mat4 projection(1.0f);
    const auto note = tileFrustumPlanesIntel({29, 29}, 10, {600, 600}, projection, 1.0f, 100.0f, IntelSidePlanes::TileBounds);
    const auto sample = tileFrustumPlanesIntel({29, 29}, 10, {600, 600}, projection, 1.0f, 100.0f, IntelSidePlanes::Sample2010);
    const auto rayPoint = [](float pxX, float pxY) {  // LH view point on the pixel's ray at z = 10
        const float xNdc = pxX / 600.0f * 2.0f - 1.0f, yNdc = 1.0f - pxY / 600.0f * 2.0f;
        return glm::vec3(xNdc * 10.0f, yNdc * 10.0f, 10.0f);
    };
    CHECK(sphereInFrustumIntel(rayPoint(295.5f, 295.5f), 0.0f, note));     // the tile's own pixel
    CHECK(sphereInFrustumIntel(rayPoint(295.5f, 295.5f), 0.0f, sample));
    CHECK_FALSE(sphereInFrustumIntel(rayPoint(285.5f, 295.5f), 0.0f, note));     // tile (28, 29)
    CHECK(sphereInFrustumIntel(rayPoint(285.5f, 295.5f), 0.0f, sample));         // ... kept by 2010
    CHECK(sphereInFrustumIntel(rayPoint(285.5f, 285.5f), 0.0f, sample));         // tile (28, 28)
    CHECK_FALSE(sphereInFrustumIntel(rayPoint(279.5f, 295.5f), 0.0f, sample));   // tile (27, 29): out
    CHECK_FALSE(sphereInFrustumIntel(rayPoint(300.5f, 295.5f), 0.0f, sample));   // tile (30, 29): out
    CHECK_FALSE(sphereInFrustumIntel(rayPoint(295.5f, 300.5f), 0.0f, sample));   // tile (29, 30): out
    // The raw 2010 left plane of tile (0, 0) is c4 + c1 = (30, 0, 31, 0): x_ndc >= -31/30, one tile
    // (10 px) left of the screen.
    const auto raw = intelSidePlanesRaw(intelTileColumns({0, 0}, 10, {600, 600}, projection), IntelSidePlanes::Sample2010);
    CHECK(raw[1] == glm::vec4(30, 0, 31, 0));
    CHECK(raw[3] == glm::vec4(0, -30, 31, 0));
}

TEST_CASE("the three constructions agree on every tile of 1280x720 (16 px tiles, 45-degree FOV)") {
    // Same FOV and aspect for the three projections, each in its own convention: 3dgep's GL-form
    // RH (near 0.1, far 1000), AMD's reversed LH (ForwardPlus11: near and far swapped) and Intel's
    // complementary LH (300, 0.05). glm computes P11 = 1 / (aspect tan(fov/2)) and P22 = 1 / tan(fov/2)
    // the same way for all three, so the side planes must coincide up to rounding of the corners,
    // cross products and normalization.
    const float fovY = glm::radians(45.0f), aspect = 1280.0f / 720.0f;
    const glm::mat4 proj3dgep = glm::perspectiveRH_NO(fovY, aspect, 0.1f, 1000.0f);
    const glm::mat4 projAmd = glm::perspectiveLH_ZO(fovY, aspect, 1000.0f, 0.1f);
    const glm::mat4 projIntel = glm::perspectiveLH_ZO(fovY, aspect, 300.0f, 0.05f);
    REQUIRE(proj3dgep[0][0] == projAmd[0][0]);
    REQUIRE(proj3dgep[1][1] == projIntel[1][1]);
    const glm::mat4 inv3dgep = glm::inverse(proj3dgep), invAmd = glm::inverse(projAmd);
    const glm::uvec2 screen(1280, 720);
    const glm::uvec2 tiles = tileCount(screen, 16);
    CHECK(tiles == glm::uvec2(80, 45));  // 3dgep article §4.2: 3,600 frustums

    float maxAmd = 0.0f, maxIntel = 0.0f, maxD = 0.0f;
    for (std::uint32_t ty = 0; ty < tiles.y; ++ty) {
        for (std::uint32_t tx = 0; tx < tiles.x; ++tx) {
            const TileSidePlanes a = commonSidePlanes(gridFrustum3dgep({tx, ty}, 16, glm::vec2(screen), inv3dgep));
            const TileSidePlanes b = commonSidePlanesFromAmd(tileSidePlanesAmd({tx, ty}, 16, screen, invAmd, AmdTileCorners::PaddedGrid));
            const TileSidePlanes c = commonSidePlanesFromIntel(
                tileFrustumPlanesIntel({tx, ty}, 16, screen, projIntel, 0.05f, 300.0f, IntelSidePlanes::TileBounds));
            for (std::size_t i = 0; i < 4; ++i) {
                const glm::vec3 da = glm::abs(a[i].N - b[i].N), dc = glm::abs(a[i].N - c[i].N);
                maxAmd = std::max({maxAmd, da.x, da.y, da.z});
                maxIntel = std::max({maxIntel, dc.x, dc.y, dc.z});
                maxD = std::max({maxD, std::fabs(a[i].d), std::fabs(b[i].d), std::fabs(c[i].d)});
            }
        }
    }
    MESSAGE("max |N component difference| over 3600 tiles x 4 planes: 3dgep vs AMD " << maxAmd << ", 3dgep vs Intel "
                                                                                     << maxIntel);
    // Bound: the corner (or column) directions carry a relative error delta of a few u = 2^-24
    // (float inverse projection, ScreenToView's 4 roundings, AMD's division by w), and the normal
    // of the plane through two directions theta apart amplifies it to ~delta / theta. A 16 px tile
    // of 1280 spans 0.025 NDC = 0.025 / P11 = 0.0184 rad at the centre and 1.54x less at the
    // screen edge (x / P11 = 0.736): theta >= 0.0120 rad. With delta = 3u: 3u / theta = 1.5e-5.
    constexpr float kU = 1.0f / 16777216.0f;
    const float bound = 3.0f * kU / 0.0120f;
    CHECK(maxAmd <= bound);
    CHECK(maxIntel <= bound);
    CHECK(maxD == 0.0f);  // all side planes pass through the eye exactly
}

TEST_CASE("AMD ForwardPlus11 padded-grid corners miss pixels at 1920x1080 (1080 = 67.5 tiles of 16)") {
    // GetNumTilesY = (uint)((1080 + 15) / 16.f) = 68, so the corners are mapped over 68 * 16 = 1088
    // rows: tile row 50 (pixel rows 800..815) gets y_ndc in [(1088-816)/1088*2-1, (1088-800)/1088*2-1]
    // = [-0.5, -0.4706], but its pixels span y_ndc = 1 - 2 py / 1080 in [-0.5111, -0.4815]. Rows
    // 810..815 lie below the frustum. A small light on the ray through pixel (808.5, 815.5), which
    // touches only that pixel's neighbourhood, is culled by the faithful frustum and kept by the
    // corrected one (corners over the screen's 1080 rows).
    const float fovY = glm::radians(45.0f), aspect = 1920.0f / 1080.0f;
    const glm::mat4 projAmd = glm::perspectiveLH_ZO(fovY, aspect, 1000.0f, 0.1f);
    const glm::mat4 invAmd = glm::inverse(projAmd);
    const glm::uvec2 screen(1920, 1080);
    const glm::uvec2 tile(50, 50);
    const float z = 10.0f;
    const float xNdc = 808.5f / 1920.0f * 2.0f - 1.0f, yNdc = 1.0f - 815.5f / 1080.0f * 2.0f;
    const glm::vec3 posView(xNdc * z / projAmd[0][0], yNdc * z / projAmd[1][1], z);
    const float radius = 1e-3f;  // about 0.08 px at z = 10
    const auto padded = tileSidePlanesAmd(tile, 16, screen, invAmd, AmdTileCorners::PaddedGrid);
    const auto corrected = tileSidePlanesAmd(tile, 16, screen, invAmd, AmdTileCorners::Screen);
    CHECK_FALSE(sphereOverlapsTileAmd(posView, radius, padded, 1.0f, 100.0f));
    CHECK(sphereOverlapsTileAmd(posView, radius, corrected, 1.0f, 100.0f));
    // With 720 rows (45 whole tiles) the two mappings are the same bits.
    const auto a = tileSidePlanesAmd({7, 44}, 16, {1280, 720}, invAmd, AmdTileCorners::PaddedGrid);
    const auto b = tileSidePlanesAmd({7, 44}, 16, {1280, 720}, invAmd, AmdTileCorners::Screen);
    for (std::size_t i = 0; i < 4; ++i) CHECK(a[i] == b[i]);
}

TEST_CASE("3dgep grid frustums under a D3D projection with near 1e-21: corners 5e-22 from the eye, planes of the usual directions") {
    // perspectiveRH_ZO: NDC z = -1 is view z = -n f / (2 f - n) = -5e-22 here. The corners' cross
    // products (~1e-43) square to 0 in binary32, so normalize(cross) was inf / NaN (192 NaN
    // planes in forward-plus's frustums dump); unitCross rescales them, and the planes are the
    // directions they are at near 0.1 (which depend only on the field of view and the screen).
    const glm::vec2 screen(64.0f, 48.0f);
    const glm::mat4 tiny = glm::inverse(glm::perspectiveRH_ZO(glm::radians(45.0f), 64.0f / 48.0f, 1e-21f, 100.0f));
    const glm::mat4 usual = glm::inverse(glm::perspectiveRH_ZO(glm::radians(45.0f), 64.0f / 48.0f, 0.1f, 100.0f));
    CHECK(screenToView(glm::vec4(16.0f, 16.0f, -1.0f, 1.0f), screen, tiny).z == doctest::Approx(-5e-22).epsilon(1e-3));
    const Frustum rescued = gridFrustum3dgep({1, 1}, 16, screen, tiny);
    const Frustum reference = gridFrustum3dgep({1, 1}, 16, screen, usual);
    for (std::size_t i = 0; i < 4; ++i) {
        CAPTURE(i);
        CHECK(rescued.planes[i].N.x == doctest::Approx(reference.planes[i].N.x).epsilon(1e-5));
        CHECK(rescued.planes[i].N.y == doctest::Approx(reference.planes[i].N.y).epsilon(1e-5));
        CHECK(rescued.planes[i].N.z == doctest::Approx(reference.planes[i].N.z).epsilon(1e-5));
        CHECK(rescued.planes[i].d == 0.0f);
    }
}

TEST_CASE("plane normals: corners 1e-21 from the eye underflow normalize(cross) and unitCross rescues them") {
    // cross of two vectors of length ~1e-21 has length ~1e-42 (subnormal), its square ~1e-84
    // flushes to 0: normalize divides by 0. Scaled by 2^70 first (exact), the same direction.
    const glm::vec3 a(1e-21f, 0.0f, -1e-21f), b(0.0f, 1e-21f, -1e-21f);
    const glm::vec3 plain = cullmath::normalize(cullmath::cross(a, b));
    CHECK_FALSE(std::isfinite(plain.x));  // 1e-42 / sqrt(0)
    const glm::vec3 rescued = cullmath::unitCross(a, b);
    const glm::vec3 expected = cullmath::normalize(cullmath::cross(a * 1e21f, b * 1e21f));
    CHECK(rescued.x == doctest::Approx(expected.x).epsilon(1e-6));
    CHECK(rescued.y == doctest::Approx(expected.y).epsilon(1e-6));
    CHECK(rescued.z == doctest::Approx(expected.z).epsilon(1e-6));
    // Ordinary inputs: the plain expression's bits.
    const glm::vec3 c(0.3f, -1.2f, 2.0f), d(1.7f, 0.4f, -0.9f);
    CHECK(cullmath::unitCross(c, d) == cullmath::normalize(cullmath::cross(c, d)));
    // And 1e19-sized corners, whose squared cross product overflows.
    const glm::vec3 big = cullmath::unitCross(a * 1e20f * 1e20f, b * 1e20f * 1e20f);
    CHECK(big.x == doctest::Approx(expected.x).epsilon(1e-6));
}

} // namespace tessera_test::culling_tile_frustum_test
