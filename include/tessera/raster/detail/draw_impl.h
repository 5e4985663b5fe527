// Template body of Device::draw: vertex stage -> setup (parallel chunks, order kept) ->
// binning into tiles -> per-tile rasterization of 2x2 quads with the pixel shader and the
// output merger, batch after batch of triangles. Included from device.h; not a public header.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstring>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <tessera/buffers/conversion.h>
#include <tessera/raster/fixed_point.h>
#include <tessera/raster/output_merger.h>
#include <tessera/raster/pixel_watch.h>
#include <tessera/raster/quad_block.h>
#include <tessera/raster/detail/tile_steps.h>
#include <tessera/raster/sample_pattern.h>
#include <tessera/shaders/block_shader.h>

namespace tessera {

template <class F>
void Device::execute(F&& f) {
    mArena->execute(std::forward<F>(f));
}

namespace detail {

inline constexpr std::uint32_t kSetupChunk = 2048;  // triangles per parallel setup task
// Triangles per batch: a draw runs setup -> binning -> rasterization on consecutive batches of
// its triangles, so the set-up triangles (about 150 bytes each with 4 varyings) are reused
// from cache-sized storage instead of streaming a whole draw's worth (150 MB for 1M
// triangles) through fresh memory. Each batch sweeps every tile's pixels once, so batches
// must not be too small either: 128K triangles measured best at 1920x1080 (bench/RESULTS.md).
// Tiles still see every triangle in submission order: batches run one after another.
inline constexpr std::uint32_t kBatchTriangles = 64 * kSetupChunk;

// The set-up triangles of one chunk of kSetupChunk input triangles, in submission order, and
// their varyings (SetupTriangle::varyingOffset indexes `varyings`). Chunks are not
// concatenated: bins refer to (chunk, index), which saves a copy of every triangle.
struct SetupChunk {
    std::vector<SetupTriangle> tris;
    std::vector<float> varyings;
};

struct TriangleRef {
    std::uint32_t chunk, index;
};

// Triangles binned into the tiles their bounds touch. Tile t's list is
// refs[offsets[t] .. offsets[t + 1]), in submission order (ascending chunk, then index).
struct TileBins {
    std::uint32_t tileSize = 0, tilesX = 0, tilesY = 0;
    std::vector<std::size_t> offsets;  // tilesX * tilesY + 1
    std::vector<TriangleRef> refs;
    std::size_t tileCount() const { return std::size_t(tilesX) * tilesY; }
};
// The grid of tileSize-px tiles over width x height targets, lists empty: the grid every draw on
// such targets is binned over (binTriangles) and a DrawBatch sweeps.
TileBins tileGrid(std::uint32_t width, std::uint32_t height, std::uint32_t tileSize);
// Parallel over groups of chunks (count, prefix sum, scatter); the lists do not depend on the
// grouping or thread count, only on the triangles.
TileBins binTriangles(const std::vector<SetupChunk>& chunks, std::uint32_t width, std::uint32_t height,
                      std::uint32_t tileSize);

// Runs triangle setup over triangles [first, end) in parallel chunks (submission order kept
// within and across chunks), reusing the chunks' storage. fetch(t, out[3]) supplies
// triangle t's vertex outputs.
template <Varyings V, class Fetch>
void setupAll(std::uint32_t first, std::uint32_t end, const SetupContext& ctx, Fetch&& fetch,
              std::vector<SetupChunk>& chunks, SetupStats& stats) {
    const std::uint32_t chunkCount = (end - first + kSetupChunk - 1) / kSetupChunk;
    // Chunks past this batch's stay allocated (DrawScratch) and empty: binning finds nothing in them.
    if (chunks.size() < chunkCount) chunks.resize(chunkCount);
    for (std::size_t c = chunkCount; c < chunks.size(); ++c) {
        chunks[c].tris.clear();
        chunks[c].varyings.clear();
    }
    std::vector<SetupStats> chunkStats(chunkCount);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, chunkCount, 1), [&](const tbb::blocked_range<std::uint32_t>& r) {
        for (std::uint32_t c = r.begin(); c != r.end(); ++c) {
            const std::uint32_t t0 = first + c * kSetupChunk, t1 = std::min(end, t0 + kSetupChunk);
            SetupChunk& chunk = chunks[c];
            chunk.tris.clear();
            chunk.varyings.clear();
            chunk.tris.reserve(t1 - t0);
            chunk.varyings.reserve(std::size_t(t1 - t0) * 3 * ctx.varyingFloats);
            for (std::uint32_t t = t0; t < t1; ++t) {
                VertexOutput<V> vert[3];
                fetch(t, vert);
                const glm::vec4 pos[3] = {vert[0].posClip, vert[1].posClip, vert[2].posClip};
                const float* var[3];
                for (int k = 0; k < 3; ++k) var[k] = reinterpret_cast<const float*>(&vert[k].varyings);
                const std::size_t before = chunk.tris.size();
                setupTriangle(ctx, pos, var, chunk.tris, chunk.varyings, chunkStats[c]);
                for (std::size_t k = before; k < chunk.tris.size(); ++k) chunk.tris[k].primitive = t;
            }
        }
    });
    for (const SetupStats& cs : chunkStats) {
        stats.trianglesIn += cs.trianglesIn;
        stats.culledFacing += cs.culledFacing;
        stats.culledDegenerate += cs.culledDegenerate;
        stats.culledNonFinite += cs.culledNonFinite;
        stats.clipped += cs.clipped;
        stats.trianglesOut += cs.trianglesOut;
        stats.touched = unite(stats.touched, cs.touched);
    }
}

// Barycentric weights from the exact integer edge values at a sample point: lambda_i =
// E_i / area2, in double, rounded once to float.
struct Bary {
    float l[3];
};
inline Bary baryFromEdges(const SetupTriangle& t, const std::int64_t e[3]) {
    Bary b;
    for (int i = 0; i < 3; ++i) b.l[i] = float(double(e[i]) * t.invArea2);
    return b;
}

// Depth at a sample: z0 + l1 (z1 - z0) + l2 (z2 - z0), linear in screen space (D3D11:
// depth is not perspective-corrected). A constant-depth triangle yields z0 exactly.
inline float depthAt(const SetupTriangle& t, const Bary& b) {
    return t.zWindow[0] + b.l[1] * (t.zWindow[1] - t.zWindow[0]) + b.l[2] * (t.zWindow[2] - t.zWindow[0]);
}

// D3D11 clamps the depth of every sample to the viewport's [MinDepth, MaxDepth]; NaN -> MinDepth.
inline float clampDepth(float z, float minDepth, float maxDepth) {
    if (!(z >= minDepth)) return minDepth;
    return z > maxDepth ? maxDepth : z;
}

// Perspective-correct varyings: sum(l_i * v_i/w_i) / sum(l_i / w_i); also returns clip w.
template <Varyings V>
inline V interpolate(const SetupTriangle& t, const float* store, const Bary& b, float& posW) {
    constexpr std::size_t n = kVaryingFloatCount<V>;
    const float q0 = b.l[0] * t.invW[0], q1 = b.l[1] * t.invW[1], q2 = b.l[2] * t.invW[2];
    const float invDenom = 1.0f / (q0 + q1 + q2);
    posW = invDenom;
    const float* p = store + t.varyingOffset;
    VaryingArray<V> out;
    for (std::size_t k = 0; k < n; ++k) out[k] = (b.l[0] * p[k] + b.l[1] * p[n + k] + b.l[2] * p[2 * n + k]) * invDenom;
    return std::bit_cast<V>(out);
}

// Barycentrics, depth and (when kVaryings) perspective-correct varyings at the four pixel
// centres of a quad, lane p = pixel p (TL, TR, BL, BR). Written as loops over the lane so the
// compiler can run the four pixels in SIMD; each lane performs exactly the operations of
// baryFromEdges, depthAt and interpolate, in the same order (SIMD and scalar IEEE operations
// round identically, and nothing is contracted), so every value equals the per-pixel one.
template <Varyings V>
struct QuadCentres {
    float l[3][4];  // barycentrics
    float z[4];     // depthAt (not clamped)
    float posW[4];  // clip w
    std::array<V, 4> varyings;
    Bary bary(int p) const { return Bary{{l[0][p], l[1][p], l[2][p]}}; }
};
// fast (DrawState::precision Fast): the barycentrics in float, float(double(E_i)) * float(1 / area2),
// about 2 ulp from the exact value instead of one rounding from double (E_i goes through double
// as the SIMD block does, which has no direct int64 -> float conversion on every target).
template <Varyings V, bool kVaryings>
inline void quadCentres(const SetupTriangle& t, const float* store, const std::int64_t (&ePix)[4][3], QuadCentres<V>& q,
                        bool fast = false) {
    if (fast) {
        const float invArea2 = float(t.invArea2);
        for (int i = 0; i < 3; ++i)
            for (int p = 0; p < 4; ++p) q.l[i][p] = float(double(ePix[p][i])) * invArea2;
    } else {
        for (int i = 0; i < 3; ++i)
            for (int p = 0; p < 4; ++p) q.l[i][p] = float(double(ePix[p][i]) * t.invArea2);
    }
    const float dz1 = t.zWindow[1] - t.zWindow[0], dz2 = t.zWindow[2] - t.zWindow[0];
    for (int p = 0; p < 4; ++p) q.z[p] = t.zWindow[0] + q.l[1][p] * dz1 + q.l[2][p] * dz2;
    if constexpr (kVaryings) {
        constexpr std::size_t n = kVaryingFloatCount<V>;
        float invDenom[4];
        for (int p = 0; p < 4; ++p) {
            const float q0 = q.l[0][p] * t.invW[0], q1 = q.l[1][p] * t.invW[1], q2 = q.l[2][p] * t.invW[2];
            invDenom[p] = 1.0f / (q0 + q1 + q2);
            q.posW[p] = invDenom[p];
        }
        const float* v = store + t.varyingOffset;
        std::array<VaryingArray<V>, 4> out;
        for (std::size_t k = 0; k < n; ++k) {
            float lane[4];
            for (int p = 0; p < 4; ++p)
                lane[p] = (q.l[0][p] * v[k] + q.l[1][p] * v[n + k] + q.l[2][p] * v[2 * n + k]) * invDenom[p];
            for (int p = 0; p < 4; ++p) out[std::size_t(p)][k] = lane[p];
        }
        for (std::size_t p = 0; p < 4; ++p) q.varyings[p] = std::bit_cast<V>(out[p]);
    }
}

template <Varyings V>
inline V subtract(const V& a, const V& b) {
    auto x = std::bit_cast<VaryingArray<V>>(a);
    const auto y = std::bit_cast<VaryingArray<V>>(b);
    for (std::size_t k = 0; k < x.size(); ++k) x[k] -= y[k];
    return std::bit_cast<V>(x);
}

// The depth/stencil kernels rasterizeTile is compiled for, one instantiation each per pixel
// shader (every instantiation costs build time, so there are three, not one per DepthPath and
// sample count): Off (DepthPath::Off); Buffer, a depth test without stencil on a D32 or D24
// buffer (DepthPath::D32 / D24, the format a run-time flag of the draw); General, the full
// DepthStencilUnit test, which every multisampled draw takes whatever its path: the Off, D32 and
// D24 paths are special cases of it with the same results (the output-merger tests hold them to it).
enum class DepthKernel : std::uint8_t { Off, Buffer, General };

constexpr DepthKernel depthKernel(DepthPath path, bool singleSample) {
    if (!singleSample || path == DepthPath::General) return DepthKernel::General;
    return path == DepthPath::Off ? DepthKernel::Off : DepthKernel::Buffer;
}

// Depth/stencil test of one sample on the draw's kernel (`d24`: Buffer's format). For D24,
// `code` returns the incoming depth converted to the buffer (reused by the update).
template <DepthKernel kKernel>
inline DepthStencilResult depthStencilTest(const DepthStencilUnit& ds, bool d24, const std::byte* texel, float z, bool front,
                                           std::uint32_t& code) {
    if constexpr (kKernel == DepthKernel::Off) {
        return DepthStencilResult::Pass;
    } else if constexpr (kKernel == DepthKernel::Buffer) {
        if (d24) {
            std::uint32_t stored;
            std::memcpy(&stored, texel, 4);
            code = convert::depthToD24(z);
            return compare(ds.desc.depthFunc, code, stored & 0xFFFFFFu) ? DepthStencilResult::Pass : DepthStencilResult::DepthFail;
        }
        float stored;
        std::memcpy(&stored, texel, 4);
        return compare(ds.desc.depthFunc, z, stored) ? DepthStencilResult::Pass : DepthStencilResult::DepthFail;
    } else {
        return ds.test(texel, z, front);
    }
}

template <DepthKernel kKernel>
inline void depthStencilUpdate(const DepthStencilUnit& ds, bool d24, std::byte* texel, float z, bool front,
                               DepthStencilResult result, std::uint32_t code) {
    if constexpr (kKernel == DepthKernel::Buffer) {
        if (result != DepthStencilResult::Pass || !ds.desc.depthWriteEnable) return;
        if (d24) {
            texel[0] = std::byte(code & 0xFF);
            texel[1] = std::byte((code >> 8) & 0xFF);
            texel[2] = std::byte((code >> 16) & 0xFF);
        } else {
            std::memcpy(texel, &z, 4);
        }
    } else if constexpr (kKernel == DepthKernel::General) {
        if (texel) ds.update(texel, z, front, result);  // null: no depth-stencil buffer bound
    }
}

struct TileCounters {
    std::uint64_t quads = 0, psInvocations = 0, samplesPassed = 0, simdBlocks = 0, leanBlocks = 0;
    std::uint64_t blockShaderCalls = 0;
    std::uint64_t clearedTiles = 0;  // the tile's rectangle cleared by a DrawBatch's recorded clears
};

// Adds a tile's counters to a draw's (or a batch's) stats; perSample: the invocations were of a
// shader that runs per sample (DrawStats::psPerSample).
inline void addTileCounters(DrawStats& stats, const TileCounters& c, bool perSample) {
    stats.quads += c.quads;
    stats.psInvocations += c.psInvocations;
    if (perSample) stats.psPerSample += c.psInvocations;
    stats.samplesPassed += c.samplesPassed;
    stats.simdBlocks += c.simdBlocks;
    stats.leanBlocks += c.leanBlocks;
    stats.blockShaderCalls += c.blockShaderCalls;
    stats.batchClearedTiles += c.clearedTiles;
}

// A draw's working storage (set-up chunks, per-tile counters, vertex outputs), kept by the
// Device from draw to draw: a Sponza pass issues ~380 draws, and allocating each draw's chunks
// afresh costs a page fault per touched page where the allocator maps large blocks anew
// (AddressSanitizer's does, for every block over 128 KiB: 72% of its mmap calls in a render
// were these chunks). Holds the largest draw's storage until the Device goes; never read
// before it is written in the same draw, so no byte of a draw depends on the draws before it.
struct DrawScratch {
    std::vector<SetupChunk> chunks;
    std::vector<TileCounters> counters;
    std::vector<std::byte> vertexBytes;  // VertexOutput<V>[n], constructed by each indexed draw
    std::atomic<bool> busy{false};

    // Storage for n vertex outputs of type T, not yet constructed (std::construct_at each).
    template <class T>
    std::span<T> vertexOutputs(std::size_t n) {
        static_assert(std::is_trivially_destructible_v<T> && alignof(T) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__);
        if (vertexBytes.size() < n * sizeof(T)) vertexBytes.resize(n * sizeof(T));
        return {reinterpret_cast<T*>(vertexBytes.data()), n};
    }
};

// The device's scratch for one draw, or a private one when another thread is drawing on the same
// device at the moment (draws may be issued concurrently; they then share nothing).
class ScratchLease {
public:
    explicit ScratchLease(DrawScratch& shared)
        : mShared(shared.busy.exchange(true, std::memory_order_acquire) ? nullptr : &shared) {
        if (!mShared) mOwn = std::make_unique<DrawScratch>();
    }
    ~ScratchLease() {
        if (mShared) mShared->busy.store(false, std::memory_order_release);
    }
    ScratchLease(const ScratchLease&) = delete;
    ScratchLease& operator=(const ScratchLease&) = delete;
    DrawScratch& operator*() const { return mShared ? *mShared : *mOwn; }

private:
    DrawScratch* mShared;
    std::unique_ptr<DrawScratch> mOwn;
};

// Everything per-draw that the tile loop reads.
struct DrawContext {
    const DrawState* state;
    DrawTargets targets;
    std::array<Surface*, kMaxRenderTargets> colors;
    std::array<RenderTargetBlendDesc, kMaxRenderTargets> blend;
    std::array<bool, kMaxRenderTargets> rgba8Overwrite;  // isRgba8UnormOverwrite per target
    // R8G8B8A8_UNORM with blending or a partial write mask (some channel written): in SIMD
    // blocks these colours are stashed too and blended 64 at a time (quadBlockBlendRgba8).
    std::array<bool, kMaxRenderTargets> rgba8Blend;
    glm::vec4 blendFactor;
    Surface* depthStencil;
    DepthStencilUnit ds;
    std::span<const SampleOffset> samples;
    bool fast = false;  // DrawState::precision == Fast
    bool simdBlocks = true;  // DeviceConfig::simdBlocks
    PixelWatch* watch = nullptr;  // Device::setPixelWatch
    ShadeCounts* shadeCounts = nullptr;  // Device::setShadeCounts
    std::uint64_t drawNumber = 0;
};

// The watched pixel's record of one resolveSamples call: the texels before it, then after it
// on destruction (every return path), appended to the watch.
struct WatchRecord {
    PixelWatch* watch = nullptr;  // null: not the watched pixel
    PixelDrawEvent event;
    const Surface* color = nullptr;
    const Surface* depthStencil = nullptr;
    std::uint32_t x = 0, y = 0;
    WatchRecord() = default;
    void begin(PixelWatch* w, const Surface* colorTarget, const Surface* ds, std::uint32_t px, std::uint32_t py) {
        watch = w;
        color = colorTarget;
        depthStencil = ds;
        x = px;
        y = py;
        if (color) {
            event.colorFormat = color->format();
            std::memcpy(event.colorBefore.data(), color->texel(x, y), formatInfo(color->format()).bytesPerTexel);
        }
        if (depthStencil) {
            event.depthFormat = depthStencil->format();
            std::memcpy(event.depthBefore.data(), depthStencil->texel(x, y), formatInfo(depthStencil->format()).bytesPerTexel);
        }
    }
    WatchRecord(const WatchRecord&) = delete;
    WatchRecord& operator=(const WatchRecord&) = delete;
    ~WatchRecord() {
        if (!watch) return;
        if (color) std::memcpy(event.colorAfter.data(), color->texel(x, y), formatInfo(color->format()).bytesPerTexel);
        if (depthStencil)
            std::memcpy(event.depthAfter.data(), depthStencil->texel(x, y), formatInfo(depthStencil->format()).bytesPerTexel);
        watch->events.push_back(event);
    }
};

// Rasterizes one tile's triangles in submission order, split as llvmpipe splits its tile loop:
// per triangle, coverage (the edge functions stepped over 8x8 blocks; the shader-independent
// steps live in tile_steps.h, compiled once) comes before shading (the SIMD block's lean
// pipeline, the block's quads, the per-quad path, and per pixel the depth/stencil test, the
// shader and the output merger in resolveSamples). Edge functions are stepped, not
// re-multiplied (TriangleEdges): integer addition is exact, and every value formed is the edge
// function at a real point of the target (|E| <= 2^61, fixed_point.h), so coverage and
// barycentrics equal the direct evaluation bit for bit.
// kSingleSample: the targets have one sample, so every per-sample loop folds away at compile time.
template <class PS, Varyings V, DepthKernel kDepth, bool kSingleSample>
class TileRasterizer {
public:
    TileRasterizer(const DrawContext& dc, const PixelRect& tile, const std::vector<SetupChunk>& chunks, const PS& ps)
        : mDc(dc), mTile(tile), mChunks(chunks), mPs(ps), mSampleCount(kSingleSample ? 1 : dc.targets.sampleCount),
          mVp(dc.state->viewport), mDepthD24(kDepth == DepthKernel::Buffer && dc.ds.path() == DepthPath::D24),
          // The watched pixel (Device::setPixelWatch), when it lies in this tile: its quads skip the
          // SIMD blocks and record what happens to it.
          mWatchHere(dc.watch && std::int32_t(dc.watch->x) >= tile.minX && std::int32_t(dc.watch->x) < tile.maxX &&
                     std::int32_t(dc.watch->y) >= tile.minY && std::int32_t(dc.watch->y) < tile.maxY) {}

    void run(std::span<const TriangleRef> list, TileCounters& tileCounters) {
        for (std::size_t k = 0; k < list.size(); ++k) {
            prefetch(list, k);
            const TriangleRef ref = list[k];
            const SetupChunk& chunk = mChunks[ref.chunk];
            mTri = &chunk.tris[ref.index];
            mStore = chunk.varyings.data();
            const SetupTriangle& t = *mTri;
            mRect = PixelRect{std::max(t.bounds.minX, mTile.minX), std::max(t.bounds.minY, mTile.minY),
                              std::min(t.bounds.maxX, mTile.maxX), std::min(t.bounds.maxY, mTile.maxY)};
            if (mRect.empty()) continue;
            mFront = t.frontFacing;
            mFailWrites = mDc.ds.failCanWrite(mFront);
            triangleEdges(t, mRect, mDc.samples, mSampleCount, mEdges);
            rasterizeTriangle();
        }
        tileCounters.quads += mCounters.quads;
        tileCounters.psInvocations += mCounters.psInvocations;
        tileCounters.samplesPassed += mCounters.samplesPassed;
        tileCounters.simdBlocks += mCounters.simdBlocks;
        tileCounters.leanBlocks += mCounters.leanBlocks;
        tileCounters.blockShaderCalls += mCounters.blockShaderCalls;
    }

private:
    static constexpr bool kHasPs = !std::is_same_v<PS, NoPixelShader>;
    static constexpr int kTargets = [] { if constexpr (kHasPs) return int(PS::kTargetCount); else return 0; }();
    static constexpr bool kWritesDepth = kHasPs && writesDepth<PS>();
    static constexpr bool kPerSample = kHasPs && perSample<PS>();
    static constexpr bool kMayDiscard = kHasPs && mayDiscard<PS>();
    static constexpr std::int32_t kBlock = QuadBlock::kSide;  // px
    // A tile's triangles lie scattered over the draw's setup output (small triangles: one
    // every few hundred bytes to kilobytes), so each is a cache and TLB miss. Prefetch the
    // triangle kAheadTri entries ahead, its varyings kAheadVary ahead (by then the triangle,
    // which holds their offset, has arrived) and the first rows of depth and colour texels
    // it covers kAheadPixels ahead. Prefetches change no result.
    static constexpr std::size_t kAheadTri = 8, kAheadVary = 4, kAheadPixels = 2;
    static constexpr std::int32_t kPrefetchRows = 8;
    static constexpr std::size_t kVaryBytes = 3 * kVaryingFloatCount<V> * sizeof(float);
    // The SIMD block path: single-sample targets, varyings that fit a QuadBlock, and at least
    // kSimdBlockMinPixels of the 8x8 block inside the triangle's rectangle. Smaller pieces stay on
    // the per-quad path, which visits only the quads in the rectangle. In bench/raster_bench at one
    // thread (best of 4 runs) thresholds 8..40 px ran the 20 px triangles about 20% faster than 64
    // and 100 (no block path); 40 keeps most 3 px triangles (bounds up to 6x6 px) per quad.
    static constexpr bool kBlockVaryings = kVaryingFloatCount<V> <= QuadBlock::kMaxVaryings;
    static constexpr std::int32_t kSimdBlockMinPixels = 40;  // px of the 8x8 block inside r
    static constexpr std::int64_t kNoEdges[4][3] = {};  // unused when single-sampled
    // The lean block pipeline: a SIMD depth test of the whole block, then the shader on the
    // passing pixels, with nothing per pixel that the state does not need. For pixel-rate
    // shaders that do not write depth, on the D32 / D24 / Off paths (stencil inactive) and when
    // failing samples cannot write (checked per triangle); otherwise the block feeds shadeQuad.
    static constexpr bool kLeanBlock = kSingleSample && !kPerSample && !kWritesDepth && kDepth != DepthKernel::General;
    // The lean block shades through the shader's block entry point when it has one.
    static constexpr bool kBlockShader = [] { if constexpr (kHasPs) return BlockPixelShader<PS>; else return false; }();
    static_assert(kBlockLanes == QuadBlock::kPixels, "block shaders see the SIMD block's lanes");
    // RGBA8 colours of one triangle's block, per target (overwrites, and blends when
    // dc.rgba8Blend): colour c of lane p at rgba[c * 64 + p].
    // Zeroed once, so the encoder never reads indeterminate lanes.
    struct ColorStash {
        alignas(64) float rgba[kTargets > 0 ? kTargets : 1][4 * QuadBlock::kPixels];
        std::uint64_t pending[kTargets > 0 ? kTargets : 1];
    };

    const SetupTriangle& triangleOf(const TriangleRef& ref) const { return mChunks[ref.chunk].tris[ref.index]; }
    std::array<std::uint32_t, 2> pixelOf(std::int32_t bx, std::int32_t by, int lane) const {
        return std::array<std::uint32_t, 2>{std::uint32_t(bx + lane % kBlock), std::uint32_t(by + lane / kBlock)};
    }
    void stashColor(int rt, int lane, const glm::vec4& src) {
        for (std::size_t c = 0; c < 4; ++c) mStash.rgba[rt][c * QuadBlock::kPixels + std::size_t(lane)] = src[int(c)];
        mStash.pending[rt] |= std::uint64_t(1) << lane;
    }
    V laneVaryings(int lane) const {
        VaryingArray<V> v;
        for (std::size_t j = 0; j < v.size(); ++j) v[j] = mBlock.varyings[j * QuadBlock::kPixels + std::size_t(lane)];
        return std::bit_cast<V>(v);
    }

    // Always inlined: as an ordinary function GCC 12 finds it free of side effects (its only
    // statements are __builtin_prefetch, which GCC models as touching no memory), takes it for
    // pure and deletes the call, so no prefetch was issued at all (1M 3 px triangles: 2x slower).
    [[gnu::always_inline]] void prefetch(std::span<const TriangleRef> list, std::size_t k) const {
        const std::vector<SetupChunk>& chunks = mChunks;
        if (k + kAheadTri < list.size()) {
            const char* next = reinterpret_cast<const char*>(&triangleOf(list[k + kAheadTri]));
            // Every cache line the triangle spans: at a 112-byte stride it starts anywhere in a
            // line, so half the triangles span three lines (the first and last byte alone miss
            // the middle one).
            for (std::size_t b = 0; b < sizeof(SetupTriangle); b += 64) __builtin_prefetch(next + b);
            __builtin_prefetch(next + sizeof(SetupTriangle) - 1);
        }
        if (k + kAheadVary < list.size()) {
            const TriangleRef ahead = list[k + kAheadVary];
            const char* vary = reinterpret_cast<const char*>(chunks[ahead.chunk].varyings.data() + triangleOf(ahead).varyingOffset);
            for (std::size_t b = 0; b < kVaryBytes; b += 64) __builtin_prefetch(vary + b);
            __builtin_prefetch(vary + kVaryBytes - 1);
        }
        if (k + kAheadPixels < list.size()) {
            const PixelRect& b = triangleOf(list[k + kAheadPixels]).bounds;
            const PixelRect& tile = mTile;
            const std::int32_t x0 = std::max(b.minX, tile.minX), x1 = std::min(b.maxX, tile.maxX);
            const std::int32_t y0 = std::max(b.minY, tile.minY), y1 = std::min({b.maxY, tile.maxY, y0 + kPrefetchRows});
            // Buffer's format, fixed for the draw: D24 (else D32).
            Surface* const pixelSurfaces[2] = {kDepth == DepthKernel::Off ? nullptr : mDc.depthStencil,
                                               kTargets > 0 ? mDc.colors[0] : nullptr};
            if (x0 < x1)
                for (Surface* surface : pixelSurfaces)
                    if (surface)
                        for (std::int32_t y = y0; y < y1; ++y) {
                            __builtin_prefetch(surface->texel(std::uint32_t(x0), std::uint32_t(y)), 1);
                            __builtin_prefetch(surface->texel(std::uint32_t(x1 - 1), std::uint32_t(y), mSampleCount - 1), 1);
                        }
        }
    }

    // The triangle's blocks: skipped when no sample can be covered (TriangleEdges::blockReach),
    // else through the SIMD block or quad by quad. Quads within a triangle cover disjoint
    // pixels, so visiting them block by block instead of row by row changes no result.
    void rasterizeTriangle() {
        const SetupTriangle& t = *mTri;
        const PixelRect& r = mRect;
        const TriangleEdges& e = mEdges;
        for (std::int32_t by = e.qy0; by < r.maxY; by += kBlock) {
            for (std::int32_t bx = e.qx0; bx < r.maxX; bx += kBlock) {
                std::int64_t eQuadRow[3];  // E_i at the centre of pixel (bx, qy)
                bool outside = false;
                for (int i = 0; i < 3; ++i) {
                    eQuadRow[i] = e.eOrigin[i] + (bx - e.qx0) * e.stepX[i] + (by - e.qy0) * e.stepY[i];
                    outside = outside || eQuadRow[i] + e.blockReach[i] < t.bias[i];
                }
                if (outside) continue;
                const std::int32_t xEnd = std::min(bx + kBlock, r.maxX), yEnd = std::min(by + kBlock, r.maxY);
                if constexpr (kSingleSample && kBlockVaryings) {
                    if (simdBlock(bx, by, xEnd, yEnd, eQuadRow)) continue;
                }
                quadsOfBlock(bx, by, xEnd, yEnd, eQuadRow);
            }
        }
    }

    // The SIMD block (quad_block.h): the same values as the per-quad path, bit for bit, 64 pixels
    // at a time. Used where enough of the block lies in r; false: the per-quad path takes it.
    bool simdBlock(std::int32_t bx, std::int32_t by, std::int32_t xEnd, std::int32_t yEnd, const std::int64_t (&eQuadRow)[3]) {
        const DrawContext& dc = mDc;
        const SetupTriangle& t = *mTri;
        const TriangleEdges& e = mEdges;
        const bool blockWatched = mWatchHere && std::int32_t(dc.watch->x) >= bx && std::int32_t(dc.watch->x) < xEnd &&
                                  std::int32_t(dc.watch->y) >= by && std::int32_t(dc.watch->y) < yEnd;
        // Pixels of r in the block, counted from r's own corner: the walk starts on the quad-aligned
        // column and row (qx0, qy0), which would add a column and a row of pixels outside r and let a
        // 3 px triangle's 6x6 rectangle count as 7x7 = 49.
        const std::int32_t inX = xEnd - std::max(bx, mRect.minX), inY = yEnd - std::max(by, mRect.minY);
        if (!(dc.simdBlocks && !blockWatched && inX * inY >= kSimdBlockMinPixels)) return false;
        const QuadBlock::Edges edges{{eQuadRow[0], eQuadRow[1], eQuadRow[2]},
                                     {e.stepX[0], e.stepX[1], e.stepX[2]},
                                     {e.stepY[0], e.stepY[1], e.stepY[2]}};
        const std::uint64_t covered = simdBlockCoverage(t, e, edges, mRect, bx, by);
        if (covered == 0) return true;
        ++mCounters.simdBlocks;
        quadBlockCentres(t, edges, mStore + t.varyingOffset, kHasPs ? std::uint32_t(kVaryingFloatCount<V>) : 0u,
                         kHasPs, dc.fast, mBlock);
        if (kLeanBlock && !mFailWrites) leanBlock(bx, by, xEnd, yEnd, covered);
        else blockQuads(bx, by, xEnd, yEnd, covered);
        // The triangle's stashed RGBA8 colours in this block, blended and encoded 64
        // at a time. Deferring them is invisible: a triangle's pixels are disjoint
        // and nothing reads a colour target before the next triangle starts.
        for (int rt = 0; rt < kTargets; ++rt) {
            if (mStash.pending[rt] == 0) continue;
            storeStashedRgba8(*dc.colors[std::size_t(rt)], mStash.rgba[rt], mStash.pending[rt], dc.rgba8Blend[std::size_t(rt)],
                              dc.blend[std::size_t(rt)], dc.blendFactor, dc.fast, bx, by);
            mStash.pending[rt] = 0;
        }
        return true;
    }

    // The lean block pipeline (kLeanBlock): the whole block's depth test at once (before any
    // shading: early depth, as the per-quad path), then the shader on the passing pixels.
    void leanBlock(std::int32_t bx, std::int32_t by, std::int32_t xEnd, std::int32_t yEnd, std::uint64_t covered) {
        const DrawContext& dc = mDc;
        const Viewport& vp = mVp;
        const QuadBlock& block = mBlock;
        const bool depthD24 = mDepthD24;
        const bool front = mFront;
        ++mCounters.leanBlocks;
        std::uint64_t pass = covered;
        alignas(64) float zClamped[QuadBlock::kPixels];
        alignas(64) std::uint32_t incoming[QuadBlock::kPixels];
        if constexpr (kDepth == DepthKernel::Buffer) {
            alignas(64) std::uint32_t stored[QuadBlock::kPixels] = {};  // lanes outside `covered` stay 0
            for (std::uint64_t m = covered; m != 0; m &= m - 1) {
                const int lane = std::countr_zero(m);
                const auto [px, py] = pixelOf(bx, by, lane);
                std::memcpy(&stored[lane], dc.depthStencil->texel(px, py), 4);
            }
            pass = quadBlockDepthTest(block.z, stored, covered, depthD24, dc.ds.desc.depthFunc,
                                      vp.minDepth, vp.maxDepth, zClamped, incoming);
        } else {
            for (std::uint64_t m = covered; m != 0; m &= m - 1) {
                const int lane = std::countr_zero(m);
                zClamped[lane] = clampDepth(block.z[lane], vp.minDepth, vp.maxDepth);
            }
        }
        // Stores the depth of a passing lane (D24: the three code bytes; the
        // stencil byte is kept).
        auto writeDepth = [&](int lane) {
            if constexpr (kDepth == DepthKernel::Buffer) {
                if (!dc.ds.desc.depthWriteEnable) return;
                const auto [px, py] = pixelOf(bx, by, lane);
                std::memcpy(dc.depthStencil->texel(px, py), &incoming[lane], depthD24 ? 3 : 4);
            }
        };
        if constexpr (!kMayDiscard)
            for (std::uint64_t m = pass; m != 0; m &= m - 1) writeDepth(std::countr_zero(m));
        if constexpr (kBlockShader) {
            blockShaded(bx, by, xEnd, yEnd, covered, pass, zClamped, writeDepth);
            return;
        }
        // The block's counts, kept in registers and added once (a per-pixel
        // add to the tile's counters was a store-to-load chain through memory).
        std::uint64_t quads = 0, shaded = 0, written = 0;
        for (std::int32_t qy = by; qy < yEnd; qy += 2) {
            for (std::int32_t qx = bx; qx < xEnd; qx += 2) {
                const int lane0 = (qy - by) * kBlock + (qx - bx);
                const std::uint64_t quadBits = (std::uint64_t(3) << lane0) | (std::uint64_t(3) << (lane0 + kBlock));
                if (!(covered & quadBits)) continue;
                ++quads;
                if constexpr (!kHasPs) {
                    written += std::uint64_t(std::popcount(pass & quadBits));
                } else {
                    if (!(pass & quadBits)) continue;
                    const V var0 = laneVaryings(lane0);
                    const V ddx = subtract(laneVaryings(lane0 + 1), var0);
                    const V ddy = subtract(laneVaryings(lane0 + kBlock), var0);
                    for (int p = 0; p < 4; ++p) {
                        const int lane = lane0 + (p & 1) + (p >> 1) * kBlock;
                        if (!((pass >> lane) & 1u)) continue;
                        const std::uint32_t px = std::uint32_t(qx + (p & 1)), py = std::uint32_t(qy + (p >> 1));
                        PixelOutput<kTargets> out;
                        const PixelInput<V> in{p == 0 ? var0 : laneVaryings(lane), ddx, ddy,
                                               glm::vec4(float(px) + 0.5f, float(py) + 0.5f, zClamped[lane],
                                                         block.posW[lane]),
                                               front, 1u, 0u};
                        mPs(in, out);
                        ++shaded;
                        if (dc.shadeCounts) [[unlikely]] dc.shadeCounts->add(px, py, false);
                        if (out.discarded) continue;
                        if constexpr (kMayDiscard) writeDepth(lane);
                        ++written;
                        for (int rt = 0; rt < kTargets; ++rt) {
                            Surface* target = dc.colors[std::size_t(rt)];
                            if (!target) continue;
                            const glm::vec4& src = out.target[std::size_t(rt)];
                            if (dc.rgba8Overwrite[std::size_t(rt)] || dc.rgba8Blend[std::size_t(rt)]) {
                                stashColor(rt, lane, src);
                            } else {
                                writeColorSample(target->format(), target->texel(px, py), src,
                                                 dc.blend[std::size_t(rt)], dc.blendFactor);
                            }
                        }
                    }
                }
            }
        }
        mCounters.quads += quads;
        mCounters.psInvocations += shaded;
        mCounters.samplesPassed += written;
    }

    // The lean block's shading through the shader's block entry point (shaders/block_shader.h):
    // one call for the passing lanes, colours written straight into the stash's layout. The
    // counts are the per-lane loop's: every quad with a covered lane, one invocation per passing
    // lane, one sample per lane not discarded.
    template <class WriteDepth>
    void blockShaded(std::int32_t bx, std::int32_t by, std::int32_t xEnd, std::int32_t yEnd, std::uint64_t covered,
                     std::uint64_t pass, const float* zClamped, WriteDepth& writeDepth) {
        const DrawContext& dc = mDc;
        std::uint64_t quads = 0;
        for (std::int32_t qy = by; qy < yEnd; qy += 2)
            for (std::int32_t qx = bx; qx < xEnd; qx += 2) {
                const int lane0 = (qy - by) * kBlock + (qx - bx);
                const std::uint64_t quadBits = (std::uint64_t(3) << lane0) | (std::uint64_t(3) << (lane0 + kBlock));
                if (covered & quadBits) ++quads;
            }
        mCounters.quads += quads;
        if (pass == 0) return;
        ++mCounters.blockShaderCalls;
        const BlockInput in{bx, by, pass, mBlock.varyings, zClamped, mBlock.posW, mFront};
        BlockOutput<kTargets> out;
        for (int rt = 0; rt < kTargets; ++rt) out.target[std::size_t(rt)] = mStash.rgba[rt];
        mPs.shadeBlock(in, out);
        mCounters.psInvocations += std::uint64_t(std::popcount(pass));
        if (dc.shadeCounts) [[unlikely]]
            for (std::uint64_t m = pass; m != 0; m &= m - 1) {
                const auto [px, py] = pixelOf(bx, by, std::countr_zero(m));
                dc.shadeCounts->add(px, py, false);
            }
        const std::uint64_t kept = kMayDiscard ? pass & ~out.discarded : pass;
        if constexpr (kMayDiscard)
            for (std::uint64_t m = kept; m != 0; m &= m - 1) writeDepth(std::countr_zero(m));
        mCounters.samplesPassed += std::uint64_t(std::popcount(kept));
        for (int rt = 0; rt < kTargets; ++rt) {
            Surface* target = dc.colors[std::size_t(rt)];
            if (!target) continue;
            if (dc.rgba8Overwrite[std::size_t(rt)] || dc.rgba8Blend[std::size_t(rt)]) {
                mStash.pending[rt] |= kept;  // stored with the block (simdBlock)
                continue;
            }
            const float* rgba = mStash.rgba[rt];
            for (std::uint64_t m = kept; m != 0; m &= m - 1) {
                const int lane = std::countr_zero(m);
                const auto [px, py] = pixelOf(bx, by, lane);
                const glm::vec4 src(rgba[lane], rgba[QuadBlock::kPixels + lane], rgba[2 * QuadBlock::kPixels + lane],
                                    rgba[3 * QuadBlock::kPixels + lane]);
                writeColorSample(target->format(), target->texel(px, py), src, dc.blend[std::size_t(rt)], dc.blendFactor);
            }
        }
    }

    // A SIMD block whose state needs more than the lean pipeline: its quads through shadeQuad,
    // their values taken from the block.
    void blockQuads(std::int32_t bx, std::int32_t by, std::int32_t xEnd, std::int32_t yEnd, std::uint64_t covered) {
        const QuadBlock& block = mBlock;
        for (std::int32_t qy = by; qy < yEnd; qy += 2) {
            for (std::int32_t qx = bx; qx < xEnd; qx += 2) {
                const int lane[4] = {(qy - by) * kBlock + (qx - bx), (qy - by) * kBlock + (qx - bx) + 1,
                                     (qy - by + 1) * kBlock + (qx - bx), (qy - by + 1) * kBlock + (qx - bx) + 1};
                std::uint32_t quadMask = 0;
                for (int p = 0; p < 4; ++p) quadMask |= std::uint32_t((covered >> lane[p]) & 1u) << p;
                if (quadMask == 0) continue;
                ++mCounters.quads;
                QuadCentres<V> qc;
                for (int p = 0; p < 4; ++p) {
                    for (int i = 0; i < 3; ++i) qc.l[i][p] = block.l[i][lane[p]];
                    qc.z[p] = block.z[lane[p]];
                    if constexpr (kHasPs) {
                        qc.posW[p] = block.posW[lane[p]];
                        qc.varyings[std::size_t(p)] = laneVaryings(lane[p]);
                    }
                }
                shadeQuad(qx, qy, quadMask, qc, kNoEdges, lane);
            }
        }
    }

    // The per-quad path over one block: coverage of every sample of each quad in r, then
    // barycentrics, depth and varyings at the four pixel centres and shadeQuad.
    void quadsOfBlock(std::int32_t bx, std::int32_t by, std::int32_t xEnd, std::int32_t yEnd, std::int64_t (&eQuadRow)[3]) {
        const SetupTriangle& t = *mTri;
        const PixelRect& r = mRect;
        const TriangleEdges& e = mEdges;
        const std::uint32_t sampleCount = mSampleCount;
        for (std::int32_t qy = by; qy < yEnd; qy += 2) {
            std::int64_t eQuad[3] = {eQuadRow[0], eQuadRow[1], eQuadRow[2]};
            for (std::int32_t qx = bx; qx < xEnd; qx += 2) {
                // E_i at the four pixel centres: TL, TR, BL, BR.
                std::int64_t ePix[4][3];
                for (int i = 0; i < 3; ++i) {
                    ePix[0][i] = eQuad[i];
                    ePix[1][i] = eQuad[i] + e.stepX[i];
                    ePix[2][i] = eQuad[i] + e.stepY[i];
                    ePix[3][i] = eQuad[i] + e.stepX[i] + e.stepY[i];
                    eQuad[i] += 2 * e.stepX[i];
                }
                // Coverage: bit (pixel * sampleCount + s); pixels 0..3 = TL, TR, BL, BR.
                std::uint32_t quadMask = 0;
                // Columns / rows of the quad inside r (bit 0: left / top, bit 1: right / bottom);
                // qx + 1 >= r.minX and qx < r.maxX hold by construction, likewise for y.
                const std::uint32_t colIn = (qx >= r.minX ? 1u : 0u) | (qx + 1 < r.maxX ? 2u : 0u);
                const std::uint32_t rowIn = (qy >= r.minY ? 1u : 0u) | (qy + 1 < r.maxY ? 2u : 0u);
                for (int p = 0; p < 4; ++p) {
                    if (!((colIn >> (p & 1)) & (rowIn >> (p >> 1)) & 1u)) continue;
                    for (std::uint32_t s = 0; s < sampleCount; ++s) {
                        bool in = true;
                        for (int i = 0; i < 3 && in; ++i) in = ePix[p][i] + e.sampleDelta[s][i] >= t.bias[i];
                        if (in) quadMask |= 1u << (p * sampleCount + s);
                    }
                }
                if (quadMask == 0) continue;
                ++mCounters.quads;

                // Barycentrics, depth and varyings at the four pixel centres (helper pixels
                // included, for derivatives).
                QuadCentres<V> qc;
                quadCentres<V, kHasPs>(t, mStore, ePix, qc, mDc.fast);
                shadeQuad(qx, qy, quadMask, qc, ePix, nullptr);
            }
            for (int i = 0; i < 3; ++i) eQuadRow[i] += 2 * e.stepY[i];
        }
    }

    // Depth/stencil, shading and the output merger for one quad whose centres are in qc;
    // ePix (E_i at the pixel centres) gives the samples' barycentrics when multisampled.
    // lanes: the pixels' lanes in the SIMD block (nullptr on the per-quad path); their RGBA8
    // overwrites go to the block's colour stash, encoded and stored when the block is done.
    void shadeQuad(std::int32_t qx, std::int32_t qy, std::uint32_t quadMask, const QuadCentres<V>& qc,
                   const std::int64_t (&ePix)[4][3], const int* lanes) {
        const DrawContext& dc = mDc;
        const SetupTriangle& t = *mTri;
        const Viewport& vp = mVp;
        const std::uint32_t sampleCount = mSampleCount;
        const auto& sampleDelta = mEdges.sampleDelta;
        [[maybe_unused]] V ddx{}, ddy{};
        if constexpr (kHasPs) {
            ddx = subtract(qc.varyings[1], qc.varyings[0]);
            ddy = subtract(qc.varyings[2], qc.varyings[0]);
        }

        for (int p = 0; p < 4; ++p) {
            const std::uint32_t pixelMask = (quadMask >> (p * sampleCount)) & ((1u << sampleCount) - 1u);
            if (pixelMask == 0) continue;
            const std::uint32_t px = std::uint32_t(qx + (p & 1)), py = std::uint32_t(qy + (p >> 1));
            // Barycentrics at sample s (the centre's when single-sampled: offset 0).
            auto sampleBary = [&](std::uint32_t s) {
                if (sampleCount == 1) return qc.bary(p);
                const std::int64_t e[3] = {ePix[p][0] + sampleDelta[s][0], ePix[p][1] + sampleDelta[s][1],
                                           ePix[p][2] + sampleDelta[s][2]};
                return baryFromEdges(t, e);
            };
            float zSample[8];
            if (sampleCount == 1) {
                zSample[0] = clampDepth(qc.z[p], vp.minDepth, vp.maxDepth);
            } else {
                for (std::uint32_t s = 0; s < sampleCount; ++s) {
                    if (!(pixelMask & (1u << s))) continue;
                    zSample[s] = clampDepth(depthAt(t, sampleBary(s)), vp.minDepth, vp.maxDepth);
                }
            }
            const PixelSite site{px, py, p, pixelMask, lanes};
            if constexpr (kPerSample) {
                for (std::uint32_t s = 0; s < sampleCount; ++s) {
                    if (!(pixelMask & (1u << s))) continue;
                    const std::int64_t X = std::int64_t(px) * fixed::kOne + fixed::kHalf + dc.samples[s].x * 16;
                    const std::int64_t Y = std::int64_t(py) * fixed::kOne + fixed::kHalf + dc.samples[s].y * 16;
                    float w = 0;
                    const V var = interpolate<V>(t, mStore, sampleBary(s), w);
                    resolveSamples(site, zSample, ddx, ddy, 1u << s, s, var, w, float(X) / 256.0f, float(Y) / 256.0f, zSample[s]);
                }
            } else if constexpr (kHasPs) {
                const float zCentre = sampleCount == 1 ? zSample[0] : clampDepth(qc.z[p], vp.minDepth, vp.maxDepth);
                resolveSamples(site, zSample, ddx, ddy, pixelMask, 0, qc.varyings[std::size_t(p)], qc.posW[p],
                               float(px) + 0.5f, float(py) + 0.5f, zCentre);
            } else {
                resolveSamples(site, zSample, ddx, ddy, pixelMask, 0, V{}, 0.0f, float(px) + 0.5f, float(py) + 0.5f, 0.0f);
            }
        }
    }

    // A pixel of a quad being resolved: its position, its index in the quad, its covered samples
    // and the quad's lanes in the SIMD block (nullptr on the per-quad path).
    struct PixelSite {
        std::uint32_t px, py;
        int p;
        std::uint32_t pixelMask;
        const int* lanes;
    };

    // Shades, tests and writes the samples in `mask` with one shader result.
    // zPs is SV_Position.z: depth at the pixel centre, or at the sample when the
    // shader runs per sample (clamped to the viewport range like the samples).
    void resolveSamples(const PixelSite& site, float (&zSample)[8], const V& ddx, const V& ddy, std::uint32_t mask,
                        std::uint32_t sampleIndex, const V& var, float posW, float xWin, float yWin, float zPs) {
        const DrawContext& dc = mDc;
        [[maybe_unused]] const SetupTriangle& t = *mTri;
        [[maybe_unused]] const Viewport& vp = mVp;
        const std::uint32_t sampleCount = mSampleCount;
        const bool front = mFront, depthD24 = mDepthD24;
        const std::uint32_t px = site.px, py = site.py;
        [[maybe_unused]] const std::uint32_t pixelMask = site.pixelMask;
        [[maybe_unused]] const int p = site.p;
        [[maybe_unused]] const int* const lanes = site.lanes;
        [[maybe_unused]] PixelOutput<kTargets> out;
        bool shaded = false;
        std::optional<WatchRecord> watched;  // engaged only at the watched pixel
        if (mWatchHere && px == dc.watch->x && py == dc.watch->y) [[unlikely]] {
            watched.emplace();
            watched->begin(dc.watch, kTargets > 0 ? dc.colors[0] : nullptr, dc.depthStencil, px, py);
            watched->event.draw = dc.drawNumber;
            watched->event.primitive = t.primitive;
            watched->event.coverage = mask;
            watched->event.frontFacing = front;
            watched->event.z = zSample[std::countr_zero(mask)];
        }
        auto shade = [&] {
            if constexpr (kHasPs) {
                PixelInput<V> in{var, ddx, ddy, glm::vec4(xWin, yWin, zPs, posW), front,
                                 pixelMask, sampleIndex};
                if (watched) [[unlikely]] {  // the inputs, and a place for the light loops' terms
                    PixelDrawEvent& ev = watched->event;
                    ev.posWindow = in.posWindow;
                    ev.sampleIndex = sampleIndex;
                    ev.inputCount = std::uint32_t(kVaryingFloatCount<V>);
                    const VaryingArray<V> floats = std::bit_cast<VaryingArray<V>>(var);
                    std::copy(floats.begin(), floats.end(), ev.inputs.begin());
                    ev.inputFields = varyingFields<V>();
                    setWatchedLightTerms(&ev.lights);
                    setWatchedSurface(&ev.surface);
                }
                mPs(in, out);
                ++mCounters.psInvocations;
                if (dc.shadeCounts) [[unlikely]] dc.shadeCounts->add(px, py, kPerSample);
                shaded = true;
                if (watched) [[unlikely]] {
                    setWatchedLightTerms(nullptr);
                    setWatchedSurface(nullptr);
                    watched->event.shaded = true;
                    watched->event.discarded = out.discarded;
                    if constexpr (kTargets > 0) watched->event.output = out.target[0];
                }
            }
        };
        if constexpr (kWritesDepth) {
            shade();
            if (out.discarded) return;
            const float zOut = clampDepth(out.depth, vp.minDepth, vp.maxDepth);
            for (std::uint32_t s = 0; s < sampleCount; ++s) zSample[s] = zOut;
        }
        DepthStencilResult result[8]{};  // zeroed: GCC -O2 cannot see that only masked samples are read
        std::uint32_t depthCode[8]{};
        std::uint32_t passMask = 0, passCount = 0;
        for (std::uint32_t s = 0; s < sampleCount; ++s) {
            if (!(mask & (1u << s))) continue;
            const std::byte* dsTexel = dc.depthStencil ? dc.depthStencil->texel(px, py, s) : nullptr;
            result[s] = depthStencilTest<kDepth>(dc.ds, depthD24, dsTexel, zSample[s], front, depthCode[s]);
            if (result[s] == DepthStencilResult::Pass) {
                passMask |= 1u << s;
                ++passCount;
            }
        }
        if (watched) [[unlikely]] {
            const DepthStencilResult first = result[std::countr_zero(mask)];
            PixelDrawEvent& ev = watched->event;
            ev.outcome = first == DepthStencilResult::Pass        ? PixelDrawEvent::Outcome::Pass
                         : first == DepthStencilResult::DepthFail ? PixelDrawEvent::Outcome::DepthFail
                                                                  : PixelDrawEvent::Outcome::StencilFail;
            if (dc.ds.stencilActive()) {
                const StencilFaceDesc& face = front ? dc.ds.desc.frontFace : dc.ds.desc.backFace;
                ev.stencilTested = true;
                ev.stencilRef = dc.ds.ref;
                ev.stencilOp = first == DepthStencilResult::Pass        ? face.passOp
                               : first == DepthStencilResult::DepthFail ? face.depthFailOp
                                                                        : face.failOp;
            }
        }
        if constexpr (kHasPs && !kWritesDepth) {
            // Early depth/stencil: the shader is skipped only where its result
            // cannot matter (no sample passes and a discard could not change
            // what the failing samples write).
            if (passMask != 0 || (kMayDiscard && mFailWrites)) shade();
            if (shaded && out.discarded) return;
        }
        if constexpr (kDepth != DepthKernel::Off) {
            for (std::uint32_t s = 0; s < sampleCount; ++s) {
                if (!(mask & (1u << s))) continue;
                std::byte* dsTexel = dc.depthStencil ? dc.depthStencil->texel(px, py, s) : nullptr;
                depthStencilUpdate<kDepth>(dc.ds, depthD24, dsTexel, zSample[s], front, result[s], depthCode[s]);
            }
        }
        if constexpr (kHasPs) {
            if (shaded && passMask != 0) {
                for (int rt = 0; rt < kTargets; ++rt) {
                    Surface* target = dc.colors[std::size_t(rt)];
                    if (!target) continue;
                    const glm::vec4& src = out.target[std::size_t(rt)];
                    const bool overwrite = dc.rgba8Overwrite[std::size_t(rt)];
                    if ((overwrite || dc.rgba8Blend[std::size_t(rt)]) && lanes) {  // single-sampled: passMask == 1
                        stashColor(rt, lanes[p], src);
                        continue;
                    }
                    for (std::uint32_t s = 0; s < sampleCount; ++s) {
                        if (!(passMask & (1u << s))) continue;
                        if (overwrite && dc.fast) writeColorRgba8UnormFast(target->texel(px, py, s), src);
                        else if (overwrite) writeColorRgba8Unorm(target->texel(px, py, s), src);
                        else writeColorSample(target->format(), target->texel(px, py, s), src,
                                              dc.blend[std::size_t(rt)], dc.blendFactor);
                    }
                }
            }
        }
        mCounters.samplesPassed += passCount;
        if (watched) [[unlikely]] watched->event.passed = passMask;
    }

    const DrawContext& mDc;
    const PixelRect mTile;
    const std::vector<SetupChunk>& mChunks;
    const PS& mPs;
    const std::uint32_t mSampleCount;
    const Viewport& mVp;
    const bool mDepthD24;  // Buffer's format, fixed for the draw: D24 (else D32)
    const bool mWatchHere;
    // Counted locally and stored once: the tiles' counters sit side by side in one vector, so
    // per-pixel increments there would bounce cache lines between threads (false sharing).
    TileCounters mCounters;
    ColorStash mStash{};
    QuadBlock mBlock;
    // The triangle being rasterized: its setup, the chunk's varyings, its rectangle in the tile,
    // its facing, whether failing samples can write (DepthStencilUnit::failCanWrite), its edges.
    const SetupTriangle* mTri = nullptr;
    const float* mStore = nullptr;
    PixelRect mRect{};
    bool mFront = true, mFailWrites = false;
    TriangleEdges mEdges;
};

// A draw without a pixel shader reads no varying: its vertex shader is run for the position
// alone (the varyings it computes are dead code once inlined) and setup stores none. Positions,
// clipping and setup's culling do not depend on the varyings (triangle_setup.cpp), so the depth,
// stencil and counters are the same bytes (tests/raster/draw_paths_test.cpp). Holds the vertex
// shader by value: a DrawBatch runs it after the caller's copy is gone.
template <class VS>
struct PositionOnlyVS {
    using Varyings = NoVaryings;
    VS vs;
    template <class Vertex>
    VertexOutput<NoVaryings> operator()(const Vertex& vertex) const {
        return {vs(vertex).posClip, NoVaryings{}};
    }
};

template <class PS, Varyings V, DepthKernel kDepth, bool kSingleSample>
void rasterizeTile(const DrawContext& dc, const PixelRect& tile, std::span<const TriangleRef> list,
                   const std::vector<SetupChunk>& chunks, const PS& ps, TileCounters& tileCounters) {
    TileRasterizer<PS, V, kDepth, kSingleSample>(dc, tile, chunks, ps).run(list, tileCounters);
}

// What a draw takes from the Device that records it.
struct DrawEnv {
    std::uint32_t tileSize = 64;
    bool simdBlocks = true;
    PixelWatch* watch = nullptr;
    ShadeCounts* shadeCounts = nullptr;
    std::uint64_t drawNumber = 0;
};

// The pixel rectangle of tile `tileIndex` in a grid of `bins`' tiles over a width x height target.
inline PixelRect tileRect(const TileBins& bins, std::size_t tileIndex, std::uint32_t width, std::uint32_t height) {
    const std::int32_t tx = std::int32_t(tileIndex % bins.tilesX), ty = std::int32_t(tileIndex / bins.tilesX);
    const std::int32_t ts = std::int32_t(bins.tileSize);
    return PixelRect{tx * ts, ty * ts, std::min((tx + 1) * ts, std::int32_t(width)), std::min((ty + 1) * ts, std::int32_t(height))};
}

// One validated draw and its steps: shadeVertices(), then per batch of triangles setup() (setup
// and binning) and rasterizeTile() for each tile. Holds copies of the state, the shaders and the
// draw context (which points at the copied state), so a DrawBatch can run it after the caller's
// locals are gone; the vertex and index spans must stay valid until it has run. Not movable:
// the context points into it.
template <class Vertex, class VS, class PS>
class DrawJob {
public:
    using V = typename VS::Varyings;

    DrawJob(const DrawState& state, const RenderTargets& targets, const DrawTargets& dt, std::span<const Vertex> vertices,
            std::span<const std::uint32_t> indices, const VS& vs, const PS& ps, const DrawEnv& env, DrawScratch& scratch)
        : mState(state), mDt(dt), mVertices(vertices), mIndices(indices), mVs(vs), mPs(ps), mTileSize(env.tileSize),
          mScratch(scratch) {
        mDc = DrawContext{&mState, dt, targets.colors, {}, {}, {},
                          glm::vec4(state.blendFactor[0], state.blendFactor[1], state.blendFactor[2], state.blendFactor[3]),
                          targets.depthStencil, {}, standardSamplePattern(dt.sampleCount), state.precision == Precision::Fast,
                          env.simdBlocks};
        mDc.watch = env.watch;
        mDc.shadeCounts = env.shadeCounts;
        mDc.drawNumber = env.drawNumber;
        bool blends = false;
        for (std::size_t rt = 0; rt < std::size_t(kMaxRenderTargets); ++rt) {
            mDc.blend[rt] = state.blend.renderTarget[state.blend.independentBlendEnable ? rt : 0];
            mDc.rgba8Overwrite[rt] = targets.colors[rt] && isRgba8UnormOverwrite(targets.colors[rt]->format(), mDc.blend[rt]);
            mDc.rgba8Blend[rt] = targets.colors[rt] && !mDc.rgba8Overwrite[rt] &&
                                 targets.colors[rt]->format() == Format::R8G8B8A8_UNORM &&
                                 (mDc.blend[rt].renderTargetWriteMask & WriteAll) != 0;
            blends = blends || (targets.colors[rt] && mDc.blend[rt].blendEnable);
        }
        if (targets.depthStencil) mDc.ds = DepthStencilUnit{targets.depthStencil->format(), state.depthStencil, state.stencilRef};
        ++mStats.paths[drawPathName(!std::is_same_v<PS, NoPixelShader>, mDc.ds.path(), dt.sampleCount, blends, state.precision)];
        mRaster = chooseKernel();
    }
    DrawJob(const DrawJob&) = delete;
    DrawJob& operator=(const DrawJob&) = delete;

    std::uint32_t triangleCount() const { return std::uint32_t((mIndices.empty() ? mVertices.size() : mIndices.size()) / 3); }
    const DrawTargets& targets() const { return mDt; }
    const TileBins& bins() const { return mBins; }
    // Setup, binning and path counters so far (DrawStats::paths set at construction).
    DrawStats& stats() { return mStats; }

    // Vertex stage: every vertex once (a pure function, so where it runs does not change its
    // result). Non-indexed draws shade each vertex inside setup, where it is used once; indexed
    // draws shade all vertices first, in parallel, and share the results.
    void shadeVertices() {
        mVsOut = mScratch.vertexOutputs<VertexOutput<V>>(mIndices.empty() ? 0 : mVertices.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mVsOut.size(), 1024), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) std::construct_at(&mVsOut[i], mVs(mVertices[i]));
        });
        mOutOfRange = mVs(Vertex{});
    }

    // Setup of triangles [first, end) into the scratch's chunks, then binning into tiles.
    void setup(std::uint32_t first, std::uint32_t end) {
        const SetupContext ctx{&mState, mDt.rect, std::uint32_t(kVaryingFloatCount<V>)};
        auto fetch = [&](std::uint32_t t, VertexOutput<V>* out) {
            for (std::size_t k = 0; k < 3; ++k) {
                if (mIndices.empty()) {
                    out[k] = mVs(mVertices[std::size_t(t) * 3 + k]);
                } else {
                    const std::size_t i = mIndices[std::size_t(t) * 3 + k];
                    out[k] = i < mVsOut.size() ? mVsOut[i] : mOutOfRange;
                }
            }
        };
        setupAll<V>(first, end, ctx, fetch, mScratch.chunks, mStats.setup);  // setupAll clears each chunk it uses
        mBins = binTriangles(mScratch.chunks, mDt.width, mDt.height, mTileSize);
        mStats.binnedTileTriangles += mBins.refs.size();
    }

    // Rasterizes this batch's triangles binned into tile `tileIndex`, adding to `counters`; false
    // when none was binned there (the draw touches no pixel of the tile).
    bool rasterizeTile(std::size_t tileIndex, TileCounters& counters) const {
        const std::span<const TriangleRef> list(mBins.refs.data() + mBins.offsets[tileIndex],
                                                mBins.offsets[tileIndex + 1] - mBins.offsets[tileIndex]);
        if (list.empty()) return false;
        mRaster(mDc, tileRect(mBins, tileIndex, mDt.width, mDt.height), list, mScratch.chunks, mPs, counters);
        return true;
    }

private:
    using RasterFn = void (*)(const DrawContext&, const PixelRect&, std::span<const TriangleRef>, const std::vector<SetupChunk>&,
                              const PS&, TileCounters&);
    static constexpr bool kSingleRate = compiledFor<PS>(SampleRates::Single);
    static constexpr bool kMultiRate = compiledFor<PS>(SampleRates::Multi);

    // Up to four instantiations per pixel shader (DepthKernel, and the sample rates it is compiled
    // for), chosen once per draw. A single-sample draw with a shader compiled for multisampled
    // targets only runs on the multisample kernel (the same results: it loops over one sample).
    RasterFn chooseKernel() const {
        if constexpr (kSingleRate) {
            if (mDt.sampleCount == 1) {
                switch (depthKernel(mDc.ds.path(), true)) {
                case DepthKernel::Off: return &detail::rasterizeTile<PS, V, DepthKernel::Off, true>;
                case DepthKernel::Buffer: return &detail::rasterizeTile<PS, V, DepthKernel::Buffer, true>;
                case DepthKernel::General: return &detail::rasterizeTile<PS, V, DepthKernel::General, true>;
                }
            }
        }
        if constexpr (kMultiRate) return &detail::rasterizeTile<PS, V, DepthKernel::General, false>;
        throw std::logic_error("draw: no rasterizer compiled for this pixel shader and sample count");
    }

    DrawState mState;
    DrawTargets mDt;
    std::span<const Vertex> mVertices;
    std::span<const std::uint32_t> mIndices;
    VS mVs;
    PS mPs;
    std::uint32_t mTileSize;
    DrawScratch& mScratch;
    DrawContext mDc{};
    RasterFn mRaster = nullptr;
    std::span<VertexOutput<V>> mVsOut;
    VertexOutput<V> mOutOfRange{};
    TileBins mBins;
    DrawStats mStats;
};

// Checks a draw's arguments before anything runs: the state and targets (validateDraw), the
// sample rates the shader is compiled for, and the vertex and index counts.
template <class PS>
DrawTargets checkDraw(const DrawState& state, const RenderTargets& targets, std::uint32_t tileSize, std::size_t vertexCount,
                      std::size_t indexCount) {
    const DrawTargets dt = validateDraw(state, targets, tileSize);
    if (!compiledFor<PS>(SampleRates::Multi) && dt.sampleCount > 1)
        throw std::logic_error("draw: the pixel shader is compiled for single-sample targets only (kSampleRates); the targets have " +
                               std::to_string(dt.sampleCount) + " samples");
    if (indexCount == 0 && vertexCount % 3 != 0)
        throw std::invalid_argument("draw: vertex count " + std::to_string(vertexCount) + " is not a multiple of 3");
    if (indexCount % 3 != 0)
        throw std::invalid_argument("draw: index count " + std::to_string(indexCount) + " is not a multiple of 3");
    return dt;
}

// The vertex shader a draw runs: the position alone when there is no pixel shader.
template <class VS, class PS>
auto drawVertexShader(const VS& vs) {
    if constexpr (std::is_same_v<PS, NoPixelShader> && !std::is_same_v<typename VS::Varyings, NoVaryings>)
        return PositionOnlyVS<VS>{vs};
    else
        return vs;
}

template <class VS, class PS>
void checkVaryings() {
    if constexpr (!std::is_same_v<PS, NoPixelShader>) {
        static_assert(std::is_same_v<typename VS::Varyings, typename PS::Varyings>,
                      "the pixel shader must read the vertex shader's varyings");
    }
}

} // namespace detail

template <class Vertex, class VS, PixelShaderOrNone PS>
    requires VertexShaderFor<VS, Vertex>
DrawStats Device::draw(const DrawState& state, const RenderTargets& targets, std::span<const Vertex> vertices,
                       std::span<const std::uint32_t> indices, const VS& vs, const PS& ps, OcclusionQuery* query) {
    detail::checkVaryings<VS, PS>();
    return drawImpl(state, targets, vertices, indices, detail::drawVertexShader<VS, PS>(vs), ps, query);
}

template <class Vertex, class VS, PixelShaderOrNone PS>
DrawStats Device::drawImpl(const DrawState& state, const RenderTargets& targets, std::span<const Vertex> vertices,
                           std::span<const std::uint32_t> indices, const VS& vs, const PS& ps, OcclusionQuery* query) {
    const DrawTargets dt = detail::checkDraw<PS>(state, targets, mConfig.tileSize, vertices.size(), indices.size());
    DrawStats stats;
    execute([&] {
        const detail::ScratchLease lease(*mScratch);
        detail::DrawScratch& scratch = *lease;
        detail::DrawJob<Vertex, VS, PS> job(state, targets, dt, vertices, indices, vs, ps, drawEnv(), scratch);
        job.shadeVertices();
        std::vector<detail::TileCounters>& counters = scratch.counters;
        counters.clear();
        const std::uint32_t triangleCount = job.triangleCount();
        for (std::uint32_t first = 0; first < triangleCount; first += std::min(detail::kBatchTriangles, triangleCount - first)) {
            job.setup(first, first + std::min(detail::kBatchTriangles, triangleCount - first));
            const std::size_t nTiles = job.bins().tileCount();
            counters.resize(nTiles);
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nTiles, 1), [&](const tbb::blocked_range<std::size_t>& r) {
                for (std::size_t tileIndex = r.begin(); tileIndex != r.end(); ++tileIndex) job.rasterizeTile(tileIndex, counters[tileIndex]);
            });
        }
        stats = job.stats();
        for (const detail::TileCounters& c : counters) detail::addTileCounters(stats, c, detail::perSample<PS>());
    });
    if (query && query->active()) query->add(stats.samplesPassed);
    return stats;
}

} // namespace tessera
