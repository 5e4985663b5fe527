// Device construction (its TBB arena), draw validation and triangle binning: the parts of
// a draw that do not depend on the shader types.
#include <tessera/raster/device.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <tbb/info.h>

namespace tessera {

DrawStats& DrawStats::operator+=(const DrawStats& o) {
    setup.trianglesIn += o.setup.trianglesIn;
    setup.culledFacing += o.setup.culledFacing;
    setup.culledDegenerate += o.setup.culledDegenerate;
    setup.culledNonFinite += o.setup.culledNonFinite;
    setup.clipped += o.setup.clipped;
    setup.trianglesOut += o.setup.trianglesOut;
    binnedTileTriangles += o.binnedTileTriangles;
    quads += o.quads;
    psInvocations += o.psInvocations;
    psPerSample += o.psPerSample;
    edgeTestedPixels += o.edgeTestedPixels;
    edgePixels += o.edgePixels;
    computeShadedPixels += o.computeShadedPixels;
    computeShadedSamples += o.computeShadedSamples;
    samplesPassed += o.samplesPassed;
    simdBlocks += o.simdBlocks;
    blockShaderCalls += o.blockShaderCalls;
    leanBlocks += o.leanBlocks;
    binnedDraws += o.binnedDraws;
    binnedRuns += o.binnedRuns;
    batchClearedTiles += o.batchClearedTiles;
    for (const auto& [path, draws] : o.paths) paths[path] += draws;
    setup.touched = unite(setup.touched, o.setup.touched);
    return *this;
}

Device::Device(DeviceConfig config) : mConfig(config), mScratch(std::make_unique<detail::DrawScratch>()) {
    if (config.tileSize < 8 || config.tileSize > 1024 || config.tileSize % 2 != 0)
        throw std::invalid_argument("tile size " + std::to_string(config.tileSize) + " px must be even and in 8..1024");
    if (config.threads > 256) throw std::invalid_argument("thread count " + std::to_string(config.threads) + " exceeds 256");
    if (config.threads > std::uint32_t(tbb::info::default_concurrency()))
        mWorkerLimit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, config.threads);
    mArena = config.threads == 0 ? std::make_unique<tbb::task_arena>()
                                 : std::make_unique<tbb::task_arena>(int(config.threads));
}

Device::~Device() = default;

detail::DrawEnv Device::drawEnv() {
    return detail::DrawEnv{mConfig.tileSize, mConfig.simdBlocks, mWatch, mShadeCounts, mDrawCount++};
}

std::unique_ptr<detail::DrawScratch> Device::takeScratch() {
    const std::lock_guard lock(mPoolMutex);
    if (mScratchPool.empty()) return std::make_unique<detail::DrawScratch>();
    std::unique_ptr<detail::DrawScratch> s = std::move(mScratchPool.back());
    mScratchPool.pop_back();
    return s;
}

void Device::returnScratch(std::unique_ptr<detail::DrawScratch> scratch) {
    const std::lock_guard lock(mPoolMutex);
    mScratchPool.push_back(std::move(scratch));
}

namespace {
[[noreturn]] void invalid(const std::string& what) { throw std::invalid_argument("draw: " + what); }

bool isColorFactor(Blend b) {
    return b == Blend::SrcColor || b == Blend::InvSrcColor || b == Blend::DestColor || b == Blend::InvDestColor ||
           b == Blend::Src1Color || b == Blend::InvSrc1Color;
}
bool isDualSource(Blend b) {
    return b == Blend::Src1Color || b == Blend::InvSrc1Color || b == Blend::Src1Alpha || b == Blend::InvSrc1Alpha;
}
} // namespace

std::string drawPathName(bool hasPixelShader, DepthPath depth, std::uint32_t sampleCount, bool blends, Precision precision) {
    static constexpr const char* kDepth[] = {"Off", "D32", "D24", "General"};
    std::string name = hasPixelShader ? "ps" : "no-ps";
    name += " depth:";
    name += kDepth[int(depth)];
    name += ' ' + std::to_string(sampleCount) + 'x';
    if (blends) name += " blend";
    name += precision == Precision::Fast ? " raster:fast" : " raster:exact";
    return name;
}

DrawTargets validateDraw(const DrawState& state, const RenderTargets& targets, std::uint32_t tileSize) {
    if (tileSize < 8 || tileSize > 1024 || tileSize % 2 != 0) invalid("tile size " + std::to_string(tileSize));
    DrawTargets dt;
    const Surface* first = nullptr;
    auto check = [&](const Surface* s, const std::string& slot) {
        if (!s) return;
        if (!first) {
            first = s;
            dt.width = s->width();
            dt.height = s->height();
            dt.sampleCount = s->sampleCount();
        } else if (s->width() != dt.width || s->height() != dt.height || s->sampleCount() != dt.sampleCount) {
            invalid(slot + " is " + std::to_string(s->width()) + "x" + std::to_string(s->height()) + "x" +
                    std::to_string(s->sampleCount()) + " samples, other targets are " + std::to_string(dt.width) + "x" +
                    std::to_string(dt.height) + "x" + std::to_string(dt.sampleCount));
        }
    };
    for (int i = 0; i < kMaxRenderTargets; ++i) {
        const Surface* s = targets.colors[std::size_t(i)];
        if (s && isDepthFormat(s->format()))
            invalid("render target " + std::to_string(i) + " has depth format " + std::string(formatInfo(s->format()).name));
        check(s, "render target " + std::to_string(i));
    }
    if (targets.depthStencil && !isDepthFormat(targets.depthStencil->format()))
        invalid("depth-stencil target has colour format " + std::string(formatInfo(targets.depthStencil->format()).name));
    check(targets.depthStencil, "depth-stencil target");
    if (!first) invalid("no render target or depth-stencil target bound");

    const Viewport& vp = state.viewport;
    auto finite = [](float v) { return std::isfinite(v); };
    if (!finite(vp.topLeftX) || !finite(vp.topLeftY) || !finite(vp.width) || !finite(vp.height) || !finite(vp.minDepth) ||
        !finite(vp.maxDepth))
        invalid("viewport has a non-finite value");
    if (!(vp.width > 0.0f) || !(vp.height > 0.0f))
        invalid("viewport size " + std::to_string(vp.width) + "x" + std::to_string(vp.height) + " is empty");
    if (vp.topLeftX < kViewportBoundsMin || vp.topLeftY < kViewportBoundsMin || vp.topLeftX + vp.width > kViewportBoundsMax ||
        vp.topLeftY + vp.height > kViewportBoundsMax)
        invalid("viewport lies outside D3D11_VIEWPORT_BOUNDS [-32768, 32767]");
    if (vp.minDepth < 0.0f || vp.maxDepth > 1.0f || vp.minDepth > vp.maxDepth)
        invalid("viewport depth range [" + std::to_string(vp.minDepth) + ", " + std::to_string(vp.maxDepth) +
                "] must satisfy 0 <= MinDepth <= MaxDepth <= 1");

    if (state.blend.alphaToCoverageEnable) invalid("AlphaToCoverageEnable is not supported");
    for (int i = 0; i < kMaxRenderTargets; ++i) {
        const RenderTargetBlendDesc& b = state.blend.renderTarget[state.blend.independentBlendEnable ? std::size_t(i) : 0];
        const Surface* s = targets.colors[std::size_t(i)];
        if (!b.blendEnable || !s) continue;
        const std::string slot = "render target " + std::to_string(i);
        if (isDualSource(b.srcBlend) || isDualSource(b.destBlend) || isDualSource(b.srcBlendAlpha) || isDualSource(b.destBlendAlpha))
            invalid(slot + ": dual-source blend factors (SRC1_*) are not supported");
        if (isColorFactor(b.srcBlendAlpha) || isColorFactor(b.destBlendAlpha))
            invalid(slot + ": *_COLOR factors are not allowed in the alpha blend (D3D11_RENDER_TARGET_BLEND_DESC)");
        if (formatInfo(s->format()).kind == FormatKind::Uint)
            invalid(slot + ": blending is not allowed on integer format " + std::string(formatInfo(s->format()).name));
    }

    dt.rect = PixelRect{0, 0, std::int32_t(dt.width), std::int32_t(dt.height)};
    if (state.rasterizer.scissorEnable) {
        const ScissorRect& sc = state.scissor;
        dt.rect.minX = std::max(dt.rect.minX, sc.left);
        dt.rect.minY = std::max(dt.rect.minY, sc.top);
        dt.rect.maxX = std::min(dt.rect.maxX, sc.right);
        dt.rect.maxY = std::min(dt.rect.maxY, sc.bottom);
    }
    return dt;
}

namespace detail {

TileBins tileGrid(std::uint32_t width, std::uint32_t height, std::uint32_t tileSize) {
    TileBins grid;
    grid.tileSize = tileSize;
    grid.tilesX = (width + tileSize - 1) / tileSize;
    grid.tilesY = (height + tileSize - 1) / tileSize;
    return grid;
}

TileBins binTriangles(const std::vector<SetupChunk>& chunks, std::uint32_t width, std::uint32_t height,
                      std::uint32_t tileSize) {
    TileBins bins = tileGrid(width, height, tileSize);
    const std::size_t nTiles = bins.tileCount();
    const std::int32_t ts = std::int32_t(tileSize);
    auto forEachTile = [&](const PixelRect& b, auto&& f) {
        const std::int32_t tx0 = b.minX / ts, ty0 = b.minY / ts;
        const std::int32_t tx1 = (b.maxX - 1) / ts, ty1 = (b.maxY - 1) / ts;
        for (std::int32_t ty = ty0; ty <= ty1; ++ty)
            for (std::int32_t tx = tx0; tx <= tx1; ++tx) f(std::size_t(ty) * bins.tilesX + std::size_t(tx));
    };
    // Groups of consecutive chunks, binned in parallel: counts[g][tile], then an exclusive
    // prefix sum in (tile, group) order gives each group its slot in every tile's list, so
    // a tile's list is the groups' lists in group order = submission order. The group count
    // only trades parallelism against the counts table (<= 2^22 entries); it never changes
    // the lists.
    const std::size_t chunkCount = chunks.size();
    const std::size_t groups =
        std::max<std::size_t>(1, std::min({chunkCount, std::size_t(64), (std::size_t(1) << 22) / std::max<std::size_t>(nTiles, 1)}));
    auto groupChunks = [&](std::size_t g) {
        return std::pair<std::size_t, std::size_t>(g * chunkCount / groups, (g + 1) * chunkCount / groups);
    };
    std::vector<std::size_t> slot(groups * nTiles, 0);  // counts, then each group's next write position
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, groups, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t g = r.begin(); g != r.end(); ++g) {
            std::size_t* count = slot.data() + g * nTiles;
            const auto [c0, c1] = groupChunks(g);
            for (std::size_t c = c0; c < c1; ++c)
                for (const SetupTriangle& t : chunks[c].tris) forEachTile(t.bounds, [&](std::size_t tile) { ++count[tile]; });
        }
    });
    bins.offsets.resize(nTiles + 1);
    std::size_t total = 0;
    for (std::size_t tile = 0; tile < nTiles; ++tile) {
        bins.offsets[tile] = total;
        for (std::size_t g = 0; g < groups; ++g) {
            const std::size_t n = slot[g * nTiles + tile];
            slot[g * nTiles + tile] = total;
            total += n;
        }
    }
    bins.offsets[nTiles] = total;
    bins.refs.resize(total);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, groups, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t g = r.begin(); g != r.end(); ++g) {
            std::size_t* next = slot.data() + g * nTiles;
            const auto [c0, c1] = groupChunks(g);
            for (std::size_t c = c0; c < c1; ++c)
                for (std::uint32_t i = 0; i < chunks[c].tris.size(); ++i)
                    forEachTile(chunks[c].tris[i].bounds, [&](std::size_t tile) {
                        bins.refs[next[tile]++] = TriangleRef{std::uint32_t(c), i};
                    });
        }
    });
    return bins;
}

} // namespace detail
} // namespace tessera
