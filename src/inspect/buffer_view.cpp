// viewBuffer (inspect/buffer_view.h): one loop per kind of buffer, each writing an RGBA8 picture
// and stating its rule. Only display code: nothing here feeds back into a render.
#include <tessera/inspect/buffer_view.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
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

constexpr std::uint32_t kTickRows = 3;  // px: the bottom rows of a bar carry its tick marks

// Tick marks in the bottom rows of the bar below row `h`: white at 0, 1/4, 1/2, 3/4 and the end of
// the bar's width (black where the ramp is already bright), so that a value can be read off it.
void drawTicks(Surface& image, std::uint32_t h) {
    if (image.height() < h + kBarRows || image.width() < 2) return;
    for (std::uint32_t q = 0; q <= 4; ++q) {
        const std::uint32_t x = std::min(image.width() - 1, (image.width() - 1) * q / 4);
        for (std::uint32_t r = kBarRows - kTickRows; r < kBarRows; ++r) {
            std::uint32_t rgba = 0;
            std::memcpy(&rgba, image.texel(x, h + r), 4);
            const std::uint32_t sum = (rgba & 0xFFu) + ((rgba >> 8) & 0xFFu) + ((rgba >> 16) & 0xFFu);
            store(image, x, h + r, sum > 3u * 160u ? 0x000000u : 0xFFFFFFu);
        }
    }
}

// "; the bar below runs 0..max, ticks at 0, max/4, ..." when `image` has the bar rows below the
// buffer's `h`, else "".
std::string barText(const Surface& image, std::uint32_t h, std::uint32_t maxValue) {
    if (image.height() <= h) return std::string();
    std::string ticks;
    for (std::uint32_t q = 0; q <= 4; ++q) {
        const double v = double(maxValue) * q / 4.0;
        char text[32];
        std::snprintf(text, sizeof text, "%g", std::round(v * 100.0) / 100.0);
        ticks += (q ? ", " : "") + std::string(text);
    }
    return "; the bar below runs 0.." + std::to_string(maxValue) + ", ticks at " + ticks;
}

constexpr std::uint32_t kListColumns = 256;  // entries per row of a wrapped index list
constexpr std::uint32_t kListEntryPx = 2;    // px: each entry's square
constexpr std::uint32_t kFrustumCellPx = 16; // px: each tile's cell in the frustum picture

// A light index list (lightindex.*: one long row of entries, the tiles' lists end to end) wrapped
// kListColumns entries per row, each entry a kListEntryPx square on the heat ramp over [0, max].
BufferView viewIndexList(const Surface& s) {
    const std::uint64_t entries = std::uint64_t(s.width()) * s.height();
    const std::uint32_t columns = std::uint32_t(std::min<std::uint64_t>(kListColumns, entries));
    const std::uint32_t rows = std::uint32_t((entries + columns - 1) / columns);
    const std::uint32_t h = std::min(rows * kListEntryPx, kMaxSurfaceDimension - kBarRows);
    std::uint32_t maxValue = 0;
    for (std::uint32_t y = 0; y < s.height(); ++y)
        for (std::uint32_t x = 0; x < s.width(); ++x) maxValue = std::max(maxValue, decodeTexelUint(s.format(), s.texel(x, y)).x);
    BufferView v{Surface({columns * kListEntryPx, h + kBarRows, Format::R8G8B8A8_UNORM, 1}), {}};
    for (std::uint32_t py = 0; py < h; ++py)
        for (std::uint32_t px = 0; px < columns * kListEntryPx; ++px) {
            const std::uint64_t i = std::uint64_t(py / kListEntryPx) * columns + px / kListEntryPx;
            const std::uint32_t value = i < entries ? decodeTexelUint(s.format(), s.texel(std::uint32_t(i % s.width()), std::uint32_t(i / s.width()))).x : 0;
            store(v.image, px, py, heatColor(maxValue ? float(double(value) / double(maxValue)) : 0.0f));
        }
    const std::uint32_t w = v.image.width();
    for (std::uint32_t x = 0; x < w; ++x)
        for (std::uint32_t r = 0; r < kBarRows; ++r) store(v.image, x, h + r, heatColor(w > 1 ? float(x) / float(w - 1) : 1.0f));
    drawTicks(v.image, h);
    v.rule = "light index list wrapped " + std::to_string(columns) + " entries per row (entry i at column i mod " + std::to_string(columns) +
             ", row i / " + std::to_string(columns) + "), each a " + std::to_string(kListEntryPx) + " px square: the index on the heat ramp, black 0 to white " +
             std::to_string(maxValue) + barText(v.image, h, maxValue);
    return v;
}

// Forward+'s tile frustums (four planes per tile side by side: left, right, top, bottom, 3dgep
// article §4.2) as one cell per tile split along its diagonals into four triangles, each the
// colour of that side's plane normal (view space, xyz * 0.5 + 0.5).
BufferView viewTileFrustums(const Surface& s) {
    const std::uint32_t tilesX = s.width() / 4, tilesY = s.height();
    const std::uint32_t cell = std::max<std::uint32_t>(1, std::min({kFrustumCellPx, kMaxSurfaceDimension / std::max(tilesX, 1u), kMaxSurfaceDimension / std::max(tilesY, 1u)}));
    BufferView v{Surface({tilesX * cell, tilesY * cell, Format::R8G8B8A8_UNORM, 1}), {}};
    for (std::uint32_t py = 0; py < tilesY * cell; ++py)
        for (std::uint32_t px = 0; px < tilesX * cell; ++px) {
            const float u = (float(px % cell) + 0.5f) / float(cell), t = (float(py % cell) + 0.5f) / float(cell);
            // Which side of the cell the texel is nearest: 0 left, 1 right, 2 top, 3 bottom.
            const std::uint32_t side = u <= t && u <= 1.0f - t ? 0 : u >= t && u >= 1.0f - t ? 1 : t < 0.5f ? 2 : 3;
            const glm::vec4 plane = s.load((px / cell) * 4 + side, py / cell);
            const glm::vec3 rgb = glm::vec3(plane) * 0.5f + 0.5f;
            store(v.image, px, py, packRgb(std::isnan(rgb.x) ? 0.0f : rgb.x, std::isnan(rgb.y) ? 0.0f : rgb.y, std::isnan(rgb.z) ? 0.0f : rgb.z));
        }
    v.rule = "tile frustums: each tile a " + std::to_string(cell) +
             " px cell cut along its diagonals into its left, right, top and bottom planes, each coloured by the plane's view-space "
             "normal as xyz * 0.5 + 0.5 (left planes face +x: reddish; top planes face -y: less green)";
    return v;
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
    drawTicks(v.image, h);
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
        drawTicks(v.image, h);
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
    if (info.kind == FormatKind::Uint && name.rfind("lightindex", 0) == 0) return viewIndexList(s);
    // A handful of counters is a record of numbers, not a picture: the report prints them, the dump keeps the TIFF.
    if (info.kind == FormatKind::Uint && name.size() > 9 && name.substr(name.size() - 9) == ".counters") return std::nullopt;
    if (name == "frustums" && s.format() == Format::R32G32B32A32_FLOAT && w % 4 == 0) return viewTileFrustums(s);
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
        drawTicks(v.image, h);
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
