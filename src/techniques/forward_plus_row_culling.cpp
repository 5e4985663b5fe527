// forward-plus's row-parallel culling ("culling": "binned", the default): CS_main's tests in
// CS_main's order, per tile row in parallel over the binned candidate lights, with the spot
// lights' per-light cone terms (forward_plus_detail.h SpotCullTerms); the same lists as the kernel.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include <tbb/parallel_for.h>

#include <tessera/buffers/conversion.h>
#include <tessera/culling/frustum.h>
#include <tessera/culling/tile_depth_range.h>

#include "forward_plus_detail.h"

namespace tessera::forward_plus_detail {
namespace {

// coneInsidePlane[Corrected](cone, plane) for a tile side plane, decided by the bounding sphere
// where it is clear (SpotCullTerms).
bool coneInsideSidePlane(const Cone& cone, const SpotCullTerms& t, const Plane& plane, bool corrected) {
    const float distance = signedDistance(plane, t.boundCentre);
    const float reach = t.boundReach + static_cast<float>(binning::kPadRelative) * std::abs(plane.d);
    if (distance > reach) return false;
    if (distance < -reach) return true;
    return corrected ? coneInsidePlaneCorrected(cone, plane) : coneInsidePlane(cone, plane);
}

// Step 1 for the tiles of row ty: asuint min / max of DepthTextureVS.Load over each tile.
void tileDepthRow(const Surface& depth, std::uint32_t block, std::uint32_t ty, glm::uvec2 tiles, TileDepthBits* out) {
    const std::uint32_t width = depth.width(), height = depth.height();
    const std::uint32_t y0 = ty * block, y1 = std::min(y0 + block, height);
    const bool rowPartial = y0 + block > height;
    const bool d24 = depth.format() == Format::D24_UNORM_S8_UINT;
    for (std::uint32_t tx = 0; tx < tiles.x; ++tx) {
        const std::uint32_t x0 = tx * block, x1 = std::min(x0 + block, width);
        std::uint32_t lo = 0xFFFFFFFFu, hi = 0;  // D24 codes, or float bits for other formats
        const std::uint32_t samples = depth.sampleCount();  // MSAA: every sample (a row's are contiguous)
        for (std::uint32_t y = y0; y < y1; ++y) {
            const std::byte* texel = depth.texel(x0, y);
            for (std::uint32_t x = x0; x < x1; ++x) {
                for (std::uint32_t i = 0; i < samples; ++i, texel += 4) {
                    std::uint32_t v;
                    if (d24) {
                        std::memcpy(&v, texel, sizeof(v));
                        v &= 0xFFFFFFu;
                    } else {
                        v = std::bit_cast<std::uint32_t>(depth.loadDepth(x, y, i));
                    }
                    lo = std::min(lo, v);
                    hi = std::max(hi, v);
                }
            }
        }
        TileDepthBits bits{d24 ? std::bit_cast<std::uint32_t>(convert::d24ToDepth(lo)) : lo,
                           d24 ? std::bit_cast<std::uint32_t>(convert::d24ToDepth(hi)) : hi};
        if (rowPartial || x0 + block > width) {  // off-screen threads load 0.0f (asuint 0)
            bits.minBits = 0;
        }
        out[tx] = bits;
    }
}

// Step 2 of cullLightsBinned.
void bucketLightsByRow(CullScratch& sc, glm::uvec2 tiles) {
    // Step 2: the lights of each tile row, ascending (CSR).
    sc.rowStart.assign(std::size_t{tiles.y} + 1, 0);
    for (const LightTileRect& r : sc.rects)
        if (r.x0 <= r.x1) {
            for (std::uint32_t ty = r.y0; ty <= r.y1; ++ty) ++sc.rowStart[ty + 1];
            for (std::uint32_t ty = r.y2; ty <= r.y3; ++ty) ++sc.rowStart[ty + 1];
        }
    for (std::uint32_t ty = 0; ty < tiles.y; ++ty) sc.rowStart[ty + 1] += sc.rowStart[ty];
    sc.rowCursor.assign(sc.rowStart.begin(), sc.rowStart.end() - 1);
    sc.rowLights.resize(sc.rowStart.back());
    for (std::size_t i = 0; i < sc.rects.size(); ++i) {
        const LightTileRect& r = sc.rects[i];
        if (r.x0 <= r.x1) {
            for (std::uint32_t ty = r.y0; ty <= r.y1; ++ty) sc.rowLights[sc.rowCursor[ty]++] = std::uint32_t(i);
            for (std::uint32_t ty = r.y2; ty <= r.y3; ++ty) sc.rowLights[sc.rowCursor[ty]++] = std::uint32_t(i);
        }
    }
}

} // namespace

// (SpotCullTerms, forward_plus_detail.h: what these terms are and why they give the same booleans.)
SpotCullTerms spotCullTerms(const Cone& cone, const BoundingSphere& bound, bool corrected, float nearClipVS) {
    const auto testPoint = [&](const glm::vec3& N) {
        return corrected ? coneTestPointCorrected(cone, N) : coneTestPoint(cone, N);
    };
    SpotCullTerms t;
    const Plane nearPlane = nearPlane3dgep(nearClipVS);
    t.nearCulls = pointInsidePlane(cone.T, nearPlane) && pointInsidePlane(testPoint(nearPlane.N), nearPlane);
    const glm::vec3 farN(0.0f, 0.0f, 1.0f), minN(0.0f, 0.0f, -1.0f);  // farPlane3dgep / nearPlane3dgep normals
    t.dotTFar = cullmath::dot(farN, cone.T);
    t.dotQFar = cullmath::dot(farN, testPoint(farN));
    t.dotTMin = cullmath::dot(minN, cone.T);
    t.dotQMin = cullmath::dot(minN, testPoint(minN));
    const double reach = bound.r + bound.pad;
    if (std::isfinite(reach) && std::isfinite(bound.c.x) && std::isfinite(bound.c.y) && std::isfinite(bound.c.z) && reach < 1e30) {
        t.boundCentre = glm::vec3(bound.c);
        t.boundReach = static_cast<float>(reach);
    }
    return t;
}

// ----- Tessera's row-parallel culling ("culling": "binned") --------------------------------------
// The same tests in the same order as CullLightsKernel, so the same lists, grids and counters
// ("culling": "brute" runs the kernel over every light; tests/techniques/forward_plus_test.cpp and
// tests/golden/forward_plus_scenes_test.cpp compare the two), organised for a CPU:
//  1. per tile, CS_main's depth range from the D24 codes: the min / max of asuint over the
//     decoded floats is the decode of the min / max code, because d24ToDepth is a correctly
//     rounded c / (2^24 - 1) (monotone) and non-negative floats order as their bits; an edge
//     tile's off-screen threads load 0.0f, the smallest value (culling/tile_depth_range.h);
//  2. per light, its tile rectangle (lightTileRect), and the lights bucketed by tile row in
//     ascending index;
//  3. per tile row, in parallel: each light of the row against each tile of its columns,
//     appended to the tile's slice of the row's list in ascending light index with an unclamped
//     count (the group-shared InterlockedAdd of the strided loop, dispatch.h order rule 2);
//  4. the global offsets the OrderedCounter hands out: the row-major exclusive prefix sum of
//     the counts in uint32 arithmetic (InterlockedAdd wraps), with the overflow tally;
//  5. per tile row, in parallel: the grid and the copy to the global list with the kernel's
//     rules (entries past the local capacity read 0, writes past the global list discarded).
// Nothing is allocated per tile; the scratch (CullScratch, forward_plus_detail.h) lives with the
// technique and only grows.
template <std::uint32_t kBlock>
void cullLightsBinned(const ForwardPlusState& st, Device& device, CullScratch& sc, const Surface& depthSurface,
                      float nearClipVS, std::uint32_t localCapacity, std::uint64_t capacity, const GlobalList& opaque,
                      const GlobalList& transparent) {
    const glm::uvec2 tiles = st.tiles;
    const std::size_t tileCount = std::size_t{tiles.x} * tiles.y;
    const std::vector<Frustum>& frustums = sc.frustums;
    OverflowTally& opaqueTally = *opaque.tally;
    OverflowTally& transparentTally = *transparent.tally;
    compute::OrderedCounter& opaqueCounter = *opaque.counter;
    compute::OrderedCounter& transparentCounter = *transparent.counter;
    bucketLightsByRow(sc, tiles);
    sc.tiles.resize(tileCount);
    sc.depthBits.resize(tileCount);
    sc.tileSlice.resize((std::size_t{tiles.x} + 1) * tiles.y);
    sc.oCount.assign(tileCount, 0);
    sc.tCount.assign(tileCount, 0);
    sc.oOffset.resize(tileCount);
    sc.tOffset.resize(tileCount);
    sc.rowO.resize(tiles.y);
    sc.rowT.resize(tiles.y);
    const bool coneCorrected = st.options.coneCorrected;
    // Steps 1 and 3, one tile row per task.
    const auto cullRow = [&](std::uint32_t ty) {
        const std::size_t rowBase = std::size_t{ty} * tiles.x;
        tileDepthRow(depthSurface, kBlock, ty, tiles, sc.depthBits.data() + rowBase);
        for (std::uint32_t tx = 0; tx < tiles.x; ++tx) {
            TileCull& tc = sc.tiles[rowBase + tx];
            const TileDepthBits& bits = sc.depthBits[rowBase + tx];
            tc.frustum = frustums[rowBase + tx];
            const float minDepthVS =
                screenToView(glm::vec4(0.0f, 0.0f, bits.minValue(), 1.0f), st.screenDimensions, st.inverseProjection).z;
            tc.maxDepthVS = screenToView(glm::vec4(0.0f, 0.0f, bits.maxValue(), 1.0f), st.screenDimensions, st.inverseProjection).z;
            tc.minPlane = nearPlane3dgep(minDepthVS);
        }
        // Each tile's slice: as many entries as the tile has candidates (a difference array
        // over the lights' column ranges, then an exclusive prefix sum).
        std::uint32_t* slice = sc.tileSlice.data() + (std::size_t{tiles.x} + 1) * ty;
        std::fill(slice, slice + tiles.x + 1, 0u);
        for (std::uint32_t k = sc.rowStart[ty]; k < sc.rowStart[ty + 1]; ++k) {
            const CullLight& c = sc.lights[sc.rowLights[k]];
            ++slice[c.x0];
            --slice[c.x1 + 1];  // uint32 wrap-around: the running sum below is exact
            if (c.x2 <= c.x3) {
                ++slice[c.x2];
                --slice[c.x3 + 1];
            }
        }
        std::uint32_t running = 0, start = 0;
        for (std::uint32_t tx = 0; tx <= tiles.x; ++tx) {
            running += slice[tx];
            slice[tx] = start;
            start += running;
        }
        std::vector<std::uint32_t>& oList = sc.rowO[ty];
        std::vector<std::uint32_t>& tList = sc.rowT[ty];
        if (oList.size() < start) oList.resize(start);
        if (tList.size() < start) tList.resize(start);
        std::uint32_t* oCount = sc.oCount.data() + rowBase;
        std::uint32_t* tCount = sc.tCount.data() + rowBase;
        for (std::uint32_t k = sc.rowStart[ty]; k < sc.rowStart[ty + 1]; ++k) {
            const std::uint32_t i = sc.rowLights[k];
            const CullLight& c = sc.lights[i];
            const auto cullTile = [&](std::uint32_t tx) {
                const TileCull& tc = sc.tiles[rowBase + tx];
                bool opaqueToo = false;
                switch (c.type) {
                case LightType::Point:
                    if (!sphereInsideFrustum(c.sphere, tc.frustum, nearClipVS, tc.maxDepthVS)) return;
                    opaqueToo = !sphereInsidePlane(c.sphere, tc.minPlane);
                    break;
                case LightType::Spot: {  // coneInsideFrustum[Corrected], then the minPlane test
                    const SpotCullTerms& t = c.spot;
                    if (t.nearCulls) return;
                    if (t.dotTFar - tc.maxDepthVS < 0.0f && t.dotQFar - tc.maxDepthVS < 0.0f) return;  // far plane
                    const Cone cone{c.sphere.c, c.sphere.r, c.direction, c.coneRadius};
                    for (const Plane& plane : tc.frustum.planes)
                        if (coneInsideSidePlane(cone, t, plane, coneCorrected)) return;
                    opaqueToo = !(t.dotTMin - tc.minPlane.d < 0.0f && t.dotQMin - tc.minPlane.d < 0.0f);
                    break;
                }
                case LightType::Directional: opaqueToo = true; break;  // always added
                case LightType::Capsule: return;  // not a 3dgep light: never listed
                }
                tList[slice[tx] + tCount[tx]++] = i;
                if (opaqueToo) oList[slice[tx] + oCount[tx]++] = i;
            };
            // The two column runs are disjoint: each tile sees the light once.
            for (std::uint32_t tx = c.x0; tx <= c.x1; ++tx) cullTile(tx);
            for (std::uint32_t tx = c.x2; tx <= c.x3; ++tx) cullTile(tx);
        }
    };
    device.execute([&] { tbb::parallel_for(std::uint32_t(0), tiles.y, cullRow); });
    // Step 4: row-major offsets, as the OrderedCounter reserves them.
    std::uint32_t oNext = 0, tNext = 0;
    for (std::size_t tile = 0; tile < tileCount; ++tile) {
        sc.oOffset[tile] = oNext;
        sc.tOffset[tile] = tNext;
        oNext += sc.oCount[tile];
        tNext += sc.tCount[tile];
        opaqueTally.add(sc.oCount[tile], localCapacity, sc.oOffset[tile], capacity);
        transparentTally.add(sc.tCount[tile], localCapacity, sc.tOffset[tile], capacity);
    }
    opaqueCounter.reset(oNext);
    transparentCounter.reset(tNext);
    // Step 5: grids and global lists.
    const auto copy = [&](const GlobalList& global, std::uint32_t count, std::uint32_t offset, const std::uint32_t* list) {
        for (std::uint32_t i = 0; i < count; ++i) {
            const std::uint32_t at = offset + i;  // uint arithmetic, as in HLSL
            if (at < global.capacity) storeUint32(global.indexList, at, i < localCapacity ? list[i] : 0u);
        }
    };
    device.execute([&] {
        tbb::parallel_for(std::uint32_t(0), tiles.y, [&](std::uint32_t ty) {
            const std::uint32_t* slice = sc.tileSlice.data() + (std::size_t{tiles.x} + 1) * ty;
            for (std::uint32_t tx = 0; tx < tiles.x; ++tx) {
                const std::size_t tile = std::size_t{ty} * tiles.x + tx;
                storeUint32(opaque.grid, tile * 2, sc.oOffset[tile]);
                storeUint32(opaque.grid, tile * 2 + 1, sc.oCount[tile]);
                storeUint32(transparent.grid, tile * 2, sc.tOffset[tile]);
                storeUint32(transparent.grid, tile * 2 + 1, sc.tCount[tile]);
                copy(opaque, sc.oCount[tile], sc.oOffset[tile], sc.rowO[ty].data() + slice[tx]);
                copy(transparent, sc.tCount[tile], sc.tOffset[tile], sc.rowT[ty].data() + slice[tx]);
            }
        });
    });
}

template void cullLightsBinned<8>(const ForwardPlusState&, Device&, CullScratch&, const Surface&, float, std::uint32_t,
                                  std::uint64_t, const GlobalList&, const GlobalList&);
template void cullLightsBinned<16>(const ForwardPlusState&, Device&, CullScratch&, const Surface&, float, std::uint32_t,
                                   std::uint64_t, const GlobalList&, const GlobalList&);
template void cullLightsBinned<32>(const ForwardPlusState&, Device&, CullScratch&, const Surface&, float, std::uint32_t,
                                   std::uint64_t, const GlobalList&, const GlobalList&);

} // namespace tessera::forward_plus_detail
