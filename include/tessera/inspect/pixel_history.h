// Pixel history (`tessera probe`, `render --probe X,Y`): the value of every named buffer at one
// pixel, recorded after every pass and after every step of the per-light techniques, kept where
// it changed; then, for the tiled techniques, the pixel's tile, its depth range and light list.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>
#include <string_view>

#include <nlohmann/json.hpp>

#include <tessera/frame/buffer_registry.h>
#include <tessera/raster/pixel_watch.h>

namespace tessera {

// One buffer's texel at (x, y), every sample, as JSON: RGBA8 as codes and values, depth as
// float (and the D24 code), stencil as its byte, UINT channels as integers, others as floats.
nlohmann::json pixelValue(const Surface& surface, std::uint32_t x, std::uint32_t y);

// Why a light added nothing at the pixel ("out of range (...)", "behind the surface (...)", ...),
// empty when it added something.
std::string lightTermWhy(const LightTerm& term);
// A LightTerm as probe's JSON: light, factors, diffuse / specular (or "added"), "none": why.
nlohmann::json lightTermJson(const LightTerm& term);

class PixelHistory {
public:
    PixelHistory(std::uint32_t x, std::uint32_t y) : mX(x), mY(y) {}
    // After a pass (or a light's step: `light` >= 0 and `step`), an event per buffer that is new
    // or whose value at the pixel changed since the last event.
    void record(std::string_view pass, const BufferRegistry& registry, long long light = -1, std::string_view step = {});
    // The rasterizer's events at the pixel (Device::setPixelWatch) since the last call, as "draw"
    // events of `pass` (and of `light`'s `step`): draw, primitive, coverage, depth outcome, shader
    // output, the colour and depth-stencil texels before and after, decoded by their formats; the
    // shader's inputs (SV_Position, the varyings by name) and what each light added there or why
    // it added nothing (out of range, outside the cone, behind the surface, disabled). A compute
    // pass's thread that shades the pixel (tiled-deferred) is an event with "compute" instead of a draw.
    void addDrawEvents(std::string_view pass, PixelWatch& watch, long long light = -1, std::string_view step = {});
    // The tiled techniques' view of the pixel from the final buffers: tile, depth range, list, and
    // (sceneLights > 0) how many of the scene's lights the list leaves out ("culled").
    void addTileInfo(const BufferRegistry& registry, std::uint32_t tileSizePx, std::size_t sceneLights = 0);
    std::uint32_t x() const { return mX; }
    std::uint32_t y() const { return mY; }
    const nlohmann::json& events() const { return mEvents; }
    const nlohmann::json& tile() const { return mTile; }
    // The buffers' last recorded values (name -> value): what the history says the frame ends with.
    const nlohmann::json& last() const { return mLast; }
    // The scene's light names by index, for text(): "light 1 'warm left'" (lights past the list,
    // such as GPU Pro 4's VPLs, and unnamed ones keep their index alone).
    void nameLights(std::vector<std::string> names) { mLightNames = std::move(names); }
    const std::vector<std::string>& lightNames() const { return mLightNames; }
    std::string text() const;

private:
    std::uint32_t mX, mY;
    nlohmann::json mEvents = nlohmann::json::array();
    nlohmann::json mLast = nlohmann::json::object();
    nlohmann::json mTile;  // null unless tiled
    std::size_t mWatchTaken = 0;  // watch events already turned into history events
    std::vector<std::string> mLightNames;
};

} // namespace tessera
