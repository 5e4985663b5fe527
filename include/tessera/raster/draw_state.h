// Everything fixed-function that a draw reads: the D3D11 state objects plus the dynamic
// values bound with them (stencil ref, blend factor, viewport, scissor), and the targets.
#pragma once

#include <array>
#include <cstdint>

#include <tessera/buffers/surface.h>
#include <tessera/state/precision.h>
#include <tessera/state/blend_state.h>
#include <tessera/state/depth_stencil_state.h>
#include <tessera/state/rasterizer_state.h>
#include <tessera/state/viewport.h>

namespace tessera {

struct DrawState {
    RasterizerState rasterizer;
    DepthStencilState depthStencil;
    std::uint8_t stencilRef = 0;                         // OMSetDepthStencilState StencilRef
    BlendState blend;
    std::array<float, 4> blendFactor{1, 1, 1, 1};        // OMSetBlendState BlendFactor
    Viewport viewport;                                   // RSSetViewports (one viewport)
    ScissorRect scissor;                                 // used when rasterizer.scissorEnable
    // Exact and Reference: the D3D11 rules bit for bit (coverage, barycentrics rounded once from
    // double, the UNORM encode of D3D11.3 §3.2.3.6). Fast: barycentrics and the RGBA8 encode in
    // float (coverage, depth/stencil and blending are unchanged); error measured in tests/precision.
    Precision precision = Precision::Exact;
};

// OMSetRenderTargets: up to 8 colour targets (null = unbound) and one depth-stencil buffer.
// All bound surfaces must have the same size and sample count.
struct RenderTargets {
    std::array<Surface*, kMaxRenderTargets> colors{};
    Surface* depthStencil = nullptr;
};

// A full-target viewport for a surface (MinDepth 0, MaxDepth 1).
inline Viewport fullViewport(const Surface& s) {
    return Viewport{0.0f, 0.0f, float(s.width()), float(s.height()), 0.0f, 1.0f};
}

} // namespace tessera
