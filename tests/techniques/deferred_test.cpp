// The `deferred` and `deferred-killzone` techniques against `forward` on a small opaque scene
// built in memory (a floor and a wall, point + spot + directional lights): the corrected options
// reproduce forward bit for bit, the faithful defaults differ only within the bound that the
// G-buffer formats and the corner sample explain, and each erratum (inscribed volumes, corner
// reconstruction, Killzone 2 with the eye inside a volume) is shown on its own.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string>

#include <glm/gtc/quaternion.hpp>

#include <tessera/errors/input_error.h>
#include <tessera/techniques/deferred.h>
#include <tessera/techniques/light_volumes.h>
#include <tessera/techniques/technique.h>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_deferred_test {

using namespace tessera;
using namespace tessera::test;

namespace {

const nlohmann::json kCorrected = {{"projection", "d3d"},     {"reconstruct", "centre"},     {"gbuffer", "float"},
                                   {"position", "gbuffer"},   {"accumulate", "lighting"},    {"lightVolumes", "circumscribed"},
                                   {"volumeRotation", "robust"}};

std::string errorOf(const std::string& technique, const nlohmann::json& options, Precision precision = Precision::Exact) {
    Rendered r;
    try {
        render(makeScene(defaultLights()), technique, options, r, precision);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("deferred: with the corrected options the image equals forward's bit for bit on an opaque scene") {
    const TestScene t = makeScene(defaultLights());
    Rendered forward, deferred, unlit;
    render(t, "forward", {{"projection", "d3d"}}, forward);
    render(t, "deferred", kCorrected, deferred);
    render(makeScene({}), "forward", {{"projection", "d3d"}}, unlit);
    // The lights do reach the image (otherwise the equality would say little).
    const Difference lit = compareRgba8(forward.back(), unlit.back());
    MESSAGE("lights change " << lit.share() * 100.0 << " % of the pixels, by up to " << lit.maxCodes << " codes");
    CHECK(lit.share() > 0.5);
    CHECK(sameBytes(forward.back(), deferred.back()));
    const Difference d = compareRgba8(forward.back(), deferred.back());
    MESSAGE("corrected deferred vs forward: max " << d.maxCodes << " codes, " << d.pixelsDiffering << " pixels differ");
    // Every light was drawn: 3 volumes + 1 quad, plus the G-buffer variants.
    CHECK(deferred.variants["light:point"] == 2);
    CHECK(deferred.variants["light:spot"] == 1);
    CHECK(deferred.variants["light:directional"] == 1);
}

TEST_CASE("deferred: per-light colour accumulation in float differs from forward by float re-association only") {
    // The faithful sum order (diffuse * D_k + specular * S_k blended light by light) against
    // forward's (diffuse * sum D + specular * sum S): equal in exact arithmetic, a few float ulps
    // apart in binary32, hence at most one 8-bit code after the final rounding.
    const TestScene t = makeScene(defaultLights());
    nlohmann::json options = kCorrected;
    options["accumulate"] = "color";
    Rendered forward, deferred;
    render(t, "forward", {{"projection", "d3d"}}, forward);
    render(t, "deferred", options, deferred);
    const Difference d = compareRgba8(forward.back(), deferred.back());
    MESSAGE("accumulate color vs forward: max " << d.maxCodes << " code, " << d.share() * 100.0 << " % of pixels differ");
    CHECK(d.maxCodes <= 1);
}

TEST_CASE("deferred: faithful defaults differ from forward only within the quantization and sample-position bound") {
    // Bound per pixel and channel, in 8-bit codes (derivation in the case body):
    //   0.5                 RT0 = UNORM8(ambient + emissive)
    //   0.5 n               one rounding per additive blend into RGBA8, n = lights drawn
    //   0.5                 forward's own final rounding
    //   0.5 (sum D + sum S) diffuse and specular colours stored in UNORM8 (|error| <= 0.5/255),
    //                       times the light sums that multiply them
    //   255 * 0.0054 * sum_k colour_k  spec-power packing: p' = p (1 + d), |d| <= 2^(10.5/510) - 1
    //                       = 0.014374; |y - y^(1+d)| <= |d| / e (1 + |d|) for y = x^p in [0, 1]
    //   255 |corner - centre|   the sample position, measured exactly on float targets
    //   255 |inscribed - circumscribed|  the volume fit, measured exactly on float targets
    //   0.25                D24 reconstruction of P (~3e-5 view units here) and float slack
    const TestScene t = makeScene(defaultLights());
    const std::vector<Light>& lights = t.scene.lights;
    Rendered faithful, forward, sums, corner, centre, inscribed;
    render(t, "deferred", nlohmann::json::object(), faithful);
    render(t, "forward", nlohmann::json::object(), forward);
    // Exact light sums (forward's D and S): float targets, interpolated P, accumulate lighting.
    render(t, "deferred", {{"gbuffer", "float"}, {"position", "gbuffer"}, {"accumulate", "lighting"}, {"lightVolumes", "circumscribed"}},
           sums);
    const nlohmann::json floatColor = {{"gbuffer", "float"}, {"lightVolumes", "circumscribed"}};
    nlohmann::json o = floatColor;
    render(t, "deferred", o, corner);
    o["reconstruct"] = "centre";
    render(t, "deferred", o, centre);
    o["lightVolumes"] = "inscribed";
    render(t, "deferred", o, inscribed);

    double colourSum[3] = {0, 0, 0};
    for (const Light& l : lights)
        for (int c = 0; c < 3; ++c) colourSum[c] += double(l.color[c]) * double(l.intensity);
    const double packing = 0.014374 / std::exp(1.0) * 1.015;
    const Surface& accCorner = corner.registry.get("accumulation");
    const Surface& accCentre = centre.registry.get("accumulation");
    const Surface& accInscribed = inscribed.registry.get("accumulation");
    const Surface& sumD = sums.registry.get("light.diffuse");
    const Surface& sumS = sums.registry.get("light.specular");
    const Surface& depth = faithful.registry.get("depth");
    const Difference d = compareRgba8(faithful.back(), forward.back());
    double worstRatio = 0.0, worstBound = 0.0;
    int violations = 0, uncovered = 0;
    for (std::uint32_t y = 0; y < kHeight; ++y)
        for (std::uint32_t x = 0; x < kWidth; ++x) {
            uncovered += depth.loadDepth(x, y) == 1.0f;
            for (int c = 0; c < 3; ++c) {
                const int diff = std::abs(std::to_integer<int>(faithful.back().texel(x, y)[c]) -
                                          std::to_integer<int>(forward.back().texel(x, y)[c]));
                const double position = std::fabs(double(accCorner.load(x, y)[c]) - double(accCentre.load(x, y)[c]));
                const double fit = std::fabs(double(accCentre.load(x, y)[c]) - double(accInscribed.load(x, y)[c]));
                const double bound = 0.5 + 0.5 * double(lights.size()) + 0.5 +
                                     0.5 * (double(sumD.load(x, y)[c]) + double(sumS.load(x, y)[c])) +
                                     255.0 * packing * colourSum[c] + 255.0 * (position + fit) + 0.25;
                worstBound = std::max(worstBound, bound);
                worstRatio = std::max(worstRatio, double(diff) / bound);
                violations += double(diff) > bound;
            }
        }
    MESSAGE("faithful deferred vs faithful forward: max " << d.maxCodes << " codes, " << d.share() * 100.0
                                                          << " % of pixels differ; worst |diff| / bound " << worstRatio
                                                          << ", largest bound " << worstBound << " codes");
    CHECK(uncovered == 0);  // the floor and the wall cover the view: no sky pixels
    CHECK(violations == 0);
    CHECK(d.pixelsDiffering > 0);  // the formats do show
}

TEST_CASE("deferred: inscribed volumes lose light near the range that circumscribed volumes keep") {
    // One point light of range 8 above the floor: its sphere cuts the floor and the wall. The
    // demo's tess-4 icosphere is inscribed (face planes down to R / 1.00114), so floor points
    // with R / 1.00114 < d <= R get no light from it; forward and circumscribed volumes light
    // them (attenuation <= 6.2e-5 there: invisible in RGBA8, exact on float targets).
    const float range = 8.0f;
    const glm::vec3 lightPos{0.0f, 6.0f, 0.0f};
    const TestScene t = makeScene({makeLight(LightType::Point, lightPos, {0, 0, -1}, range, {1, 1, 1})}, {0.0f, 3.0f, 8.0f});
    const nlohmann::json base = {{"gbuffer", "float"}, {"position", "gbuffer"}, {"projection", "d3d"}};
    nlohmann::json circ = base;
    circ["lightVolumes"] = "circumscribed";
    Rendered in, out;
    render(t, "deferred", base, in);
    render(t, "deferred", circ, out);
    const float innerRadius = range / LightVolumes().sphereCircumscribeScale();
    const Surface& accIn = in.registry.get("accumulation");
    const Surface& accOut = out.registry.get("accumulation");
    const Surface& pos = out.registry.get("gbuffer.position");
    const glm::mat4 view = t.camera.viewFromWorld();
    const glm::vec3 lightView(view * glm::vec4(lightPos, 1.0f));
    int lost = 0, outsideBand = 0, gained = 0;
    for (std::uint32_t y = 0; y < kHeight; ++y)
        for (std::uint32_t x = 0; x < kWidth; ++x) {
            const glm::vec4 a = accIn.load(x, y), b = accOut.load(x, y);
            if (a == b) continue;
            if (a.x < b.x) ++lost;
            else ++gained;
            const float dist = glm::length(glm::vec3(pos.load(x, y)) - lightView);
            if (dist < innerRadius * (1.0f - 1e-5f) || dist > range * (1.0f + 1e-5f)) ++outsideBand;
        }
    MESSAGE(lost << " pixels lose the light with inscribed volumes (band " << innerRadius << " < d <= " << range << ")");
    CHECK(lost > 0);
    CHECK(gained == 0);
    CHECK(outsideBand == 0);
}

TEST_CASE("deferred: the corner sample moves P off the pixel centre, the centre reconstruction matches forward's P") {
    // Float targets and forward's sum order, so that only P differs: P interpolated (position
    // gbuffer, = forward) against P from ScreenToView at the centre and at the corner.
    const TestScene t = makeScene(defaultLights());
    nlohmann::json o = kCorrected;
    Rendered interpolated, centre, corner;
    render(t, "deferred", o, interpolated);
    o["position"] = "reconstruct";
    render(t, "deferred", o, centre);
    o["reconstruct"] = "corner";
    render(t, "deferred", o, corner);
    const Difference dc = compareRgba8(interpolated.back(), centre.back());
    const Difference dk = compareRgba8(interpolated.back(), corner.back());
    MESSAGE("centre: max " << dc.maxCodes << " codes on " << dc.share() * 100.0 << " %; corner: max " << dk.maxCodes
                           << " codes on " << dk.share() * 100.0 << " %");
    CHECK(dc.maxCodes <= 1);  // float round-off of ScreenToView with D32F depth
    CHECK(dk.maxCodes > dc.maxCodes);
    CHECK(dk.pixelsDiffering > 4 * std::max(dc.pixelsDiffering, 1));
}

TEST_CASE("deferred-killzone: with the eye inside a point light's volume nothing is lit by it, deferred lights it") {
    // The camera at (0, 3, 8) inside a point light of range 6 at (0, 2.5, 5): the count pass's
    // front faces are behind the eye (clipped), the query counts 0, the shade draw is skipped.
    const Light inside = makeLight(LightType::Point, {0.0f, 2.5f, 5.0f}, {0, 0, -1}, 6.0f, {1, 1, 1});
    Light disabled = inside;
    disabled.enabled = false;
    Rendered deferredLit, killzone, dark;
    render(makeScene({inside}), "deferred", nlohmann::json::object(), deferredLit);
    render(makeScene({inside}), "deferred-killzone", nlohmann::json::object(), killzone);
    render(makeScene({disabled}), "deferred", nlohmann::json::object(), dark);
    const Difference lit = compareRgba8(deferredLit.back(), dark.back());
    MESSAGE("deferred lights " << lit.share() * 100.0 << " % of the pixels; killzone samples "
                               << killzone.registry.get("killzone.samples").loadUint(0, 0).x);
    CHECK(lit.share() > 0.3);
    CHECK(killzone.registry.get("killzone.samples").loadUint(0, 0).x == 0u);
    CHECK(killzone.variants["killzone-skipped:point"] == 1);
    CHECK(sameBytes(killzone.back(), dark.back()));

    // The same light seen from outside its volume: counted and shaded.
    Rendered outside;
    render(makeScene({makeLight(LightType::Point, {0.0f, 1.5f, -2.0f}, {0, 0, -1}, 4.0f, {1, 1, 1})}), "deferred-killzone",
           nlohmann::json::object(), outside);
    CHECK(outside.registry.get("killzone.samples").loadUint(0, 0).x > 0u);
    CHECK(outside.variants["light:point"] == 1);
}

TEST_CASE("deferred-killzone: the threshold skips lights with few samples, samples are stored per light") {
    const TestScene t = makeScene(defaultLights());
    Rendered all, none;
    render(t, "deferred-killzone", nlohmann::json::object(), all);
    render(t, "deferred-killzone", {{"threshold", kWidth * kHeight}}, none);
    const Surface& samples = all.registry.get("killzone.samples");
    CHECK(samples.width() == 4);
    CHECK(samples.loadUint(0, 0).x > 0u);
    CHECK(samples.loadUint(2, 0).x == kKillzoneNotCounted);  // the directional light
    CHECK(all.variants["killzone-skipped:point"] == 0);
    CHECK(none.variants["killzone-skipped:point"] == 2);
    CHECK(none.variants["killzone-skipped:spot"] == 1);
    CHECK(none.variants["light:directional"] == 1);
}

TEST_CASE("deferred: option values are InputErrors naming the key path, and every precision is accepted") {
    CHECK(errorOf("deferred", {{"reconstruct", "middle"}}).find("memory.json: /options/reconstruct: \"middle\" is not one of corner | centre") !=
          std::string::npos);
    CHECK(errorOf("deferred", {{"gbuffer", 1}}).find("/options/gbuffer") != std::string::npos);
    CHECK(errorOf("deferred", {{"threshold", 3}}).find("/options/threshold") != std::string::npos);  // killzone only
    CHECK(errorOf("deferred-killzone", {{"threshold", -1}}).find("/options/threshold") != std::string::npos);
    CHECK(errorOf("deferred-killzone", {{"threshold", 1.5}}).find("/options/threshold") != std::string::npos);
    for (const Precision p : {Precision::Reference, Precision::Fast}) {
        CHECK(errorOf("deferred", nlohmann::json::object(), p).empty());
        CHECK(errorOf("deferred-killzone", nlohmann::json::object(), p).empty());
    }
    CHECK(errorOf("deferred", {{"lightVolumes", "circumscribed"}, {"volumeRotation", "robust"}}).empty());
}

TEST_CASE("deferred: G-buffer formats and buffers per option") {
    Rendered demo, flt;
    render(makeScene(defaultLights()), "deferred", nlohmann::json::object(), demo);
    render(makeScene(defaultLights()), "deferred", kCorrected, flt);
    CHECK(demo.registry.get("gbuffer.diffuse").format() == Format::R8G8B8A8_UNORM);
    CHECK(demo.registry.get("gbuffer.specular").format() == Format::R8G8B8A8_UNORM);
    CHECK(demo.registry.get("gbuffer.normal").format() == Format::R32G32B32A32_FLOAT);
    CHECK(demo.registry.get("depth").format() == Format::D24_UNORM_S8_UINT);
    CHECK(demo.registry.get("depth.copy").format() == Format::D24_UNORM_S8_UINT);
    CHECK(!demo.registry.contains("accumulation"));
    CHECK(flt.registry.get("accumulation").format() == Format::R32G32B32A32_FLOAT);
    CHECK(flt.registry.get("gbuffer.specular").format() == Format::R32G32B32A32_FLOAT);
    CHECK(flt.registry.get("depth").format() == Format::D32_FLOAT_S8X24_UINT);
    CHECK(flt.registry.contains("gbuffer.position"));
    CHECK(flt.registry.contains("light.diffuse"));
    // The wall's specular power 245 (roughness 0.3): packed log2(245)/10.5 -> code 193 in the
    // demo target, unpacked in the float one. Pixel (64, 20) lies on the wall.
    CHECK(std::to_integer<int>(demo.registry.get("gbuffer.specular").texel(64, 20)[3]) ==
          int(std::lround(std::log2(flt.registry.get("gbuffer.specular").load(64, 20).w) / 10.5 * 255.0)));
}

TEST_CASE("deferred: per-light steps: a light's shade pass changes no pixel its unmark pass cleared, lights some it kept, and the last step is the frame") {
    // The buffers after each step of every light (TechniqueContext::afterLightStep, what
    // --dump-lights writes): the stencil after "unmark" and the back buffer before and after "shade".
    const test::TestScene t = test::makeScene(test::defaultLights());
    struct Step {
        std::size_t light;
        std::string step;
        Surface stencilDepth, back;
    };
    std::vector<Step> steps;
    test::Rendered r;
    test::render(t, "deferred", {}, r, Precision::Exact, 2, {test::kWidth, test::kHeight},
                 [&](std::size_t light, std::string_view step, const BufferRegistry& reg) {
                     steps.push_back({light, std::string(step), *reg.find("depth"), *reg.find(kBackBufferName)});
                 });
    // Lights 0, 1, 3 are volumes (unmark + shade), 2 is directional (shade only): 7 steps in order.
    REQUIRE(steps.size() == 7);
    CHECK(steps[4].light == 2);
    CHECK(steps[4].step == "shade");
    std::size_t unmarkedSomewhere = 0, litSomewhere = 0;
    for (std::size_t i = 0; i + 1 < steps.size(); ++i) {
        if (steps[i].step != "unmark") continue;
        const Step& unmark = steps[i];
        const Step& shade = steps[i + 1];
        REQUIRE(shade.light == unmark.light);
        REQUIRE(shade.step == "shade");
        for (std::uint32_t y = 0; y < test::kHeight; ++y)
            for (std::uint32_t x = 0; x < test::kWidth; ++x) {
                const bool same = std::memcmp(unmark.back.texel(x, y), shade.back.texel(x, y), 4) == 0;
                if (unmark.stencilDepth.loadStencil(x, y) == 0) {
                    ++unmarkedSomewhere;
                    CHECK_MESSAGE(same, "light " << unmark.light << " shaded unmarked pixel " << x << "," << y);
                } else if (!same) {
                    ++litSomewhere;
                }
            }
    }
    CHECK(unmarkedSomewhere > 0);  // the test sees both kinds of pixel
    CHECK(litSomewhere > 0);
    // The last step's buffers are the frame's.
    CHECK(std::memcmp(steps.back().back.bytes().data(), r.back().bytes().data(), r.back().bytes().size()) == 0);
}

} // namespace tessera_test::techniques_deferred_test
