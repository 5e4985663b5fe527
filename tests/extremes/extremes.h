// The extremes catalogue's harness: renders one extreme scene with every technique and checks
// the properties every case shares (no NaN or Inf in a stored float buffer, the same bytes at 1
// and 3 threads, culling and the stencil trick conservative: their corrected forms equal
// forward's bits), and records the exact precision's error against `reference`.
#pragma once

#include <doctest/doctest.h>

#include <filesystem>
#include <optional>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <tessera/buffers/format.h>
#include <tessera/errors/input_error.h>
#include <tessera/scene/depth_precision.h>
#include <tessera/techniques/technique.h>

#include "support/room_scene.h"

namespace tessera::test::extremes {

// Options under which a technique's image must equal forward's {projection: d3d} bit for bit when
// its culling (tile lists, light volumes and stencil marking) keeps every light that reaches a
// pixel: the lights it leaves out add exactly 0 in forward (tests/techniques: forward_plus_test,
// tiled_deferred_test, deferred_test derive each equality).
struct Equality {
    std::string technique;
    nlohmann::json options;
};
inline const std::vector<Equality>& conservativeEqualities() {
    static const std::vector<Equality> list{
        {"forward-plus", {{"projection", "d3d"}, {"lightLists", "unbounded"}}},
        {"tiled-deferred", {{"shading", "3dgep"}, {"gbuffer", "float"}, {"position", "gbuffer"}}},
        {"deferred",
         {{"projection", "d3d"}, {"reconstruct", "centre"}, {"gbuffer", "float"}, {"position", "gbuffer"},
          {"accumulate", "lighting"}, {"lightVolumes", "circumscribed"}, {"volumeRotation", "robust"}}}};
    return list;
}

struct CaseOptions {
    glm::uvec2 sizePx{64, 48};
    // Techniques rendered with their default (faithful) options; empty: every ready technique.
    std::vector<std::string> techniques;
    bool equalities = true;          // the conservative-culling equalities above, and AMD's binned = all-lights
    bool threadAgreement = true;     // every buffer identical at 1 and 3 threads
    // "technique/buffer" pairs allowed to hold NaN or Inf, each with the reason in the case.
    std::set<std::string> nonFiniteAllowed;
    // Largest RGBA8 code difference of forward (exact) from forward (reference) the case accepts.
    int maxReferenceCodes = 1;
    // Techniques that must refuse the scene with an InputError (the case says why).
    std::set<std::string> refused;
    // depthPrecisionWarning (scene/depth_precision.h) must warn: the depth buffer cannot resolve
    // the scene, and the equalities (which compare depth-tested images) are not asserted.
    bool depthWarning = false;
    // Pixels an equality may miss, where the case derives why (binary32 world positions).
    int maxEqualityPixels = 0;
};

struct CaseReport {
    std::string name;
    int referenceMaxCodes = 0, referencePixels = 0;   // forward exact vs reference
    int nonFiniteTexels = 0;                          // outside nonFiniteAllowed (must be 0)
    std::vector<std::pair<std::string, int>> equalityPixels;  // technique: pixels differing from forward
    std::vector<std::string> checked;                 // techniques rendered
};

inline std::vector<std::string> readyTechniques() {
    std::vector<std::string> ids;
    for (const TechniqueInfo& t : techniques())
        if (t.build) ids.emplace_back(t.id);
    return ids;
}

// Texels (every sample, every channel the format has) that are NaN or +-Inf in a float or
// float-depth surface. UNORM/SNORM/UINT formats cannot hold them.
inline int nonFiniteTexels(const Surface& s) {
    const FormatInfo& info = formatInfo(s.format());
    const bool floatColour = info.kind == FormatKind::Float;
    const bool floatDepth = s.format() == Format::D32_FLOAT || s.format() == Format::D32_FLOAT_S8X24_UINT;
    if (!floatColour && !floatDepth) return 0;
    int bad = 0;
    for (std::uint32_t y = 0; y < s.height(); ++y)
        for (std::uint32_t x = 0; x < s.width(); ++x)
            for (std::uint32_t k = 0; k < s.sampleCount(); ++k) {
                if (floatDepth) {
                    bad += !std::isfinite(s.loadDepth(x, y, k));
                    continue;
                }
                const glm::vec4 v = s.load(x, y, k);
                for (std::uint32_t c = 0; c < info.channels; ++c) bad += !std::isfinite(v[static_cast<int>(c)]);
            }
    return bad;
}

inline bool sameRegistries(const BufferRegistry& a, const BufferRegistry& b, std::string& firstDifference) {
    if (a.names() != b.names()) {
        firstDifference = "the buffer lists";
        return false;
    }
    for (const std::string& name : a.names())
        if (!sameBytes(*a.find(name), *b.find(name))) {
            firstDifference = name;
            return false;
        }
    return true;
}

inline std::string fileNameOf(const std::string& caseName) {
    std::string out;
    for (const char c : caseName) out += std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' ? c : '_';
    return out;
}

// Writes extremes-results/<case>.json in the test's working folder (tests/ in the build tree):
// the recorded errors, which tests/extremes/README.md tabulates.
inline void record(const CaseReport& r) {
    const std::filesystem::path dir = std::filesystem::path(TESSERA_TEST_OUTPUT_DIR) / "extremes-results";
    std::filesystem::create_directories(dir);
    nlohmann::json j{{"case", r.name},
                     {"referenceMaxCodes", r.referenceMaxCodes},
                     {"referencePixels", r.referencePixels},
                     {"nonFiniteTexels", r.nonFiniteTexels},
                     {"techniques", r.checked}};
    for (const auto& [technique, pixels] : r.equalityPixels) j["equalityPixels"][technique] = pixels;
    std::ofstream(dir / (fileNameOf(r.name) + ".json")) << j.dump(1) << '\n';
}

// Renders `t` as the case says and checks the shared properties; returns what it measured.
inline CaseReport runCase(const std::string& name, const TestScene& t, const CaseOptions& o = {}) {
    CaseReport report;
    report.name = name;
    const std::vector<std::string> list = o.techniques.empty() ? readyTechniques() : o.techniques;
    const std::optional<std::string> depthWarning = depthPrecisionWarning(t.camera, t.scene.bounds());
    CHECK_MESSAGE(depthWarning.has_value() == o.depthWarning, "depth warning: " << depthWarning.value_or("none"));
    for (const std::string& technique : list) {
        CAPTURE(technique);
        if (o.refused.count(technique)) {
            Rendered r;
            CHECK_THROWS_AS(render(t, technique, nlohmann::json::object(), r, Precision::Exact, 2, o.sizePx), InputError);
            continue;
        }
        Rendered two;
        render(t, technique, nlohmann::json::object(), two, Precision::Exact, 2, o.sizePx);
        for (const std::string& buffer : two.registry.names()) {
            const int bad = nonFiniteTexels(two.get(buffer));
            if (bad == 0 || o.nonFiniteAllowed.count(technique + "/" + buffer)) continue;
            CAPTURE(buffer);
            CHECK_MESSAGE(bad == 0, "NaN or Inf stored");
            report.nonFiniteTexels += bad;
        }
        if (o.threadAgreement) {
            Rendered one, three;
            render(t, technique, nlohmann::json::object(), one, Precision::Exact, 1, o.sizePx);
            render(t, technique, nlohmann::json::object(), three, Precision::Exact, 3, o.sizePx);
            std::string where;
            CHECK_MESSAGE(sameRegistries(one.registry, two.registry, where), "1 vs 2 threads differ in " << where);
            CHECK_MESSAGE(sameRegistries(three.registry, two.registry, where), "3 vs 2 threads differ in " << where);
        }
        report.checked.push_back(technique);
    }
    if (o.equalities && !o.depthWarning) {
        Rendered forward;
        render(t, "forward", {{"projection", "d3d"}}, forward, Precision::Exact, 2, o.sizePx);
        for (const Equality& e : conservativeEqualities()) {
            if (o.refused.count(e.technique)) continue;
            CAPTURE(e.technique);
            Rendered other;
            render(t, e.technique, e.options, other, Precision::Exact, 2, o.sizePx);
            const int pixels = differingPixels(forward.back(), other.back());
            CHECK_MESSAGE(pixels <= o.maxEqualityPixels, "the corrected " << e.technique << " differs from forward on " << pixels << " pixels");
            report.equalityPixels.emplace_back(e.technique, pixels);
        }
        Rendered binned, all;
        render(t, "forward-plus-amd", nlohmann::json::object(), binned, Precision::Exact, 2, o.sizePx);
        render(t, "forward-plus-amd", {{"lightLoop", "all-lights"}}, all, Precision::Exact, 2, o.sizePx);
        const int pixels = differingPixels(binned.back(), all.back());
        CHECK_MESSAGE(pixels <= o.maxEqualityPixels, "forward-plus-amd's binned lists miss light on " << pixels << " pixels");
        report.equalityPixels.emplace_back("forward-plus-amd", pixels);
    }
    {
        Rendered exact, reference;
        render(t, "forward", nlohmann::json::object(), exact, Precision::Exact, 2, o.sizePx);
        render(t, "forward", nlohmann::json::object(), reference, Precision::Reference, 2, o.sizePx);
        const Difference d = compareRgba8(exact.back(), reference.back());
        report.referenceMaxCodes = d.maxCodes;
        report.referencePixels = d.pixelsDiffering;
        CHECK_MESSAGE(d.maxCodes <= o.maxReferenceCodes,
                      "forward exact is " << d.maxCodes << " codes from reference on " << d.pixelsDiffering << " pixels");
    }
    record(report);
    return report;
}

} // namespace tessera::test::extremes
