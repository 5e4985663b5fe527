// The D24 depth a D3D11 rasterizer must store for an opaque pass, in double precision, to judge
// tessera's and llvmpipe's depth buffers on the same frame (bench/same_frame_bench.cpp --depth-analysis, tests/conformance/llvmpipe_depth_test.cpp).
//
// From the vertex shader's float clip positions (tessera's own PhongVS, which GL's port
// reproduces bit for bit: coverage matches exactly): clipping against 0 <= z <= w (depth clip on)
// and w > 0 in double; the divide and the D3D viewport transform in binary32, as D3D11 specifies
// them (toWindow); 16.8 snapping of x and y (round to nearest even); and, exactly, the depth at the
// pixel centre as the plane through the *snapped* (x, y) and the window z of the vertices (D3D11.3 §3.4.1
// "Coordinate Snapping": "Interpolation of pixel attributes is set up based on the snapped vertex
// positions"), z linear in screen space, clamped to the viewport's [0, 1], rounded to nearest
// into UNORM24. Coverage: the pixel centre inside the snapped triangle with the top-left rule
// (exact int64 edge functions). The stored code is the minimum over the covering triangles that
// survive culling (depth LESS with writes: the first of equal codes is kept, the value is the
// same). Alpha-tested draws are not modelled (no texture lookups): use it only on passes without
// discard (forward's opaque pass, Forward+'s depth pre-pass).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace tessera::depth_truth {

inline constexpr std::uint32_t kFarCode = 0xFFFFFFu;

// Round to nearest (ties to even) of z in [0, 1] scaled by 2^24 - 1; NaN -> 0.
inline std::uint32_t d24(double z) {
    if (!(z > 0.0)) return 0;
    if (z >= 1.0) return kFarCode;
    return std::uint32_t(std::nearbyint(z * 16777215.0));
}

// One triangle as the truth rasterizes it: snapped vertices (16.8, y down), window z, oriented
// clockwise (area2 > 0), with the top-left bias per edge.
struct Triangle {
    std::int64_t x[3], y[3];
    double z[3];
    std::int64_t area2 = 0;
    std::int64_t bias[3];
    bool front = true;
    // E_i at (px, py) in 16.8 units: edge i runs from vertex i+1 to i+2; E_i / area2 is vertex
    // i's barycentric weight.
    std::int64_t edge(int i, std::int64_t px, std::int64_t py) const {
        const int a = (i + 1) % 3, b = (i + 2) % 3;
        return (y[a] - y[b]) * (px - x[a]) + (x[b] - x[a]) * (py - y[a]);
    }
};

// Clip-space polygon clipped against 0 <= z, z <= w, w >= tiny in double (Sutherland-Hodgman,
// interpolating from the inside vertex). Returns the vertex count (0..9).
inline int clip(const glm::dvec4 in[3], glm::dvec4 out[12]) {
    std::array<glm::dvec4, 12> a{}, b{};
    int n = 3;
    for (int i = 0; i < 3; ++i) a[std::size_t(i)] = in[i];
    const auto dist = [](int p, const glm::dvec4& c) {
        return p == 0 ? c.z : p == 1 ? c.w - c.z : c.w - 1e-30;
    };
    for (int p = 0; p < 3 && n >= 3; ++p) {
        int m = 0;
        for (int i = 0; i < n; ++i) {
            const glm::dvec4& cur = a[std::size_t(i)];
            const glm::dvec4& nxt = a[std::size_t((i + 1) % n)];
            const double dc = dist(p, cur), dn = dist(p, nxt);
            if (dc >= 0.0) b[std::size_t(m++)] = cur;
            if ((dc >= 0.0) != (dn >= 0.0)) {
                const glm::dvec4& inV = dc >= 0.0 ? cur : nxt;
                const glm::dvec4& outV = dc >= 0.0 ? nxt : cur;
                const double di = dc >= 0.0 ? dc : dn, dout = dc >= 0.0 ? dn : dc;
                const double t = di / (di - dout);
                glm::dvec4 v = inV + t * (outV - inV);
                if (p == 0) v.z = 0.0;
                if (p == 1) v.z = v.w;
                b[std::size_t(m++)] = v;
            }
        }
        n = m;
        std::swap(a, b);
    }
    for (int i = 0; i < n; ++i) out[i] = a[std::size_t(i)];
    return n;
}

// Window position of a clip vertex (viewport 0, 0, width, height, depth 0..1). The divide and
// the viewport transform are binary32 operations in D3D11 (D3D11.3 §15.6: x = (x/w + 1) *
// Width/2 + TopLeftX, y = (1 - y/w) * Height/2 + TopLeftY, z = MinDepth + z/w * (MaxDepth -
// MinDepth)), so the rasterizer's inputs are those binary32 values (a clipped vertex is rounded to
// binary32 first, as a clipper's output is); x and y are then snapped to 16.8 (round to nearest
// even). Everything after, the plane and its conversion, is exact here.
inline void toWindow(const glm::dvec4& c, double width, double height, std::int64_t& x, std::int64_t& y, double& z) {
    const glm::vec4 v(c);
    const float xNdc = v.x / v.w, yNdc = v.y / v.w, zNdc = v.z / v.w;
    const float xw = (xNdc + 1.0f) * (float(width) * 0.5f);
    const float yw = (1.0f - yNdc) * (float(height) * 0.5f);
    x = std::int64_t(std::nearbyint(double(xw) * 256.0));
    y = std::int64_t(std::nearbyint(double(yw) * 256.0));
    z = double(0.0f + zNdc * (1.0f - 0.0f));
}

// Builds the snapped triangle; false when degenerate (zero snapped area).
inline bool makeTriangle(const glm::dvec4 c[3], double width, double height, bool frontCounterClockwise, Triangle& t) {
    for (int i = 0; i < 3; ++i) toWindow(c[i], width, height, t.x[i], t.y[i], t.z[i]);
    std::int64_t area2 = (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.y[1] - t.y[0]) * (t.x[2] - t.x[0]);
    if (area2 == 0) return false;
    const bool clockwise = area2 > 0;
    t.front = frontCounterClockwise ? !clockwise : clockwise;
    if (!clockwise) {
        std::swap(t.x[1], t.x[2]);
        std::swap(t.y[1], t.y[2]);
        std::swap(t.z[1], t.z[2]);
        area2 = -area2;
    }
    t.area2 = area2;
    for (int i = 0; i < 3; ++i) {
        const int a = (i + 1) % 3, b = (i + 2) % 3;
        const bool top = t.y[a] == t.y[b] && t.x[b] > t.x[a];
        const bool left = t.y[b] < t.y[a];
        t.bias[i] = (top || left) ? 0 : 1;
    }
    return true;
}

// Depth at pixel (px, py)'s centre when covered (else false): sum of E_i z_i / area2.
inline bool depthAt(const Triangle& t, std::int64_t px, std::int64_t py, double& z) {
    const std::int64_t cx = px * 256 + 128, cy = py * 256 + 128;
    std::int64_t e[3];
    for (int i = 0; i < 3; ++i) {
        e[i] = t.edge(i, cx, cy);
        if (e[i] < t.bias[i]) return false;
    }
    // e_i <= area2 < 2^53 on screen-sized triangles: each weight exact to one rounding.
    const double inv = 1.0 / double(t.area2);
    z = (double(e[0]) * inv) * t.z[0] + (double(e[1]) * inv) * t.z[1] + (double(e[2]) * inv) * t.z[2];
    return true;
}

} // namespace tessera::depth_truth
