// Extremes catalogue, projection: near/far ratios up to 1e23, near planes down to the smallest
// normal float, fields of view of 0.5 and 179 degrees, aspect 1:1000 and 1000:1, orthographic
// cameras, an infinite far plane, and near and far planes that cut through the scene.
#include <limits>

#include "extremes/extremes.h"
#include "extremes/scenes.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::extremes_projection_extremes_test {

using namespace tessera;
using namespace tessera::test;
using namespace tessera::test::extremes;

namespace {

// Every ready technique must refuse `t` with an InputError whose text contains `what`.
void expectRefused(const TestScene& t, const std::string& what) {
    for (const std::string& technique : readyTechniques()) {
        CAPTURE(technique);
        Rendered r;
        CHECK_THROWS_WITH_AS(render(t, technique, nlohmann::json::object(), r), doctest::Contains(what.c_str()), InputError);
    }
}

} // namespace

TEST_CASE("projection: near 1e-5 far 1e7 (ratio 1e12)") {
    // At distance 20 one depth step spans 20^2 x 6e-8 / 1e-5 = 2.4 view units (12%): warned, and
    // depth-bounded culling and stencil volumes are only that exact (284 pixels of deferred's
    // stencil marking and 26 of forward-plus's tile bounds differ from forward).
    CaseOptions o;
    o.depthWarning = true;
    runCase("projection near 1e-5 far 1e7", withNearFar(room(), 1e-5f, 1e7f), o);
}

TEST_CASE("projection: near 1e-3 far 1e5 (ratio 1e8) resolves the room") {
    // Step at distance 20: 20^2 x 6e-8 / 1e-3 = 0.024 units (0.12%): no warning, equalities hold.
    runCase("projection near 1e-3 far 1e5", withNearFar(room(), 1e-3f, 1e5f));
}

TEST_CASE("projection: near 1e-7 far 1e9 (ratio 1e16) collapses every depth to 1.0") {
    // n/z ~ 1e-8 < half a step: every surface stores 1.0, the cleared value. Forward's LESS test
    // draws nothing; the pre-pass techniques (LESS_EQUAL) draw unsorted. Warned, not refused:
    // that is what D3D11 does with this projection.
    CaseOptions o;
    o.depthWarning = true;
    o.maxReferenceCodes = 0;
    const CaseReport r = runCase("projection near 1e-7 far 1e9", withNearFar(room(), 1e-7f, 1e9f), o);
    CHECK(r.referencePixels == 0);
}

TEST_CASE("projection: near 1e-21") {
    // Every depth rounds to 1.0 (n/z ~ 1e-22): warned. The tile planes stay finite: the plane
    // normals' power-of-two rescue (cullmath::unitCross).
    CaseOptions o;
    o.depthWarning = true;
    o.maxReferenceCodes = 0;
    runCase("projection near 1e-21", withNearFar(room(), 1e-21f, 100.0f), o);
}

TEST_CASE("projection: near at the smallest normal float") {
    CaseOptions o;
    o.depthWarning = true;
    o.maxReferenceCodes = 0;
    runCase("projection near FLT_MIN", withNearFar(room(), std::numeric_limits<float>::min(), 100.0f), o);
}

TEST_CASE("projection: a subnormal near plane is refused") {
    // n f / (f - n) and the inverse projection lose every bit below FLT_MIN (checkFrameInputs).
    expectRefused(withNearFar(room(), 1e-45f, 100.0f), "positive normal binary32");
}

TEST_CASE("projection: far below near is refused") {
    expectRefused(withNearFar(room(), 10.0f, 1.0f), "is not greater than near");
}

TEST_CASE("projection: far equal to near is refused") {
    expectRefused(withNearFar(room(), 1.0f, 1.0f), "is not greater than near");
}

TEST_CASE("projection: FOV 0.5 degrees") {
    TestScene t = room();
    t.camera.fovYDeg = 0.5f;
    runCase("projection fov 0.5", t);
}

TEST_CASE("projection: FOV 179 degrees") {
    TestScene t = room();
    t.camera.fovYDeg = 179.0f;
    runCase("projection fov 179", t);
}

TEST_CASE("projection: FOV 180 degrees is refused") {
    TestScene t = room();
    t.camera.fovYDeg = 180.0f;
    expectRefused(t, "outside (0, 180)");
}

TEST_CASE("projection: aspect 1:1000") {
    TestScene t = room();
    t.camera.aspect = 0.001f;
    runCase("projection aspect 1:1000", t);
}

TEST_CASE("projection: aspect 1000:1") {
    TestScene t = room();
    t.camera.aspect = 1000.0f;
    runCase("projection aspect 1000:1", t);
}

TEST_CASE("projection: orthographic") {
    // forward-plus built its tile planes through the eye, which for parallel rays are not the
    // tile's sides; here the demo's corners (view z = f - 2n = 99.8, behind the eye) make them
    // nearly right, the next case shows them fail: gridFrustumOrthographic.
    TestScene t = room();
    t.camera.projection = ProjectionKind::Orthographic;
    t.camera.xMag = 8.0f;
    t.camera.yMag = 6.0f;
    CaseOptions o;
    o.refused = {"tiled-deferred"};  // Intel's tile planes are built for a perspective projection
    runCase("projection orthographic", t, o);
}

TEST_CASE("projection: orthographic with far = 2 x near") {
    // The demo's corners at NDC z = -1 lie at view z = f - 2n under an orthographic ZO projection:
    // here 0, the eye itself, so planes through the eye and those corners are degenerate (the
    // prober's NaN frustums). Planes through near and far corners do not depend on it.
    TestScene t = withNearFar(room(), 4.5f, 9.0f);
    t.camera.projection = ProjectionKind::Orthographic;
    t.camera.xMag = 8.0f;
    t.camera.yMag = 6.0f;
    CaseOptions o;
    o.refused = {"tiled-deferred"};
    runCase("projection orthographic far 2 near", t, o);
}

TEST_CASE("projection: orthographic with a 1e-4 wide view") {
    TestScene t = room();
    t.camera.projection = ProjectionKind::Orthographic;
    t.camera.xMag = 1e-4f;
    t.camera.yMag = 0.75e-4f;
    CaseOptions o;
    o.refused = {"tiled-deferred"};
    runCase("projection orthographic 1e-4", t, o);
}

TEST_CASE("projection: orthographic with near 0 (the eye on the near plane)") {
    // glTF 2.0 §5.13 allows camera.orthographic.znear = 0: depth (zView - 0) / f, the tile planes
    // through near corners on the eye plane (gridFrustumOrthographic) and far corners.
    TestScene t = withNearFar(room(), 0.0f, 100.0f);
    t.camera.projection = ProjectionKind::Orthographic;
    t.camera.xMag = 8.0f;
    t.camera.yMag = 6.0f;
    CaseOptions o;
    o.refused = {"tiled-deferred"};
    runCase("projection orthographic near 0", t, o);
}

TEST_CASE("projection: orthographic with near 0 and far through the room") {
    // far 11 cuts the floor: the far plane's clipping with the near plane on the eye.
    TestScene t = withNearFar(room(), 0.0f, 11.0f);
    t.camera.projection = ProjectionKind::Orthographic;
    t.camera.xMag = 8.0f;
    t.camera.yMag = 6.0f;
    CaseOptions o;
    o.refused = {"tiled-deferred"};
    runCase("projection orthographic near 0 far 11", t, o);
}

TEST_CASE("projection: near 0 is refused for a perspective camera") {
    expectRefused(withNearFar(room(), 0.0f, 100.0f), "only an orthographic camera may take near 0");
}

TEST_CASE("projection: infinite far plane") {
    // glTF's infinite perspective (zfar absent): far = +inf.
    TestScene t = withNearFar(room(), 0.1f, std::numeric_limits<float>::infinity());
    runCase("projection infinite far", t);
}

TEST_CASE("projection: the near plane cuts through the room") {
    // near 7.5: the floor and the lights' volumes cross the near plane; clipped triangles.
    runCase("projection near plane through the scene", withNearFar(room(), 7.5f, 100.0f));
}

TEST_CASE("projection: the far plane cuts through the room") {
    runCase("projection far plane through the scene", withNearFar(room(), 0.1f, 11.0f));
}

} // namespace tessera_test::extremes_projection_extremes_test
