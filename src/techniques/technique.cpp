// The technique registry: the built-in techniques (each declares its pass captions in its own
// header and its options in the catalogue) and any a program or test registers; the command line,
// the report and the tests ask it, and never compare technique ids.
#include <tessera/techniques/technique.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include <tessera/buffers/conversion.h>
#include <tessera/errors/input_error.h>
#include <tessera/techniques/deferred.h>
#include <tessera/techniques/deferred_classic.h>
#include <tessera/techniques/light_prepass.h>
#include <tessera/techniques/deferred_cookbook.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/forward_plus.h>
#include <tessera/techniques/forward_plus_amd.h>
#include <tessera/techniques/preview.h>
#include <tessera/techniques/tiled_deferred.h>

namespace tessera {
namespace {

// The built-in rows; each technique's option table and pass captions are declared in its own header.
std::vector<TechniqueInfo> builtinTechniques() {
    std::vector<TechniqueInfo> rows{
        {"preview", "base colour x head light, alpha mask and blend; no light model (inspection view)", "tessera",
         &buildPreview, {}, kPreviewPassCaptions, TexturePolicy::Gltf, true, kOwnHeadLight | kInspectionView, 0},
        {"forward", "forward shading: opaque pass, then transparent pass with alpha blending", "3dgep (van Oosten 2015)",
         &buildForward, kForwardOptions, kForwardPassCaptions, TexturePolicy::AllLinear, true, kComparisonBaseline, 0},
        {"deferred", "G-buffer, per-light stencil light volumes (unmark + shade), transparent forward",
         "3dgep (van Oosten 2015)", &buildDeferred, kDeferredOptions, kDeferredPassCaptions, TexturePolicy::AllLinear, true, kPerLightSteps, 0},
        {"deferred-killzone", "Killzone 2 stencil marking with occlusion-query thresholds", "3dgep (van Oosten 2015)",
         &buildDeferredKillzone, kKillzoneOptions, kKillzonePassCaptions, TexturePolicy::AllLinear, true, kPerLightSteps, 0},
        {"forward-plus", "tiled Forward+: depth pre-pass, grid frustums, light culling, light grid",
         "3dgep (van Oosten 2015)", &buildForwardPlus, kForwardPlusOptions, kForwardPlusPassCaptions, TexturePolicy::AllLinear, true, 0, 16},
        {"forward-plus-amd", "AMD Forward+: 8x8 tiles, two-level light list, 2.5D culling, half-Z, AMD lighting",
         "GPU Pro 4 ch. 5 + AMD ForwardPlus11/TiledLighting11", &buildForwardPlusAmd, kForwardPlusAmdOptions, kForwardPlusAmdPassCaptions,
         TexturePolicy::AllLinear, true, kShadowRaysAndVpls, 8},
        {"tiled-deferred", "Intel tiled deferred shading in one compute dispatch", "Intel 2010 sample (Lauritzen)",
         &buildTiledDeferred, kTiledDeferredOptions, kTiledDeferredPassCaptions, TexturePolicy::AllLinear, true, 0, 16},
        {"deferred-cookbook", "G-buffer with packed specular power, directional quad, tessellated point/spot/capsule volumes",
         "HLSL Development Cookbook ch. 2 (Feinstein 2013)", &buildDeferredCookbook, kDeferredCookbookOptions, kDeferredCookbookPassCaptions,
         TexturePolicy::AllLinear, true, kShadesCapsuleLights, 0},
        {"deferred-classic", "4 x RGBA32F G-buffer, one additive pass per light over a quad, scissored quad or volume",
         "PR&C D3D11 ch. 11 (Zink, Pettineo, Hoxley 2011)", &buildDeferredClassic, kDeferredClassicOptions, kDeferredClassicPassCaptions,
         TexturePolicy::AllLinear, true, kHonoursLightGroups, 0},
        {"light-prepass", "32 B/px G-buffer, lights summed into a light buffer, the geometry drawn again to apply albedos",
         "PR&C D3D11 ch. 11 §11.3 (Zink, Pettineo, Hoxley 2011)", &buildLightPrePass, kLightPrePassOptions, kLightPrePassPassCaptions,
         TexturePolicy::AllLinear, true, kHonoursLightGroups, 0},
    };
    return rows;
}

// Room for this many techniques, reserved once, so that a registration never moves the rows that
// findTechnique's pointers and techniques()'s spans point into.
constexpr std::size_t kMaxTechniques = 64;

std::vector<TechniqueInfo>& registry() {
    static std::vector<TechniqueInfo> rows = [] {
        std::vector<TechniqueInfo> r;
        r.reserve(kMaxTechniques);
        for (const TechniqueInfo& t : builtinTechniques()) r.push_back(t);
        return r;
    }();
    return rows;
}

constexpr std::array<PassCaption, 4> kCommonPasses{{
    {"clear", "Clears the targets the frame writes (the demo's clear colour, depth 1, stencil 0)."},
    {"transparent", "Transparent draws, alpha-blended after the opaque ones and forward-shaded with every light, in "
                    "scene order (3dgep article §2, §3; ERRATA #8: the article says sorted, the demo does not sort)."},
    {"edges", "MSAA: the edge detector (option msaaEdges) sets stencil bit 0x80 on pixels whose samples differ, so that "
              "the light passes shade those per sample and every other pixel once (Intel 2010 sample's stencil mark; "
              "PR&C D3D11 ch. 11 §11.5)."},
    {"resolve", "MSAA: each pixel's samples averaged into the back buffer (ResolveSubresource, in the format's linear "
                "values)."},
}};

} // namespace

const std::span<const PassCaption> kCommonPassCaptions = kCommonPasses;

std::span<const TechniqueInfo> techniques() { return registry(); }

void registerTechnique(const TechniqueInfo& info) {
    if (info.id.empty()) throw std::invalid_argument("registerTechnique: empty technique id");
    if (!info.build) throw std::invalid_argument("registerTechnique: technique '" + std::string(info.id) + "' has no build function");
    if (findTechnique(info.id))
        throw std::invalid_argument("registerTechnique: technique '" + std::string(info.id) + "' is already registered");
    if (registry().size() == kMaxTechniques)
        throw std::invalid_argument("registerTechnique: the registry holds its maximum of " + std::to_string(kMaxTechniques) +
                                    " techniques");
    registry().push_back(info);
}

const TechniqueInfo* findTechnique(std::string_view id) {
    for (const TechniqueInfo& t : registry())
        if (t.id == id) return &t;
    return nullptr;
}

std::span<const OptionInfo> techniqueOptions(std::string_view id) {
    const TechniqueInfo* t = findTechnique(id);
    return t ? t->options : std::span<const OptionInfo>{};
}

const OptionInfo* findOption(std::string_view id, std::string_view key) {
    for (const OptionInfo& o : techniqueOptions(id))
        if (o.key == key) return &o;
    return nullptr;
}

std::string_view passCaption(const TechniqueInfo& info, std::string_view pass) {
    for (const PassCaption& c : info.passes)
        if (c.pass == pass) return c.text;
    for (const PassCaption& c : kCommonPasses)
        if (c.pass == pass) return c.text;
    return {};
}

const TechniqueInfo& requireTechnique(std::string_view id, const std::string& sceneFile) {
    const TechniqueInfo* t = findTechnique(id);
    if (!t) {
        std::string known;
        for (const TechniqueInfo& k : registry()) known += (known.empty() ? "" : ", ") + std::string(k.id);
        throw inputError(sceneFile, "/technique", "unknown technique '" + std::string(id) + "' (known: " + known + ")");
    }
    return *t;
}

Frame buildTechnique(std::string_view id, const TechniqueContext& context, const std::string& sceneFile) {
    const TechniqueInfo* t = &requireTechnique(id, sceneFile);
    if (!t->build) {
        std::string ready;
        for (const TechniqueInfo& k : registry())
            if (k.build) ready += (ready.empty() ? "" : ", ") + std::string(k.id);
        throw inputError(sceneFile, "/technique",
                         "technique '" + std::string(id) + "' is not implemented yet (implemented: " + ready + ")");
    }
    if (context.options.is_object()) {
        for (const auto& [key, value] : context.options.items()) {
            bool known = false;
            for (const OptionInfo& k : t->options) known = known || k.key == key;
            if (!known) throw inputError(sceneFile, "/options/" + key, "technique '" + std::string(id) + "' has no option '" + key + "'");
        }
    }
    checkSampleCount(*t, context.sampleCount, sceneFile);
    checkFrameInputs(context, sceneFile);
    return t->build(context);
}

FrameMemoryEstimate estimateFrameMemory(std::string_view id, const TechniqueContext& context, const std::string& sceneFile) {
    const std::vector<Light>& all = context.lights();
    const std::size_t lights1 = std::min<std::size_t>(all.size(), 32), lights2 = std::min<std::size_t>(all.size(), 64);
    constexpr std::uint32_t kProbeHeight = 64, kProbeWidth1 = 64, kProbeWidth2 = 128;  // px, multiples of every tile size
    std::map<std::string, double> rowSlack;  // buffer name -> one row of it, bytes
    const auto total = [&](std::uint32_t width, std::size_t lightCount) {
        TechniqueContext probe = context;
        const std::vector<Light> prefix(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(lightCount));
        probe.lightsOverride = &prefix;
        if (!(probe.camera.aspect > 0.0f)) probe.camera.aspect = float(context.width) / float(context.height);
        probe.width = width;
        probe.height = kProbeHeight;
        probe.stats = nullptr;
        probe.variantCounts = nullptr;
        probe.afterLightStep = {};
        BufferRegistry registry;
        buildTechnique(id, probe, sceneFile).run(registry);
        // Structured buffers are stored in rows of kMaxSurfaceDimension elements, so a long one
        // grows in whole rows: allow one more row for each (forward-plus's light index lists).
        for (const std::string& name : registry.names()) {
            const Surface& s = *registry.find(name);
            if (s.height() == 1 || s.width() == kMaxSurfaceDimension)
                rowSlack[name] = double(kMaxSurfaceDimension) * s.bytesPerTexel() * s.sampleCount();
        }
        return double(registry.bytes());
    };
    const double p1 = double(kProbeWidth1) * kProbeHeight, p2 = double(kProbeWidth2) * kProbeHeight;
    const double b11 = total(kProbeWidth1, lights1), b21 = total(kProbeWidth2, lights1);
    double b = (b21 - b11) / (p2 - p1), a = b11 - b * p1, c = 0.0, d = 0.0;
    if (lights2 > lights1) {
        const double l1 = double(lights1), l2 = double(lights2);
        const double b12 = total(kProbeWidth1, lights2), b22 = total(kProbeWidth2, lights2);
        d = (b22 - b21 - b12 + b11) / ((p2 - p1) * (l2 - l1));
        b = (b21 - b11) / (p2 - p1) - d * l1;
        c = (b12 - b11) / (l2 - l1) - d * p1;
        a = b11 - b * p1 - c * l1 - d * p1 * l1;
    }
    const double pixels = double(context.width) * double(context.height), lightCount = double(all.size());
    FrameMemoryEstimate e;
    e.bytesPerPixel = std::max(0.0, b + d * lightCount);
    e.fixedBytes = std::max(0.0, a + c * lightCount);
    double slack = 0.0;
    for (const auto& [name, bytes] : rowSlack) slack += bytes;
    e.fixedBytes += slack;
    e.bytes = std::max(b11, e.fixedBytes + e.bytesPerPixel * pixels);
    return e;
}

void checkFrameInputs(const TechniqueContext& context, const std::string& sceneFile) {
    const Camera& c = context.camera;
    const auto number = [](float v) {
        std::ostringstream out;
        out << v;
        return out.str();
    };
    // A normal float: below FLT_MIN the projection's n*f/(f - n) and its inverse lose every bit.
    // An orthographic camera may take exactly 0 (glTF 2.0 §5.13 camera.orthographic.znear ">= 0"):
    // its depth (zView - n) / (f - n) (D3D11 / glm orthoRH_ZO) has no n in a denominator.
    const bool orthographicZero = c.projection == ProjectionKind::Orthographic && c.nearZ == 0.0f;
    if (!orthographicZero && (!(c.nearZ >= std::numeric_limits<float>::min()) || !std::isfinite(c.nearZ)))
        throw inputError(sceneFile, "/camera/near",
                         number(c.nearZ) + " is not a positive normal binary32 number (>= 1.18e-38)" +
                             (c.nearZ == 0.0f ? "; only an orthographic camera may take near 0" : ""));
    if (!(c.farZ > c.nearZ))
        throw inputError(sceneFile, "/camera/far", "far " + number(c.farZ) + " is not greater than near " + number(c.nearZ));
    if (c.projection == ProjectionKind::Perspective && !(c.fovYDeg > 0.0f && c.fovYDeg < 180.0f))
        throw inputError(sceneFile, "/camera/fovYDeg", number(c.fovYDeg) + " is outside (0, 180) degrees");
    if (c.projection == ProjectionKind::Orthographic &&
        !(c.xMag > 0.0f && c.yMag > 0.0f && std::isfinite(c.xMag) && std::isfinite(c.yMag)))
        throw inputError(sceneFile, "/camera", "orthographic magnifications " + number(c.xMag) + ", " + number(c.yMag) +
                                                   " must be positive and finite");
    if (!std::isfinite(c.positionWorld.x) || !std::isfinite(c.positionWorld.y) || !std::isfinite(c.positionWorld.z))
        throw inputError(sceneFile, "/camera/position", "not finite");
    if (context.resources == nullptr) return;
    const std::vector<Light>& lights = context.lights();
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const Light& l = lights[i];
        const std::string which = "light " + std::to_string(i) + (l.name.empty() ? "" : " ('" + l.name + "')");
        // Every technique multiplies colour by intensity in binary32 (3dgep Light.Color * Intensity,
        // AMD and Intel alike); an infinite product turns 0 x inf into NaN in the lighting sums.
        const glm::vec3 radiance = l.color * l.intensity;
        if (!std::isfinite(radiance.x) || !std::isfinite(radiance.y) || !std::isfinite(radiance.z))
            throw inputError(sceneFile, "/lights", which + ": colour x intensity (" + number(l.color.x) + ", " + number(l.color.y) +
                                                       ", " + number(l.color.z) + ") x " + number(l.intensity) +
                                                       " overflows binary32 (each product must stay below 3.4e38)");
        if (l.type != LightType::Directional && !(l.range > 0.0f))
            throw inputError(sceneFile, "/lights", which + ": range " + number(l.range) + " is not positive");
    }
}


std::vector<std::string> withReferenceBuffer(std::vector<std::string> names, Precision precision) {
    if (precision == Precision::Reference) names.emplace(names.begin() + (names.empty() ? 0 : 1), kReferenceBufferName);
    return names;
}

void storeAsUnorm(const Surface& from, Surface& to) {
    for (std::uint32_t y = 0; y < to.height(); ++y)
        for (std::uint32_t x = 0; x < to.width(); ++x)
            for (std::uint32_t s = 0; s < to.sampleCount(); ++s) to.store(x, y, s, convert::clampUnorm(from.load(x, y, s)));
}

// (Appended in place: GCC 12 at -O2 reports a false -Warray-bounds on string + literal here.)
std::string backBufferTarget(std::uint32_t sampleCount) {
    std::string name(kBackBufferName);
    if (sampleCount > 1) name.append(".msaa");
    return name;
}

std::string referenceBufferTarget(std::uint32_t sampleCount) {
    std::string name(kReferenceBufferName);
    if (sampleCount > 1) name.append(".msaa");
    return name;
}

std::vector<std::string> withBackBufferTargets(std::vector<std::string> names, std::uint32_t sampleCount) {
    // backBufferTarget / referenceBufferTarget of each, appended in place.
    if (sampleCount > 1)
        for (std::string& n : names)
            if (n == kBackBufferName || n == kReferenceBufferName) n.append(".msaa");
    return names;
}

Pass resolveBackBufferPass(std::uint32_t sampleCount, Precision precision) {
    const std::vector<std::string> resolved = withReferenceBuffer({std::string(kBackBufferName)}, precision);
    return {"resolve", withBackBufferTargets(resolved, sampleCount), resolved, [sampleCount, precision](BufferRegistry& reg) {
                const Surface& msaa = reg.get(backBufferTarget(sampleCount));
                Surface back = msaa.resolve(msaa.format());
                reg.create(std::string(kBackBufferName), back.desc()) = std::move(back);
                if (precision == Precision::Reference) {
                    Surface ref = reg.get(referenceBufferTarget(sampleCount)).resolve(Format::R32G32B32A32_FLOAT);
                    reg.create(std::string(kReferenceBufferName), ref.desc()) = std::move(ref);
                }
            }};
}

void checkSampleCount(const TechniqueInfo& info, std::uint32_t sampleCount, const std::string& sceneFile) {
    if (sampleCount != 1 && sampleCount != 2 && sampleCount != 4 && sampleCount != 8)
        throw inputError(sceneFile, "/technique", "MSAA sample count " + std::to_string(sampleCount) + " is not 1, 2, 4 or 8");
    if (sampleCount > 1 && !info.msaa) {
        std::string ready;
        for (const TechniqueInfo& k : registry())
            if (k.msaa) ready += (ready.empty() ? "" : ", ") + std::string(k.id);
        throw inputError(sceneFile, "/technique",
                         "technique '" + std::string(info.id) + "' does not render with MSAA yet (MSAA: " + ready + ")");
    }
}

nlohmann::json techniqueRegistryJson(std::string_view only) {
    static constexpr std::string_view kKindNames[] = {"word", "bool", "integer", "integer-or-word", "number"};
    nlohmann::json out = nlohmann::json::array();
    for (const TechniqueInfo& t : techniques()) {
        if (!only.empty() && t.id != only) continue;
        nlohmann::json options = nlohmann::json::array();
        for (const OptionInfo& o : t.options) {
            nlohmann::json values = nlohmann::json::array();
            for (const std::string_view v : o.values) values.push_back(std::string(v));
            nlohmann::json row{{"key", std::string(o.key)}, {"kind", std::string(kKindNames[std::size_t(o.kind)])},
                               {"values", values}, {"faithful", std::string(o.faithful)},
                               {"corrected", std::string(o.corrected)}, {"erratum", o.erratum},
                               {"meaning", std::string(o.meaning)}};
            if (o.minInteger >= 0) {
                row["minInteger"] = o.minInteger;
                if (o.maxInteger < std::numeric_limits<std::int64_t>::max()) row["maxInteger"] = o.maxInteger;
            }
            if (o.kind == OptionInfo::Kind::Number) row["range"] = {o.minNumber, o.maxNumber};
            options.push_back(std::move(row));
        }
        nlohmann::json passes = nlohmann::json::object();
        for (const PassCaption& c : t.passes) passes[std::string(c.pass)] = std::string(c.text);
        out.push_back({{"id", std::string(t.id)}, {"summary", std::string(t.summary)}, {"source", std::string(t.source)},
                       {"ready", t.build != nullptr}, {"msaa", t.msaa}, {"baseline", (t.features & kComparisonBaseline) != 0},
                       {"inspectionView", (t.features & kInspectionView) != 0}, {"tileSize", t.tileSize},
                       {"passes", passes}, {"options", options}});
    }
    return out;
}

} // namespace tessera
