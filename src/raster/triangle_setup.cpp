// Clipping (Sutherland-Hodgman in homogeneous clip space), perspective divide, D3D viewport
// transform, 16.8 snapping and edge-function setup for one triangle. The clipper always
// interpolates from the inside vertex towards the outside one, so two triangles that share
// an edge produce bit-identical clip vertices on it and the fill rule still holds there.
#include <tessera/raster/triangle_setup.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <tessera/raster/fixed_point.h>
#include <tessera/shaders/shader_stages.h>

namespace tessera {
namespace {

// Up to 3 + 7 vertices after 7 planes (each plane adds at most one vertex to a convex polygon).
constexpr int kMaxClipVertices = 10;
constexpr int kPlaneCount = 7;
// Smallest clip w kept: points with w <= 0 are behind the eye; 2^-64 keeps x/w finite.
constexpr float kMinClipW = 5.42101086e-20f;

struct ClipVertex {
    glm::vec4 pos;
    std::array<float, kMaxVaryingFloats> v;
};

struct ClipPlanes {
    bool depthClip;
    float gx, gy;  // guard band half-extent in NDC units
    // Signed distance to plane p (>= 0 inside).
    float distance(int p, const glm::vec4& c) const {
        switch (p) {
        case 0: return c.z;                 // near: 0 <= z
        case 1: return c.w - c.z;           // far: z <= w
        case 2: return c.w - kMinClipW;     // in front of the eye
        case 3: return gx * c.w - c.x;      // guard band, right
        case 4: return gx * c.w + c.x;      // guard band, left
        case 5: return gy * c.w - c.y;      // guard band, bottom (NDC y up)
        default: return gy * c.w + c.y;     // guard band, top
        }
    }
    bool enabled(int p) const { return p >= 2 || depthClip; }
    // Puts an interpolated vertex exactly on plane p. With far-away vertices (|x| ~ 1e30)
    // the interpolation cancels catastrophically; the plane equation is exact by definition.
    void project(int p, glm::vec4& c) const {
        switch (p) {
        case 0: c.z = 0.0f; break;
        case 1: c.z = c.w; break;
        case 2: c.w = kMinClipW; break;
        case 3: c.x = gx * c.w; break;
        case 4: c.x = -gx * c.w; break;
        case 5: c.y = gy * c.w; break;
        default: c.y = -gy * c.w; break;
        }
    }
};

bool allFinite(const glm::vec4& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

// Clips `poly` (n vertices) against plane p into `out`; returns the new count.
int clipAgainst(const ClipPlanes& planes, int p, const ClipVertex* poly, int n, ClipVertex* out,
                std::uint32_t nf) {
    int count = 0;
    for (int i = 0; i < n; ++i) {
        const ClipVertex& cur = poly[i];
        const ClipVertex& next = poly[(i + 1) % n];
        const float dCur = planes.distance(p, cur.pos);
        const float dNext = planes.distance(p, next.pos);
        const bool inCur = dCur >= 0.0f, inNext = dNext >= 0.0f;
        if (inCur) out[count++] = cur;
        if (inCur != inNext) {
            // Interpolate from the inside vertex to the outside one (see the file comment).
            const ClipVertex& in = inCur ? cur : next;
            const ClipVertex& outV = inCur ? next : cur;
            const float dIn = inCur ? dCur : dNext, dOut = inCur ? dNext : dCur;
            const float t = dIn / (dIn - dOut);
            ClipVertex& nv = out[count++];
            nv.pos = in.pos + t * (outV.pos - in.pos);
            planes.project(p, nv.pos);
            for (std::uint32_t k = 0; k < nf; ++k) nv.v[k] = in.v[k] + t * (outV.v[k] - in.v[k]);
        }
    }
    return count;
}

std::int64_t floorDiv(std::int64_t a, std::int64_t b) {  // b > 0
    return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// Emits one projected triangle (already inside every enabled plane).
void emitTriangle(const SetupContext& ctx, const glm::vec4 pos[3], const float* const var[3],
                  std::vector<SetupTriangle>& out, std::vector<float>& store, SetupStats& stats) {
    const DrawState& st = *ctx.state;
    const Viewport& vp = st.viewport;
    SetupTriangle t{};
    std::int32_t xFixed[3], yFixed[3];  // 16.8 window position of each vertex
    float xWin[3], yWin[3];
    for (int i = 0; i < 3; ++i) {
        // Perspective divide and the D3D viewport transform (D3D11.3 §15.6 "Viewport"):
        //   x = (x_ndc + 1) * Width/2 + TopLeftX, y = (1 - y_ndc) * Height/2 + TopLeftY,
        //   z = MinDepth + z_ndc * (MaxDepth - MinDepth).
        const float invW = 1.0f / pos[i].w;
        const float xNdc = pos[i].x / pos[i].w, yNdc = pos[i].y / pos[i].w, zNdc = pos[i].z / pos[i].w;
        xWin[i] = (xNdc + 1.0f) * (vp.width * 0.5f) + vp.topLeftX;
        yWin[i] = (1.0f - yNdc) * (vp.height * 0.5f) + vp.topLeftY;
        t.zWindow[i] = vp.minDepth + zNdc * (vp.maxDepth - vp.minDepth);
        t.invW[i] = invW;
        if (!std::isfinite(xWin[i]) || !std::isfinite(yWin[i]) || std::fabs(xWin[i]) > fixed::kGuardBandPx ||
            std::fabs(yWin[i]) > fixed::kGuardBandPx) {
            ++stats.culledNonFinite;
            return;
        }
        xFixed[i] = fixed::snap(xWin[i]);
        yFixed[i] = fixed::snap(yWin[i]);
    }
    // Doubled signed area from the snapped positions; > 0 is clockwise in window space (y down).
    std::int64_t area2 = (std::int64_t(xFixed[1]) - xFixed[0]) * (std::int64_t(yFixed[2]) - yFixed[0]) -
                         (std::int64_t(yFixed[1]) - yFixed[0]) * (std::int64_t(xFixed[2]) - xFixed[0]);
    if (area2 == 0) {
        ++stats.culledDegenerate;
        return;
    }
    const bool clockwise = area2 > 0;
    t.frontFacing = st.rasterizer.frontCounterClockwise ? !clockwise : clockwise;
    if ((st.rasterizer.cullMode == CullMode::Back && !t.frontFacing) ||
        (st.rasterizer.cullMode == CullMode::Front && t.frontFacing)) {
        ++stats.culledFacing;
        return;
    }
    int order[3] = {0, 1, 2};
    if (!clockwise) {  // orient clockwise so that inside means every E_i > 0
        std::swap(order[1], order[2]);
        std::swap(xFixed[1], xFixed[2]);
        std::swap(yFixed[1], yFixed[2]);
        std::swap(t.zWindow[1], t.zWindow[2]);
        std::swap(t.invW[1], t.invW[2]);
        area2 = -area2;
    }
    t.invArea2 = 1.0 / double(area2);
    for (int i = 0; i < 3; ++i) {
        const int a = (i + 1) % 3, b = (i + 2) % 3;
        const std::int32_t xa = xFixed[a], ya = yFixed[a], xb = xFixed[b], yb = yFixed[b];
        // |xb - xa|, |ya - yb| <= 2^30: no int32 overflow (fixed_point.h, guard band).
        t.a[i] = ya - yb;
        t.b[i] = xb - xa;
        t.edgeX[i] = xa;
        t.edgeY[i] = ya;
        // Top-left rule (D3D11.3 §15.? "Triangle Rasterization Rules"), for a clockwise
        // triangle in y-down space: a top edge is horizontal and runs towards +x (the
        // triangle lies below it); a left edge runs upwards (towards -y). Samples exactly
        // on an edge are covered only for top and left edges.
        const bool topEdge = ya == yb && xb > xa;
        const bool leftEdge = yb < ya;
        t.bias[i] = (topEdge || leftEdge) ? 0 : 1;
    }
    // Pixel bounds: a pixel's samples lie within +-7/16 px (112 units) of its centre.
    constexpr std::int64_t kReach = fixed::kHalf + 7 * 16;
    const std::int64_t xMin = std::min({xFixed[0], xFixed[1], xFixed[2]});
    const std::int64_t xMax = std::max({xFixed[0], xFixed[1], xFixed[2]});
    const std::int64_t yMin = std::min({yFixed[0], yFixed[1], yFixed[2]});
    const std::int64_t yMax = std::max({yFixed[0], yFixed[1], yFixed[2]});
    PixelRect r;
    r.minX = std::int32_t(std::max<std::int64_t>(ctx.targetRect.minX, floorDiv(xMin - kReach, fixed::kOne)));
    r.minY = std::int32_t(std::max<std::int64_t>(ctx.targetRect.minY, floorDiv(yMin - kReach, fixed::kOne)));
    r.maxX = std::int32_t(std::min<std::int64_t>(ctx.targetRect.maxX, floorDiv(xMax + kReach, fixed::kOne) + 1));
    r.maxY = std::int32_t(std::min<std::int64_t>(ctx.targetRect.maxY, floorDiv(yMax + kReach, fixed::kOne) + 1));
    if (r.empty()) return;
    t.bounds = r;
    t.varyingOffset = std::uint32_t(store.size());
    for (int i = 0; i < 3; ++i) {
        const float* src = var[order[i]];
        for (std::uint32_t k = 0; k < ctx.varyingFloats; ++k) store.push_back(src[k] * t.invW[i]);
    }
    out.push_back(t);
    ++stats.trianglesOut;
    stats.touched = unite(stats.touched, r);
}

} // namespace

void setupTriangle(const SetupContext& ctx, const glm::vec4 posClip[3], const float* const varyings[3],
                   std::vector<SetupTriangle>& out, std::vector<float>& varyingStore, SetupStats& stats) {
    ++stats.trianglesIn;
    // D3D11: a primitive with a non-finite position is discarded (tessera's defined
    // behaviour for NaN/Inf; clipping cannot place such a vertex anywhere meaningful).
    if (!allFinite(posClip[0]) || !allFinite(posClip[1]) || !allFinite(posClip[2])) {
        ++stats.culledNonFinite;
        return;
    }
    const Viewport& vp = ctx.state->viewport;
    ClipPlanes planes;
    planes.depthClip = ctx.state->rasterizer.depthClipEnable;
    // Guard band in NDC: window |x| <= 2^21 px needs (|x_ndc| + 1) * W/2 + |TopLeftX| <= 2^21.
    planes.gx = float((fixed::kGuardBandPx - std::fabs(double(vp.topLeftX))) / (double(vp.width) * 0.5) - 2.0);
    planes.gy = float((fixed::kGuardBandPx - std::fabs(double(vp.topLeftY))) / (double(vp.height) * 0.5) - 2.0);

    unsigned outside[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i)
        for (int p = 0; p < kPlaneCount; ++p)
            if (planes.enabled(p) && planes.distance(p, posClip[i]) < 0.0f) outside[i] |= 1u << p;
    if ((outside[0] | outside[1] | outside[2]) == 0) {  // the common case: nothing to clip
        emitTriangle(ctx, posClip, varyings, out, varyingStore, stats);
        return;
    }
    if ((outside[0] & outside[1] & outside[2]) != 0) return;  // wholly outside one plane

    ++stats.clipped;
    std::array<ClipVertex, kMaxClipVertices> bufA, bufB;
    for (int i = 0; i < 3; ++i) {
        bufA[i].pos = posClip[i];
        std::copy(varyings[i], varyings[i] + ctx.varyingFloats, bufA[i].v.begin());
    }
    ClipVertex* poly = bufA.data();
    ClipVertex* next = bufB.data();
    int n = 3;
    const unsigned any = outside[0] | outside[1] | outside[2];
    for (int p = 0; p < kPlaneCount && n >= 3; ++p) {
        if (!(any & (1u << p))) continue;
        n = clipAgainst(planes, p, poly, n, next, ctx.varyingFloats);
        std::swap(poly, next);
    }
    // Fan triangulation (v0, vi, vi+1): adjacent fan triangles share an edge, the fill rule
    // covers each pixel once.
    for (int i = 1; i + 1 < n; ++i) {
        const glm::vec4 pos[3] = {poly[0].pos, poly[i].pos, poly[i + 1].pos};
        const float* var[3] = {poly[0].v.data(), poly[i].v.data(), poly[i + 1].v.data()};
        emitTriangle(ctx, pos, var, out, varyingStore, stats);
    }
}

} // namespace tessera
