// light-prepass (techniques/light_prepass.h, PR&C D3D11 ch. 11 §11.3) on the test room: under white
// lights its image equals deferred-classic's within float rounding (distributivity), under coloured
// lights its monochrome specular differs (the technique's known approximation); its light geometries
// fill the same light buffer. Light groups and the MSAA final pass are tested with deferred-classic
// (deferred_classic_test) and the MSAA techniques (msaa_deferred_test).
#include <doctest/doctest.h>

#include <algorithm>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_light_prepass_test {

using namespace tessera;
using namespace tessera::test;

namespace {

nlohmann::json geometry(const std::string& g) {
    return {{"lightGeometry", g}, {"scissorRound", "out"}, {"stencil", false}};
}

} // namespace

TEST_CASE("light-prepass: under white lights it equals deferred-classic within float rounding, under coloured lights its monochrome specular does not") {
    // Classic sums per light (N.L c albedo + pow(N.H, p) c specAlbedo N.L) att; the light pre-pass
    // sums N.L c att and pow(N.H, p) att N.L first and applies the albedos once. With c = 1 the two
    // are the same sum by distributivity: in reference mode (double arithmetic, float targets) they
    // differ only by the float storage of the partial sums, < 1e-5 on values <= 1 (4 lights, a few
    // float roundings each of 2^-24 relative). With coloured lights the specular loses c.
    std::vector<Light> white = test::defaultLights();
    for (Light& l : white) l.color = glm::vec3(1.0f);
    const auto maxRgbDifference = [](const Surface& a, const Surface& b, int& over) {
        float worst = 0.0f;
        over = 0;
        for (std::uint32_t y = 0; y < a.height(); ++y)
            for (std::uint32_t x = 0; x < a.width(); ++x) {
                const glm::vec3 d = glm::abs(glm::vec3(a.load(x, y)) - glm::vec3(b.load(x, y)));
                const float m = std::max({d.x, d.y, d.z});
                worst = std::max(worst, m);
                over += m > 1e-3f ? 1 : 0;
            }
        return worst;
    };
    for (const bool coloured : {false, true}) {
        CAPTURE(coloured);
        const test::TestScene t = test::makeScene(coloured ? test::defaultLights() : white);
        test::Rendered classic, lpp;
        test::render(t, "deferred-classic", nlohmann::json::object(), classic, Precision::Reference);
        test::render(t, "light-prepass", nlohmann::json::object(), lpp, Precision::Reference);
        int over = 0;
        const float worst = maxRgbDifference(classic.get(kReferenceBufferName), lpp.get(kReferenceBufferName), over);
        if (coloured) {
            CHECK(worst > 1e-3f);
            CHECK(over > 100);
        } else {
            CHECK(worst < 1e-5f);
        }
    }
    // Its light geometries agree as classic's do.
    const test::TestScene t = test::makeScene(test::defaultLights(), {-1.0f, 2.0f, 1.0f});
    test::Rendered quads, volumes;
    test::render(t, "light-prepass", geometry("quads"), quads, Precision::Reference);
    test::render(t, "light-prepass", geometry("volumes"), volumes, Precision::Reference);
    CHECK(test::sameBytes(quads.get("lightbuffer"), volumes.get("lightbuffer")));
    CHECK(test::sameBytes(quads.get(kReferenceBufferName), volumes.get(kReferenceBufferName)));
}

} // namespace tessera_test::techniques_light_prepass_test
