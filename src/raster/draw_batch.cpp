// DrawBatch::run: the recorded draws' vertex stages, setup and binning in parallel across draws,
// then one parallel sweep over the tiles, each replaying every recorded command (draws' triangles
// binned there, clears) in submission order. Compiled once: the draws are reached through
// detail::RecordedJob.
#include <tessera/raster/draw_batch.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace tessera {

namespace {

// One depth-stencil clear's arguments (DrawBatch::clearDepthStencil's).
struct ClearArgs {
    bool clearDepth = false;
    float depth = 0.0f;
    bool clearStencil = false;
    std::uint8_t stencil = 0, stencilWriteMask = 0xFF;
    bool onlyWhereDrawn = false;

    void onRect(Surface& surface, const PixelRect& rect) const {
        surface.clearDepthStencilRect(std::uint32_t(rect.minX), std::uint32_t(rect.minY), std::uint32_t(rect.maxX),
                                      std::uint32_t(rect.maxY), clearDepth, depth, clearStencil, stencil, stencilWriteMask);
    }
};

// A recorded depth-stencil clear: clears a tile's rectangle when the sweep reaches it.
struct RecordedClear final : detail::RecordedDraw {
    RecordedClear(Surface& s, const ClearArgs& a) : RecordedDraw(nullptr), surface(s), args(a) {}
    void prepare() override {}
    bool replayTile(std::size_t, const PixelRect& tile, detail::TileCounters& counters, bool drawn) const override {
        if (drawn || !args.onlyWhereDrawn) {
            args.onRect(surface, tile);
            ++counters.clearedTiles;
        }
        return false;  // nothing drawn there since this clear
    }
    bool isDraw() const override { return false; }
    DrawStats& stats() override { return none; }

    Surface& surface;
    ClearArgs args;
    DrawStats none;
};

} // namespace

DrawBatch::DrawBatch(Device& device) : mDevice(device) {}

DrawBatch::~DrawBatch() {
    discard();
    mKept.clear();
}

void DrawBatch::useTargets(std::uint32_t width, std::uint32_t height, std::uint32_t sampleCount) {
    if (!mTileDirty.empty() && width == mWidth && height == mHeight && sampleCount == mSampleCount) return;
    flush();  // the recorded commands were binned over the old grid
    mWidth = width;
    mHeight = height;
    mSampleCount = sampleCount;
    mTileDirty.assign(detail::tileGrid(width, height, mDevice.config().tileSize).tileCount(), 1);
}

void DrawBatch::markDrawn(const PixelRect& rect) {
    if (rect.empty()) return;
    const detail::TileBins grid = detail::tileGrid(mWidth, mHeight, mDevice.config().tileSize);
    const std::int32_t ts = std::int32_t(grid.tileSize);
    const std::int32_t tx1 = std::min((rect.maxX + ts - 1) / ts, std::int32_t(grid.tilesX));
    const std::int32_t ty1 = std::min((rect.maxY + ts - 1) / ts, std::int32_t(grid.tilesY));
    for (std::int32_t ty = std::max(rect.minY, 0) / ts; ty < ty1; ++ty)
        for (std::int32_t tx = std::max(rect.minX, 0) / ts; tx < tx1; ++tx) mTileDirty[std::size_t(ty) * grid.tilesX + std::size_t(tx)] = 1;
}

void DrawBatch::clearDepthStencil(Surface& depthStencil, bool clearDepth, float depth, bool clearStencil, std::uint8_t stencil,
                                  std::uint8_t stencilWriteMask, bool onlyWhereDrawn) {
    const SurfaceDesc& desc = depthStencil.desc();
    if (!formatInfo(desc.format).hasDepth) throw std::invalid_argument("DrawBatch::clearDepthStencil on " + std::string(formatInfo(desc.format).name));
    useTargets(desc.width, desc.height, desc.sampleCount);
    const ClearArgs args{clearDepth, depth, clearStencil, stencil, stencilWriteMask, onlyWhereDrawn};
    if (mDevice.config().binPasses) {
        mDraws.push_back(std::make_unique<RecordedClear>(depthStencil, args));
        return;
    }
    // Draw by draw: one clear of the rectangle bounding the drawn tiles (or all of them).
    const detail::TileBins grid = detail::tileGrid(mWidth, mHeight, mDevice.config().tileSize);
    PixelRect rect;
    for (std::size_t t = 0; t < mTileDirty.size(); ++t)
        if (mTileDirty[t] || !onlyWhereDrawn) {
            rect = unite(rect, detail::tileRect(grid, t, mWidth, mHeight));
            ++mStats.batchClearedTiles;
        }
    if (!rect.empty()) args.onRect(depthStencil, rect);
    std::fill(mTileDirty.begin(), mTileDirty.end(), std::uint8_t(0));
}

void DrawBatch::discard() {
    for (std::unique_ptr<detail::RecordedDraw>& d : mDraws)
        if (d->scratch) mDevice.returnScratch(std::move(d->scratch));
    mDraws.clear();
}

void DrawBatch::flush() {
    if (mDraws.empty()) return;
    DrawStats stats;
    std::size_t draws = 0;
    for (const std::unique_ptr<detail::RecordedDraw>& d : mDraws) draws += d->isDraw() ? 1 : 0;
    mDevice.execute([&] {
        // Each draw's steps are those of Device::draw (detail::DrawJob), into its own scratch, so
        // where and in which order draws are prepared changes nothing.
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mDraws.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) mDraws[i]->prepare();
        });
        // Every draw was binned over this grid (same targets, the device's tile size).
        const detail::TileBins grid = detail::tileGrid(mWidth, mHeight, mDevice.config().tileSize);
        const std::size_t nTiles = grid.tileCount();
        std::vector<detail::TileCounters> counters(nTiles);
        std::vector<std::uint64_t> perSampleInvocations(nTiles, 0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nTiles, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t tile = r.begin(); tile != r.end(); ++tile) {
                const PixelRect rect = detail::tileRect(grid, tile, mWidth, mHeight);
                bool drawn = mTileDirty[tile] != 0;
                for (const std::unique_ptr<detail::RecordedDraw>& d : mDraws) {
                    if (d->bins && d->bins->offsets[tile] == d->bins->offsets[tile + 1]) continue;  // the draw misses the tile
                    const std::uint64_t before = counters[tile].psInvocations;
                    drawn = d->replayTile(tile, rect, counters[tile], drawn);
                    if (d->perSample) perSampleInvocations[tile] += counters[tile].psInvocations - before;
                }
                mTileDirty[tile] = drawn ? 1 : 0;
            }
        });
        for (const std::unique_ptr<detail::RecordedDraw>& d : mDraws) stats += d->stats();
        for (std::size_t tile = 0; tile < nTiles; ++tile) {
            detail::addTileCounters(stats, counters[tile], false);
            stats.psPerSample += perSampleInvocations[tile];
        }
    });
    stats.binnedDraws = draws;
    stats.binnedRuns = draws > 0 ? 1 : 0;
    mStats += stats;
    discard();
}

void DrawBatch::runInto(DrawStats* stats) {
    const DrawStats s = run();
    if (stats) *stats += s;
}

DrawStats DrawBatch::run() {
    flush();
    mKept.clear();  // after every draw that may point into them has run
    return std::exchange(mStats, DrawStats{});
}

} // namespace tessera
