// Template body of DrawBatch::draw and keep(): a recorded draw is a detail::DrawJob behind a
// virtual interface, so that run() (src/raster/draw_batch.cpp) is compiled once. Included from
// draw_batch.h; not a public header.
#pragma once

#include <memory>
#include <utility>

namespace tessera {

namespace detail {

// A recorded command of a batch, replayed tile by tile: a draw (RecordedJob) or a depth-stencil
// clear (RecordedClear, src/raster/draw_batch.cpp). A draw holds its own scratch (taken from the
// device's pool, returned when the batch is done with it).
struct RecordedDraw {
    explicit RecordedDraw(std::unique_ptr<DrawScratch> s) : scratch(std::move(s)) {}
    virtual ~RecordedDraw() = default;
    // Vertex stage, setup and binning of every triangle of the draw (nothing for a clear).
    virtual void prepare() = 0;
    // Runs the command over tile `tileIndex`. `drawn`: whether a draw may have touched the tile
    // since the last clear; returns the same after this command.
    virtual bool replayTile(std::size_t tileIndex, const PixelRect& tile, TileCounters& counters, bool drawn) const = 0;
    virtual bool isDraw() const = 0;
    virtual DrawStats& stats() = 0;
    std::unique_ptr<DrawScratch> scratch;
    // Read by the tile sweep without a virtual call: a draw's tile lists (filled by prepare(); a
    // tile with an empty list is skipped) and whether its shader runs per sample; a clear has no
    // lists and runs on every tile.
    const TileBins* bins = nullptr;
    bool perSample = false;
};

template <class Vertex, class VS, class PS>
struct RecordedJob final : RecordedDraw {
    RecordedJob(std::unique_ptr<DrawScratch> s, const DrawState& state, const RenderTargets& targets, const DrawTargets& dt,
                std::span<const Vertex> vertices, std::span<const std::uint32_t> indices, const VS& vs, const PS& ps,
                const DrawEnv& env)
        : RecordedDraw(std::move(s)), job(state, targets, dt, vertices, indices, vs, ps, env, *scratch) {
        bins = &job.bins();
        perSample = detail::perSample<PS>();
    }
    void prepare() override {
        job.shadeVertices();
        job.setup(0, job.triangleCount());
    }
    bool replayTile(std::size_t tileIndex, const PixelRect&, TileCounters& counters, bool drawn) const override {
        return job.rasterizeTile(tileIndex, counters) || drawn;
    }
    bool isDraw() const override { return true; }
    DrawStats& stats() override { return job.stats(); }
    DrawJob<Vertex, VS, PS> job;
};

} // namespace detail

template <class Vertex, class VS, PixelShaderOrNone PS>
    requires VertexShaderFor<VS, Vertex>
void DrawBatch::draw(const DrawState& state, const RenderTargets& targets, std::span<const Vertex> vertices,
                     std::span<const std::uint32_t> indices, const VS& vs, const PS& ps) {
    detail::checkVaryings<VS, PS>();
    const DrawTargets dt = detail::checkDraw<PS>(state, targets, mDevice.config().tileSize, vertices.size(), indices.size());
    const std::size_t triangles = (indices.empty() ? vertices.size() : indices.size()) / 3;
    useTargets(dt.width, dt.height, dt.sampleCount);  // runs what is recorded first if the grid changes
    if (!mDevice.config().binPasses || triangles > detail::kBatchTriangles) {
        // Not binned: what is recorded runs first, so the order is kept.
        flush();
        const DrawStats s = mDevice.draw(state, targets, vertices, indices, vs, ps);
        markDrawn(s.setup.touched);
        mStats += s;
        return;
    }
    const auto shader = detail::drawVertexShader<VS, PS>(vs);
    using DrawVS = std::remove_cvref_t<decltype(shader)>;
    mDraws.push_back(std::make_unique<detail::RecordedJob<Vertex, DrawVS, PS>>(mDevice.takeScratch(), state, targets, dt, vertices,
                                                                             indices, shader, ps, mDevice.drawEnv()));
}

template <class T>
const T& DrawBatch::keep(T value) {
    auto kept = std::make_unique<KeptValue<T>>(std::move(value));
    const T& ref = kept->value;
    mKept.push_back(std::move(kept));
    return ref;
}

} // namespace tessera
