// Extremes catalogue, geometry: the whole world scaled by 1e-15 .. 1e15 or moved 1e6 away,
// triangles of 1e-6, slivers, vertices at w = 0, triangles across the near plane and behind the eye.
#include "extremes/extremes.h"
#include "extremes/scenes.h"

using namespace tessera;
using namespace tessera::test;
using namespace tessera::test::extremes;

TEST_CASE("geometry: world scaled by 1e-15") {
    runCase("geometry scale 1e-15", scaled(room(), 1e-15f));
}

TEST_CASE("geometry: world scaled by 1e-10") {
    runCase("geometry scale 1e-10", scaled(room(), 1e-10f));
}
