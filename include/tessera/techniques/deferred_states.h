// Fixed-function states of the deferred techniques: the 3dgep G-buffer pass, per-light
// unmark and shade passes and the directional full-screen quad (3dgep article §3.3, 3dgep demo's main.cpp
// and DeferredLightingPass.cpp), and the Killzone 2 mark / count / shade variant the
// article describes but does not use. The deferred and deferred-killzone techniques bind these.
#pragma once

#include <cstdint>

#include <tessera/raster/draw_state.h>

namespace tessera {

// The fixed-function part of a pass: everything in DrawState except viewport and scissor.
struct PassState {
    RasterizerState rasterizer;
    DepthStencilState depthStencil;
    std::uint8_t stencilRef = 0;
    BlendState blend;
};

namespace deferred_detail {

// The demo's RasterizerStateDX11 defaults: cull BACK, FrontCounterClockwise TRUE (volumes and
// scene meshes are counter-clockwise seen from outside), depth clip on.
constexpr RasterizerState demoRasterizer(CullMode cull, bool depthClip) {
    RasterizerState r;
    r.cullMode = cull;
    r.frontCounterClockwise = true;
    r.depthClipEnable = depthClip;
    return r;
}

constexpr BlendState additive() {
    BlendState b;
    b.renderTarget[0] = kAdditiveBlend;  // ONE, ONE, ADD (colour and alpha)
    return b;
}

constexpr DepthStencilState depthTestNoWrite(ComparisonFunc func) {
    DepthStencilState d;
    d.depthEnable = true;
    d.depthWriteEnable = false;
    d.depthFunc = func;
    return d;
}

constexpr PassState gbuffer() {
    PassState p;
    p.rasterizer = demoRasterizer(CullMode::Back, true);
    // 3dgep demo's main.cpp g_pGeometryPipeline: the demo's DepthMode defaults, depth on, write on, LESS;
    // stencil off (the G-buffer clear leaves stencil 0, 3dgep demo's main.cpp).
    p.depthStencil.depthEnable = true;
    p.depthStencil.depthWriteEnable = true;
    p.depthStencil.depthFunc = ComparisonFunc::Less;
    p.depthStencil.stencilEnable = false;
    return p;
}

constexpr PassState unmark() {
    PassState p;
    // 3dgep article §3.3.1 Unmark Pixels: cull BACK "to render only the front faces"; 3dgep demo's main.cpp
    // g_pDeferredLightingPipeline1: SetCullMode(Back), SetDepthClipEnabled(true).
    p.rasterizer = demoRasterizer(CullMode::Back, true);
    // Article §3.3.1: depth test on, writes off, function GREATER (3dgep demo's main.cpp DepthFunction = Greater).
    p.depthStencil = depthTestNoWrite(ComparisonFunc::Greater);
    // Article §3.3.1: stencil on, function ALWAYS, DECR_SAT on depth pass; 3dgep demo's main.cpp
    // StencilReference = 1, FrontFace.StencilDepthPass = DecrementClamp, masks 0xFF (defaults);
    // BackFace keeps the defaults {KEEP, KEEP, KEEP, ALWAYS} (demo DepthStencilState.h).
    p.depthStencil.stencilEnable = true;
    p.depthStencil.stencilReadMask = 0xFF;
    p.depthStencil.stencilWriteMask = 0xFF;
    p.depthStencil.frontFace = StencilFaceDesc{StencilOp::Keep, StencilOp::Keep, StencilOp::DecrSat, ComparisonFunc::Always};
    p.depthStencil.backFace = StencilFaceDesc{StencilOp::Keep, StencilOp::Keep, StencilOp::Keep, ComparisonFunc::Always};
    p.stencilRef = 1;
    return p;  // no pixel shader, depth-stencil target only
}

constexpr PassState shade() {
    PassState p;
    // Article §3.3.2 Shade Pixels: cull FRONT (back faces only), depth clipping disabled;
    // 3dgep demo's main.cpp g_pDeferredLightingPipeline2: SetCullMode(Front), SetDepthClipEnabled(false).
    p.rasterizer = demoRasterizer(CullMode::Front, false);
    // Article §3.3.2: depth test on, writes off, function GREATER_EQUAL (3dgep demo's main.cpp GreaterOrEqual).
    p.depthStencil = depthTestNoWrite(ComparisonFunc::GreaterEqual);
    // Article §3.3.2: stencil reference 1, function EQUAL, ops KEEP; 3dgep demo's main.cpp sets it on BackFace only,
    // FrontFace keeps the defaults {KEEP, KEEP, KEEP, ALWAYS} (front faces are culled anyway).
    p.depthStencil.stencilEnable = true;
    p.depthStencil.stencilReadMask = 0xFF;
    p.depthStencil.stencilWriteMask = 0xFF;
    p.depthStencil.frontFace = StencilFaceDesc{StencilOp::Keep, StencilOp::Keep, StencilOp::Keep, ComparisonFunc::Always};
    p.depthStencil.backFace = StencilFaceDesc{StencilOp::Keep, StencilOp::Keep, StencilOp::Keep, ComparisonFunc::Equal};
    p.stencilRef = 1;
    // Article §3.3.2: blending on, source ONE, destination ONE, operation ADD.
    p.blend = additive();
    return p;
}

constexpr PassState directional() {
    PassState p;
    // 3dgep demo's main.cpp g_pDirectionalLightsPipeline: rasterizer defaults; the quad
    // CreateScreenQuad(-1,1,-1,1,-1) under ortho(-1,1,-1,1,0,1) lies at depth 1 (far plane).
    p.rasterizer = demoRasterizer(CullMode::Back, true);
    // 3dgep demo's main.cpp: depth on, writes off, GREATER ("only light pixels in front of the quad",
    // excluding sky pixels at the cleared depth 1); stencil off; additive blending.
    p.depthStencil = depthTestNoWrite(ComparisonFunc::Greater);
    p.depthStencil.stencilEnable = false;
    p.blend = additive();
    return p;
}

constexpr PassState killzoneMark() {
    PassState p;
    // 3dgep article §3.2.1.1 Mark Pixels (Killzone 2): VS only, cull FRONT (back faces), depth
    // clip as default (disabling depth clipping does not help, article §3.3).
    p.rasterizer = demoRasterizer(CullMode::Front, true);
    // Depth GREATER_EQUAL (writes off), stencil ref 1, ALWAYS, REPLACE on depth pass.
    p.depthStencil = depthTestNoWrite(ComparisonFunc::GreaterEqual);
    p.depthStencil.stencilEnable = true;
    const StencilFaceDesc replaceOnPass{StencilOp::Keep, StencilOp::Keep, StencilOp::Replace, ComparisonFunc::Always};
    p.depthStencil.frontFace = replaceOnPass;
    p.depthStencil.backFace = replaceOnPass;
    p.stencilRef = 1;
    return p;  // no pixel shader
}

constexpr PassState killzoneCount() {
    PassState p;
    // Article §3.2.1.2 Count Pixels: cull BACK (front faces), depth LESS_EQUAL, stencil EQUAL 1,
    // KEEP, plus an occlusion query.
    p.rasterizer = demoRasterizer(CullMode::Back, true);
    p.depthStencil = depthTestNoWrite(ComparisonFunc::LessEqual);
    p.depthStencil.stencilEnable = true;
    const StencilFaceDesc equalKeep{StencilOp::Keep, StencilOp::Keep, StencilOp::Keep, ComparisonFunc::Equal};
    p.depthStencil.frontFace = equalKeep;
    p.depthStencil.backFace = equalKeep;
    p.stencilRef = 1;
    return p;  // no pixel shader; draw with an OcclusionQuery
}

constexpr PassState killzoneShade() {
    // Article §3.2.2 Shade Pixels: the Count states plus PS, accumulation target, ONE/ONE/ADD.
    PassState p = killzoneCount();
    p.blend = additive();
    return p;
}

} // namespace deferred_detail

// G-buffer pass (3dgep): cull back, depth LESS with writes, no stencil, no blending. Targets:
// accumulation (back buffer), diffuse, specular, normal, D24S8 (3dgep article §3.1.1).
inline constexpr PassState kDeferredGBufferPass = deferred_detail::gbuffer();
// Per light, after clearing stencil to 1 (DeferredLightingPass.cpp `Clear(Stencil, ..., 1)`):
// unmark = front faces, depth GREATER, stencil ALWAYS / DECR_SAT on pass, ref 1; VS only.
inline constexpr PassState kDeferredUnmarkPass = deferred_detail::unmark();
// shade = back faces, no depth clip, depth GREATER_EQUAL, stencil EQUAL 1 on back faces, ONE+ONE.
inline constexpr PassState kDeferredShadePass = deferred_detail::shade();
// Directional lights: full-screen quad at depth 1, depth GREATER, no stencil, ONE+ONE.
inline constexpr PassState kDeferredDirectionalPass = deferred_detail::directional();

// Killzone 2 variant, per light after clearing stencil to 0 (3dgep article §3.2):
// mark = back faces, depth GREATER_EQUAL, stencil ALWAYS / REPLACE on pass, ref 1; VS only.
inline constexpr PassState kKillzoneMarkPass = deferred_detail::killzoneMark();
// count = front faces, depth LESS_EQUAL, stencil EQUAL 1, KEEP, inside an occlusion query.
inline constexpr PassState kKillzoneCountPass = deferred_detail::killzoneCount();
// shade = the count states with the lighting PS and ONE+ONE blending.
inline constexpr PassState kKillzoneShadePass = deferred_detail::killzoneShade();
// The shade draw is skipped unless the count query's samples exceed this threshold (3dgep article
// §3.2.1.2 leaves the value open; 0 = shade whenever any sample passed).
inline constexpr std::uint64_t kKillzoneDefaultThreshold = 0;

// The stencil values each method clears to before a light's passes.
inline constexpr std::uint8_t kDeferredStencilClear = 1;  // 3dgep: every pixel starts marked
inline constexpr std::uint8_t kKillzoneStencilClear = 0;  // Killzone 2: nothing marked

// A DrawState for a pass with a viewport (scissor off).
DrawState makeDrawState(const PassState& pass, const Viewport& viewport);

// Killzone 2: run the shade draw only if the count pass's occlusion query exceeds `threshold`.
bool killzoneShouldShade(std::uint64_t samplesPassed, std::uint64_t threshold = kKillzoneDefaultThreshold);

} // namespace tessera
