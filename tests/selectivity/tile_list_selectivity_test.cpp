// The tiled techniques' light lists against geometric truth in double, per tile: the opaque list
// holds every light that reaches a surface point of the tile (its pixels' surfaces rebuilt from the
// pre-pass depth), the transparent list every light that reaches the tile's frustum between the
// near plane and the opaque max depth; and no list holds a light that is wholly outside one of the
// tile's planes (the culling's own conservative bound). How much longer the lists are than the
// lights that reach a surface is reported, not asserted.
#include "selectivity/selectivity.h"

#include <cstring>
#include <set>
#include <utility>

#include <tessera/techniques/forward_plus_amd.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera::test::selectivity::tile_list_selectivity_test {
namespace {

// 48 point and 16 spot lights of range 0.4-1.6 scattered over the room's lower part, many of
// them hanging in the air in front of the floor and the wall (what the transparent lists see).
TestScene litRoom() {
    std::vector<Light> lights;
    std::uint64_t state = 0x9E3779B97F4A7C15ull;  // splitmix64: a fixed sequence, no library
    const auto next = [&state] {
        std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return double((z ^ (z >> 31)) >> 11) / double(1ull << 53);  // [0, 1)
    };
    const auto in = [&](double lo, double hi) { return float(lo + (hi - lo) * next()); };
    for (int i = 0; i < 64; ++i) {
        const glm::vec3 pos{in(-4.0, 4.0), in(0.1, 3.0), in(-5.8, 5.0)};
        const float range = in(0.4, 1.6);
        if (i % 4 == 3) {
            const glm::vec3 dir{in(-0.5, 0.5), -1.0f, in(-0.5, 0.5)};
            lights.push_back(makeLight(LightType::Spot, pos, dir, range, {1, 1, 1}, in(15.0, 45.0)));
        } else {
            lights.push_back(makeLight(LightType::Point, pos, {0, 0, -1}, range, {1, 1, 1}));
        }
    }
    return makeScene(lights);
}

std::vector<std::uint32_t> readList(const Surface& grid, const Surface& pool, std::uint32_t tx, std::uint32_t ty) {
    std::uint32_t entry[2];
    std::memcpy(entry, grid.texel(tx, ty), sizeof(entry));
    std::vector<std::uint32_t> list(entry[1]);
    for (std::uint32_t i = 0; i < entry[1]; ++i) {
        const std::uint32_t e = entry[0] + i;
        std::memcpy(&list[i], pool.texel(e % pool.width(), e / pool.width()), sizeof(std::uint32_t));
    }
    return list;
}

// Margin in world units, as in deferred_selectivity_test.cpp (D24 step and vertex snapping at the
// farthest surfaces, 1.3e-4 and 3.4e-4, times three); the tile planes and depth bounds here are
// built by the technique in float from the same depths: 1e-5 relative at distance 15 is 1.5e-4.
constexpr double kMargin = 2e-3;

struct ListTally {
    std::uint64_t tiles = 0, needed = 0, listed = 0, missing = 0, outsidePlane = 0;
};

// The light's region: sphere of its range, or the cone ended by that sphere (forward's tests).
double lightExcess(const Light& l, const glm::dvec3& pWorld) { return volumeExcess(l, pWorld, 1.0, 1.0, true); }

// Does the eye ray segment [tNear, tFar] (world distance along a unit ray) enter the light's
// region by more than the margin? Points: closest approach, exactly; spots: 96 points along the
// segment (a sampled subset: truth can only be missed, never invented).
bool segmentReaches(const Light& l, const glm::dvec3& eye, const glm::dvec3& ray, double tNear, double tFar) {
    if (!(tFar > tNear)) return false;
    if (l.type == LightType::Point) {
        const glm::dvec3 c(l.positionWorld);
        const double t = std::clamp(glm::dot(c - eye, ray), tNear, tFar);
        return glm::length(eye + t * ray - c) < double(l.range) - kMargin;
    }
    for (int i = 0; i <= 95; ++i) {
        const double t = tNear + (tFar - tNear) * i / 95.0;
        if (lightExcess(l, eye + t * ray) < -kMargin) return true;
    }
    return false;
}

// The technique's six tile planes in the view space of the eye (RH, z < 0 ahead), exact in double:
// sides through the tile's pixel-corner rays, near / far at view depths zNear / zFar.
// Returns how far the sphere (centreWorld, r) lies wholly outside the farthest of them (> 0:
// outside that plane, so no conservative culler of a light inside that sphere may keep it).
double sphereOutsideTile(const glm::dvec3& centreWorld, double r, const glm::dmat4& viewFromWorld, double p00, double p11,
                         std::uint32_t tx, std::uint32_t ty, std::uint32_t tilePx, double zNear, double zFar) {
    const glm::dvec3 c = glm::dvec3(viewFromWorld * glm::dvec4(centreWorld, 1.0));
    const double x0 = 2.0 * double(tx * tilePx) / kW - 1.0, x1 = 2.0 * double(std::min((tx + 1) * tilePx, kW)) / kW - 1.0;
    const double y1 = 1.0 - 2.0 * double(ty * tilePx) / kH, y0 = 1.0 - 2.0 * double(std::min((ty + 1) * tilePx, kH)) / kH;
    // inside iff n . c >= 0 for the side planes (normals inward, through the eye)
    const glm::dvec3 n[4] = {glm::normalize(glm::dvec3(p00, 0, x0)), glm::normalize(glm::dvec3(-p00, 0, -x1)),
                             glm::normalize(glm::dvec3(0, -p11, -y1)), glm::normalize(glm::dvec3(0, p11, y0))};
    double out = -HUGE_VAL;
    for (const glm::dvec3& ni : n) out = std::max(out, -glm::dot(ni, c) - r);
    out = std::max(out, (zNear - (-c.z)) - r);  // in front of the near plane
    out = std::max(out, ((-c.z) - zFar) - r);   // beyond the far plane
    return out;
}

struct TiledCase {
    const char* technique;
    std::uint32_t tilePx;
    nlohmann::json options;
    bool amdSpotSpheres;  // spots culled by ForwardPlus11's sphere around the cone (forward_plus_amd.h)
};

// A sphere holding everything the culler may test a light by: the point's range sphere; a spot's
// flat-based cone (3dgep: apex, height R, base radius R tan(angle)) lies in the sphere about the
// apex of radius R / cos(angle); AMD tests its own sphere around the cone.
std::pair<glm::dvec3, double> cullSphere(const Light& l, bool amdSpotSpheres) {
    const glm::dvec3 apex(l.positionWorld);
    if (l.type != LightType::Spot) return {apex, double(l.range)};
    if (amdSpotSpheres) {
        const SpotBoundingSphere b = spotBoundingSphere(l.range, l.spotHalfAngleDeg);
        return {apex + double(b.centerOffset) * glm::normalize(glm::dvec3(l.directionWorld)), double(b.radius)};
    }
    return {apex, double(l.range) / std::cos(glm::radians(double(l.spotHalfAngleDeg)))};
}

void checkLists(const TiledCase& tc) {
    const TestScene t = litRoom();
    ShadeFrame f = renderCounted(t, tc.technique, tc.options);
    const Camera& cam = t.camera;
    const std::vector<PixelSurface> px = surfaces(f.rendered.get("depth"), cam);
    const glm::dmat4 viewFromWorld(cam.viewFromWorld());
    const double tanHalf = std::tan(glm::radians(double(cam.fovYDeg)) / 2.0);
    const double p11 = 1.0 / tanHalf, p00 = p11 * double(kH) / double(kW);
    const std::uint32_t tilesX = (kW + tc.tilePx - 1) / tc.tilePx, tilesY = (kH + tc.tilePx - 1) / tc.tilePx;
    const std::vector<Light>& lights = t.scene.lights;
    ListTally opaque, transparent;
    for (std::uint32_t ty = 0; ty < tilesY; ++ty)
        for (std::uint32_t tx = 0; tx < tilesX; ++tx) {
            // The tile's opaque depth range in view depth (-z), from the rebuilt surfaces; a pixel
            // without a surface counts as the far plane (the pre-pass's cleared 1.0).
            double zMin = HUGE_VAL, zMax = -HUGE_VAL;
            std::vector<std::size_t> pixels;
            for (std::uint32_t y = ty * tc.tilePx; y < std::min((ty + 1) * tc.tilePx, kH); ++y)
                for (std::uint32_t x = tx * tc.tilePx; x < std::min((tx + 1) * tc.tilePx, kW); ++x) {
                    const std::size_t i = std::size_t(y) * kW + x;
                    pixels.push_back(i);
                    const double z = px[i].surface ? -(viewFromWorld * glm::dvec4(px[i].posWorld, 1.0)).z : double(cam.farZ);
                    zMin = std::min(zMin, z);
                    zMax = std::max(zMax, z);
                }
            const std::vector<std::uint32_t> oList = readList(f.rendered.get("lightgrid.opaque"), f.rendered.get("lightindex.opaque"), tx, ty);
            const std::vector<std::uint32_t> tList =
                readList(f.rendered.get("lightgrid.transparent"), f.rendered.get("lightindex.transparent"), tx, ty);
            std::set<std::uint32_t> oSet(oList.begin(), oList.end());
            if (f.rendered.registry.contains("lightgrid.opaque.far")) {  // AMD's half-Z: a pixel reads one of two lists
                const std::vector<std::uint32_t> farList =
                    readList(f.rendered.get("lightgrid.opaque.far"), f.rendered.get("lightindex.opaque"), tx, ty);
                oSet.insert(farList.begin(), farList.end());
            }
            const std::set<std::uint32_t> tSet(tList.begin(), tList.end());
            ++opaque.tiles;
            ++transparent.tiles;
            opaque.listed += oList.size();
            transparent.listed += tList.size();
            for (std::uint32_t li = 0; li < lights.size(); ++li) {
                const Light& l = lights[li];
                bool touchesSurface = false, reachesFront = false;
                for (const std::size_t i : pixels) {
                    const PixelSurface& p = px[i];
                    if (p.surface && lightExcess(l, p.posWorld) < -kMargin) touchesSurface = true;
                    if (touchesSurface) break;
                }
                // Transparent truth: the pixel rays between the near plane and the tile's max depth.
                for (const std::size_t i : pixels) {
                    const PixelSurface& p = px[i];
                    const double cosRay = -(viewFromWorld * glm::dvec4(p.rayWorld, 0.0)).z;  // view depth per unit length
                    if (segmentReaches(l, p.eyeWorld, p.rayWorld, double(cam.nearZ) / cosRay, zMax / cosRay)) {
                        reachesFront = true;
                        break;
                    }
                }
                opaque.needed += touchesSurface;
                transparent.needed += reachesFront;
                if (touchesSurface && !oSet.count(li)) {
                    ++opaque.missing;
                    MESSAGE(std::string(tc.technique) << ": tile (" << tx << ", " << ty << ") opaque list lacks light " << li);
                }
                if (reachesFront && !tSet.count(li)) {
                    ++transparent.missing;
                    MESSAGE(std::string(tc.technique) << ": tile (" << tx << ", " << ty << ") transparent list lacks light " << li);
                }
                const std::pair<glm::dvec3, double> bound = cullSphere(l, tc.amdSpotSpheres);
                if (oSet.count(li) &&
                    sphereOutsideTile(bound.first, bound.second, viewFromWorld, p00, p11, tx, ty, tc.tilePx, zMin, zMax) > kMargin)
                    ++opaque.outsidePlane;
                if (tSet.count(li) && sphereOutsideTile(bound.first, bound.second, viewFromWorld, p00, p11, tx, ty, tc.tilePx,
                                                        double(cam.nearZ), zMax) > kMargin)
                    ++transparent.outsidePlane;
            }
        }
    const auto report = [&](const char* which, const ListTally& lt) {
        MESSAGE(std::string(tc.technique) << " " << std::string(which) << " lists over " << lt.tiles << " tiles: " << lt.listed << " entries, "
                             << lt.needed << " needed (" << (lt.needed ? double(lt.listed) / double(lt.needed) : 0.0)
                             << "x), missing " << lt.missing << ", wholly outside a tile plane " << lt.outsidePlane);
    };
    report("opaque", opaque);
    report("transparent", transparent);
    CHECK(opaque.needed > 20);        // the lights do reach surfaces
    CHECK(transparent.needed > opaque.needed);  // and hang in front of them
    CHECK(opaque.missing == 0);
    CHECK(transparent.missing == 0);
    CHECK(opaque.outsidePlane == 0);
    CHECK(transparent.outsidePlane == 0);
}

} // namespace

TEST_CASE("selectivity forward-plus: every light that reaches a tile's surface or its transparent range is listed, none wholly outside it") {
    // The article's cone test misses lights (ERRATA #10): the corrected one, and unbounded lists.
    checkLists({"forward-plus", 16, {{"projection", "d3d"}, {"coneTest", "corrected"}, {"lightLists", "unbounded"}}, false});
}

TEST_CASE("selectivity forward-plus-amd: every light that reaches a tile's surface or its transparent range is listed, none wholly outside it") {
    checkLists({"forward-plus-amd", 8, {{"shading", "3dgep"}, {"projection", "d3d"}}, true});
}

} // namespace tessera::test::selectivity::tile_list_selectivity_test
