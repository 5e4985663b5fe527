// Primitive assembly after the vertex shader: homogeneous clipping, perspective divide,
// viewport transform, 16.8 snapping, facing and culling, and the integer edge functions.
// Output: SetupTriangles in submission order, ready to bin and rasterize.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/raster/draw_state.h>

namespace tessera {

// Pixel-space rectangle [minX, maxX) x [minY, maxY).
struct PixelRect {
    std::int32_t minX = 0, minY = 0, maxX = 0, maxY = 0;
    bool empty() const { return minX >= maxX || minY >= maxY; }
};

// The smallest rectangle holding both (an empty one adds nothing).
inline PixelRect unite(const PixelRect& a, const PixelRect& b) {
    if (a.empty()) return b;
    if (b.empty()) return a;
    return {a.minX < b.minX ? a.minX : b.minX, a.minY < b.minY ? a.minY : b.minY, a.maxX > b.maxX ? a.maxX : b.maxX,
            a.maxY > b.maxY ? a.maxY : b.maxY};
}

// One triangle ready to rasterize, oriented so that its doubled signed area is positive
// (clockwise in window space, y down) whatever its facing.
//   E_i(P) = A_i * (P.x - X_i) + B_i * (P.y - Y_i), edge i runs from vertex i+1 to i+2
//   (indices mod 3), so E_i(P) / area2 is the barycentric weight of vertex i.
// Kept small (112 bytes, asserted below): a draw of 1M triangles holds 1M of these. A_i, B_i are differences
// of two snapped coordinates, |.| <= 2^30 (fixed_point.h), so they fit int32; every edge
// value is evaluated in int64 (same bound argument).
struct SetupTriangle {
    std::int32_t a[3], b[3];             // edge i: A = Ya - Yb, B = Xb - Xa (a = i+1, b = i+2)
    std::int32_t edgeX[3], edgeY[3];     // 16.8 start vertex (i+1) of edge i
    double invArea2;                     // 1 / (twice the area in units^2), area2 > 0
    float zWindow[3];                    // depth after the viewport transform (not clamped)
    float invW[3];                       // 1 / clip w
    std::uint32_t varyingOffset;         // index of vertex 0's varyings*invW in the float store
    PixelRect bounds;                    // covered-pixel bounds clipped to the scissor/target
    std::uint8_t bias[3];                // 0 on top/left edges, 1 elsewhere: cover when E >= bias
    bool frontFacing;
    std::uint32_t primitive;             // the triangle's index in its draw (set by setupAll)
};
// 108 bytes of members padded to the double's 8-byte alignment. Growing it costs the tile loop a
// cache line per triangle more often (bench/raster_bench, 1M 3 px triangles): change it knowingly.
static_assert(sizeof(SetupTriangle) == 112, "SetupTriangle's size changed: update the comment above and measure");

struct SetupStats {
    std::uint64_t trianglesIn = 0, culledFacing = 0, culledDegenerate = 0, culledNonFinite = 0,
                  clipped = 0, trianglesOut = 0;
    // The union of the set-up triangles' pixel bounds: every pixel the draw may write lies in it
    // (empty when no triangle survived). Lets a caller clear or copy only what changed
    // (deferred's per-light stencil clear).
    PixelRect touched;
};

// The per-draw constants setup needs.
struct SetupContext {
    const DrawState* state;
    PixelRect targetRect;          // [0,w) x [0,h) of the bound targets, ∩ scissor when enabled
    std::uint32_t varyingFloats;   // floats per vertex
};

// Sets up triangle (v0, v1, v2) given clip positions and varyings (varyingFloats floats
// each). Clipping may produce up to 8 triangles; they are appended in fan order to `out`,
// their varyings (premultiplied by 1/w) to `varyingStore`.
void setupTriangle(const SetupContext& ctx, const glm::vec4 posClip[3], const float* const varyings[3],
                   std::vector<SetupTriangle>& out, std::vector<float>& varyingStore, SetupStats& stats);

} // namespace tessera
