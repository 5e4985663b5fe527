// The `forward-plus` technique (3dgep article §4; the demo's g_ForwardPlusTechnique in its main.cpp and
// ForwardPlusRendering.hlsl): clear -> depth pre-pass -> CS_ComputeFrustums -> CS_main (light
// culling: row-parallel, or with culling "brute" emulated with compute::dispatch) -> heat map
// (CS_main's DebugTexture) -> opaque pass -> transparent pass, the last two through forward's
// passes with the tile's light list (forward.h ForwardPassOverrides).
// The passes live beside this file: forward_plus_prepass.cpp (clear, depth pre-pass),
// forward_plus_light_culling.cpp (CS_main; forward_plus_cull_kernel.cpp, forward_plus_row_culling.cpp,
// forward_plus_binning.cpp), forward_plus_heat_map.cpp; the options in forward_plus_options.cpp.
#include <tessera/techniques/forward_plus.h>

#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <tessera/compute/dispatch.h>
#include <tessera/culling/frustum.h>
#include <tessera/culling/tile_frustum.h>
#include <tessera/techniques/forward.h>

#include "forward_plus_detail.h"

namespace tessera {
namespace {

// ----- CS_ComputeFrustums (3dgep article §4.2) ---------------------------------------------------
// One thread per tile, BLOCK_SIZE x BLOCK_SIZE threads per group, ceil(tiles / BLOCK_SIZE) groups;
// threads past numThreads (= tiles) write nothing.
template <std::uint32_t kBlock>
struct ComputeFrustumsKernel {
    static constexpr glm::uvec3 groupSize{kBlock, kBlock, 1};
    using Shared = compute::NoShared;
    glm::uvec2 numThreads{0};  // DispatchParams.numThreads: tiles per axis
    glm::vec2 screenDimensions{0.0f};
    glm::mat4 inverseProjection{1.0f};
    bool orthographic = false;  // planes through near and far corners (gridFrustumOrthographic)
    Frustum* outFrustums = nullptr;  // RWStructuredBuffer<Frustum> out_Frustums, x + y * numThreads.x
    void operator()(compute::GroupContext<Shared>& g) const {
        g.forEachThread([&](const compute::ThreadIds& t) {
            if (t.dispatchThreadId.x < numThreads.x && t.dispatchThreadId.y < numThreads.y) {
                const std::size_t index = t.dispatchThreadId.x + std::size_t{t.dispatchThreadId.y} * numThreads.x;
                outFrustums[index] =
                    orthographic ? gridFrustumOrthographic(glm::uvec2(t.dispatchThreadId), kBlock, screenDimensions, inverseProjection,
                                                           0.0f, 1.0f)
                                 : gridFrustum3dgep(glm::uvec2(t.dispatchThreadId), kBlock, screenDimensions, inverseProjection);
            }
        });
    }
};

} // namespace

using forward_plus_detail::cullLights;
using forward_plus_detail::ForwardPlusState;
using forward_plus_detail::parseOptions;
using forward_plus_detail::writeHeatMap;

ForwardPlusCounters readForwardPlusCounters(const BufferRegistry& registry) {
    const Surface* s = registry.find("lightlist.counters");
    if (!s) throw std::out_of_range("no buffer 'lightlist.counters' (not a forward-plus frame)");
    ForwardPlusCounters c;
    std::memcpy(&c.opaque, s->texel(0, 0), sizeof(LightListCounters));
    std::memcpy(&c.transparent, s->texel(0, 1), sizeof(LightListCounters));
    return c;
}

Frame buildForwardPlus(const TechniqueContext& ctx) {
    const std::string file = ctx.errorFile();
    auto st = std::make_shared<ForwardPlusState>();
    st->options = parseOptions(ctx, file);
    st->setup = makeForwardPassSetup(ctx, st->options.projection, st->options.sampler, st->options.alphaTest);
    const std::uint32_t block = st->options.tileSizePx;
    st->tiles = tileCount(glm::uvec2(ctx.width, ctx.height), block);
    // ScreenToViewParams (3dgep demo's main.cpp): InverseProjection = glm::inverse(projection), ScreenDimensions.
    st->inverseProjection = glm::inverse(st->setup->clipFromView);
    st->screenDimensions = glm::vec2(float(ctx.width), float(ctx.height));
    st->orthographic = ctx.camera.projection == ProjectionKind::Orthographic;

    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;
    std::map<std::string, std::uint64_t>* variantCounts = ctx.variantCounts;
    const SceneResources* res = ctx.resources;
    const std::string back(kBackBufferName);

    Frame frame;
    addForwardPlusClearAndPrepass(frame, st->setup, device, res, stats);
    frame.add({"frustums", {}, {"frustums"}, [st, device](BufferRegistry& reg) {
                   const glm::uvec2 tiles = st->tiles;
                   std::vector<Frustum> frustums(std::size_t{tiles.x} * tiles.y);
                   const auto run = [&]<std::uint32_t kBlock>() {
                       ComputeFrustumsKernel<kBlock> kernel;
                       kernel.numThreads = tiles;
                       kernel.screenDimensions = st->screenDimensions;
                       kernel.inverseProjection = st->inverseProjection;
                       kernel.orthographic = st->orthographic;
                       kernel.outFrustums = frustums.data();
                       const glm::uvec3 groups((tiles.x + kBlock - 1) / kBlock, (tiles.y + kBlock - 1) / kBlock, 1);
                       device->execute([&] { compute::dispatch(kernel, groups, {compute::GroupOrder::Parallel, {}}); });
                   };
                   if (st->options.tileSizePx == 8) run.template operator()<8>();
                   else if (st->options.tileSizePx == 32) run.template operator()<32>();
                   else run.template operator()<16>();
                   Surface& s = reg.create("frustums", {4 * tiles.x, tiles.y, Format::R32G32B32A32_FLOAT, 1});
                   for (std::size_t t = 0; t < frustums.size(); ++t)
                       for (std::size_t i = 0; i < 4; ++i) {
                           const Plane& p = frustums[t].planes[i];
                           const float plane[4] = {p.N.x, p.N.y, p.N.z, p.d};
                           std::memcpy(s.texel(std::uint32_t(t % tiles.x * 4 + i), std::uint32_t(t / tiles.x)), plane, sizeof(plane));
                       }
               }});
    const std::vector<std::string> cullWrites{"lightgrid.opaque", "lightgrid.transparent", "lightindex.opaque",
                                              "lightindex.transparent", "lightlist.counters"};
    frame.add({"light-culling", {"depth", "frustums"}, cullWrites, [st, device](BufferRegistry& reg) {
                   if (st->options.tileSizePx == 8) cullLights<8>(*st, *device, reg);
                   else if (st->options.tileSizePx == 32) cullLights<32>(*st, *device, reg);
                   else cullLights<16>(*st, *device, reg);
               }});
    // The demo's culling CS writes the DebugTexture in its last phase; tessera writes the same
    // texels in a pass of their own, from the opaque grid (writeHeatMap), so that the culling's
    // time is the culling's.
    frame.add({"heatmap", {"lightgrid.opaque"}, {"heatmap"}, [st, device](BufferRegistry& reg) {
                   const Surface& grid = reg.get("lightgrid.opaque");
                   Surface& heatmap =
                       reg.create("heatmap", {st->setup->width, st->setup->height, Format::R32G32B32A32_FLOAT, 1});
                   writeHeatMap(*device, grid, st->options.tileSizePx, heatmap);
               },
               {"heatmap"}});
    const auto drawPass = [st, device, stats, variantCounts, res](bool transparentPass) {
        return [st, device, stats, variantCounts, res, transparentPass](BufferRegistry& reg) {
            const ForwardPlusCounters counters = readForwardPlusCounters(reg);
            TileLightList& bound = transparentPass ? st->transparentList : st->opaqueList;
            bound = bindTileLightList(reg, transparentPass, (transparentPass ? counters.transparent : counters.opaque).capacity,
                                      st->options.tileSizePx);
            const RenderTargets rt = forwardPassTargets(*st->setup, reg);
            // Both Forward+ pipelines test LESS_EQUAL: the opaque pass against its own pre-pass
            // depth, the transparent pass without writes (3dgep demo's main.cpp).
            ForwardPassOverrides overrides;
            overrides.depthFunc = ComparisonFunc::LessEqual;
            overrides.tileLights = &bound;
            drawForwardPass(*st->setup, *device, *res, rt, transparentPass, stats, variantCounts, overrides);
        };
    };
    // Precision reference: the listed lights shaded in double into the float copy as well. With
    // MSAA the multisampled targets, resolved last.
    const auto withColors = [&ctx](std::vector<std::string> names) {
        return withBackBufferTargets(withReferenceBuffer(std::move(names), ctx.precision), ctx.sampleCount);
    };
    const std::vector<std::string> colors = withColors({back});
    frame.add({"opaque", withColors({back, "depth", "lightgrid.opaque", "lightindex.opaque", "lightlist.counters"}),
               withColors({back, "depth"}), drawPass(false)});
    frame.add({"transparent",
               withColors({back, "depth", "lightgrid.transparent", "lightindex.transparent", "lightlist.counters"}),
               colors,
               drawPass(true)});
    if (ctx.sampleCount > 1) frame.add(resolveBackBufferPass(ctx.sampleCount, ctx.precision));
    return frame;
}

} // namespace tessera
