// Replays a peer::PeerFrame (the draws and states the llvmpipe peer renders) through tessera with
// the same state: targets of the frame's sample count and depth format, one device of the given
// tile size, and an occlusion query over all draws; and the one llvmpipe peer of the test
// executable (created on first use). Shared by the conformance tests.
#pragma once

#include <doctest/doctest.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gl_peer.h"
#include "support/test_draw.h"

namespace tessera::test {

// The llvmpipe peer shared by every conformance test of the executable; fails the calling test
// when EGL or llvmpipe cannot be set up.
inline peer::GlPeer& glPeer() {
    static std::optional<peer::GlPeer> instance = [] {
        std::string why;
        auto p = peer::GlPeer::create(&why);
        if (!p) FAIL("cannot create the llvmpipe peer: " << why);
        return p;
    }();
    return *instance;
}

struct TesseraResult {
    Surface color, ds;
    std::uint64_t samplesPassed = 0;
};

inline Blend toTessera(peer::BlendFactor f) {
    switch (f) {
    case peer::BlendFactor::Zero: return Blend::Zero;
    case peer::BlendFactor::One: return Blend::One;
    case peer::BlendFactor::SrcColor: return Blend::SrcColor;
    case peer::BlendFactor::InvSrcColor: return Blend::InvSrcColor;
    case peer::BlendFactor::SrcAlpha: return Blend::SrcAlpha;
    case peer::BlendFactor::InvSrcAlpha: return Blend::InvSrcAlpha;
    case peer::BlendFactor::DestAlpha: return Blend::DestAlpha;
    case peer::BlendFactor::InvDestAlpha: return Blend::InvDestAlpha;
    case peer::BlendFactor::DestColor: return Blend::DestColor;
    case peer::BlendFactor::InvDestColor: return Blend::InvDestColor;
    case peer::BlendFactor::BlendFactor: return Blend::BlendFactor;
    case peer::BlendFactor::InvBlendFactor: return Blend::InvBlendFactor;
    }
    return Blend::One;
}

inline TesseraResult renderTessera(const peer::PeerFrame& frame, std::uint32_t tileSize) {
    const auto n = std::uint32_t(frame.samples);
    const Format dsFormat = frame.depthFormat == peer::DepthFormat::D24S8 ? Format::D24_UNORM_S8_UINT : Format::D32_FLOAT_S8X24_UINT;
    TesseraResult r{Surface({std::uint32_t(frame.width), std::uint32_t(frame.height), Format::R8G8B8A8_UNORM, n}),
                    Surface({std::uint32_t(frame.width), std::uint32_t(frame.height), dsFormat, n})};
    r.color.clearColor(glm::vec4(frame.clearColor[0], frame.clearColor[1], frame.clearColor[2], frame.clearColor[3]));
    r.ds.clearDepthStencil(true, frame.clearDepth, true, frame.clearStencil);
    Device dev(DeviceConfig{tileSize, 2});
    RenderTargets rt;
    rt.colors[0] = &r.color;
    rt.depthStencil = &r.ds;
    OcclusionQuery query;
    query.begin();
    for (const peer::PeerDraw& d : frame.draws) {
        std::vector<ColorVertex> v;
        for (std::size_t i = 0; i < d.posClip.size(); ++i) {
            const auto& p = d.posClip[i];
            const auto& c = d.colorPerTriangle[i / 3];
            v.push_back({glm::vec4(p[0], p[1], p[2], p[3]), glm::vec4(c[0], c[1], c[2], c[3])});
        }
        DrawState st;
        st.viewport = fullViewport(r.color);
        st.rasterizer.cullMode = CullMode(int(d.cull) + 1);
        st.rasterizer.frontCounterClockwise = d.frontCounterClockwise;
        st.rasterizer.depthClipEnable = d.depthClipEnable;
        st.rasterizer.scissorEnable = d.scissorEnable;
        st.scissor = ScissorRect{d.scissor[0], d.scissor[1], d.scissor[2], d.scissor[3]};
        st.depthStencil.depthEnable = d.depthEnable;
        st.depthStencil.depthWriteEnable = d.depthWrite;
        st.depthStencil.depthFunc = ComparisonFunc(int(d.depthFunc) + 1);
        st.depthStencil.stencilEnable = d.stencilEnable;
        st.depthStencil.stencilReadMask = d.stencilReadMask;
        st.depthStencil.stencilWriteMask = d.stencilWriteMask;
        auto face = [](const peer::StencilFace& f) {
            return StencilFaceDesc{StencilOp(int(f.failOp) + 1), StencilOp(int(f.depthFailOp) + 1),
                                   StencilOp(int(f.passOp) + 1), ComparisonFunc(int(f.func) + 1)};
        };
        st.depthStencil.frontFace = face(d.front);
        st.depthStencil.backFace = face(d.back);
        st.stencilRef = d.stencilRef;
        RenderTargetBlendDesc& b = st.blend.renderTarget[0];
        if (d.additiveBlend) {
            b = kAdditiveBlend;
        } else if (d.blend.enable) {
            b = RenderTargetBlendDesc{true, toTessera(d.blend.src), toTessera(d.blend.dst), BlendOp(int(d.blend.op) + 1),
                                      toTessera(d.blend.srcAlpha), toTessera(d.blend.dstAlpha), BlendOp(int(d.blend.opAlpha) + 1), WriteAll};
        }
        b.renderTargetWriteMask = d.colorWrite ? std::uint8_t(d.colorWriteMask & 0xF) : std::uint8_t(0);
        st.blendFactor = d.blendFactor;
        dev.draw(st, rt, std::span<const ColorVertex>(v), {}, PassThroughVS{}, ColorPS{}, &query);
    }
    query.end();
    r.samplesPassed = query.samplesPassed();
    return r;
}

} // namespace tessera::test
