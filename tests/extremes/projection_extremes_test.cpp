// Extremes catalogue, projection: near/far ratios up to 1e16, near planes down to the smallest
// float, fields of view of 0.5 and 179 degrees, aspect 1:1000 and 1000:1, orthographic cameras.
#include "extremes/extremes.h"
#include "extremes/scenes.h"

using namespace tessera;
using namespace tessera::test;
using namespace tessera::test::extremes;

TEST_CASE("projection: near 1e-5 far 1e7 (ratio 1e12)") {
    // At distance 20 one depth step spans 20^2 x 6e-8 / 1e-5 = 2.4 view units (12%): warned, and
    // depth-bounded culling and stencil volumes are only that exact (284 pixels of deferred's
    // stencil marking and 26 of forward-plus's tile bounds differ from forward).
    CaseOptions o;
    o.depthWarning = true;
    runCase("projection near 1e-5 far 1e7", withNearFar(room(), 1e-5f, 1e7f), o);
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

TEST_CASE("projection: near 1e-21") {
    // Every depth rounds to 1.0 (n/z ~ 1e-22): forward's LESS test draws nothing, the pre-pass
    // techniques draw unsorted. Warned; the tile planes stay finite (unitCross, the ZO corners).
    CaseOptions o;
    o.depthWarning = true;
    o.maxReferenceCodes = 0;
    runCase("projection near 1e-21", withNearFar(room(), 1e-21f, 100.0f), o);
}

TEST_CASE("projection: orthographic") {
    TestScene t = room();
    t.camera.projection = ProjectionKind::Orthographic;
    t.camera.xMag = 8.0f;
    t.camera.yMag = 6.0f;
    CaseOptions o;
    o.refused = {"tiled-deferred"};  // Intel's tile planes are built for a perspective projection
    runCase("projection orthographic", t, o);
}
