// Shared test scaffolding: a clip-space vertex with a colour, pass-through shaders, and a
// one-call way to draw triangle lists with a given state into given targets.
#pragma once

#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/raster/device.h>

namespace tessera::test {

struct ColorVertex {
    glm::vec4 posClip{0, 0, 0, 1};
    glm::vec4 color{1, 1, 1, 1};
};

struct ColorVaryings {
    glm::vec4 color;
};

struct PassThroughVS {
    using Varyings = ColorVaryings;
    VertexOutput<ColorVaryings> operator()(const ColorVertex& v) const { return {v.posClip, {v.color}}; }
};

// Writes the interpolated colour to target 0.
struct ColorPS {
    using Varyings = ColorVaryings;
    static constexpr int kTargetCount = 1;
    void operator()(const PixelInput<ColorVaryings>& in, PixelOutput<1>& out) const { out.target[0] = in.varyings.color; }
};

// Window position (px, D3D: origin top-left, y down) to clip space for a full-target
// viewport of size w x h, with clip w = `clipW` and NDC depth z.
inline glm::vec4 windowToClip(float xWin, float yWin, float w, float h, float z = 0.5f, float clipW = 1.0f) {
    const float xNdc = xWin / w * 2.0f - 1.0f, yNdc = 1.0f - yWin / h * 2.0f;
    return glm::vec4(xNdc * clipW, yNdc * clipW, z * clipW, clipW);
}

// Path-equality tests (SIMD blocks on and off, block shaders against operator()) draw the same
// random geometry and cycling states through both paths. `count` large triangles (whole 8x8
// blocks inside them), clip w in [0.5, 2.5), z and colours a little outside [0, 1] (clipping,
// depth clamping and colour clamping on every path).
inline std::vector<ColorVertex> randomLargeTriangles(std::mt19937& rng, int count) {
    std::uniform_real_distribution<float> u(-1.3f, 1.3f), zr(-0.2f, 1.2f), wr(0.5f, 2.5f), c(-0.1f, 1.1f);
    std::vector<ColorVertex> verts;
    for (int i = 0; i < 3 * count; ++i) {
        const float w = wr(rng);
        verts.push_back({glm::vec4(u(rng) * w, u(rng) * w, zr(rng) * w, w), glm::vec4(c(rng), c(rng), c(rng), c(rng))});
    }
    return verts;
}

// Draw number `draw`'s state for those tests: the viewport's depth range, cull mode, depth
// enable, write and function, the stencil (the General depth path) and the precision, each
// cycling with its own period so that the draws meet every combination.
inline DrawState cyclingDepthState(int draw, const Surface& target) {
    DrawState st;
    st.viewport = fullViewport(target);
    st.viewport.minDepth = draw % 5 == 2 ? 0.2f : 0.0f;
    st.viewport.maxDepth = draw % 5 == 3 ? 0.8f : 1.0f;
    st.rasterizer.cullMode = CullMode(1 + draw % 3);
    st.depthStencil.depthEnable = draw % 6 != 5;
    st.depthStencil.depthWriteEnable = draw % 4 != 3;
    st.depthStencil.depthFunc = ComparisonFunc(1 + (draw * 3) % 8);
    st.depthStencil.stencilEnable = draw % 7 == 6;  // the General path: no lean block
    st.precision = draw % 8 == 4 ? Precision::Fast : Precision::Exact;
    return st;
}

// An additive R32_FLOAT "coverage counter": each covered pixel sample gets +1 per triangle.
inline DrawState countingState(const Surface& target) {
    DrawState st;
    st.rasterizer.cullMode = CullMode::None;
    st.depthStencil.depthEnable = false;
    st.blend.renderTarget[0] = kAdditiveBlend;
    st.viewport = fullViewport(target);
    return st;
}

} // namespace tessera::test

// The pass-through draw most raster tests use, instantiated once in test_draw.cpp (the rasteriser's
// templates are the costliest code to compile; each test file that draws would repeat them).
extern template tessera::DrawStats tessera::Device::draw<tessera::test::ColorVertex, tessera::test::PassThroughVS,
                                                         tessera::test::ColorPS>(
    const DrawState&, const RenderTargets&, std::span<const tessera::test::ColorVertex>, std::span<const std::uint32_t>,
    const tessera::test::PassThroughVS&, const tessera::test::ColorPS&, OcclusionQuery*);
