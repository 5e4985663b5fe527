// Viewable companions of dumped buffers: an R8G8B8A8_UNORM picture of any named buffer that a
// person can open in an image viewer (a D24 depth buffer spans 0.96-1.0, a stencil count peaks
// at 3 of 255, a light grid holds raw integers: stored as they are, they look blank), and the
// rule that made it, for the dump's manifest. The stored buffers stay the exact record.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <tessera/buffers/surface.h>

namespace tessera {

struct BufferView {
    Surface image;     // R8G8B8A8_UNORM, opaque; a colour bar below the buffer where `rule` says so
    std::string rule;  // how a pixel of `image` reads, in one line
};

// Which picture of a buffer: its main view (Depth is that for every format; the name says what
// it shows for depth formats), its stencil, or a colour format's alpha channel alone (G-buffers
// keep data there: opacity, the packed specular power).
enum class ViewChannel : std::uint8_t { Depth, Stencil, Alpha, Rgb };

// The picture of `surface` (sample 0), chosen by format and name:
//  - depth (ViewChannel::Depth of a depth format): covered depths (< 1) stretched over their
//    [min, max], near white and far dark grey, the cleared 1.0 black;
//  - stencil (ViewChannel::Stencil): 0 black, each other value its own colour of a fixed
//    12-colour palette (value mod 12), a legend bar of 0..max below;
//  - UINT: a heat ramp from black (0) through blue, green, yellow to white (the buffer's max),
//    with a colour bar ticked at each quarter; for "lightgrid*" buffers (offset, count) the count,
//    else channel 0; "lightindex*" lists wrapped 256 entries per row, 2 px each; "*.counters":
//    nullopt (a few numbers, not a picture);
//  - "frustums" (R32G32B32A32_FLOAT, four planes per tile: left, right, top, bottom): a 16 px
//    cell per tile cut along its diagonals into four triangles coloured by the planes' normals;
//  - float / SNORM / packed formats: names containing "normal" as n * 0.5 + 0.5, others
//    rgb * exposure clamped to [0, 1] (one channel as grey);
//  - R8G8B8A8 formats: nullopt (the dump is already viewable);
//  - ViewChannel::Rgb of a four-channel colour format: its rgb, opaque (a G-buffer target whose
//    alpha holds data, e.g. the Cookbook's specular intensity, looks empty in a viewer otherwise);
//    nullopt for other formats;
//  - ViewChannel::Alpha of a colour format: alpha as grey over [0, 1], or over [0, max] when the
//    alpha exceeds 1 (a float G-buffer's unpacked specular power); nullopt for other formats.
std::optional<BufferView> viewBuffer(std::string_view name, const Surface& surface, ViewChannel channel = ViewChannel::Depth,
                                     float exposure = 1.0f);

// The light count of each tile (a light grid of (offset, count) texels, one per tileSizePx tile)
// as the heat ramp blended half and half over `image` (an RGBA8 buffer of the frame's size), so the
// counts sit on the geometry they belong to; a colour bar below. nullopt when the sizes disagree.
std::optional<BufferView> overlayTileCounts(const Surface& grid, std::uint32_t tileSizePx, const Surface& image);

// The heat ramp of viewBuffer for t in [0, 1] (0 black, 1 white), as 8-bit RGB in one word
// (R in the low byte).
std::uint32_t heatColor(float t);

} // namespace tessera
