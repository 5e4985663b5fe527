// Template body of Device::draw: vertex stage -> setup (parallel chunks, order kept) ->
// binning into tiles -> per-tile rasterization of 2x2 quads with the pixel shader and the
// output merger. Included from device.h; not a public header on its own.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <tessera/raster/fixed_point.h>
#include <tessera/raster/output_merger.h>
#include <tessera/raster/sample_pattern.h>

namespace tessera {

template <class F>
void Device::execute(F&& f) {
    mArena->execute(std::forward<F>(f));
}

namespace detail {

inline constexpr std::uint32_t kSetupChunk = 2048;  // triangles per parallel setup task

// Bins triangles (in submission order) into the tiles their bounds touch.
struct TileBins {
    std::uint32_t tileSize = 0, tilesX = 0, tilesY = 0;
    std::vector<std::vector<std::uint32_t>> lists;  // per tile: triangle ids, ascending
};
TileBins binTriangles(const std::vector<SetupTriangle>& tris, std::uint32_t width, std::uint32_t height,
                      std::uint32_t tileSize);

// Runs triangle setup over `triangleCount` triangles in parallel chunks and concatenates
// the results in submission order. fetch(t, pos[3], var[3]) supplies triangle t's vertices.
template <class Fetch>
void setupAll(std::uint32_t triangleCount, const SetupContext& ctx, Fetch&& fetch, std::vector<SetupTriangle>& tris,
              std::vector<float>& varyingStore, SetupStats& stats) {
    const std::uint32_t chunks = (triangleCount + kSetupChunk - 1) / kSetupChunk;
    std::vector<std::vector<SetupTriangle>> chunkTris(chunks);
    std::vector<std::vector<float>> chunkVary(chunks);
    std::vector<SetupStats> chunkStats(chunks);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, chunks, 1), [&](const tbb::blocked_range<std::uint32_t>& r) {
        for (std::uint32_t c = r.begin(); c != r.end(); ++c) {
            const std::uint32_t end = std::min(triangleCount, (c + 1) * kSetupChunk);
            chunkTris[c].reserve(end - c * kSetupChunk);
            for (std::uint32_t t = c * kSetupChunk; t < end; ++t) {
                glm::vec4 pos[3];
                const float* var[3];
                fetch(t, pos, var);
                setupTriangle(ctx, pos, var, chunkTris[c], chunkVary[c], chunkStats[c]);
            }
        }
    });
    std::size_t nTris = 0, nVary = 0;
    for (std::uint32_t c = 0; c < chunks; ++c) {
        nTris += chunkTris[c].size();
        nVary += chunkVary[c].size();
        stats.trianglesIn += chunkStats[c].trianglesIn;
        stats.culledFacing += chunkStats[c].culledFacing;
        stats.culledDegenerate += chunkStats[c].culledDegenerate;
        stats.culledNonFinite += chunkStats[c].culledNonFinite;
        stats.clipped += chunkStats[c].clipped;
        stats.trianglesOut += chunkStats[c].trianglesOut;
    }
    tris.resize(nTris);
    varyingStore.resize(nVary);
    std::vector<std::size_t> triBase(chunks + 1, 0), varyBase(chunks + 1, 0);
    for (std::uint32_t c = 0; c < chunks; ++c) {
        triBase[c + 1] = triBase[c] + chunkTris[c].size();
        varyBase[c + 1] = varyBase[c] + chunkVary[c].size();
    }
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, chunks, 1), [&](const tbb::blocked_range<std::uint32_t>& r) {
        for (std::uint32_t c = r.begin(); c != r.end(); ++c) {
            for (std::size_t i = 0; i < chunkTris[c].size(); ++i) {
                SetupTriangle t = chunkTris[c][i];
                t.varyingOffset += std::uint32_t(varyBase[c]);
                tris[triBase[c] + i] = t;
            }
            std::copy(chunkVary[c].begin(), chunkVary[c].end(), varyingStore.begin() + std::ptrdiff_t(varyBase[c]));
        }
    });
}

// Barycentric weights at a sample point (16.8 units): lambda_i = E_i / area2, in double
// from the exact integer edge values, rounded once to float.
struct Bary {
    float l[3];
};
inline Bary baryAt(const SetupTriangle& t, std::int64_t X, std::int64_t Y) {
    Bary b;
    for (int i = 0; i < 3; ++i) {
        const std::int64_t e = t.a[i] * (X - t.edgeX[i]) + t.b[i] * (Y - t.edgeY[i]);
        b.l[i] = float(double(e) * t.invArea2);
    }
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

template <Varyings V>
inline V subtract(const V& a, const V& b) {
    auto x = std::bit_cast<VaryingArray<V>>(a);
    const auto y = std::bit_cast<VaryingArray<V>>(b);
    for (std::size_t k = 0; k < x.size(); ++k) x[k] -= y[k];
    return std::bit_cast<V>(x);
}

struct TileCounters {
    std::uint64_t quads = 0, psInvocations = 0, samplesPassed = 0;
};

// Everything per-draw that the tile loop reads.
struct DrawContext {
    const DrawState* state;
    DrawTargets targets;
    std::array<Surface*, kMaxRenderTargets> colors;
    std::array<RenderTargetBlendDesc, kMaxRenderTargets> blend;
    glm::vec4 blendFactor;
    Surface* depthStencil;
    DepthStencilUnit ds;
    std::span<const SampleOffset> samples;
};

template <class PS, Varyings V>
void rasterizeTile(const DrawContext& dc, const PixelRect& tile, const std::vector<std::uint32_t>& list,
                   const std::vector<SetupTriangle>& tris, const float* store, const PS& ps, TileCounters& counters) {
    constexpr bool kHasPs = !std::is_same_v<PS, NoPixelShader>;
    constexpr int kTargets = [] { if constexpr (kHasPs) return int(PS::kTargetCount); else return 0; }();
    constexpr bool kWritesDepth = kHasPs && writesDepth<PS>();
    constexpr bool kPerSample = kHasPs && perSample<PS>();
    constexpr bool kMayDiscard = kHasPs && mayDiscard<PS>();
    const std::uint32_t sampleCount = dc.targets.sampleCount;
    const Viewport& vp = dc.state->viewport;

    for (const std::uint32_t id : list) {
        const SetupTriangle& t = tris[id];
        PixelRect r{std::max(t.bounds.minX, tile.minX), std::max(t.bounds.minY, tile.minY),
                    std::min(t.bounds.maxX, tile.maxX), std::min(t.bounds.maxY, tile.maxY)};
        if (r.empty()) continue;
        const bool front = t.frontFacing;
        const bool failWrites = dc.ds.failCanWrite(front);
        for (std::int32_t qy = r.minY & ~1; qy < r.maxY; qy += 2) {
            for (std::int32_t qx = r.minX & ~1; qx < r.maxX; qx += 2) {
                // Coverage: bit (pixel * sampleCount + s); pixels 0..3 = TL, TR, BL, BR.
                std::uint32_t quadMask = 0;
                for (int p = 0; p < 4; ++p) {
                    const std::int32_t px = qx + (p & 1), py = qy + (p >> 1);
                    if (px < r.minX || px >= r.maxX || py < r.minY || py >= r.maxY) continue;
                    for (std::uint32_t s = 0; s < sampleCount; ++s) {
                        const std::int64_t X = std::int64_t(px) * fixed::kOne + fixed::kHalf + dc.samples[s].x * 16;
                        const std::int64_t Y = std::int64_t(py) * fixed::kOne + fixed::kHalf + dc.samples[s].y * 16;
                        bool in = true;
                        for (int i = 0; i < 3 && in; ++i)
                            in = t.a[i] * (X - t.edgeX[i]) + t.b[i] * (Y - t.edgeY[i]) >= t.bias[i];
                        if (in) quadMask |= 1u << (p * sampleCount + s);
                    }
                }
                if (quadMask == 0) continue;
                ++counters.quads;

                // Varyings at the four pixel centres (helper pixels included) for derivatives.
                [[maybe_unused]] std::array<V, 4> centre;
                [[maybe_unused]] std::array<float, 4> centreW{};
                [[maybe_unused]] V ddx{}, ddy{};
                if constexpr (kHasPs) {
                    for (int p = 0; p < 4; ++p) {
                        const std::int64_t X = std::int64_t(qx + (p & 1)) * fixed::kOne + fixed::kHalf;
                        const std::int64_t Y = std::int64_t(qy + (p >> 1)) * fixed::kOne + fixed::kHalf;
                        centre[p] = interpolate<V>(t, store, baryAt(t, X, Y), centreW[p]);
                    }
                    ddx = subtract(centre[1], centre[0]);
                    ddy = subtract(centre[2], centre[0]);
                }

                for (int p = 0; p < 4; ++p) {
                    const std::uint32_t pixelMask = (quadMask >> (p * sampleCount)) & ((1u << sampleCount) - 1u);
                    if (pixelMask == 0) continue;
                    const std::uint32_t px = std::uint32_t(qx + (p & 1)), py = std::uint32_t(qy + (p >> 1));
                    float zSample[8];
                    for (std::uint32_t s = 0; s < sampleCount; ++s) {
                        if (!(pixelMask & (1u << s))) continue;
                        const std::int64_t X = std::int64_t(px) * fixed::kOne + fixed::kHalf + dc.samples[s].x * 16;
                        const std::int64_t Y = std::int64_t(py) * fixed::kOne + fixed::kHalf + dc.samples[s].y * 16;
                        zSample[s] = clampDepth(depthAt(t, baryAt(t, X, Y)), vp.minDepth, vp.maxDepth);
                    }
                    // Shades, tests and writes the samples in `mask` with one shader result.
                    // zPs is SV_Position.z: depth at the pixel centre, or at the sample when the
                    // shader runs per sample (clamped to the viewport range like the samples).
                    auto resolveSamples = [&](std::uint32_t mask, std::uint32_t sampleIndex, const V& var, float posW,
                                              float xWin, float yWin, float zPs) {
                        [[maybe_unused]] PixelOutput<kTargets> out;
                        bool shaded = false;
                        auto shade = [&] {
                            if constexpr (kHasPs) {
                                PixelInput<V> in{var, ddx, ddy, glm::vec4(xWin, yWin, zPs, posW), front,
                                                 pixelMask, sampleIndex};
                                ps(in, out);
                                ++counters.psInvocations;
                                shaded = true;
                            }
                        };
                        if constexpr (kWritesDepth) {
                            shade();
                            if (out.discarded) return;
                            const float zOut = clampDepth(out.depth, vp.minDepth, vp.maxDepth);
                            for (std::uint32_t s = 0; s < sampleCount; ++s) zSample[s] = zOut;
                        }
                        DepthStencilResult result[8];
                        std::uint32_t passMask = 0;
                        for (std::uint32_t s = 0; s < sampleCount; ++s) {
                            if (!(mask & (1u << s))) continue;
                            const std::byte* dsTexel = dc.depthStencil ? dc.depthStencil->texel(px, py, s) : nullptr;
                            result[s] = dc.ds.test(dsTexel, zSample[s], front);
                            if (result[s] == DepthStencilResult::Pass) passMask |= 1u << s;
                        }
                        if constexpr (kHasPs && !kWritesDepth) {
                            // Early depth/stencil: the shader is skipped only where its result
                            // cannot matter (no sample passes and a discard could not change
                            // what the failing samples write).
                            if (passMask != 0 || (kMayDiscard && failWrites)) shade();
                            if (shaded && out.discarded) return;
                        }
                        for (std::uint32_t s = 0; s < sampleCount; ++s) {
                            if (!(mask & (1u << s))) continue;
                            if (dc.depthStencil) dc.ds.update(dc.depthStencil->texel(px, py, s), zSample[s], front, result[s]);
                        }
                        if constexpr (kHasPs) {
                            if (shaded && passMask != 0) {
                                for (int rt = 0; rt < kTargets; ++rt) {
                                    Surface* target = dc.colors[std::size_t(rt)];
                                    if (!target) continue;
                                    for (std::uint32_t s = 0; s < sampleCount; ++s)
                                        if (passMask & (1u << s))
                                            writeColorSample(target->format(), target->texel(px, py, s),
                                                             out.target[std::size_t(rt)], dc.blend[std::size_t(rt)],
                                                             dc.blendFactor);
                                }
                            }
                        }
                        counters.samplesPassed += std::uint64_t(std::popcount(passMask));
                    };
                    if constexpr (kPerSample) {
                        for (std::uint32_t s = 0; s < sampleCount; ++s) {
                            if (!(pixelMask & (1u << s))) continue;
                            const std::int64_t X = std::int64_t(px) * fixed::kOne + fixed::kHalf + dc.samples[s].x * 16;
                            const std::int64_t Y = std::int64_t(py) * fixed::kOne + fixed::kHalf + dc.samples[s].y * 16;
                            float w = 0;
                            const V var = interpolate<V>(t, store, baryAt(t, X, Y), w);
                            resolveSamples(1u << s, s, var, w, float(X) / 256.0f, float(Y) / 256.0f, zSample[s]);
                        }
                    } else if constexpr (kHasPs) {
                        const std::int64_t X = std::int64_t(px) * fixed::kOne + fixed::kHalf;
                        const std::int64_t Y = std::int64_t(py) * fixed::kOne + fixed::kHalf;
                        const float zCentre = sampleCount == 1 ? zSample[0]
                                                               : clampDepth(depthAt(t, baryAt(t, X, Y)), vp.minDepth, vp.maxDepth);
                        resolveSamples(pixelMask, 0, centre[p], centreW[p], float(px) + 0.5f, float(py) + 0.5f, zCentre);
                    } else {
                        resolveSamples(pixelMask, 0, V{}, 0.0f, float(px) + 0.5f, float(py) + 0.5f, 0.0f);
                    }
                }
            }
        }
    }
}

} // namespace detail

template <class Vertex, class VS, PixelShaderOrNone PS>
    requires VertexShaderFor<VS, Vertex>
DrawStats Device::draw(const DrawState& state, const RenderTargets& targets, std::span<const Vertex> vertices,
                       std::span<const std::uint32_t> indices, const VS& vs, const PS& ps, OcclusionQuery* query) {
    using V = typename VS::Varyings;
    if constexpr (!std::is_same_v<PS, NoPixelShader>) {
        static_assert(std::is_same_v<V, typename PS::Varyings>, "the pixel shader must read the vertex shader's varyings");
    }
    const DrawTargets dt = validateDraw(state, targets, mConfig.tileSize);
    DrawStats stats;
    if (indices.empty() && vertices.size() % 3 != 0)
        throw std::invalid_argument("draw: vertex count " + std::to_string(vertices.size()) + " is not a multiple of 3");
    if (!indices.empty() && indices.size() % 3 != 0)
        throw std::invalid_argument("draw: index count " + std::to_string(indices.size()) + " is not a multiple of 3");

    execute([&] {
        // Vertex stage: every vertex once (a pure function, so parallel is deterministic).
        std::vector<VertexOutput<V>> vsOut(vertices.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertices.size(), 1024),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t i = r.begin(); i != r.end(); ++i) vsOut[i] = vs(vertices[i]);
                          });
        const VertexOutput<V> outOfRange = vs(Vertex{});

        SetupContext ctx{&state, dt.rect, std::uint32_t(kVaryingFloatCount<V>)};
        const std::uint32_t triangleCount = std::uint32_t((indices.empty() ? vertices.size() : indices.size()) / 3);
        std::vector<SetupTriangle> tris;
        std::vector<float> store;
        detail::setupAll(
            triangleCount, ctx,
            [&](std::uint32_t t, glm::vec4* pos, const float** var) {
                for (int k = 0; k < 3; ++k) {
                    const std::size_t i = indices.empty() ? std::size_t(t) * 3 + std::size_t(k) : indices[std::size_t(t) * 3 + std::size_t(k)];
                    const VertexOutput<V>& o = i < vsOut.size() ? vsOut[i] : outOfRange;
                    pos[k] = o.posClip;
                    var[k] = reinterpret_cast<const float*>(&o.varyings);
                }
            },
            tris, store, stats.setup);

        const detail::TileBins bins = detail::binTriangles(tris, dt.width, dt.height, mConfig.tileSize);
        detail::DrawContext dc{&state, dt, targets.colors, {}, glm::vec4(state.blendFactor[0], state.blendFactor[1],
                               state.blendFactor[2], state.blendFactor[3]), targets.depthStencil, {},
                               standardSamplePattern(dt.sampleCount)};
        for (int rt = 0; rt < kMaxRenderTargets; ++rt)
            dc.blend[std::size_t(rt)] = state.blend.renderTarget[state.blend.independentBlendEnable ? std::size_t(rt) : 0];
        if (targets.depthStencil) dc.ds = DepthStencilUnit{targets.depthStencil->format(), state.depthStencil, state.stencilRef};

        const std::size_t nTiles = bins.lists.size();
        std::vector<detail::TileCounters> counters(nTiles);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nTiles, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t tileIndex = r.begin(); tileIndex != r.end(); ++tileIndex) {
                if (bins.lists[tileIndex].empty()) continue;
                const std::int32_t tx = std::int32_t(tileIndex % bins.tilesX), ty = std::int32_t(tileIndex / bins.tilesX);
                const std::int32_t ts = std::int32_t(bins.tileSize);
                const PixelRect tile{tx * ts, ty * ts, std::min((tx + 1) * ts, std::int32_t(dt.width)),
                                     std::min((ty + 1) * ts, std::int32_t(dt.height))};
                detail::rasterizeTile<PS, V>(dc, tile, bins.lists[tileIndex], tris, store.data(), ps, counters[tileIndex]);
            }
        });
        for (std::size_t i = 0; i < nTiles; ++i) {
            stats.binnedTileTriangles += bins.lists[i].size();
            stats.quads += counters[i].quads;
            stats.psInvocations += counters[i].psInvocations;
            stats.samplesPassed += counters[i].samplesPassed;
        }
    });
    if (query && query->active()) query->add(stats.samplesPassed);
    return stats;
}

} // namespace tessera
