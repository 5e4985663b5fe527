// The option catalogue (techniques/option_catalog.h) against the parsers: for every implemented
// technique the catalogue lists exactly the keys the technique accepts, every value it lists
// (and the faithful default and the correction) builds, and values it does not list are rejected
// by both the catalogue and the technique, naming /options/KEY.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <set>
#include <span>
#include <string>
#include <vector>

#include <tessera/errors/input_error.h>
#include <tessera/techniques/option_catalog.h>
#include <tessera/techniques/technique.h>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_option_catalog_test {

using namespace tessera;

namespace {

// One triangle lit by a shadow-casting point light and an indirect spot light, so that every
// option value of forward-plus-amd's shadows and VPLs (including "on") has something to act on.
Scene catalogueScene() {
    Scene scene = test::oneTriangle(-2.0f);
    Light point = test::makeLight(LightType::Point, {0.0f, 0.0f, -1.0f}, {0, 0, -1}, 5.0f, glm::vec3(1.0f));
    point.castsShadows = true;
    Light spot = test::makeLight(LightType::Spot, {0.0f, 0.0f, 0.0f}, {0, 0, -1}, 5.0f, glm::vec3(1.0f));
    spot.indirect = true;
    scene.lights = {point, spot};
    return scene;
}

// A 16x16 px frame of catalogueScene() on `device` with these options.
TechniqueContext catalogueContext(Device& device, const nlohmann::json& options) {
    static const Scene scene = catalogueScene();
    static const SceneResources resources(scene);
    TechniqueContext ctx;
    ctx.device = &device;
    ctx.resources = &resources;
    ctx.width = 16;
    ctx.height = 16;
    ctx.options = options;
    ctx.sceneFile = "memory.json";
    return ctx;
}

// "" when the technique builds and renders with these options, else the InputError's text.
std::string buildError(std::string_view technique, const nlohmann::json& options) {
    Device device(DeviceConfig{64, 1});
    const TechniqueContext ctx = catalogueContext(device, options);
    try {
        BufferRegistry registry;
        buildTechnique(technique, ctx, ctx.sceneFile).run(registry);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// The JSON values an option's catalogue entry says are valid.
std::vector<nlohmann::json> listedValues(const OptionInfo& o) {
    std::vector<nlohmann::json> values;
    for (const std::string_view v : o.values) {
        if (o.kind == OptionInfo::Kind::Bool) values.push_back(v == "true");
        else if (o.kind == OptionInfo::Kind::Integer) values.push_back(std::stoll(std::string(v)));
        else values.push_back(std::string(v));
    }
    if (o.kind == OptionInfo::Kind::Number) {  // both ends of the closed range and its middle
        values.push_back(o.minNumber);
        values.push_back(o.maxNumber);
        values.push_back(0.5 * (o.minNumber + o.maxNumber));
    }
    if (o.minInteger >= 0) {
        values.push_back(o.minInteger);
        values.push_back(o.minInteger + 7);
        if (o.maxInteger < std::numeric_limits<std::int64_t>::max() && o.maxInteger <= 128) values.push_back(o.maxInteger);
    }
    return values;
}

// The default options, then each listed value of each option alone: the option sets the registry
// tests build frames for.
std::vector<nlohmann::json> optionSets(const TechniqueInfo& t) {
    std::vector<nlohmann::json> sets{nlohmann::json::object()};
    for (const OptionInfo& o : t.options)
        for (const nlohmann::json& value : listedValues(o)) sets.push_back({{std::string(o.key), value}});
    return sets;
}

// catalogueContext with a sample count and precision.
TechniqueContext frameContext(Device& device, const nlohmann::json& options, std::uint32_t samples, Precision precision) {
    TechniqueContext ctx = catalogueContext(device, options);
    ctx.sampleCount = samples;
    ctx.precision = precision;
    return ctx;
}

} // namespace

TEST_CASE("option catalogue: every implemented technique's keys, values, defaults and corrections build") {
    int techniquesChecked = 0, valuesChecked = 0;
    for (const TechniqueInfo& t : techniques()) {
        if (!t.build) continue;
        ++techniquesChecked;
        CAPTURE(t.id);
        // The registry's options are the technique's table (declared in its header), each key once.
        std::set<std::string> catalogued;
        for (const OptionInfo& o : techniqueOptions(t.id)) CHECK(catalogued.insert(std::string(o.key)).second);
        CHECK(techniqueOptions(t.id).data() == t.options.data());
        CHECK(buildError(t.id, {{"noSuchOption", 1}}).find("/options/noSuchOption") != std::string::npos);
        for (const OptionInfo& o : techniqueOptions(t.id)) {
            CAPTURE(o.key);
            CHECK(!o.meaning.empty());
            CHECK(!o.faithful.empty());
            for (const nlohmann::json& value : listedValues(o)) {
                CAPTURE(value.dump());
                CHECK(!optionValueProblem(o, value));
                CHECK(buildError(t.id, {{std::string(o.key), value}}) == "");
                ++valuesChecked;
            }
            // The faithful default (its first word) and the correction are listed values.
            const std::string faithful(o.faithful.substr(0, o.faithful.find(' ')));
            const auto asJson = [&](const std::string& text) -> nlohmann::json {
                if (o.kind == OptionInfo::Kind::Bool) return text == "true";
                if (o.kind == OptionInfo::Kind::Number) return std::stod(text);
                if (o.kind != OptionInfo::Kind::Word && text.find_first_not_of("0123456789") == std::string::npos)
                    return std::stoll(text);
                return text;
            };
            CHECK(!optionValueProblem(o, asJson(faithful)));
            if (!o.corrected.empty()) CHECK(!optionValueProblem(o, asJson(std::string(o.corrected))));
            // Values outside the list: rejected by the catalogue and by the technique, which names the key.
            // The technique's OptionReader checks only the keys it reads, so this also shows that every
            // key in the table is read (a key declared and never read would build without an error).
            std::vector<nlohmann::json> wrong = {"no-such-value", -3, nlohmann::json::array()};
            if (o.minInteger >= 0 && o.maxInteger < std::numeric_limits<std::int64_t>::max()) wrong.push_back(o.maxInteger + 1);
            for (const nlohmann::json& value : wrong) {
                CAPTURE(value.dump());
                CHECK(optionValueProblem(o, value));
                CHECK(buildError(t.id, {{std::string(o.key), value}}).find("/options/" + std::string(o.key)) != std::string::npos);
            }
        }
    }
    CHECK(techniquesChecked == 10);  // preview (no options) and the nine techniques with options
    CHECK(valuesChecked >= 90);      // 94 listed values today: the loop really ran over them
}

TEST_CASE("option catalogue: value text and problems name the accepted values") {
    const OptionInfo* cone = findOption("forward-plus", "coneTest");
    REQUIRE(cone);
    CHECK(optionValuesText(*cone) == "demo | corrected");
    CHECK(cone->erratum == 10);
    CHECK(*optionValueProblem(*cone, "x") == "\"x\" is not one of demo | corrected");
    const OptionInfo* capacity = findOption("tiled-deferred", "tileListCapacity");
    REQUIRE(capacity);
    // 1..2^32 - 2: 2^32 - 1 is the technique's "unbounded" sentinel.
    CHECK(optionValuesText(*capacity) == "integer in 1..4294967294 | unbounded");
    CHECK(!optionValueProblem(*capacity, 4294967294LL));
    CHECK(optionValueProblem(*capacity, 4294967295LL));
    CHECK(!optionValueProblem(*capacity, 1));
    CHECK(optionValueProblem(*capacity, 0));
    CHECK(!findOption("forward", "coneTest"));
    CHECK(techniqueOptions("preview").empty());
}

// Every pass a technique's frames can hold has a caption in the registry (TechniqueInfo::passes or
// the shared ones): the report and the inspector show it, and a missing one would silently be "".
// Frames are only built, not run, for the default options, each listed value of each option, 1
// and 4 samples, and precision exact and reference.
TEST_CASE("technique registry: every pass of every option value, sample count and precision has a caption") {
    std::set<std::string> seen;  // "technique/pass"
    for (const TechniqueInfo& t : techniques()) {
        if (!t.build) continue;
        for (const nlohmann::json& options : optionSets(t))
            for (const std::uint32_t samples : {1u, 4u})
                for (const Precision precision : {Precision::Exact, Precision::Reference}) {
                    if (samples > 1 && !t.msaa) continue;
                    Device device(DeviceConfig{64, 1});
                    const TechniqueContext ctx = frameContext(device, options, samples, precision);
                    Frame frame;
                    try {
                        frame = buildTechnique(t.id, ctx, ctx.sceneFile);
                    } catch (const InputError&) {
                        continue;  // a refused combination (e.g. an option that needs one sample) has no passes
                    }
                    for (const Pass& pass : frame.passes()) {
                        CAPTURE(t.id);
                        CAPTURE(pass.name);
                        CAPTURE(options.dump());
                        CHECK(!passCaption(t, pass.name).empty());
                        seen.insert(std::string(t.id) + "/" + pass.name);
                    }
                }
        // No caption for a pass that no frame holds (a renamed pass leaves none behind).
        for (const PassCaption& c : t.passes) {
            CAPTURE(c.pass);
            CHECK(seen.count(std::string(t.id) + "/" + std::string(c.pass)) == 1);
        }
    }
    // The loop reached the passes that only some option sets, sample counts or precisions add.
    for (const char* pass : {"forward/resolve", "deferred/edges", "deferred/compose", "deferred/present",
                             "forward-plus-amd/shadow-rays", "forward-plus-amd/indirect", "light-prepass/final"}) {
        CAPTURE(pass);
        CHECK(seen.count(pass) == 1);
    }
}

// The buffer audit (frame/frame.h auditBuffers) of every frame a technique can build: for the
// default options, each listed value of each option, 1 and 4 samples, and every precision, a
// 16x16 frame of catalogueScene() registers only buffers that a later pass reads, the image, or
// buffers its writer declares for inspection (none of which a later pass reads); a single-sample
// frame holds no multisampled buffer; skipping the inspection-only passes changes no other buffer;
// and fast changes no buffer, reference only widens formats or adds buffers that a later pass
// reads. Frame::run itself refuses an undeclared buffer.
TEST_CASE("technique registry: every buffer of every option value, sample count and precision is read later, the image, or for inspection") {
    const std::array<std::string_view, 2> images{kBackBufferName, kReferenceBufferName};
    std::size_t framesRun = 0, inspectionSeen = 0, widenedAtReference = 0, skippedPasses = 0;
    for (const TechniqueInfo& t : techniques()) {
        if (!t.build) continue;
        for (const nlohmann::json& options : optionSets(t))
            for (const std::uint32_t samples : {1u, 4u}) {
                if (samples > 1 && !t.msaa) continue;
                std::map<std::string, SurfaceDesc> exactBuffers;
                for (const Precision precision : {Precision::Exact, Precision::Fast, Precision::Reference}) {
                    CAPTURE(t.id);
                    CAPTURE(options.dump());
                    CAPTURE(samples);
                    CAPTURE(precisionName(precision));
                    Device device(DeviceConfig{64, 1});
                    const TechniqueContext ctx = frameContext(device, options, samples, precision);
                    Frame frame;
                    BufferRegistry registry;
                    try {
                        frame = buildTechnique(t.id, ctx, ctx.sceneFile);
                        frame.run(registry);
                    } catch (const InputError&) {
                        continue;  // a refused combination (e.g. an option that needs one sample)
                    }
                    ++framesRun;
                    std::map<std::string, SurfaceDesc> buffers;
                    for (const BufferUse& u : auditBuffers(frame, registry, images)) {
                        CAPTURE(u.name);
                        CHECK(u.role != BufferUse::Role::Unread);
                        inspectionSeen += u.role == BufferUse::Role::Inspection;
                        buffers[u.name] = registry.get(u.name).desc();
                        if (samples == 1) CHECK(buffers[u.name].sampleCount == 1);
                    }
                    for (const Pass& pass : frame.passes())
                        for (const std::string& name : pass.inspection) {
                            CAPTURE(name);
                            CHECK(std::find_if(frame.passes().begin(), frame.passes().end(), [&](const Pass& later) {
                                      return &later > &pass && std::find(later.reads.begin(), later.reads.end(), name) != later.reads.end();
                                  }) == frame.passes().end());
                        }
                    if (precision == Precision::Exact) {
                        exactBuffers = buffers;
                        // Without inspection the inspection-only passes are skipped: their buffers
                        // are missing and every other buffer holds the same bytes (such a pass has
                        // no other effect, as Pass::inspectionOnly promises).
                        Device lean(DeviceConfig{64, 1});
                        const TechniqueContext leanCtx = frameContext(lean, options, samples, precision);
                        const Frame leanFrame = buildTechnique(t.id, leanCtx, leanCtx.sceneFile);
                        BufferRegistry leanRegistry;
                        leanFrame.run(leanRegistry, {}, false);
                        for (const Pass& pass : leanFrame.passes()) {
                            skippedPasses += pass.inspectionOnly();
                            if (pass.inspectionOnly())
                                for (const std::string& name : pass.writes) {
                                    CAPTURE(name);
                                    CHECK_FALSE(leanRegistry.contains(name));
                                }
                        }
                        for (const std::string& name : leanRegistry.names()) {
                            CAPTURE(name);
                            const std::span<const std::byte> all = registry.get(name).bytes(), without = leanRegistry.get(name).bytes();
                            CHECK(std::equal(all.begin(), all.end(), without.begin(), without.end()));
                        }
                        continue;
                    }
                    // "name: exact's -> this precision's" for each buffer that differs.
                    const auto text = [](const SurfaceDesc& d) {
                        return std::to_string(d.width) + "x" + std::to_string(d.height) + " " + std::string(formatInfo(d.format).name) +
                               " x" + std::to_string(d.sampleCount);
                    };
                    const auto same = [](const SurfaceDesc& a, const SurfaceDesc& b) {
                        return a.width == b.width && a.height == b.height && a.format == b.format && a.sampleCount == b.sampleCount;
                    };
                    std::string changed;
                    for (const auto& [name, d] : exactBuffers) {
                        const auto it = buffers.find(name);
                        if (it == buffers.end()) changed += name + ": " + text(d) + " -> none; ";
                        else if (precision == Precision::Fast ? !same(it->second, d)
                                                              : it->second.width != d.width || it->second.height != d.height ||
                                                                    it->second.sampleCount != d.sampleCount ||
                                                                    formatInfo(it->second.format).bytesPerTexel < formatInfo(d.format).bytesPerTexel)
                            changed += name + ": " + text(d) + " -> " + text(it->second) + "; ";
                        else widenedAtReference += !same(it->second, d);
                    }
                    if (precision == Precision::Fast)
                        for (const auto& [name, d] : buffers)
                            if (!exactBuffers.contains(name)) changed += name + ": none -> " + text(d) + "; ";
                    // fast changes arithmetic only; reference may widen a format (float G-buffer and
                    // depth: the truth without storage rounding) or add a buffer a later pass reads
                    // (checked above), never narrow or drop one.
                    CHECK(changed == "");
                }
            }
    }
    CHECK(framesRun > 300);
    CHECK(inspectionSeen > 0);
    CHECK(widenedAtReference > 0);
    CHECK(skippedPasses > 0);  // forward-plus's heatmap, forward-plus-amd's indirect
}

// The faithful choices the render note and the report's "why" column name: forward's two erratum
// options at their defaults (table order), one fewer when the run corrects it; forward-plus-amd's
// projection, whose default follows its shading, never.
TEST_CASE("option catalogue: faithful choices are the erratum options a run leaves at their faithful value") {
    const auto keys = [](std::string_view id, const nlohmann::json& options) {
        std::vector<std::string> out;
        for (const FaithfulChoice& c : faithfulChoices(techniqueOptions(id), options))
            out.push_back(std::string(c.option->key) + "=" + c.value);
        return out;
    };
    CHECK(keys("forward", nlohmann::json::object()) == std::vector<std::string>{"projection=demo-gl", "alphaTest=false"});
    CHECK(keys("forward", {{"alphaTest", true}}) == std::vector<std::string>{"projection=demo-gl"});
    CHECK(keys("forward", {{"alphaTest", false}, {"projection", "d3d"}}) == std::vector<std::string>{"alphaTest=false"});
    for (const std::string& k : keys("forward-plus-amd", nlohmann::json::object())) CHECK(k.rfind("projection=", 0) != 0);
    CHECK(keys("preview", nlohmann::json::object()).empty());
}

} // namespace tessera_test::techniques_option_catalog_test
