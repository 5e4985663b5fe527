// The immediate context: draw() runs vertex shading, setup, binning and tile-parallel
// rasterization of one draw, in that order, and returns when every target is written.
// Determinism: tiles own disjoint pixels and process their triangles in submission order,
// so the bytes of every buffer are independent of thread count and scheduling.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <vector>
#include <string>
#include <span>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <tessera/raster/draw_state.h>
#include <tessera/raster/occlusion_query.h>
#include <tessera/raster/pixel_watch.h>
#include <tessera/raster/output_merger.h>
#include <tessera/raster/triangle_setup.h>
#include <tessera/shaders/shader_stages.h>

namespace tessera {

struct DeviceConfig {
    std::uint32_t tileSize = 64;  // px, even, 8..1024: the unit of parallel work
    std::uint32_t threads = 0;    // worker threads, 1..256; 0 = all hardware threads (TBB default)
    // Single-sample draws rasterize 8x8 blocks through the SIMD kernel (raster/quad_block.h)
    // where enough of a block is inside the triangle's bounds; false keeps every quad on the
    // scalar path. Both give the same bits (the scalar path is the tests' oracle).
    bool simdBlocks = true;
    // A DrawBatch (raster/draw_batch.h) bins all its draws and rasterizes each tile once through
    // their lists; false runs each of its draws at once, as Device::draw does. Both give the same
    // bits (tests/raster/draw_batch_test.cpp); false is the oracle and the speed baseline.
    bool binPasses = true;
};

// Counters of one draw (and, summed, of a frame) for --stats.
struct DrawStats {
    SetupStats setup;
    std::uint64_t binnedTileTriangles = 0;  // sum over tiles of triangles binned there
    std::uint64_t quads = 0;                // 2x2 quads with at least one covered sample
    std::uint64_t psInvocations = 0;        // pixel (or sample) shader calls, helpers excluded
    std::uint64_t psPerSample = 0;          // of psInvocations, those of shaders that run per sample
    // MSAA deferred techniques (src/techniques/msaa_deferred.h, gbuffer/msaa_edges.h): pixels the edge pass classified and
    // those it marked for per-sample shading; compute passes that shade G-buffers count their
    // per-pixel and per-sample shading here too (shader draws count in psInvocations).
    std::uint64_t edgeTestedPixels = 0, edgePixels = 0;
    std::uint64_t computeShadedPixels = 0, computeShadedSamples = 0;
    std::uint64_t samplesPassed = 0;        // samples passing depth/stencil, not discarded
    // 8x8 blocks rasterized through the SIMD kernels (raster/quad_block.h), and those of them
    // that also ran the lean pipeline (SIMD depth test, no per-pixel stage the state lacks).
    std::uint64_t simdBlocks = 0, leanBlocks = 0;
    // Lean blocks shaded by one call of the shader's block entry point (shaders/block_shader.h)
    // instead of one call per pixel.
    std::uint64_t blockShaderCalls = 0;
    // Draws rasterized through a DrawBatch's shared tile lists (raster/draw_batch.h), and the
    // batch runs that rasterized them: draws / runs is how many draws shared one sweep of the tiles.
    std::uint64_t binnedDraws = 0, binnedRuns = 0;
    // Tiles cleared by a DrawBatch's recorded depth-stencil clears (DrawBatch::clearDepthStencil):
    // every tile for a whole clear, else those a draw of the batch binned a triangle into since the
    // last whole clear. Binned, each is one tile's clear; draw by draw, the batch clears their
    // bounding rectangle once, and counts the same tiles.
    std::uint64_t batchClearedTiles = 0;
    // Draws per pipeline path the rasterizer specialised for (what the draw's state and shader
    // require, nothing more): "ps depth:D24 1x raster:exact", "no-ps depth:General 4x ...",
    // with "blend" when a target blends. The paths a frame took, for --stats.
    std::map<std::string, std::uint64_t> paths;
    DrawStats& operator+=(const DrawStats& o);
};

// The validated facts about a draw's targets.
struct DrawTargets {
    std::uint32_t width = 0, height = 0, sampleCount = 1;
    PixelRect rect;  // pixels that may be written: the target, ∩ scissor when enabled
};

// Throws std::invalid_argument naming the problem for invalid state combinations: no target
// bound, mismatched target sizes or sample counts, a depth format bound as colour or the
// reverse, a viewport outside D3D11's bounds, NaN or empty, MinDepth/MaxDepth outside [0,1]
// or crossed, dual-source blend factors, *_COLOR factors in the alpha blend, blending on an
// integer target, alpha-to-coverage, a tile size that is odd or outside 8..1024.
DrawTargets validateDraw(const DrawState& state, const RenderTargets& targets, std::uint32_t tileSize);

// The DrawStats::paths key of a draw.
std::string drawPathName(bool hasPixelShader, DepthPath depth, std::uint32_t sampleCount, bool blends, Precision precision);

namespace detail {
struct DrawScratch;
struct DrawEnv;
}
class DrawBatch;

class Device {
public:
    explicit Device(DeviceConfig config = {});
    ~Device();
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    const DeviceConfig& config() const { return mConfig; }

    // Draws a triangle list. With `indices` empty, vertices are taken three at a time;
    // otherwise indices (three per triangle) select them. An index past the vertex count
    // fetches a value-initialised Vertex{} (D3D11: out-of-range vertex fetches return 0).
    template <class Vertex, class VS, PixelShaderOrNone PS>
        requires VertexShaderFor<VS, Vertex>
    DrawStats draw(const DrawState& state, const RenderTargets& targets, std::span<const Vertex> vertices,
                   std::span<const std::uint32_t> indices, const VS& vs, const PS& ps,
                   OcclusionQuery* query = nullptr);

    // Runs f inside this device's thread arena (so that its parallel loops use the
    // configured thread count). Used by draw() and by compute dispatches.
    template <class F>
    void execute(F&& f);

    // Records what every later draw does at one pixel into `watch` (raster/pixel_watch.h);
    // null stops. The watch must outlive the draws; its pixel always takes the per-quad path.
    void setPixelWatch(PixelWatch* watch) { mWatch = watch; }
    // The watch set above (null: none); compute passes that shade pixels record into it too.
    PixelWatch* pixelWatch() const { return mWatch; }
    // Counts every later draw's pixel-shader invocations per pixel into `counts`
    // (raster/pixel_watch.h); null stops. Adds one predictable branch per shaded pixel, nothing else.
    void setShadeCounts(ShadeCounts* counts) { mShadeCounts = counts; }

private:
    friend class DrawBatch;
    // What a draw recorded now takes from the device (tile size, watch, its draw number).
    detail::DrawEnv drawEnv();
    // A draw's working storage for a DrawBatch, from a pool kept from batch to batch, and its return.
    std::unique_ptr<detail::DrawScratch> takeScratch();
    void returnScratch(std::unique_ptr<detail::DrawScratch> scratch);

    // draw() after choosing the vertex stage: a draw without a pixel shader runs its vertex shader
    // for the position alone (detail::PositionOnlyVS).
    template <class Vertex, class VS, PixelShaderOrNone PS>
    DrawStats drawImpl(const DrawState& state, const RenderTargets& targets, std::span<const Vertex> vertices,
                       std::span<const std::uint32_t> indices, const VS& vs, const PS& ps, OcclusionQuery* query);

    DeviceConfig mConfig;
    PixelWatch* mWatch = nullptr;
    ShadeCounts* mShadeCounts = nullptr;
    std::uint64_t mDrawCount = 0;  // draws issued, for PixelDrawEvent::draw
    std::unique_ptr<detail::DrawScratch> mScratch;  // a draw's working storage, reused (detail/draw_impl.h)
    std::mutex mPoolMutex;
    std::vector<std::unique_ptr<detail::DrawScratch>> mScratchPool;  // DrawBatch's, reused
    std::unique_ptr<tbb::task_arena> mArena;
    // More threads than cores (e.g. the 7-thread determinism runs on 2 cores) need TBB's
    // process-wide worker limit raised while this device lives.
    std::unique_ptr<tbb::global_control> mWorkerLimit;
};

} // namespace tessera

#include <tessera/raster/detail/draw_impl.h>
