// Template body of DrawBatch::draw and keep(): a recorded draw is a detail::DrawJob behind a
// virtual interface, so that run() (src/raster/draw_batch.cpp) is compiled once. Included from
// draw_batch.h; not a public header.
#pragma once

#include <memory>
#include <utility>

namespace tessera {

namespace detail {

// A recorded draw: its job's steps behind one indirect call each. The job holds its own scratch
// (taken from the device's pool, returned when the batch is done with it).
struct RecordedDraw {
    explicit RecordedDraw(std::unique_ptr<detail::DrawScratch> s) : scratch(std::move(s)) {}
    virtual ~RecordedDraw() = default;
    // Vertex stage, setup and binning of every triangle of the draw.
    virtual void prepare() = 0;
    virtual void rasterizeTile(std::size_t tileIndex, TileCounters& counters) const = 0;
    virtual bool perSampleShader() const = 0;
    virtual const TileBins& bins() const = 0;
    virtual DrawStats& stats() = 0;
    std::unique_ptr<DrawScratch> scratch;
};

template <class Vertex, class VS, class PS>
struct RecordedJob final : RecordedDraw {
    RecordedJob(std::unique_ptr<DrawScratch> s, const DrawState& state, const RenderTargets& targets, const DrawTargets& dt,
                std::span<const Vertex> vertices, std::span<const std::uint32_t> indices, const VS& vs, const PS& ps,
                const DrawEnv& env)
        : RecordedDraw(std::move(s)), job(state, targets, dt, vertices, indices, vs, ps, env, *scratch) {}
    void prepare() override {
        job.shadeVertices();
        job.setup(0, job.triangleCount());
    }
    void rasterizeTile(std::size_t tileIndex, TileCounters& counters) const override { job.rasterizeTile(tileIndex, counters); }
    bool perSampleShader() const override { return perSample<PS>(); }
    const TileBins& bins() const override { return job.bins(); }
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
    const bool sameTargets = mDraws.empty() || (dt.width == mWidth && dt.height == mHeight && dt.sampleCount == mSampleCount);
    if (!mDevice.config().binPasses || triangles > detail::kBatchTriangles) {
        // Not binned: what is recorded runs first, so the order is kept.
        flush();
        mStats += mDevice.draw(state, targets, vertices, indices, vs, ps);
        return;
    }
    if (!sameTargets) flush();  // a tile grid of other targets: the recorded draws run first
    const auto shader = detail::drawVertexShader<VS, PS>(vs);
    using DrawVS = std::remove_cvref_t<decltype(shader)>;
    record(std::make_unique<detail::RecordedJob<Vertex, DrawVS, PS>>(mDevice.takeScratch(), state, targets, dt, vertices, indices,
                                                                     shader, ps, mDevice.drawEnv()),
           dt.width, dt.height, dt.sampleCount);
}

template <class T>
const T& DrawBatch::keep(T value) {
    auto kept = std::make_unique<KeptValue<T>>(std::move(value));
    const T& ref = kept->value;
    mKept.push_back(std::move(kept));
    return ref;
}

} // namespace tessera
