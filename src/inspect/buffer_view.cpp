// viewBuffer (inspect/buffer_view.h): one loop per kind of buffer, each writing an RGBA8 picture
// and stating its rule. Only display code: nothing here feeds back into a render.
#include <tessera/inspect/buffer_view.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include <tessera/buffers/texel_codec.h>
#include <tessera/state/viewport.h>

namespace tessera {
namespace {

constexpr std::uint32_t kBarRows = 8;  // px: the colour bar / legend below a heat or palette view

void store(Surface& image, std::uint32_t x, std::uint32_t y, std::uint32_t rgb) {
    const std::uint32_t rgba = rgb | 0xFF000000u;
    std::memcpy(image.texel(x, y), &rgba, 4);
}

std::uint32_t packRgb(float r, float g, float b) {
    const auto code = [](float v) { return std::uint32_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    return code(r) | (code(g) << 8) | (code(b) << 16);
}

// 12 distinct colours for stencil values 1, 2, ... (value mod 12; 0 is black).
constexpr std::array<std::uint32_t, 12> kPalette{0x4040E0, 0x40C040, 0xE0B020, 0xE04040, 0x20C0E0, 0xC040C0,
                                                 0x8080FF, 0x90E090, 0xF0E070, 0xF09090, 0x80F0F0, 0xFFFFFF};
std::uint32_t paletteColor(std::uint32_t value) {
    if (value == 0) return 0;
    const std::uint32_t bgr = kPalette[(value - 1) % kPalette.size()];
    return ((bgr >> 16) & 0xFF) | (bgr & 0xFF00) | ((bgr & 0xFF) << 16);
}

// The view's image: the buffer's size, plus the colour bar's rows below when `bar` and they fit
// under the largest surface (a 16384-row buffer gets no bar rather than a surface past the limit).
Surface makeImage(const Surface& s, bool bar) {
    const bool fits = s.height() + kBarRows <= kMaxSurfaceDimension;
    return Surface({s.width(), s.height() + (bar && fits ? kBarRows : 0), Format::R8G8B8A8_UNORM, 1});
}

// "; the bar below runs 0..max" when `image` has the bar rows below the buffer's `h`, else "".
std::string barText(const Surface& image, std::uint32_t h, std::uint32_t maxValue) {
    return image.height() > h ? "; the bar below runs 0.." + std::to_string(maxValue) : std::string();
}

} // namespace

std::optional<BufferView> overlayTileCounts(const Surface& grid, std::uint32_t tileSizePx, const Surface& image) {
    if (tileSizePx == 0 || formatInfo(grid.format()).kind != FormatKind::Uint || formatInfo(grid.format()).channels < 2 ||
        image.format() != Format::R8G8B8A8_UNORM)
        return std::nullopt;
    const std::uint32_t w = image.width(), h = image.height();
    if ((w + tileSizePx - 1) / tileSizePx != grid.width() || (h + tileSizePx - 1) / tileSizePx != grid.height()) return std::nullopt;
    std::uint32_t maxCount = 0;
    for (std::uint32_t ty = 0; ty < grid.height(); ++ty)
        for (std::uint32_t tx = 0; tx < grid.width(); ++tx) maxCount = std::max(maxCount, decodeTexelUint(grid.format(), grid.texel(tx, ty)).y);
    BufferView v{makeImage(image, true), {}};
    for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) {
            const std::uint32_t count = decodeTexelUint(grid.format(), grid.texel(x / tileSizePx, y / tileSizePx)).y;
            const std::uint32_t heat = heatColor(maxCount ? float(double(count) / double(maxCount)) : 0.0f);
            std::uint32_t rgb = 0;
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t under = std::to_integer<std::uint32_t>(image.texel(x, y)[c]);
                rgb |= (((under + ((heat >> (8 * c)) & 0xFFu) + 1) / 2) & 0xFFu) << (8 * c);
            }
            store(v.image, x, y, rgb);
        }
    for (std::uint32_t x = 0; x < w; ++x)
        for (std::uint32_t r = 0; h + r < v.image.height(); ++r) store(v.image, x, h + r, heatColor(w > 1 ? float(x) / float(w - 1) : 1.0f));
    v.rule = "lights per " + std::to_string(tileSizePx) + " px tile on the heat ramp (black 0 .. white " + std::to_string(maxCount) +
             "), averaged with the image" + barText(v.image, h, maxCount);
    return v;
}

std::uint32_t heatColor(float t) {
    if (!(t > 0.0f)) return 0;
    t = std::min(t, 1.0f);
    // black -> blue -> green -> yellow -> white, piecewise linear over four equal steps
    static constexpr std::array<std::array<float, 3>, 5> kStops{{{0, 0, 0}, {0.1f, 0.2f, 0.9f}, {0.1f, 0.8f, 0.3f},
                                                                 {0.95f, 0.85f, 0.1f}, {1, 1, 1}}};
    const float f = t * 4.0f;
    const int i = std::min(int(f), 3);
    const float w = f - float(i);
    const auto& a = kStops[std::size_t(i)];
    const auto& b = kStops[std::size_t(i) + 1];
    return packRgb(a[0] + (b[0] - a[0]) * w, a[1] + (b[1] - a[1]) * w, a[2] + (b[2] - a[2]) * w);
}

std::optional<BufferView> viewBuffer(std::string_view name, const Surface& s, ViewChannel channel, float exposure) {
    const FormatInfo& info = formatInfo(s.format());
    const std::uint32_t w = s.width(), h = s.height();
    if (channel == ViewChannel::Rgb) {
        if (info.hasDepth || info.kind == FormatKind::Uint || info.channels < 4) return std::nullopt;
        BufferView v{makeImage(s, false), {}};
        for (std::uint32_t y = 0; y < h; ++y)
            for (std::uint32_t x = 0; x < w; ++x) {
                const glm::vec3 rgb = glm::vec3(s.load(x, y)) * exposure;
                store(v.image, x, y, packRgb(std::isnan(rgb.x) ? 0.0f : rgb.x, std::isnan(rgb.y) ? 0.0f : rgb.y,
                                             std::isnan(rgb.z) ? 0.0f : rgb.z));
            }
        v.rule = "rgb x " + std::to_string(exposure) + " (exposure), opaque, clamped to [0, 1], NaN black";
        return v;
    }
    if (channel == ViewChannel::Alpha) {
        if (info.hasDepth || info.kind == FormatKind::Uint || info.channels < 4) return std::nullopt;
        float maxAlpha = 1.0f;
        for (std::uint32_t y = 0; y < h; ++y)
            for (std::uint32_t x = 0; x < w; ++x) {
                const float a = s.load(x, y).w;
                if (a > maxAlpha && std::isfinite(a)) maxAlpha = a;
            }
        BufferView v{makeImage(s, false), {}};
        for (std::uint32_t y = 0; y < h; ++y)
            for (std::uint32_t x = 0; x < w; ++x) {
                const float a = s.load(x, y).w / maxAlpha;
                store(v.image, x, y, packRgb(std::isnan(a) ? 0.0f : a, std::isnan(a) ? 0.0f : a, std::isnan(a) ? 0.0f : a));
            }
        v.rule = "alpha channel as grey over [0, " + std::to_string(maxAlpha) + "] (black 0, white " + std::to_string(maxAlpha) + ")";
        return v;
    }
    if (info.hasDepth && channel == ViewChannel::Stencil) {
        if (!info.hasStencil) return std::nullopt;
        std::uint32_t maxValue = 0;
        for (std::uint32_t y = 0; y < h; ++y)
            for (std::uint32_t x = 0; x < w; ++x) maxValue = std::max<std::uint32_t>(maxValue, s.loadStencil(x, y));
        BufferView v{makeImage(s, true), {}};
        for (std::uint32_t y = 0; y < h; ++y)
            for (std::uint32_t x = 0; x < w; ++x) store(v.image, x, y, paletteColor(s.loadStencil(x, y)));
        for (std::uint32_t x = 0; x < w; ++x)  // legend: 0..max left to right
            for (std::uint32_t r = 0; h + r < v.image.height(); ++r) store(v.image, x, h + r, paletteColor(x * (maxValue + 1) / w));
        v.rule = "stencil: 0 black, values 1.." + std::to_string(maxValue) +
                 " each its own colour (12-colour palette, value mod 12)" + barText(v.image, h, maxValue);
        return v;
    }
    if (info.hasDepth) {
        float lo = 1.0f, hi = 0.0f;
        for (std::uint32_t y = 0; y < h; ++y)
            for (std::uint32_t x = 0; x < w; ++x) {
                const float d = s.loadDepth(x, y);
                if (d < 1.0f) {
                    lo = std::min(lo, d);
                    hi = std::max(hi, d);
                }
            }
        BufferView v{makeImage(s, false), {}};
        const float span = hi > lo ? hi - lo : 1.0f;
        for (std::uint32_t y = 0; y < h; ++y)
            for (std::uint32_t x = 0; x < w; ++x) {
                const float d = s.loadDepth(x, y);
                const float g = d < 1.0f ? 1.0f - 0.8f * ((d - lo) / span) : 0.0f;  // near 1, far 0.2, cleared 0
                store(v.image, x, y, packRgb(g, g, g));
            }
        v.rule = lo <= hi ? "depth: covered values [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                "] stretched from white (near) to dark grey (far); 1.0 (cleared) black"
                          : "depth: every pixel holds the cleared 1.0 (black)";
        return v;
    }
    if (info.kind == FormatKind::Uint) {
        const bool grid = name.rfind("lightgrid", 0) == 0 && info.channels >= 2;
        const int c = grid ? 1 : 0;
        std::uint32_t maxValue = 0;
        for (std::uint32_t y = 0; y < h; ++y)
            for (std::uint32_t x = 0; x < w; ++x) maxValue = std::max(maxValue, decodeTexelUint(s.format(), s.texel(x, y))[c]);
        BufferView v{makeImage(s, true), {}};
        const auto t = [&](std::uint32_t value) { return maxValue ? float(double(value) / double(maxValue)) : 0.0f; };
        for (std::uint32_t y = 0; y < h; ++y)
            for (std::uint32_t x = 0; x < w; ++x) store(v.image, x, y, heatColor(t(decodeTexelUint(s.format(), s.texel(x, y))[c])));
        for (std::uint32_t x = 0; x < w; ++x)
            for (std::uint32_t r = 0; h + r < v.image.height(); ++r) store(v.image, x, h + r, heatColor(w > 1 ? float(x) / float(w - 1) : 1.0f));
        v.rule = std::string(grid ? "light count (channel 1 of (offset, count))" : "channel 0") +
                 ": heat ramp from black (0) through blue, green, yellow to white (" + std::to_string(maxValue) +
                 ")" + barText(v.image, h, maxValue);
        return v;
    }
    if (s.format() == Format::R8G8B8A8_UNORM || s.format() == Format::R8G8B8A8_UNORM_SRGB) return std::nullopt;
    // Signed normals (view or world xyz in [-1, 1]) are remapped; an unsigned format can only hold
    // an already encoded normal (the Cookbook's n * 0.5 + 0.5 in R11G11B10_FLOAT), shown as stored.
    const bool normal = name.find("normal") != std::string_view::npos && s.format() != Format::R11G11B10_FLOAT;
    const bool encodedNormal = name.find("normal") != std::string_view::npos && !normal;
    BufferView v{makeImage(s, false), {}};
    for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) {
            glm::vec4 p = s.load(x, y);
            if (info.channels == 1) p = glm::vec4(p.x, p.x, p.x, 1.0f);
            const glm::vec3 rgb = normal ? glm::vec3(p) * 0.5f + 0.5f : encodedNormal ? glm::vec3(p) : glm::vec3(p) * exposure;
            store(v.image, x, y, packRgb(std::isnan(rgb.x) ? 0.0f : rgb.x, std::isnan(rgb.y) ? 0.0f : rgb.y,
                                         std::isnan(rgb.z) ? 0.0f : rgb.z));
        }
    v.rule = normal          ? "normal: rgb = xyz * 0.5 + 0.5" :
             encodedNormal   ? "normal stored as xyz * 0.5 + 0.5: rgb as stored" :
                      "colour: rgb x " + std::to_string(exposure) + " (exposure), clamped to [0, 1], NaN black" +
                          (info.channels == 1 ? " (one channel as grey)" : "");
    return v;
}

} // namespace tessera
