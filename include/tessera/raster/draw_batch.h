// A run of draws binned together: each draw's vertex stage, setup and binning run in parallel
// across the draws, then every tile is rasterized once through all the draws' triangles in
// submission order (llvmpipe's scene binning), instead of one setup -> tiles -> barrier per draw.
// A tile's pixels see the same operations in the same order as draw after draw, so the bytes match.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <tessera/raster/device.h>

namespace tessera {

namespace detail {
struct RecordedDraw;
}

// Records draws and runs them at run() (or at once where they cannot be binned: see draw()).
// The caller's contract while draws are recorded and not yet run:
// - vertex and index data, and whatever a shader points to, stay alive and unchanged (keep()
//   holds such data for the batch);
// - no recorded draw reads (as a texture or otherwise) a surface another recorded draw writes,
//   and nothing reads or writes the bound targets outside the batch.
// The state, targets and shaders themselves are copied at draw(). Draws are numbered (pixel
// watch, PixelDrawEvent::draw) when recorded. A batch destroyed with draws not yet run discards
// them (an exception between draw() and run() leaves the targets as they were before the batch).
class DrawBatch {
public:
    explicit DrawBatch(Device& device);
    ~DrawBatch();
    DrawBatch(const DrawBatch&) = delete;
    DrawBatch& operator=(const DrawBatch&) = delete;

    // Device::draw's arguments, without an occlusion query (a query is read between draws; draw
    // those on the Device). Validated now: invalid state throws here, and nothing is recorded.
    // Runs the recorded draws first, then this one at once, when the device's binPasses is off,
    // when the draw has more than detail::kBatchTriangles triangles (its set-up triangles are
    // streamed in batches, as Device::draw does), or when its targets differ in size or sample
    // count from the recorded draws'.
    template <class Vertex, class VS, PixelShaderOrNone PS>
        requires VertexShaderFor<VS, Vertex>
    void draw(const DrawState& state, const RenderTargets& targets, std::span<const Vertex> vertices,
              std::span<const std::uint32_t> indices, const VS& vs, const PS& ps);

    // Surface::clearDepthStencilRect's clear, ordered with the recorded draws: each tile clears
    // when the sweep reaches it, between the draws recorded before and after (the deferred light
    // loop's per-light stencil clear). With `onlyWhereDrawn`, only tiles that a draw of this batch
    // may have touched since its last clear of all tiles are cleared (a tile is drawn where the
    // draw binned a triangle into it): the caller states that every other pixel already holds the
    // cleared values. Sets the batch's targets' size to `depthStencil`'s, like a draw.
    void clearDepthStencil(Surface& depthStencil, bool clearDepth, float depth, bool clearStencil, std::uint8_t stencil,
                           std::uint8_t stencilWriteMask, bool onlyWhereDrawn);

    // Moves `value` into storage that lives until the next run() returns (or the batch is
    // destroyed): shader data the draws point to, including draws that draw() runs at once.
    template <class T>
    const T& keep(T value);

    // Runs the recorded draws; returns the stats of every draw since the last run(), summed
    // (those run at once by draw() included).
    DrawStats run();
    // run(), with the stats added to *stats when it is not null (a pass's optional --stats sink).
    void runInto(DrawStats* stats);

    std::size_t pending() const { return mDraws.size(); }

private:
    struct Kept {
        virtual ~Kept() = default;
    };
    template <class T>
    struct KeptValue final : Kept {
        explicit KeptValue(T v) : value(std::move(v)) {}
        T value;
    };

    // Establishes the tile grid of width x height targets with `sampleCount` samples; runs what
    // is recorded first, and forgets which tiles were drawn, when it differs from the current one.
    void useTargets(std::uint32_t width, std::uint32_t height, std::uint32_t sampleCount);
    // Marks the tiles overlapping `rect` as drawn (a draw run at once).
    void markDrawn(const PixelRect& rect);
    // Runs the recorded draws, adding their stats to mStats, and releases their scratch; kept
    // values stay (a draw about to be issued may point into them).
    void flush();
    // Releases the recorded draws without running them.
    void discard();

    Device& mDevice;
    std::vector<std::unique_ptr<detail::RecordedDraw>> mDraws;
    std::vector<std::unique_ptr<Kept>> mKept;
    std::uint32_t mWidth = 0, mHeight = 0, mSampleCount = 0;  // the recorded draws' targets
    // Per tile of the grid: 1 where a draw may have written since the last clear of all tiles
    // (all 1 when the grid is established: what came before the batch is not known).
    std::vector<std::uint8_t> mTileDirty;
    DrawStats mStats;                                          // of draws run since the last run()
};

} // namespace tessera

#include <tessera/raster/detail/draw_batch_impl.h>
