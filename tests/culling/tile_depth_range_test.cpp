// Per-tile depth ranges as the culling kernels compute them (culling/tile_depth_range.h): hand-
// derived 3dgep, AMD and Intel cases with exact projections, the edge-tile behaviour of each
// kernel (an out-of-range Load returns 0), and the plain loops against the same reduction run
// through the compute emulation (compute/dispatch.h) with D3D11 out-of-bounds loads.
#include <doctest/doctest.h>

#include <bit>
#include <cstdint>
#include <vector>

#include <glm/ext/matrix_clip_space.hpp>

#include <tessera/compute/dispatch.h>
#include <tessera/compute/resources.h>
#include <tessera/culling/tile_depth_range.h>

#include "support/unit_projections.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::culling_tile_depth_range_test {

using namespace tessera;
namespace tc = tessera::compute;

namespace {

using test::inverseGlFormUnit;


}  // namespace

TEST_CASE("3dgep: asuint min/max over every pixel, then ScreenToView(0, 0, d, 1).z") {
    // 4x4 screen, one 4x4 tile: depths 0.25 .. 1 (cleared pixels count: the demo's CS_main has no skip).
    const std::vector<float> depth{0.5f, 0.5f, 1.0f, 1.0f,   //
                                   0.5f, 0.25f, 1.0f, 1.0f,  //
                                   0.75f, 0.5f, 0.5f, 1.0f,  //
                                   0.75f, 0.75f, 0.5f, 1.0f};
    const DepthImageView image{depth, 4, 4};
    const TileDepthBits bits = tileDepthBits3dgep(image, {0, 0}, 4);
    CHECK(bits.minBits == std::bit_cast<std::uint32_t>(0.25f));  // 0x3E800000
    CHECK(bits.maxBits == 0x3F800000u);                          // 1.0f
    const TileDepthRange3dgep range = tileDepthRange3dgep(image, {0, 0}, 4, {4.0f, 4.0f}, inverseGlFormUnit());
    CHECK(range.minDepth == 0.25f);
    CHECK(range.maxDepth == 1.0f);
    CHECK(range.minDepthVS == -1.0f / 0.6875f);  // -16/11: w = 0.75 - 0.0625 = 0.6875 exactly
    CHECK(range.maxDepthVS == -2.0f);            // w = 0.5
    CHECK(range.nearClipVS == -1.0f / 0.75f);    // -4/3 rounded once
}

TEST_CASE("3dgep edge tiles: loads past the screen return 0, so minDepth = 0 and minDepthVS = nearClipVS") {
    // 20x18 screen, 16 px tiles -> 2x2 groups; every pixel 0.5. Tile (0,0) is whole: min = max =
    // 0.5. Tiles (1,0), (0,1), (1,1) have threads at x >= 20 or y >= 18 whose Load returns 0.
    const std::vector<float> depth(20 * 18, 0.5f);
    const DepthImageView image{depth, 20, 18};
    const glm::mat4 inv = inverseGlFormUnit();
    const TileDepthRange3dgep whole = tileDepthRange3dgep(image, {0, 0}, 16, {20.0f, 18.0f}, inv);
    CHECK(whole.minDepth == 0.5f);
    CHECK(whole.maxDepth == 0.5f);
    for (const glm::uvec2 g : {glm::uvec2(1, 0), glm::uvec2(0, 1), glm::uvec2(1, 1)}) {
        const TileDepthRange3dgep edge = tileDepthRange3dgep(image, g, 16, {20.0f, 18.0f}, inv);
        CHECK(edge.minDepth == 0.0f);
        CHECK(edge.maxDepth == 0.5f);
        CHECK(edge.minDepthVS == edge.nearClipVS);  // the opaque list's minPlane culls nothing in front
    }
}

namespace {

// The 3dgep reduction as the kernel runs it (demo ForwardPlusRendering.hlsl CS_main), through compute::dispatch.
struct DepthBounds3dgepKernel {
    static constexpr glm::uvec3 groupSize{16, 16, 1};
    struct Shared {
        std::uint32_t uMinDepth;
        std::uint32_t uMaxDepth;
    };
    tc::Texture2D<float> depthTextureVS;
    tc::RWTexture2D<std::uint32_t> minOut, maxOut;

    void operator()(tc::GroupContext<Shared>& g) const {
        Shared& s = g.shared();
        g.forOneThread(0, [&](const tc::ThreadIds&) {
            s.uMinDepth = 0xFFFFFFFFu;
            s.uMaxDepth = 0u;
        });
        g.forEachThread([&](const tc::ThreadIds& t) {
            const std::uint32_t uDepth = std::bit_cast<std::uint32_t>(depthTextureVS.load(glm::uvec2(t.dispatchThreadId)));
            tc::interlockedMin(s.uMinDepth, uDepth);
            tc::interlockedMax(s.uMaxDepth, uDepth);
        });
        g.forOneThread(0, [&](const tc::ThreadIds&) {
            minOut.store(glm::uvec2(g.groupId()), s.uMinDepth);
            maxOut.store(glm::uvec2(g.groupId()), s.uMaxDepth);
        });
    }
};

}  // namespace

TEST_CASE("the plain loop gives the bits of the dispatched 3dgep kernel (37x23 px, partial tiles)") {
    const std::uint32_t w = 37, h = 23;
    std::vector<float> depth(w * h);
    std::uint32_t state = 12345u;
    for (float& d : depth) {  // LCG (Numerical Recipes), depths in (0, 1], some cleared to 1
        state = state * 1664525u + 1013904223u;
        d = (state >> 8) % 7u == 0u ? 1.0f : static_cast<float>((state >> 8) & 0xFFFFu) / 65536.0f + 1.0f / 131072.0f;
    }
    const glm::uvec2 tiles = (glm::uvec2(w, h) + glm::uvec2(15u)) / 16u;  // 3 x 2
    std::vector<std::uint32_t> minBits(tiles.x * tiles.y), maxBits(tiles.x * tiles.y);
    DepthBounds3dgepKernel kernel{tc::Texture2D<float>(depth, w, h), tc::RWTexture2D<std::uint32_t>(minBits, tiles.x, tiles.y),
                                  tc::RWTexture2D<std::uint32_t>(maxBits, tiles.x, tiles.y)};
    tc::dispatch(kernel, glm::uvec3(tiles, 1u));
    const DepthImageView image{depth, w, h};
    for (std::uint32_t ty = 0; ty < tiles.y; ++ty) {
        for (std::uint32_t tx = 0; tx < tiles.x; ++tx) {
            const TileDepthBits bits = tileDepthBits3dgep(image, {tx, ty}, 16);
            CHECK(bits.minBits == minBits[ty * tiles.x + tx]);
            CHECK(bits.maxBits == maxBits[ty * tiles.x + tx]);
            // Tiles with threads past the screen (column 2: x 32..47 > 36, row 1: y 16..31 > 22)
            // get min 0; the whole tiles (0,0) and (1,0) do not (their depths are > 0).
            const bool partial = (tx + 1) * 16 > w || (ty + 1) * 16 > h;
            CHECK((bits.minBits == 0u) == partial);
        }
    }
}

TEST_CASE("AMD GPU Pro 4 (§5.3.1): LH view z, depth 1 skipped, empty tile = (NaN, +0), edge load 0 = near") {
    // LH D3D projection n = 1, f = 2: z_ndc = (2 z - 2) / z; its inverse has view.z = W and
    // view.w = -0.5 Z + W, so view z = 1 / (1 - 0.5 D): D = 0 -> 1 (near), 0.5 -> 4/3, 1 -> 2.
    glm::mat4 inv(0.0f);
    inv[0][0] = 1.0f;
    inv[1][1] = 1.0f;
    inv[3][2] = 1.0f;
    inv[2][3] = -0.5f;
    inv[3][3] = 1.0f;
    // 10 x 8 px, 8 px tiles: tile (0,0) whole, tile (1,0) has 2 columns on screen.
    std::vector<float> depth(10 * 8, 1.0f);
    depth[3 * 10 + 2] = 0.5f;  // one covered pixel in tile (0,0)
    const DepthImageView image{depth, 10, 8};
    const TileDepthBits t0 = tileViewZBitsAmdGpuPro4(image, {0, 0}, 8, inv);
    CHECK(t0.minValue() == 1.0f / 0.75f);  // 4/3: only the 0.5 pixel counts, the 1.0 ones are skipped
    CHECK(t0.maxValue() == 1.0f / 0.75f);
    // Tile (1,0): its on-screen pixels are all 1.0 (skipped), but its 48 threads past x = 10 load
    // depth 0 (!= 1), view z 1 (the near plane), which enters both min and max.
    const TileDepthBits t1 = tileViewZBitsAmdGpuPro4(image, {1, 0}, 8, inv);
    CHECK(t1.minValue() == 1.0f);
    CHECK(t1.maxValue() == 1.0f);
    // An all-cleared, fully on-screen tile keeps the initial values: minZ = asfloat(0xffffffff) (a
    // NaN), maxZ = +0.
    const std::vector<float> cleared(8 * 8, 1.0f);
    const TileDepthBits empty = tileViewZBitsAmdGpuPro4(DepthImageView{cleared, 8, 8}, {0, 0}, 8, inv);
    CHECK(empty.minBits == 0xFFFFFFFFu);
    CHECK(empty.minValue() != empty.minValue());
    CHECK(empty.maxBits == 0u);
}

TEST_CASE("AMD ForwardPlus11: reversed depth, 1 / (d _34 + _44), depth 0 skipped (edge loads too), empty = (FLT_MAX, 0)") {
    // Reversed LH projection with near 1, far 2: D(z) = (2 - z) / z... i.e. z_ndc = (-z + 2) / z,
    // D = 1 at z = 1, 0 at z = 2. Inverse: view.z = W, view.w = 0.5 Z + 0.5 W: _34 = m[2][3] = 0.5,
    // _44 = m[3][3] = 0.5, view z = 1 / (0.5 D + 0.5): D = 1 -> 1, 0.5 -> 4/3.
    glm::mat4 inv(0.0f);
    inv[0][0] = 1.0f;
    inv[1][1] = 1.0f;
    inv[3][2] = 1.0f;
    inv[2][3] = 0.5f;
    inv[3][3] = 0.5f;
    std::vector<float> depth(20 * 16, 0.0f);  // cleared to 0 (far)
    depth[2 * 20 + 17] = 0.5f;                 // tile (1,0): pixel (17, 2)
    depth[5 * 20 + 19] = 1.0f;                 // tile (1,0): pixel (19, 5), on the near plane
    const DepthImageView image{depth, 20, 16};
    // Tile (1,0) spans x 16..31, of which 20..31 are off screen: their 0 loads are skipped.
    const TileDepthBits t = tileViewZBitsAmdForwardPlus11(image, {1, 0}, 16, inv);
    CHECK(t.minValue() == 1.0f);
    CHECK(t.maxValue() == 1.0f / 0.75f);
    const TileDepthBits empty = tileViewZBitsAmdForwardPlus11(image, {0, 0}, 16, inv);
    CHECK(empty.minBits == 0x7F7FFFFFu);  // FLT_MAX: -c.z + minZ < r fails for every light
    CHECK(empty.maxBits == 0u);
}

TEST_CASE("Intel 2010: viewZ = _43 / (z - _33), valid near <= z < far, out-of-range loads (z = 0) and the far plane") {
    // The sample's complementary Z: SetProjParams(pi/4, aspect, 300, 0.05) = PerspectiveFovLH with
    // zn = 300, zf = 0.05 (glm::perspectiveLH_ZO(fov, aspect, 300, 0.05) has the same _33 =
    // zf / (zf - zn) and _43 = -zn zf / (zf - zn)); mCameraNearFar = (0.05, 300) ("swap near/far back").
    const glm::mat4 proj = glm::perspectiveLH_ZO(glm::radians(45.0f), 16.0f / 9.0f, 300.0f, 0.05f);
    const float proj43 = proj[3][2], proj33 = proj[2][2];
    // Depth 1 = view z 0.05 (near), depth 0 = view z 300 (far) in exact arithmetic. In binary32:
    const float zAtDepth0 = proj43 / (0.0f - proj33);
    const float zAtDepth1 = proj43 / (1.0f - proj33);
    // (_33 and _43 do not depend on the FOV, so these bits do not depend on a libm tan.)
    CHECK(zAtDepth0 == 300.0f);  // exactly the far distance: fails `< mCameraNearFar.y`
    CHECK(zAtDepth1 == doctest::Approx(0.05).epsilon(1e-6));
    // A 24 x 16 screen with 16 px tiles: tile (1,0) has 8 columns on screen, all at depth 0.5.
    std::vector<float> depth(24 * 16, 0.5f);
    const DepthImageView image{depth, 24, 16};
    const float zHalf = proj43 / (0.5f - proj33);  // ~0.1 (0.09998)
    const TileDepthBits t = tileViewZBitsIntel(image, {1, 0}, 16, proj, 0.05f, 300.0f);
    CHECK(t.minValue() == zHalf);
    // The off-screen threads read zBuffer = 0, i.e. view z = 300 exactly, which is not < 300: they
    // are invalid samples, so the edge tile is bounded by its on-screen pixels only.
    CHECK(t.maxValue() == zHalf);
    // Tile (0,0), wholly on screen: min = max = the pixels' view z.
    const TileDepthBits whole = tileViewZBitsIntel(image, {0, 0}, 16, proj, 0.05f, 300.0f);
    CHECK(whole.minValue() == zHalf);
    CHECK(whole.maxValue() == zHalf);
}

} // namespace tessera_test::culling_tile_depth_range_test
