// PixelHistory (inspect/pixel_history.h): snapshots of one pixel through the frame's passes and light steps.
#include <tessera/inspect/pixel_history.h>

#include <bit>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <set>

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
const char* outcomeName(PixelDrawEvent::Outcome o) {
    switch (o) {
    case PixelDrawEvent::Outcome::StencilFail: return "stencil fail";
    case PixelDrawEvent::Outcome::DepthFail: return "depth fail";
    case PixelDrawEvent::Outcome::Pass: return "pass";
    case PixelDrawEvent::Outcome::NotTested: break;
    }
    return "not tested";
}

// D3D11_STENCIL_OP names.
const char* stencilOpName(StencilOp op) {
    switch (op) {
    case StencilOp::Keep: return "KEEP";
    case StencilOp::Zero: return "ZERO";
    case StencilOp::Replace: return "REPLACE";
    case StencilOp::IncrSat: return "INCR_SAT";
    case StencilOp::DecrSat: return "DECR_SAT";
    case StencilOp::Invert: return "INVERT";
    case StencilOp::Incr: return "INCR";
    case StencilOp::Decr: return "DECR";
    }
    return "?";
}

nlohmann::json vec(const glm::vec4& v, int n) {
    nlohmann::json a = nlohmann::json::array();
    for (int c = 0; c < n; ++c) a.push_back(v[c]);
    return a;
}

// SV_Position, SV_SampleIndex and the varyings by name (v0, v1, ... when the type names none), in
// declaration order: [{"name", "value"}, ...].
nlohmann::json shaderInputs(const PixelDrawEvent& d) {
    nlohmann::json in = nlohmann::json::array();
    const auto add = [&in](std::string name, nlohmann::json value) {
        in.push_back({{"name", std::move(name)}, {"value", std::move(value)}});
    };
    add("SV_Position", vec(d.posWindow, 4));
    if (!d.compute) add("SV_SampleIndex", d.sampleIndex);
    std::uint32_t at = 0;
    for (const VaryingField& field : d.inputFields) {
        nlohmann::json values = nlohmann::json::array();
        for (std::uint32_t k = 0; k < field.floats && at < d.inputCount; ++k) values.push_back(d.inputs[at++]);
        add(field.name, values.size() == 1 ? values[0] : values);
    }
    for (; at < d.inputCount; ++at) {
        std::string name = std::to_string(at);
        name.insert(name.begin(), 'v');  // not "v" + to_string: GCC 12's -Wrestrict misfires on it
        add(std::move(name), d.inputs[at]);
    }
    return in;
}
} // namespace

std::string lightTermWhy(const LightTerm& t) {
    switch (t.skip) {
    case LightTerm::Skip::Disabled: return "disabled";
    case LightTerm::Skip::OutOfRange: return "out of range (distance " + nlohmann::json(t.distance).dump() + " >= range " +
                                             nlohmann::json(t.range).dump() + ")";
    case LightTerm::Skip::OutsideCone: return "outside the cone";
    case LightTerm::Skip::None: break;
    }
    if (t.diffuse != glm::vec4(0.0f) || t.specular != glm::vec4(0.0f)) return {};
    if (t.falloff == 0.0f) return "at the end of its falloff (attenuation 0 at distance " + nlohmann::json(t.distance).dump() + ")";
    if (t.cone == 0.0f) return "outside the cone (cone factor 0)";
    if (!(t.nDotL > 0.0f)) return "behind the surface (N.L = " + nlohmann::json(t.nDotL).dump() + " <= 0)";
    return "adds 0 (zero colour or intensity)";
}

nlohmann::json lightTermJson(const LightTerm& t) {
    nlohmann::json j{{"light", t.light}, {"nDotL", t.nDotL}, {"falloff", t.falloff}, {"cone", t.cone}};
    if (t.light == kAmbientLightTerm) j["light"] = "ambient";
    if (t.distance != 0.0f || t.range != std::numeric_limits<float>::infinity()) {
        j["distance"] = t.distance;
        if (t.range != std::numeric_limits<float>::infinity()) j["range"] = t.range;
    }
    if (t.combined) {
        j["added"] = vec(t.diffuse, 3);
    } else {
        j["diffuse"] = vec(t.diffuse, 4);
        j["specular"] = vec(t.specular, 4);
    }
    if (const std::string why = lightTermWhy(t); !why.empty()) j["none"] = why;
    return j;
}

void PixelHistory::addDrawEvents(std::string_view pass, PixelWatch& watch, long long light, std::string_view step) {
    for (; mWatchTaken < watch.events.size(); ++mWatchTaken) {
        const PixelDrawEvent& d = watch.events[mWatchTaken];
        nlohmann::json e{{"pass", pass}, {"shaded", d.shaded}, {"discarded", d.discarded}};
        if (d.compute) {
            e["compute"] = true;
        } else {
            e["draw"] = d.draw;
            e["primitive"] = d.primitive;
            e["face"] = d.frontFacing ? "front" : "back";
            e["coverage"] = d.coverage;
            e["z"] = d.z;
            e["passed"] = d.passed;
            if (d.outcome != PixelDrawEvent::Outcome::NotTested) e["test"] = outcomeName(d.outcome);
            if (d.stencilTested) e["stencil"] = {{"op", stencilOpName(d.stencilOp)}, {"ref", d.stencilRef}};
        }
        if (d.shaded) {
            e["inputs"] = shaderInputs(d);
            e["output"] = {d.output.x, d.output.y, d.output.z, d.output.w};
        }
        if (d.surface.recorded) {  // the material the light terms multiply (textures sampled)
            const auto v4 = [](const glm::dvec4& c) { return nlohmann::json{c.x, c.y, c.z, c.w}; };
            e["surface"] = {{"diffuse", v4(d.surface.diffuse)},   {"alpha", d.surface.alpha},
                            {"ambient", v4(d.surface.ambient)},   {"emissive", v4(d.surface.emissive)},
                            {"specular", v4(d.surface.specular)}, {"specularPower", d.surface.specularPower}};
        }
        if (!d.lights.empty()) {
            nlohmann::json lights = nlohmann::json::array();
            for (const LightTerm& term : d.lights) lights.push_back(lightTermJson(term));
            e["lights"] = lights;
        }
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

void PixelHistory::addTileInfo(const BufferRegistry& registry, std::uint32_t tileSizePx, std::size_t sceneLights) {
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
    if (sceneLights > 0) {
        std::set<std::uint32_t> listed;
        for (const auto& l : lights) listed.insert(l.get<std::uint32_t>());
        mTile["culled"] = sceneLights > listed.size() ? sceneLights - listed.size() : 0;
    }
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

namespace {

// A value for the text listing: every float rounded to kTextDigits significant digits (the
// --json output keeps them all), so that a term reads 0.170333, not 0.17033250629901886.
constexpr int kTextDigits = 6;  // significant decimal digits of a float in probe's text
nlohmann::json rounded(const nlohmann::json& value) {
    if (value.is_number_float()) {
        char text[32];
        std::snprintf(text, sizeof text, "%.*g", kTextDigits, value.get<double>());
        return std::strtod(text, nullptr);
    }
    if (!value.is_structured()) return value;
    nlohmann::json copy = value;
    for (auto& item : copy.items()) item.value() = rounded(item.value());
    return copy;
}
std::string readable(const nlohmann::json& value) { return rounded(value).dump(); }

} // namespace

std::string PixelHistory::text() const {
    const auto lightLabel = [this](const nlohmann::json& light) {
        if (light.is_string()) return "light " + light.get<std::string>();  // "ambient"
        const long long index = light.get<long long>();
        std::string label = "light " + std::to_string(index);
        if (index >= 0 && std::size_t(index) < mLightNames.size() && !mLightNames[std::size_t(index)].empty())
            label += " '" + mLightNames[std::size_t(index)] + "'";
        return label;
    };
    std::string out = "pixel (" + std::to_string(mX) + ", " + std::to_string(mY) + ")\n";
    for (const auto& e : mEvents) {
        std::string where = e["pass"].get<std::string>();
        if (e.contains("light")) where += " " + lightLabel(e["light"]) + " " + e["step"].get<std::string>();
        if (e.contains("compute")) {  // a compute pass's thread for the pixel
            out += "  " + where + ": compute thread shades the pixel\n";
        } else if (e.contains("draw")) {  // a rasterizer event
            out += "  " + where + ": draw " + std::to_string(e["draw"].get<std::uint64_t>()) + " primitive " +
                   std::to_string(e["primitive"].get<std::uint32_t>()) + " (" + e["face"].get<std::string>() + "), coverage " +
                   std::to_string(e["coverage"].get<std::uint32_t>()) + ", z " + readable(e["z"]) + ", " +
                   (e["passed"].get<std::uint32_t>() ? "passed" : "failed") +
                   (e.contains("test") ? " (" + e["test"].get<std::string>() + ")" : std::string()) +
                   (e.contains("stencil") ? ", stencil op " + e["stencil"]["op"].get<std::string>() + " ref " +
                                                std::to_string(e["stencil"]["ref"].get<int>())
                                          : std::string()) +
                   (e["shaded"].get<bool>() ? ", shaded" : "") + (e["discarded"].get<bool>() ? ", discarded" : "") + "\n";
        }
        if (e.contains("draw") || e.contains("compute")) {
            if (e.contains("inputs"))
                for (const auto& input : e["inputs"])
                    out += "      in  " + input["name"].get<std::string>() + " " + readable(input["value"]) + "\n";
            if (e.contains("surface")) {
                const auto& m = e["surface"];
                out += "      material diffuse " + readable(m["diffuse"]) + " (textures sampled), alpha " + readable(m["alpha"]) +
                       ", ambient " + readable(m["ambient"]) + ", emissive " + readable(m["emissive"]) + ", specular " +
                       readable(m["specular"]) + " power " + readable(m["specularPower"]) + "\n";
            }
            if (e.contains("lights"))
                for (const auto& l : e["lights"]) {
                    out += "      " + lightLabel(l["light"]) + ": ";
                    if (l.contains("none")) {
                        out += "none, " + l["none"].get<std::string>() + "\n";
                        continue;
                    }
                    out += l.contains("added") ? "added " + readable(l["added"]) : "diffuse " + readable(l["diffuse"]) + " specular " + readable(l["specular"]);
                    out += " (N.L " + readable(l["nDotL"]) + ", falloff " + readable(l["falloff"]) + ", cone " + readable(l["cone"]) + ")\n";
                }
            if (e.contains("output")) out += "      shader output " + readable(e["output"]) + "\n";
            if (e.contains("depthStencil"))
                out += "      depth/stencil " + readable(e["depthStencil"]["before"]) + " -> " + readable(e["depthStencil"]["after"]) + "\n";
            if (e.contains("color")) out += "      colour " + readable(e["color"]["before"]) + " -> " + readable(e["color"]["after"]) + "\n";
            continue;
        }
        out += "  " + where + ": " + e["buffer"].get<std::string>() + " " +
               (e.contains("before") ? readable(e["before"]) + " -> " : std::string("= ")) + readable(e["after"]) + "\n";
    }
    if (!mTile.is_null()) {
        out += "tile     " + readable(mTile) + "\n";
        if (mTile.contains("culled"))
            out += "         " + std::to_string(mTile["culled"].get<std::size_t>()) +
                   " of the scene's lights are not in this tile's list (culled): the shader never reads them\n";
    }
    return out;
}

} // namespace tessera
