// deferred-cookbook (techniques/deferred_cookbook.h) on the test room: with the corrections its
// tessellated volumes shade exactly what a full-screen pass per light shades (bit for bit), and
// each faithful value shows its erratum as a measured property: the printed specular decode only
// darkens, the table's cull mode lights the wrong side, the exact-range volumes and the book's spot
// scale miss light, the per-vertex cpPos moves the rebuilt position, the book's directional pass
// blackens the background. Capsule lights light the Cookbook's image and no other technique's.
#include <doctest/doctest.h>

#include <cmath>

#include <tessera/buffers/texel_codec.h>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_deferred_cookbook_test {

using namespace tessera;

namespace {

// Every correction on.
nlohmann::json corrected() {
    return {{"specPowerUnpack", "once"}, {"volumeCull", "front"}, {"spotVolume", "demo"}, {"cpPos", "pixel"}, {"background", "stencil"}};
}

nlohmann::json with(nlohmann::json options, const std::string& key, const std::string& value) {
    options[key] = value;
    return options;
}

// Pixels whose RGB differ between two surfaces of the same format (sample 0).
int differingPixels(const Surface& a, const Surface& b) {
    int n = 0;
    for (std::uint32_t y = 0; y < a.height(); ++y)
        for (std::uint32_t x = 0; x < a.width(); ++x)
            if (glm::vec3(a.load(x, y)) != glm::vec3(b.load(x, y))) ++n;
    return n;
}

// The room with a 12 degree spot 3 units above the floor, pointing straight down, range 3.2: the
// floor lies at 0.94..0.97 of the range inside the cone. The book's volume (a 45 degree unit cone
// scaled by R tan(12)/sqrt(1/2) = 0.30 R across) reaches only 0.914 R at 8 degrees off the axis
// (sqrt(k^2 sin^2 g + cos^2 g) with k = 0.30, tan g = tan 8 / k), so it misses that floor ring,
// where the light is (1 - 0.947)^2 x ((cos 8 - cos 12) / (1 - cos 12))^2 = 0.0028 x 0.31 of its colour.
test::TestScene narrowSpotRoom() {
    std::vector<Light> lights = test::defaultLights();
    lights.push_back(test::makeLight(LightType::Spot, {-1.0f, 3.0f, 1.0f}, {0.0f, -1.0f, 0.0f}, 3.2f, {0.8f, 0.9f, 1.0f}, 12.0f));
    return test::makeScene(lights);
}

} // namespace

TEST_CASE("deferred-cookbook: corrected volumes shade exactly the pixels a full-screen pass per light shades, for less work") {
    const test::TestScene t = narrowSpotRoom();
    for (const Precision precision : {Precision::Exact, Precision::Reference}) {
        CAPTURE(int(precision));
        test::Rendered volumes, quads;
        test::render(t, "deferred-cookbook", corrected(), volumes, precision);
        test::render(t, "deferred-cookbook", with(corrected(), "lightGeometry", "quads"), quads, precision);
        CHECK(test::sameBytes(volumes.back(), quads.back()));
        if (precision == Precision::Reference) CHECK(test::sameBytes(volumes.get(kReferenceBufferName), quads.get(kReferenceBufferName)));
    }
    // What the volumes save: pixel-shader invocations of the lights pass.
    const DrawStats volumeStats = test::renderStats(t, "deferred-cookbook", corrected());
    const DrawStats quadStats = test::renderStats(t, "deferred-cookbook", with(corrected(), "lightGeometry", "quads"));
    CHECK(volumeStats.psInvocations < quadStats.psInvocations);
}

TEST_CASE("deferred-cookbook: exact-range volumes miss the light between their flat faces and the sphere") {
    // The point light of range 5 at height 1.5 cuts the floor in a circle; the unit sphere mesh's
    // chords lie up to ~0.5 % inside it, so a ring of floor pixels just inside the range is missed.
    // Its light is (1 - d/R)^2 <= 0.005^2 of the colour: visible in the reference mode's floats.
    const test::TestScene t = narrowSpotRoom();
    test::Rendered padded, range, quads;
    test::render(t, "deferred-cookbook", corrected(), padded, Precision::Reference);
    test::render(t, "deferred-cookbook", with(corrected(), "volumeScale", "range"), range, Precision::Reference);
    test::render(t, "deferred-cookbook", with(corrected(), "lightGeometry", "quads"), quads, Precision::Reference);
    CHECK(differingPixels(padded.get(kReferenceBufferName), quads.get(kReferenceBufferName)) == 0);
    CHECK(differingPixels(range.get(kReferenceBufferName), quads.get(kReferenceBufferName)) > 0);
}

TEST_CASE("deferred-cookbook: the book's spot scale falls short of the range off the axis of a narrow cone (ERRATA #24)") {
    const test::TestScene t = narrowSpotRoom();
    test::Rendered book, quads;
    test::render(t, "deferred-cookbook", with(corrected(), "spotVolume", "book"), book, Precision::Reference);
    test::render(t, "deferred-cookbook", with(corrected(), "lightGeometry", "quads"), quads, Precision::Reference);
    const int missed = differingPixels(book.get(kReferenceBufferName), quads.get(kReferenceBufferName));
    CHECK(missed > 20);
    // Missed, not added: wherever they differ the book's image is darker.
    const Surface& a = book.get(kReferenceBufferName);
    const Surface& b = quads.get(kReferenceBufferName);
    for (std::uint32_t y = 0; y < a.height(); ++y)
        for (std::uint32_t x = 0; x < a.width(); ++x)
            for (int c = 0; c < 3; ++c) CHECK(a.load(x, y)[c] <= b.load(x, y)[c]);
}

TEST_CASE("deferred-cookbook: the recipe table's CULL_BACK lights what lies in front of each volume (ERRATA #23)") {
    // With GREATER_EQUAL, the faces towards the camera pass where the scene is in front of the
    // volume: the geometry inside it (what the light reaches) is not shaded by those faces.
    const test::TestScene t = narrowSpotRoom();
    test::Rendered table, front, quads;
    test::render(t, "deferred-cookbook", with(corrected(), "volumeCull", "table"), table);
    test::render(t, "deferred-cookbook", corrected(), front);
    test::render(t, "deferred-cookbook", with(corrected(), "lightGeometry", "quads"), quads);
    CHECK(test::sameBytes(front.back(), quads.back()));
    CHECK(differingPixels(table.back(), quads.back()) > int(test::kWidth * test::kHeight / 10));
}

TEST_CASE("deferred-cookbook: the printed specular decode (251 x norm, decoded twice) only removes highlights (ERRATA #22)") {
    const test::TestScene t = narrowSpotRoom();
    test::Rendered printed, once;
    test::render(t, "deferred-cookbook", with(corrected(), "specPowerUnpack", "printed"), printed, Precision::Reference);
    test::render(t, "deferred-cookbook", corrected(), once, Precision::Reference);
    // pow(x, p) for x in [0, 1] falls as p grows, and the printed power is >= the intended one:
    // every channel is at most the corrected one's, and the highlights make some strictly less.
    const Surface& a = printed.get(kReferenceBufferName);
    const Surface& b = once.get(kReferenceBufferName);
    int darker = 0;
    for (std::uint32_t y = 0; y < a.height(); ++y)
        for (std::uint32_t x = 0; x < a.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                CHECK(a.load(x, y)[c] <= b.load(x, y)[c]);
                darker += a.load(x, y)[c] < b.load(x, y)[c] ? 1 : 0;
            }
    CHECK(darker > 100);
}

TEST_CASE("deferred-cookbook: the per-vertex cpPos rebuilds positions off the pixel, the pixel's own is exact (ERRATA #25)") {
    const test::TestScene t = narrowSpotRoom();
    test::Rendered vertex, pixel, quads;
    test::render(t, "deferred-cookbook", with(corrected(), "cpPos", "vertex"), vertex, Precision::Reference);
    test::render(t, "deferred-cookbook", corrected(), pixel, Precision::Reference);
    test::render(t, "deferred-cookbook", with(corrected(), "lightGeometry", "quads"), quads, Precision::Reference);
    // The quads' cpPos is affine (w = 1) and so exact either way: only the volumes' differ.
    CHECK(differingPixels(pixel.get(kReferenceBufferName), quads.get(kReferenceBufferName)) == 0);
    CHECK(differingPixels(vertex.get(kReferenceBufferName), quads.get(kReferenceBufferName)) > 100);
}

TEST_CASE("deferred-cookbook: the book's directional pass paints the background black, the stencil keeps the clear colour (ERRATA #26)") {
    // From 30 units back the 10-unit wall ends below the top of the view: background above it.
    const test::TestScene t = test::makeScene(test::defaultLights(), {0.0f, 3.0f, 30.0f});
    test::Rendered book, stencil;
    test::render(t, "deferred-cookbook", with(corrected(), "background", "book"), book);
    test::render(t, "deferred-cookbook", corrected(), stencil);
    const Surface& depth = stencil.get("depth");
    const glm::uvec4 clearCodes(99, 148, 237, 255);  // kDemoClearColor (0.39, 0.58, 0.93, 1) in 8 bits
    int background = 0;
    for (std::uint32_t y = 0; y < depth.height(); ++y)
        for (std::uint32_t x = 0; x < depth.width(); ++x) {
            if (depth.loadDepth(x, y) != 1.0f) continue;
            ++background;
            const std::byte* s = stencil.back().texel(x, y);
            const std::byte* b = book.back().texel(x, y);
            for (int c = 0; c < 4; ++c) CHECK(std::to_integer<unsigned>(s[c]) == clearCodes[c]);
            for (int c = 0; c < 3; ++c) CHECK(std::to_integer<unsigned>(b[c]) == 0u);
        }
    CHECK(background > 100);
}

TEST_CASE("deferred-cookbook: a capsule light lights the floor along its segment, other techniques skip it") {
    std::vector<Light> lights = test::defaultLights();
    Light capsule = test::makeLight(LightType::Capsule, {-3.0f, 0.5f, 1.0f}, {1.0f, 0.0f, 0.0f}, 3.0f, {1.0f, 0.2f, 0.2f});
    capsule.length = 6.0f;  // from x = -3 to 3 at height 0.5
    lights.push_back(capsule);
    const test::TestScene with = test::makeScene(lights);
    const test::TestScene without = test::makeScene(test::defaultLights());
    test::Rendered a, b;
    test::render(with, "deferred-cookbook", corrected(), a);
    test::render(without, "deferred-cookbook", corrected(), b);
    // The capsule adds red: no pixel loses red, many gain it.
    int redder = 0;
    for (std::uint32_t y = 0; y < test::kHeight; ++y)
        for (std::uint32_t x = 0; x < test::kWidth; ++x) {
            const unsigned ra = std::to_integer<unsigned>(a.back().texel(x, y)[0]);
            const unsigned rb = std::to_integer<unsigned>(b.back().texel(x, y)[0]);
            CHECK(ra >= rb);
            redder += ra > rb ? 1 : 0;
        }
    CHECK(redder > 200);
    // The volumes still match the quads with a capsule.
    test::Rendered quads;
    test::render(with, "deferred-cookbook", techniques_deferred_cookbook_test::with(corrected(), "lightGeometry", "quads"), quads);
    CHECK(test::sameBytes(a.back(), quads.back()));
    // forward, deferred, forward-plus: the capsule changes nothing.
    for (const char* technique : {"forward", "deferred", "forward-plus", "forward-plus-amd", "tiled-deferred"}) {
        CAPTURE(technique);
        test::Rendered p, q;
        test::render(with, technique, nlohmann::json::object(), p);
        test::render(without, technique, nlohmann::json::object(), q);
        CHECK(test::sameBytes(p.back(), q.back()));
    }
}

TEST_CASE("deferred-cookbook: the same bytes at 1, 2 and 7 threads, every buffer") {
    const test::TestScene t = narrowSpotRoom();
    test::Rendered one, two, seven;
    test::render(t, "deferred-cookbook", nlohmann::json::object(), one, Precision::Exact, 1);
    test::render(t, "deferred-cookbook", nlohmann::json::object(), two, Precision::Exact, 2);
    test::render(t, "deferred-cookbook", nlohmann::json::object(), seven, Precision::Exact, 7);
    for (const std::string& name : one.registry.names()) {
        CAPTURE(name);
        CHECK(test::sameBytes(one.get(name), two.get(name)));
        CHECK(test::sameBytes(one.get(name), seven.get(name)));
    }
}

} // namespace tessera_test::techniques_deferred_cookbook_test
