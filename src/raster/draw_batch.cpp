// DrawBatch::run: the recorded draws' vertex stages, setup and binning in parallel across draws,
// then one parallel sweep over the tiles, each replaying every draw's triangles binned there in
// submission order. Compiled once: the draws are reached through detail::RecordedJob.
#include <tessera/raster/draw_batch.h>

#include <utility>

namespace tessera {

DrawBatch::DrawBatch(Device& device) : mDevice(device) {}

DrawBatch::~DrawBatch() {
    discard();
    mKept.clear();
}

void DrawBatch::record(std::unique_ptr<detail::RecordedDraw> draw, std::uint32_t width, std::uint32_t height, std::uint32_t sampleCount) {
    mWidth = width;
    mHeight = height;
    mSampleCount = sampleCount;
    mDraws.push_back(std::move(draw));
}

void DrawBatch::discard() {
    for (std::unique_ptr<detail::RecordedDraw>& d : mDraws) mDevice.returnScratch(std::move(d->scratch));
    mDraws.clear();
}

void DrawBatch::flush() {
    if (mDraws.empty()) return;
    DrawStats stats;
    mDevice.execute([&] {
        // Each draw's steps are those of Device::draw (detail::DrawJob), into its own scratch, so
        // where and in which order draws are prepared changes nothing.
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mDraws.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) mDraws[i]->prepare();
        });
        // Every draw was binned over the same grid (same targets, the device's tile size).
        const std::size_t nTiles = mDraws.front()->bins().tileCount();
        std::vector<detail::TileCounters> counters(nTiles);
        std::vector<std::uint64_t> perSampleInvocations(nTiles, 0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nTiles, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t tile = r.begin(); tile != r.end(); ++tile) {
                for (const std::unique_ptr<detail::RecordedDraw>& d : mDraws) {
                    const std::uint64_t before = counters[tile].psInvocations;
                    d->rasterizeTile(tile, counters[tile]);
                    if (d->perSampleShader()) perSampleInvocations[tile] += counters[tile].psInvocations - before;
                }
            }
        });
        for (const std::unique_ptr<detail::RecordedDraw>& d : mDraws) stats += d->stats();
        for (std::size_t tile = 0; tile < nTiles; ++tile) {
            detail::addTileCounters(stats, counters[tile], false);
            stats.psPerSample += perSampleInvocations[tile];
        }
    });
    stats.binnedDraws = mDraws.size();
    stats.binnedRuns = 1;
    mStats += stats;
    discard();
}

DrawStats DrawBatch::run() {
    flush();
    mKept.clear();  // after every draw that may point into them has run
    return std::exchange(mStats, DrawStats{});
}

} // namespace tessera
