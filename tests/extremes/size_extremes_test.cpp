// Extremes catalogue, sizes: 1x1, 2x2, 1x17 and 17x1 targets, 67x37 (no multiple of any tile
// size), and 16384x16 / 16x16384 strips at the largest surface dimension.
#include "extremes/extremes.h"
#include "extremes/scenes.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::extremes_size_extremes_test {

using namespace tessera;
using namespace tessera::test;
using namespace tessera::test::extremes;

namespace {

CaseOptions sized(std::uint32_t w, std::uint32_t h) {
    CaseOptions o;
    o.sizePx = {w, h};
    return o;
}

// The strips: 262,144 pixels each, so the techniques with tiles and compute dispatches (where a
// dimension of 16384 meets tile counts and group counts) and forward as the equality anchor,
// without the thread sweep (262k-pixel frames x 3 thread counts x 10 techniques under ASan).
CaseOptions strip(std::uint32_t w, std::uint32_t h) {
    CaseOptions o = sized(w, h);
    o.techniques = {"forward", "deferred", "forward-plus", "forward-plus-amd", "tiled-deferred"};
    o.threadAgreement = false;
    o.equalities = false;
    return o;
}

} // namespace

TEST_CASE("sizes: 1x1") { runCase("sizes 1x1", room(), sized(1, 1)); }

TEST_CASE("sizes: 2x2") { runCase("sizes 2x2", room(), sized(2, 2)); }

TEST_CASE("sizes: 1x17") { runCase("sizes 1x17", room(), sized(1, 17)); }

TEST_CASE("sizes: 17x1") { runCase("sizes 17x1", room(), sized(17, 1)); }

TEST_CASE("sizes: 67x37 (no multiple of 8, 16 or 32)") { runCase("sizes 67x37", room(), sized(67, 37)); }

TEST_CASE("sizes: 33x65 (one pixel past a tile multiple)") { runCase("sizes 33x65", room(), sized(33, 65)); }

TEST_CASE("sizes: 16384x16") { runCase("sizes 16384x16", room(), strip(16384, 16)); }

TEST_CASE("sizes: 16x16384") { runCase("sizes 16x16384", room(), strip(16, 16384)); }

} // namespace tessera_test::extremes_size_extremes_test
