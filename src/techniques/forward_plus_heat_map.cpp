// forward-plus's heat map: the demo's DebugTexture (CS_main's last phase, tile grid lines and
// LightCountHeatMap of the opaque counts) written in a pass of its own, and the gradient's colour
// for a light count (forwardPlusHeatMapColor, public).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "forward_plus_detail.h"

namespace tessera {
namespace {

// LightCountHeatMap's u = o_LightCount / 50.0f (ForwardPlusRendering.hlsl CS_main).
constexpr float kHeatMapFullScale = 50.0f;  // lights at the gradient's end

} // namespace

namespace forward_plus_detail {

// The "heatmap" pass: the demo's DebugTexture as CS_main's last phase writes it, from the opaque
// grid's counts (o_LightCount): thread rows / columns 0 of a tile (0, 0, 0, 0.9), then rows /
// columns 1 (1, 1, 1, 0.5), else LightCountHeatMap(o_LightCount / 50) for o_LightCount > 0 and
// (0, 0, 0, 1) for 0. Off-screen threads write nothing (no texel there).
void writeHeatMap(Device& device, const Surface& grid, std::uint32_t block, Surface& heatmap) {
    const glm::vec4 edge(0.0f, 0.0f, 0.0f, 0.9f), inner(1.0f, 1.0f, 1.0f, 0.5f);
    const std::uint32_t width = heatmap.width(), height = heatmap.height(), tilesX = grid.width();
    device.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, height, block), [&](const tbb::blocked_range<std::uint32_t>& r) {
            for (std::uint32_t y = r.begin(); y < r.end(); ++y) {
                const std::uint32_t ty = y / block, gy = y % block;
                std::byte* out = heatmap.texel(0, y);
                for (std::uint32_t tx = 0; tx < tilesX; ++tx) {
                    std::uint32_t count;
                    std::memcpy(&count, grid.texel(tx, ty) + sizeof(std::uint32_t), sizeof(count));
                    const glm::vec4 heat = count > 0 ? forwardPlusHeatMapColor(count) : glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
                    const std::uint32_t x0 = tx * block, x1 = std::min(x0 + block, width);
                    for (std::uint32_t x = x0; x < x1; ++x, out += sizeof(glm::vec4)) {
                        const std::uint32_t gx = x - x0;
                        const glm::vec4& color = gx == 0 || gy == 0 ? edge : gx == 1 || gy == 1 ? inner : heat;
                        std::memcpy(out, &color, sizeof(color));
                    }
                }
            }
        });
    });
}

} // namespace forward_plus_detail

glm::vec4 forwardPlusHeatMapColor(std::uint32_t lightCount) {
    static constexpr std::array<glm::vec4, 5> kGradient{glm::vec4(0.0f, 0.0f, 1.0f, 1.0f), glm::vec4(0.0f, 1.0f, 1.0f, 1.0f),
                                                        glm::vec4(0.0f, 1.0f, 0.0f, 1.0f), glm::vec4(1.0f, 1.0f, 0.0f, 1.0f),
                                                        glm::vec4(1.0f, 0.0f, 0.0f, 1.0f)};
    const float u = float(lightCount) / kHeatMapFullScale;
    // Linear filtering, clamp addressing: texel space t = u * 5 - 0.5, clamped to the end texels.
    const float t = std::clamp(u * float(kGradient.size()) - 0.5f, 0.0f, float(kGradient.size() - 1));
    const float base = std::floor(t);
    const auto i0 = static_cast<std::size_t>(base);
    const std::size_t i1 = std::min(i0 + 1, kGradient.size() - 1);
    const float f = t - base;
    return kGradient[i0] + (kGradient[i1] - kGradient[i0]) * f;
}

} // namespace tessera
