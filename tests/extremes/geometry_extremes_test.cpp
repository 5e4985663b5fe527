// Extremes catalogue, geometry: the whole world scaled by 1e-15 .. 1e15 or moved 1e6 away,
// triangles of 1e-6, slivers, vertices at w = 0, triangles across the near plane and behind the
// eye, degenerate and coincident triangles, and a triangle 1e30 wide.
#include <cmath>

#include "extremes/extremes.h"
#include "extremes/scenes.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::extremes_geometry_extremes_test {

using namespace tessera;
using namespace tessera::test;
using namespace tessera::test::extremes;

namespace {

// The room plus one extra primitive (world = view-independent object space), material 0.
TestScene withTriangle(TestScene t, std::vector<glm::vec3> positionsWorld, std::vector<std::uint32_t> indices) {
    MeshPrimitive p;
    p.positionsObject = positionsWorld;
    const glm::vec3 n(0.0f, 0.0f, 1.0f);
    p.normalsObject.assign(positionsWorld.size(), n);
    p.tangentsObject.assign(positionsWorld.size(), glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    p.texCoords0.assign(positionsWorld.size(), glm::vec2(0.5f));
    p.indices = std::move(indices);
    p.material = 0;
    Mesh mesh;
    mesh.primitives.push_back(p);
    t.scene.meshes.push_back(mesh);
    t.scene.instances.push_back(MeshInstance{static_cast<int>(t.scene.meshes.size() - 1), glm::mat4(1.0f), "extra"});
    return t;
}

// A point in world space at view position (x, y, z) of the room's camera.
glm::vec3 fromView(const TestScene& t, glm::vec3 posView) {
    return glm::vec3(glm::inverse(t.camera.viewFromWorld()) * glm::vec4(posView, 1.0f));
}

} // namespace

TEST_CASE("geometry: world scaled by 1e-15") {
    // forward-plus-amd's side planes were normalize(cross) of corners ~1e-13 from the eye, whose
    // squared length (~1e-52) underflows: NaN planes culled every light (33.5% of pixels).
    runCase("geometry scale 1e-15", scaled(room(), 1e-15f));
}

TEST_CASE("geometry: world scaled by 1e-10") {
    runCase("geometry scale 1e-10", scaled(room(), 1e-10f));
}

TEST_CASE("geometry: world scaled by 1e-6 (triangles of about 1e-6)") {
    runCase("geometry scale 1e-6", scaled(room(), 1e-6f));
}

TEST_CASE("geometry: world scaled by 1e6") {
    runCase("geometry scale 1e6", scaled(room(), 1e6f));
}

TEST_CASE("geometry: world scaled by 1e15") {
    runCase("geometry scale 1e15", scaled(room(), 1e15f));
}

TEST_CASE("geometry: coordinates near 1e6") {
    // binary32 spacing at 1e6 is 0.0625: vertices, lights and the eye snap to it, so the image
    // is not the room's, but every technique agrees with itself and with forward.
    // Positions carry up to 0.03 units of rounding, which the double-precision reference does
    // not: 6 codes on about half the pixels. The light volume's vertices and forward's range test
    // round differently by that much, so a pixel lying within 0.03 of a range boundary (where the
    // attenuation is below 1e-2) may fall on either side: at most 1 pixel here.
    CaseOptions o;
    o.maxReferenceCodes = 8;
    o.maxEqualityPixels = 1;
    runCase("geometry translated 1e6", translated(room(), {1e6f, -1e6f, 1e6f}), o);
}

TEST_CASE("geometry: sliver triangles 1e-4 wide") {
    TestScene t = room();
    t = withTriangle(t, {{-5.0f, 0.5f, -2.0f}, {5.0f, 0.5f, -2.0f}, {-5.0f, 0.5001f, -2.0f}, {5.0f, 0.5001f, -2.0f}}, {0, 1, 2, 1, 3, 2});
    runCase("geometry slivers", t);
}

TEST_CASE("geometry: a vertex at w = 0 (in the eye plane)") {
    TestScene t = room();
    t = withTriangle(t, {fromView(t, {-1.0f, 0.0f, 0.0f}), fromView(t, {1.0f, -1.0f, -5.0f}), fromView(t, {1.0f, 1.0f, -5.0f})}, {0, 1, 2});
    runCase("geometry vertex at w 0", t);
}

TEST_CASE("geometry: a triangle across the near plane") {
    TestScene t = room();
    t = withTriangle(t, {fromView(t, {-1.0f, 0.0f, -0.05f}), fromView(t, {1.0f, -1.0f, -3.0f}), fromView(t, {1.0f, 1.0f, -3.0f})}, {0, 1, 2});
    runCase("geometry across the near plane", t);
}

TEST_CASE("geometry: a triangle through the eye plane (one vertex behind the eye)") {
    TestScene t = room();
    t = withTriangle(t, {fromView(t, {-1.0f, 0.0f, 2.0f}), fromView(t, {1.0f, -1.0f, -3.0f}), fromView(t, {1.0f, 1.0f, -3.0f})}, {0, 1, 2});
    runCase("geometry through the eye plane", t);
}

TEST_CASE("geometry: a triangle entirely behind the eye") {
    TestScene t = room();
    t = withTriangle(t, {fromView(t, {-1.0f, 0.0f, 2.0f}), fromView(t, {1.0f, -1.0f, 3.0f}), fromView(t, {1.0f, 1.0f, 3.0f})}, {0, 1, 2});
    runCase("geometry behind the eye", t);
}

TEST_CASE("geometry: degenerate triangles (collinear and repeated vertices)") {
    TestScene t = room();
    t = withTriangle(t, {{-2.0f, 1.0f, -1.0f}, {0.0f, 1.0f, -1.0f}, {2.0f, 1.0f, -1.0f}, {1.0f, 2.0f, -1.0f}}, {0, 1, 2, 3, 3, 3, 0, 0, 1});
    runCase("geometry degenerate", t);
}

TEST_CASE("geometry: a triangle 1e30 wide (beyond the guard band)") {
    TestScene t = room();
    t = withTriangle(t, {{-1e30f, -1e30f, -5.5f}, {1e30f, -1e30f, -5.5f}, {0.0f, 1e30f, -5.5f}}, {0, 1, 2});
    runCase("geometry 1e30 wide", t);
}

TEST_CASE("geometry: coincident surfaces (the same quad twice)") {
    // Equal depths: LESS keeps the first, LESS_EQUAL the last; every technique must still give
    // the same bytes at 1, 2 and 3 threads (draw order is submission order).
    TestScene t = room();
    t = withTriangle(t, {{-2.0f, 0.5f, -1.0f}, {2.0f, 0.5f, -1.0f}, {2.0f, 2.5f, -1.0f}, {-2.0f, 2.5f, -1.0f}}, {0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 2, 3});
    CaseOptions o;
    o.equalities = false;  // forward (LESS) and the pre-pass techniques (LESS_EQUAL) may pick either copy
    runCase("geometry coincident", t, o);
}

TEST_CASE("geometry: world scaled by every decade from 1e-20 to 1e20, no NaN in any buffer") {
    // Scale 1e20 (camera 7e20 from the origin, near 1e19, far 1e22): the projection's
    // -(f n) / (f - n) overflowed (f n = 1e41), so the inverse projection and forward-plus's
    // `frustums` held NaN (960 texels at 16-px tiles); scale 1e-20 puts f n = 1e-39 below the
    // normal range. nearFarTerm (math/projection_terms.h) rescales by powers of two there.
    // Lighting squares view distances in binary32: beyond ~1e19 they overflow (every light
    // falls out of range, the image is ambient) and below ~1e-19 they lose bits, while
    // `reference` squares them in double: the error against reference is not bounded here.
    // At 1e20 the vertex shaders' view normals have length 1e20: hlsl::normalize's power-of-two
    // rescue keeps them unit (before it, their square overflowed, normalize returned 0 and the
    // Cookbook and PR&C G-buffers stored NaN in gbuffer.normal on every covered pixel).
    // Every buffer must stay finite, identical at 1, 2 and 3 threads, and the corrected culling
    // must equal forward at every decade.
    for (int decade = -20; decade <= 20; ++decade) {
        CAPTURE(decade);
        const float s = static_cast<float>(std::pow(10.0, decade));
        CaseOptions o;
        o.maxReferenceCodes = 255;
        runCase("geometry decade 1e" + std::to_string(decade), scaled(room(), s), o);
    }
}

} // namespace tessera_test::extremes_geometry_extremes_test
