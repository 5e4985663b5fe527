// PixelHistory (inspect/pixel_history.h): snapshots of one pixel through the frame's passes and light steps.
#include <tessera/inspect/pixel_history.h>

#include <bit>
#include <cstring>

#include <tessera/buffers/texel_codec.h>

namespace tessera {

nlohmann::json pixelValue(const Surface& s, std::uint32_t x, std::uint32_t y) {
    const FormatInfo& info = formatInfo(s.format());
    nlohmann::json samples = nlohmann::json::array();
    for (std::uint32_t i = 0; i < s.sampleCount(); ++i) {
        nlohmann::json v;
        if (info.hasDepth) {
            v["depth"] = s.loadDepth(x, y, i);
            if (s.format() == Format::D24_UNORM_S8_UINT) {
                std::uint32_t bits = 0;
                std::memcpy(&bits, s.texel(x, y, i), 4);
                v["d24"] = bits & 0xFFFFFFu;
            }
            if (info.hasStencil) v["stencil"] = s.loadStencil(x, y, i);
        } else if (info.kind == FormatKind::Uint) {
            const glm::uvec4 u = decodeTexelUint(s.format(), s.texel(x, y, i));
            v = nlohmann::json::array();
            for (std::uint32_t c = 0; c < info.channels; ++c) v.push_back(u[int(c)]);
        } else {
            const glm::vec4 f = s.load(x, y, i);
            nlohmann::json values = nlohmann::json::array();
            for (std::uint32_t c = 0; c < info.channels; ++c) values.push_back(f[int(c)]);
            if (s.format() == Format::R8G8B8A8_UNORM || s.format() == Format::R8G8B8A8_UNORM_SRGB) {
                nlohmann::json codes = nlohmann::json::array();
                for (int c = 0; c < 4; ++c) codes.push_back(std::to_integer<int>(s.texel(x, y, i)[c]));
                v = {{"codes", codes}, {"values", values}};
            } else {
                v = values;
            }
        }
        samples.push_back(v);
    }
    return samples.size() == 1 ? samples[0] : samples;
}

void PixelHistory::record(std::string_view pass, const BufferRegistry& registry, long long light, std::string_view step) {
    for (const std::string& name : registry.names()) {
        const Surface& s = *registry.find(name);
        if (mX >= s.width() || mY >= s.height()) continue;  // per-tile and other small buffers
        const nlohmann::json value = pixelValue(s, mX, mY);
        const bool known = mLast.contains(name);
        if (known && mLast[name] == value) continue;
        nlohmann::json e{{"pass", pass}, {"buffer", name}, {"after", value}};
        if (known) e["before"] = mLast[name];
        if (light >= 0) {
            e["light"] = light;
            e["step"] = step;
        }
        mEvents.push_back(e);
        mLast[name] = value;
    }
}

namespace {
// One texel's bytes decoded as pixelValue decodes a buffer's (a 1x1 surface of that format).
nlohmann::json texelValue(Format format, const std::byte* bytes) {
    if (format == Format::Unknown) return nullptr;
    Surface one({1, 1, format, 1});
    std::memcpy(one.texel(0, 0), bytes, formatInfo(format).bytesPerTexel);
    return pixelValue(one, 0, 0);
}
} // namespace

void PixelHistory::addDrawEvents(std::string_view pass, PixelWatch& watch, long long light, std::string_view step) {
    for (; mWatchTaken < watch.events.size(); ++mWatchTaken) {
        const PixelDrawEvent& d = watch.events[mWatchTaken];
        nlohmann::json e{{"pass", pass},
                         {"draw", d.draw},
                         {"primitive", d.primitive},
                         {"face", d.frontFacing ? "front" : "back"},
                         {"coverage", d.coverage},
                         {"z", d.z},
                         {"passed", d.passed},
                         {"shaded", d.shaded},
                         {"discarded", d.discarded}};
        if (d.shaded) e["output"] = {d.output.x, d.output.y, d.output.z, d.output.w};
        if (d.colorFormat != Format::Unknown)
            e["color"] = {{"before", texelValue(d.colorFormat, d.colorBefore.data())}, {"after", texelValue(d.colorFormat, d.colorAfter.data())}};
        if (d.depthFormat != Format::Unknown)
            e["depthStencil"] = {{"before", texelValue(d.depthFormat, d.depthBefore.data())},
                                 {"after", texelValue(d.depthFormat, d.depthAfter.data())}};
        if (light >= 0) {
            e["light"] = light;
            e["step"] = step;
        }
        mEvents.push_back(e);
    }
}

void PixelHistory::addTileInfo(const BufferRegistry& registry, std::uint32_t tileSizePx) {
    // forward-plus / forward-plus-amd: lightgrid.opaque + lightindex.opaque; tiled-deferred:
    // tiles.grid + tiles.lightIndices. (offset, count) per tile; element e of a list at (e % W, e / W).
    const Surface* grid = registry.find("lightgrid.opaque");
    const Surface* list = registry.find("lightindex.opaque");
    if (!grid) {
        grid = registry.find("tiles.grid");
        list = registry.find("tiles.lightIndices");
    }
    if (!grid || !list || tileSizePx == 0) return;
    const std::uint32_t tx = mX / tileSizePx, ty = mY / tileSizePx;
    if (tx >= grid->width() || ty >= grid->height()) return;
    const glm::uvec4 cell = decodeTexelUint(grid->format(), grid->texel(tx, ty));
    nlohmann::json lights = nlohmann::json::array();
    const std::uint64_t elements = std::uint64_t(list->width()) * list->height();
    for (std::uint32_t k = 0; k < cell.y; ++k) {
        const std::uint64_t e = std::uint64_t(cell.x) + k;
        if (e >= elements) break;  // an overflowed list (lightLists demo): the count says more than is stored
        lights.push_back(decodeTexelUint(list->format(), list->texel(std::uint32_t(e % list->width()), std::uint32_t(e / list->width())))[0]);
    }
    mTile = {{"tile", {tx, ty}}, {"tileSizePx", tileSizePx}, {"listOffset", cell.x}, {"listCount", cell.y}, {"lights", lights}};
    if (const Surface* range = registry.find("tiles.depthRange"); range && tx < range->width() && ty < range->height()) {
        const glm::uvec4 bits = decodeTexelUint(range->format(), range->texel(tx, ty));
        mTile["depthRange"] = {std::bit_cast<float>(bits.x), std::bit_cast<float>(bits.y)};
    }
    if (const Surface* frustums = registry.find("frustums"); frustums && 4 * tx + 3 < frustums->width() && ty < frustums->height()) {
        nlohmann::json planes = nlohmann::json::array();
        for (std::uint32_t i = 0; i < 4; ++i) {
            const glm::vec4 p = frustums->load(4 * tx + i, ty);
            planes.push_back({p.x, p.y, p.z, p.w});
        }
        mTile["frustumPlanes"] = planes;  // (N.x, N.y, N.z, d), view space: left, right, top, bottom
    }
}

std::string PixelHistory::text() const {
    std::string out = "pixel (" + std::to_string(mX) + ", " + std::to_string(mY) + ")\n";
    for (const auto& e : mEvents) {
        std::string where = e["pass"].get<std::string>();
        if (e.contains("light")) where += " light " + std::to_string(e["light"].get<long long>()) + " " + e["step"].get<std::string>();
        if (e.contains("draw")) {  // a rasterizer event
            out += "  " + where + ": draw " + std::to_string(e["draw"].get<std::uint64_t>()) + " primitive " +
                   std::to_string(e["primitive"].get<std::uint32_t>()) + " (" + e["face"].get<std::string>() + "), coverage " +
                   std::to_string(e["coverage"].get<std::uint32_t>()) + ", z " + e["z"].dump() + ", " +
                   (e["passed"].get<std::uint32_t>() ? "passed" : "failed") + (e["shaded"].get<bool>() ? ", shaded" : "") +
                   (e["discarded"].get<bool>() ? ", discarded" : "") + "\n";
            if (e.contains("output")) out += "      shader output " + e["output"].dump() + "\n";
            if (e.contains("depthStencil"))
                out += "      depth/stencil " + e["depthStencil"]["before"].dump() + " -> " + e["depthStencil"]["after"].dump() + "\n";
            if (e.contains("color")) out += "      colour " + e["color"]["before"].dump() + " -> " + e["color"]["after"].dump() + "\n";
            continue;
        }
        out += "  " + where + ": " + e["buffer"].get<std::string>() + " " +
               (e.contains("before") ? e["before"].dump() + " -> " : std::string("= ")) + e["after"].dump() + "\n";
    }
    if (!mTile.is_null()) out += "tile     " + mTile.dump() + "\n";
    return out;
}

} // namespace tessera
