// MSAA for the G-buffer techniques: G-buffer pixel shaders built from an encoder (and, with MSAA,
// two more per-sample targets for the edge detectors), the edge pass that marks edge pixels in a
// stencil bit, and the light passes' split (once per pixel where the bit is clear, once per sample
// where it is set: PR&C D3D11 §11.5 after Persson 2008; the Intel 2010 sample's stencil paths).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include <tessera/buffers/target_reader.h>
#include <tessera/gbuffer/msaa_edges.h>
#include <tessera/shading/phong_surface.h>
#include <tessera/techniques/deferred_states.h>
#include <tessera/techniques/technique.h>
#include <tessera/techniques/technique_options.h>

#include "gbuffer_pass.h"

namespace tessera::gbuffer_detail {

// The stencil bit of edge pixels; the techniques' own stencil values stay below it.
inline constexpr std::uint8_t kEdgeStencilBit = 0x80;
// The detectors' per-sample data (EdgeSample), written beside each G-buffer layout under MSAA:
// (normalView, viewZ) and (partial coverage 0/1, viewZSlope, 0, 0), both R32G32B32A32_FLOAT.
inline constexpr std::string_view kEdgeSurfaceTarget = "msaa.surface";
inline constexpr std::string_view kEdgeCoverageTarget = "msaa.coverage";
// 1 at every sample of an edge pixel, else 0 (R32_FLOAT, the G-buffer's sample count).
inline constexpr std::string_view kEdgesBuffer = "edges";
inline constexpr int kEdgeDataTargets = 2;

// A G-buffer pixel shader: the Phong gather (discarding where its alpha test says), then
// `Encoder::encode(surface, input, out)` into the layout's kTargetCount targets; with kEdgeData
// also the two EdgeSample targets after them.
template <class Encoder, bool kDiscard, bool kEdgeData = false>
struct GBufferShader : Encoder {
    using Varyings = PhongVaryings;
    static constexpr int kTargetCount = Encoder::kTargetCount + (kEdgeData ? kEdgeDataTargets : 0);
    static constexpr bool kMayDiscard = kDiscard;
    // The edge-data layout is the multisampled G-buffer's; the plain one is drawn at one sample.
    static constexpr SampleRates kSampleRates = kEdgeData ? SampleRates::Multi : SampleRates::Single;
    PhongGatherFn gather = nullptr;
    const PhongShaderData<float>* data = nullptr;
    std::uint32_t sampleCount = 1;
    void operator()(const PixelInput<PhongVaryings>& in, PixelOutput<kTargetCount>& out) const {
        PhongSurface<float> s;
        if (!gather(*data, in, s)) {
            out.discard();
            return;
        }
        this->encode(s, in, out);
        if constexpr (kEdgeData) {
            constexpr int k = Encoder::kTargetCount;
            const glm::vec3 n = glm::vec3(s.normalView);
            const float len = std::sqrt(glm::dot(n, n));
            // View space is right-handed (z < 0 in front): viewZ = -posView.z. GBuffer.hlsl's
            // positionViewDX/DY are ddx_coarse / ddy_coarse, the quad's differences here.
            out.target[k] = glm::vec4(len > 0.0f ? n / len : n, -in.varyings.posView.z);
            const float slope = std::fabs(in.ddx.posView.z) + std::fabs(in.ddy.posView.z);
            out.target[k + 1] = glm::vec4(partialCoverage(in.coverage, sampleCount) ? 1.0f : 0.0f, slope, 0.0f, 0.0f);
        }
    }
};

// The same shader, run once per covered sample (SV_SampleIndex read: D3D11 sample frequency).
template <class PS>
struct PerSample : PS {
    static constexpr bool kPerSample = true;
    static constexpr SampleRates kSampleRates = SampleRates::Multi;
};

// `p` limited to pixels whose edge bit is clear (edgePixels false) or set (true). A pass without
// stencil gets EQUAL on the bit alone (no writes); a pass that already tests EQUAL keeps its
// reference in the other bits. Throws std::logic_error for a pass whose stencil does something else.
inline PassState withEdgeTest(PassState p, bool edgePixels) {
    const std::uint8_t bit = edgePixels ? kEdgeStencilBit : 0;
    if (!p.depthStencil.stencilEnable) {
        stencilTestOnly(p, ComparisonFunc::Equal, kEdgeStencilBit, bit);
        return p;
    }
    const auto keepsEqual = [](const StencilFaceDesc& f) {
        return f.func == ComparisonFunc::Equal && f.failOp == StencilOp::Keep && f.depthFailOp == StencilOp::Keep &&
               f.passOp == StencilOp::Keep;
    };
    const CullMode cull = p.rasterizer.cullMode;
    if ((cull != CullMode::Front && !keepsEqual(p.depthStencil.frontFace)) || (cull != CullMode::Back && !keepsEqual(p.depthStencil.backFace)))
        throw std::logic_error("withEdgeTest: the pass's stencil test is not EQUAL/KEEP on its drawn faces");
    if (p.stencilRef & kEdgeStencilBit) throw std::logic_error("withEdgeTest: the pass's stencil reference uses the edge bit");
    p.depthStencil.stencilReadMask = std::uint8_t(p.depthStencil.stencilReadMask | kEdgeStencilBit);
    p.depthStencil.frontFace.func = p.depthStencil.backFace.func = ComparisonFunc::Equal;
    p.stencilRef = std::uint8_t(p.stencilRef | bit);
    return p;
}

// Draws `ps` under `pass` through `draw(state, shader)`; with MSAA twice: once per pixel where the
// edge bit is clear, once per sample (PerSample<PS>) where it is set. The shader reads its
// G-buffer sample through SV_SampleIndex, which is 0 when it runs per pixel.
template <class PS, class Draw>
void drawPerPixelThenEdgeSamples(bool msaa, const PassState& pass, const PS& ps, Draw&& draw) {
    if (!msaa) {
        draw(pass, ps);
        return;
    }
    draw(withEdgeTest(pass, false), ps);
    draw(withEdgeTest(pass, true), PerSample<PS>{ps});
}

// The "msaaEdges" option (kEdgesPrcOption or kEdgesIntelOption: the table chooses the default).
inline EdgeDetector parseEdgeDetector(const OptionReader& options) {
    return options.is("msaaEdges", "coverage")      ? EdgeDetector::Coverage
           : options.is("msaaEdges", "depthNormal") ? EdgeDetector::DepthNormal
                                                    : EdgeDetector::All;
}

// The EdgeSample targets, cleared (viewZ 0: no surface), and the edges buffer.
inline void createEdgeTargets(BufferRegistry& reg, std::uint32_t w, std::uint32_t h, std::uint32_t samples) {
    reg.create(std::string(kEdgeSurfaceTarget), {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(glm::vec4(0.0f));
    reg.create(std::string(kEdgeCoverageTarget), {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(glm::vec4(0.0f));
    reg.create(std::string(kEdgesBuffer), {w, h, Format::R32_FLOAT, samples}).clearColor(glm::vec4(0.0f));
}

// Binds the EdgeSample targets after the layout's `layoutTargets` colour targets.
inline void bindEdgeTargets(RenderTargets& rt, BufferRegistry& reg, int layoutTargets) {
    rt.colors[std::size_t(layoutTargets)] = &reg.get(std::string(kEdgeSurfaceTarget));
    rt.colors[std::size_t(layoutTargets) + 1] = &reg.get(std::string(kEdgeCoverageTarget));
}

// The detector's verdict for pixel (x, y) from the EdgeSample targets (all their samples).
inline bool edgePixelAt(EdgeDetector detector, const TargetReader& surface, const TargetReader& coverage, std::uint32_t sampleCount,
                        std::uint32_t x, std::uint32_t y) {
    std::array<EdgeSample, 8> samples{};
    for (std::uint32_t i = 0; i < sampleCount; ++i) {
        const glm::vec4 a = surface.load(x, y, i), b = coverage.load(x, y, i);
        samples[i] = EdgeSample{glm::vec3(a), a.w, b.y, b.x != 0.0f};
    }
    return isEdgePixel(detector, std::span<const EdgeSample>(samples.data(), sampleCount));
}

struct QuadVertex {
    glm::vec3 posClip;
};
struct QuadVS {
    using Varyings = NoVaryings;
    VertexOutput<NoVaryings> operator()(const QuadVertex& v) const { return {glm::vec4(v.posClip, 1.0f), {}}; }
};

// The edge pass's shader: the pixel's samples through the detector; discards where they agree,
// writes 1 (and, through the state, the stencil edge bit) where they do not.
struct EdgeMarkPS {
    using Varyings = NoVaryings;
    static constexpr int kTargetCount = 1;
    static constexpr bool kMayDiscard = true;
    static constexpr SampleRates kSampleRates = SampleRates::Multi;  // edges exist only in multisampled buffers
    TargetReader surface, coverage;
    std::uint32_t sampleCount = 1;
    EdgeDetector detector = EdgeDetector::Coverage;
    void operator()(const PixelInput<NoVaryings>& in, PixelOutput<1>& out) const {
        if (!edgePixelAt(detector, surface, coverage, sampleCount, std::uint32_t(in.posWindow.x), std::uint32_t(in.posWindow.y))) {
            out.discard();
            return;
        }
        out.target[0] = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
    }
};

// The pass between the G-buffer and the lights (Intel's "stencil mark": a full-screen quad, depth
// off, stencil ALWAYS / REPLACE of the edge bit only). Counts the pixels into `stats`.
inline Pass edgePass(Device* device, DrawStats* stats, EdgeDetector detector) {
    const std::string surface(kEdgeSurfaceTarget), coverage(kEdgeCoverageTarget), edges(kEdgesBuffer);
    return {"edges", {surface, coverage, "depth"}, {edges, "depth"}, [=](BufferRegistry& reg) {
                Surface& edgeBuffer = reg.get(edges);
                const std::uint32_t w = edgeBuffer.width(), h = edgeBuffer.height(), n = edgeBuffer.sampleCount();
                PassState p;
                p.rasterizer.cullMode = CullMode::None;
                p.depthStencil.depthEnable = false;
                p.depthStencil.depthWriteEnable = false;
                p.depthStencil.stencilEnable = true;
                p.depthStencil.stencilWriteMask = kEdgeStencilBit;
                const StencilFaceDesc replace{StencilOp::Keep, StencilOp::Keep, StencilOp::Replace, ComparisonFunc::Always};
                p.depthStencil.frontFace = replace;
                p.depthStencil.backFace = replace;
                p.stencilRef = kEdgeStencilBit;
                const DrawState st = makeDrawState(p, Viewport{0.0f, 0.0f, float(w), float(h), 0.0f, 1.0f});
                RenderTargets rt;
                rt.colors[0] = &edgeBuffer;
                rt.depthStencil = &reg.get("depth");
                std::array<QuadVertex, 4> quad;
                for (std::size_t i = 0; i < 4; ++i) quad[i].posClip = kQuadClip[i];
                const EdgeMarkPS ps{TargetReader(reg.get(surface)), TargetReader(reg.get(coverage)), n, detector};
                DrawBatch batch(*device);  // one draw, swept tile by tile like every other pass's
                batch.draw(st, rt, std::span<const QuadVertex>(quad), kQuadIndices, QuadVS{}, ps);
                DrawStats s = batch.run();
                s.edgeTestedPixels = std::uint64_t(w) * h;
                s.edgePixels = s.samplesPassed / n;
                if (stats) *stats += s;
            },
            {edges}};  // the light passes read the stencil's edge bit; this picture of it is for inspection
}

} // namespace tessera::gbuffer_detail
