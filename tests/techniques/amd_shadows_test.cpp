// forward-plus-amd's ray-cast shadows (GPU Pro 4 ch. 5 §5.6.2) on hand-built scenes whose
// occluders are known: the per-pixel shadow mask against a brute-force occlusion test in double
// precision over every triangle (a plane between a light and a floor, a light on a surface,
// grazing rays and the acne the normal offset removes, more than 128 lights in a pixel), the job
// format's bit split, masked lights shading as absent lights, and 1 = 2 = 7 threads.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <tessera/errors/input_error.h>
#include <tessera/techniques/amd_shadow_rays.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/technique.h>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::techniques_amd_shadows_test {

using namespace tessera;
using tessera::test::sameBytes;

namespace {

constexpr std::uint32_t kW = 96, kH = 64;  // px: 12 x 8 tiles of 8 px

// Opaque grey material; floor 20 x 20 at y = 0 facing up; optional extra quads.
test::TestScene shadowScene(const std::vector<Light>& lights, const std::vector<MeshPrimitive>& extra, glm::vec3 eye) {
    test::TestScene t;
    Material grey;
    grey.baseColorFactor = {0.7f, 0.7f, 0.7f, 1.0f};
    grey.doubleSided = true;
    t.scene.materials = {grey};
    Mesh mesh;
    mesh.primitives.push_back(test::quad({-10.0f, 0.0f, 10.0f}, {20.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -20.0f}, 0));
    for (const MeshPrimitive& p : extra) mesh.primitives.push_back(p);
    t.scene.meshes.push_back(mesh);
    t.scene.instances.push_back(MeshInstance{0, glm::mat4(1.0f), "floor"});
    t.scene.lights = lights;
    t.camera.positionWorld = eye;
    t.camera.orientationWorld = glm::quatLookAtRH(glm::normalize(glm::vec3(0.0f, 0.0f, 0.0f) - eye), glm::vec3(0, 1, 0));
    t.camera.nearZ = 0.1f;
    t.camera.farZ = 100.0f;
    return t;
}

Light caster(glm::vec3 position, float range, glm::vec3 color = glm::vec3(1.0f)) {
    Light l = test::makeLight(LightType::Point, position, {0, 0, -1}, range, color);
    l.castsShadows = true;
    return l;
}

test::Rendered render(const test::TestScene& t, const nlohmann::json& options, std::uint32_t threads = 2) {
    test::Rendered out;
    test::render(t, "forward-plus-amd", options, out, Precision::Exact, threads, {kW, kH});
    return out;
}

// The buffers job creation read, back from the registry, and the rebuild's matrix formed as the
// technique forms it (forward.h projection3dgep, D3D convention: forward-plus-amd's default).
struct PixelData {
    std::vector<float> depth;
    std::vector<glm::vec4> normal;
    ShadowPixels pixels;
};
PixelData pixelData(test::Rendered& r, const Camera& camera) {
    PixelData d;
    const Surface& depth = r.get("depth");
    const Surface& normal = r.get("gbuffer.normal");
    d.depth.resize(std::size_t{kW} * kH);
    d.normal.resize(std::size_t{kW} * kH);
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x) {
            d.depth[std::size_t{y} * kW + x] = depth.loadDepth(x, y);
            std::memcpy(&d.normal[std::size_t{y} * kW + x], normal.texel(x, y), sizeof(glm::vec4));
        }
    const glm::dmat4 clipFromWorld = glm::dmat4(projection3dgep(camera, float(kW) / float(kH), ProjectionConvention::D3d)) *
                                     glm::dmat4(camera.viewFromWorld());
    d.pixels = ShadowPixels{kW, kH, d.depth, d.normal, glm::inverse(clipFromWorld)};
    return d;
}

// A pixel's opaque tile list, read from "lightgrid.opaque" / "lightindex.opaque".
std::vector<std::uint32_t> tileList(test::Rendered& r, std::uint32_t x, std::uint32_t y) {
    const Surface& grid = r.get("lightgrid.opaque");
    const Surface& pool = r.get("lightindex.opaque");
    std::uint32_t entry[2];
    std::memcpy(entry, grid.texel(x / 8, y / 8), sizeof(entry));
    std::vector<std::uint32_t> list(entry[1]);
    for (std::uint32_t i = 0; i < entry[1]; ++i) {
        const std::uint32_t e = entry[0] + i;
        std::memcpy(&list[i], pool.texel(e % pool.width(), e / pool.width()), sizeof(std::uint32_t));
    }
    return list;
}

std::array<std::uint32_t, 4> maskAt(test::Rendered& r, std::uint32_t x, std::uint32_t y) {
    std::array<std::uint32_t, 4> m{};
    std::memcpy(m.data(), r.get("shadow.mask").texel(x, y), sizeof(m));
    return m;
}

std::array<std::uint32_t, 5> counters(test::Rendered& r) {
    std::array<std::uint32_t, 5> c{};
    std::memcpy(c.data(), r.get("shadow.counters").texel(0, 0), sizeof(c));
    return c;
}

// Every triangle of the scene in world space, in double.
std::vector<std::array<glm::dvec3, 3>> trianglesOf(const Scene& scene) {
    std::vector<std::array<glm::dvec3, 3>> out;
    for (const MeshInstance& inst : scene.instances)
        for (const MeshPrimitive& p : scene.meshes[inst.mesh].primitives)
            for (std::size_t i = 0; i + 2 < p.indices.size(); i += 3) {
                std::array<glm::dvec3, 3> t;
                for (int k = 0; k < 3; ++k)
                    t[k] = glm::dvec3(glm::dmat4(inst.worldFromObject) * glm::dvec4(glm::dvec3(p.positionsObject[p.indices[i + k]]), 1.0));
                out.push_back(t);
            }
    return out;
}

enum class Truth { Lit, Shadowed, Ambiguous };

// Whether the segment o + t d, t in [0, tFar], meets a triangle (Moller-Trumbore in double).
// Ambiguous when a hit or miss is decided within `eps` of an edge (barycentric), of the
// segment's ends (t), or of the triangle's plane (a ray in it): float Embree may go either way.
Truth bruteForce(const std::vector<std::array<glm::dvec3, 3>>& tris, glm::dvec3 o, glm::dvec3 d, double tFar) {
    constexpr double eps = 1e-5;
    bool ambiguous = false;
    for (const auto& tri : tris) {
        const glm::dvec3 e1 = tri[1] - tri[0], e2 = tri[2] - tri[0];
        const glm::dvec3 p = glm::cross(d, e2);
        const double det = glm::dot(e1, p);
        const double scale = glm::length(d) * glm::length(e1) * glm::length(e2);
        if (std::fabs(det) <= eps * scale) {
            // Ray parallel to the plane: only ambiguous if it runs inside it.
            const glm::dvec3 n = glm::normalize(glm::cross(e1, e2));
            if (std::fabs(glm::dot(o - tri[0], n)) < eps) ambiguous = true;
            continue;
        }
        const glm::dvec3 s = o - tri[0];
        const double u = glm::dot(s, p) / det;
        const glm::dvec3 q = glm::cross(s, e1);
        const double v = glm::dot(d, q) / det;
        const double t = glm::dot(e2, q) / det;
        const double w = 1.0 - u - v;
        const double margin = std::min({u, v, w});
        const double tMargin = std::min(t, tFar - t) * glm::length(d);
        if (margin > eps && tMargin > eps) return Truth::Shadowed;
        if (margin > -eps && tMargin > -eps) ambiguous = true;
    }
    return ambiguous ? Truth::Ambiguous : Truth::Lit;
}

struct MaskCheck {
    std::uint64_t jobsChecked = 0, shadowed = 0, lit = 0, ambiguous = 0, mismatches = 0, backface = 0;
};

// Every slot < 128 of every drawn pixel: the mask bit against the brute-force truth. Job
// creation's rules, restated: only casting lights within range make jobs; a light with
// dot(N, L) <= 0 is masked without a ray (ShadowBackfaces::Mask) or cast (Cast).
MaskCheck checkMask(test::Rendered& r, const test::TestScene& t, float normalOffset, bool castBackfaces = false) {
    MaskCheck c;
    const PixelData d = pixelData(r, t.camera);
    const auto tris = trianglesOf(t.scene);
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x) {
            const std::uint32_t pixel = y * kW + x;
            const std::array<std::uint32_t, 4> mask = maskAt(r, x, y);
            if (!(d.depth[pixel] < 1.0f)) {
                CHECK(mask == std::array<std::uint32_t, 4>{});
                continue;
            }
            const std::vector<std::uint32_t> list = tileList(r, x, y);
            const glm::vec3 pos = shadowSurfacePoint(d.pixels, pixel);
            const glm::vec3 origin = shadowRayOrigin(d.pixels, pixel, normalOffset);
            for (std::uint32_t slot = 0; slot < list.size() && slot < kShadowMaxSlots; ++slot) {
                const Light& light = t.scene.lights[list[slot]];
                const bool bit = shadowMaskBit(mask, slot);
                const double distance = glm::length(glm::dvec3(light.positionWorld) - glm::dvec3(pos));
                if (!light.castsShadows || std::fabs(distance - light.range) < 1e-4) {
                    if (!light.castsShadows) CHECK(!bit);
                    continue;
                }
                if (distance >= light.range) {
                    CHECK(!bit);
                    continue;
                }
                const double facing = glm::dot(glm::dvec3(d.normal[pixel]), glm::dvec3(light.positionWorld) - glm::dvec3(pos));
                if (!castBackfaces && facing <= 0.0) {
                    ++c.backface;
                    CHECK(bit);
                    continue;
                }
                const Truth truth = bruteForce(tris, glm::dvec3(origin), glm::dvec3(light.positionWorld) - glm::dvec3(origin),
                                               1.0 - double(kShadowRayEndFraction));
                ++c.jobsChecked;
                if (truth == Truth::Ambiguous) {
                    ++c.ambiguous;
                    continue;
                }
                (truth == Truth::Shadowed ? c.shadowed : c.lit) += 1;
                if (bit != (truth == Truth::Shadowed)) ++c.mismatches;
            }
        }
    return c;
}

// An occluder: a 2 x 2 square at height y, centred over the origin (both faces).
MeshPrimitive occluderSquare(float y) { return test::quad({-1.0f, y, 1.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -2.0f}, 0); }

} // namespace

TEST_CASE("shadow jobs: the 25 + 7 bit split and the int4 mask slots") {
    // 7 slot bits (0..127) and 25 pixel bits: the largest job is all ones.
    static_assert(kShadowMaxSlots == 128 && kShadowMaskWords == 4 && kShadowMaxPixels == 33554432);
    CHECK(packShadowJob(0, 0) == 0u);
    CHECK(packShadowJob(1, 0) == 128u);
    CHECK(packShadowJob(33554431u, 127u) == 0xFFFFFFFFu);
    for (const std::uint32_t pixel : {0u, 1u, 921599u, 33554431u})
        for (const std::uint32_t slot : {0u, 31u, 32u, 127u}) {
            const std::uint32_t job = packShadowJob(pixel, slot);
            CHECK(shadowJobPixel(job) == pixel);
            CHECK(shadowJobSlot(job) == slot);
        }
    // GPU Pro 4 §10 item 9: slot s is mask[s >> 5] bit (s & 31): slot 37 is word 1, bit 5.
    const std::array<std::uint32_t, 4> mask{0u, 1u << 5, 0u, 0x80000000u};
    CHECK(shadowMaskBit(mask, 37));
    CHECK(!shadowMaskBit(mask, 36));
    CHECK(shadowMaskBit(mask, 127));
    CHECK(!shadowMaskBit(mask, 5));
}

TEST_CASE("shadow rays: a square between a light and a floor shadows what a brute-force ray test says") {
    // Light 3 above the floor, the square at height 1.5: its shadow on the floor is the square
    // scaled by 3 / (3 - 1.5) = 2 about the point below the light: |x|, |z| < 2.
    const test::TestScene t = shadowScene({caster({0.0f, 3.0f, 0.0f}, 12.0f)}, {occluderSquare(1.5f)}, {0.0f, 7.0f, 6.0f});
    test::Rendered r = render(t, {});
    const MaskCheck c = checkMask(r, t, 0.01f);
    CAPTURE(c.jobsChecked);
    CAPTURE(c.ambiguous);
    CHECK(c.mismatches == 0);
    CHECK(c.shadowed > 200);   // the floor under the square, and the square's own underside is not seen
    CHECK(c.lit > 1000);
    CHECK(c.ambiguous * 50 < c.jobsChecked);  // at most 2% of the rays pass within 1e-5 of an edge
    // The counters: every checked ray was a job; occluded = shadowed (+ the ambiguous that hit).
    const std::array<std::uint32_t, 5> k = counters(r);
    CHECK(k[0] == c.jobsChecked);
    CHECK(k[1] >= c.shadowed);
    CHECK(k[1] <= c.shadowed + c.ambiguous);
    // Shading: a shadowed pixel equals the render without the light; a lit one differs.
    test::TestScene dark = t;
    dark.scene.lights[0].enabled = false;
    test::Rendered unlit = render(dark, {});
    const PixelData d = pixelData(r, t.camera);
    int shadowedPixels = 0, litPixels = 0;
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x) {
            if (!(d.depth[y * kW + x] < 1.0f)) continue;
            const bool shadowed = maskAt(r, x, y)[0] & 1u;
            const bool same = std::memcmp(r.back().texel(x, y), unlit.back().texel(x, y), 4) == 0;
            if (shadowed) {
                ++shadowedPixels;
                CHECK(same);
            } else if (!same) {
                ++litPixels;
            }
        }
    CHECK(shadowedPixels > 200);
    CHECK(litPixels > 1000);
}

TEST_CASE("shadow rays: a light exactly on the floor, and a light behind it") {
    // Light on the floor plane (y = 0) before a wall z = -3. Floor pixels see it at dot(N, L) = 0
    // up to the rebuilt position's rounding: masked without a ray where that is <= 0, otherwise
    // a ray from 0.01 above the floor that ends 2^-10 short of the light and so stays above the
    // floor it lies on. The wall's rays end at the light on the floor. Nothing is occluded.
    const MeshPrimitive wall = test::quad({-10.0f, 0.0f, -3.0f}, {20.0f, 0.0f, 0.0f}, {0.0f, 10.0f, 0.0f}, 0);
    const test::TestScene onFloor = shadowScene({caster({0.0f, 0.0f, 0.0f}, 8.0f)}, {wall}, {0.0f, 4.0f, 6.0f});
    test::Rendered r = render(onFloor, {});
    const MaskCheck m = checkMask(r, onFloor, 0.01f);
    CHECK(m.mismatches == 0);
    CHECK(m.shadowed == 0);
    CHECK(m.lit > 1000);
    CHECK(counters(r)[1] == 0);
    CHECK(counters(r)[2] == m.backface);
    test::Rendered cast = render(onFloor, {{"shadowBackfaces", "cast"}});
    const MaskCheck c = checkMask(cast, onFloor, 0.01f, true);
    CHECK(c.mismatches == 0);
    CHECK(c.shadowed == 0);
    CHECK(counters(cast)[1] == 0);

    // A light under the floor: every floor pixel in range has it clearly behind (dot(N, L) < 0).
    // "mask" (default): masked without rays; "cast": the rays cross the floor: occluded all the
    // same; "lit": neither rays nor bits.
    const test::TestScene below = shadowScene({caster({0.0f, -1.0f, 0.0f}, 6.0f)}, {}, {0.0f, 4.0f, 6.0f});
    test::Rendered masked = render(below, {});
    const MaskCheck b = checkMask(masked, below, 0.01f);
    CHECK(b.backface > 1000);
    CHECK(counters(masked)[0] == 0);
    CHECK(counters(masked)[2] == b.backface);
    test::Rendered castBelow = render(below, {{"shadowBackfaces", "cast"}});
    const MaskCheck cb = checkMask(castBelow, below, 0.01f, true);
    CHECK(cb.mismatches == 0);
    CHECK(cb.shadowed == b.backface);
    CHECK(sameBytes(masked.get("shadow.mask"), castBelow.get("shadow.mask")));
    test::Rendered lit = render(below, {{"shadowBackfaces", "lit"}});
    CHECK(counters(lit)[0] == 0);
    CHECK(counters(lit)[2] == 0);
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x) CHECK(maskAt(lit, x, y) == std::array<std::uint32_t, 4>{});
}

TEST_CASE("shadow rays: self-shadowing acne without the normal offset, none with the default") {
    // A light 0.05 above the floor: rays from floor points graze it. Rebuilt positions carry the
    // depth buffer's D24 rounding, so with offset 0 about half start below the plane and hit it
    // (acne); 0.01 along the normal lifts every origin clear of it.
    const test::TestScene t = shadowScene({caster({0.0f, 0.05f, 0.0f}, 9.0f)}, {}, {0.0f, 5.0f, 7.0f});
    test::Rendered clean = render(t, {});
    const MaskCheck c = checkMask(clean, t, 0.01f);
    CHECK(c.mismatches == 0);
    CHECK(c.shadowed == 0);
    CHECK(c.lit > 1000);
    CHECK(counters(clean)[1] == 0);
    test::Rendered acne = render(t, {{"shadowNormalOffset", 0}});
    const MaskCheck a = checkMask(acne, t, 0.0f);
    CHECK(a.mismatches == 0);               // the acne is what the rays really hit
    CHECK(counters(acne)[1] > 100);         // self-shadowed floor pixels
    CHECK(a.shadowed + a.ambiguous >= counters(acne)[1]);
}

TEST_CASE("shadow rays: more than 128 lights in a pixel: slots past 127 are counted, lit or dropped") {
    // 200 casters of range 100 over the floor: every tile lists all 200, so every drawn pixel has
    // 200 - 128 = 72 overlapping lights past the mask.
    std::vector<Light> lights;
    for (int i = 0; i < 200; ++i)
        lights.push_back(caster({std::cos(0.1f * float(i)) * 4.0f, 2.0f + 0.01f * float(i), std::sin(0.1f * float(i)) * 4.0f},
                                100.0f, glm::vec3(0.004f)));
    const test::TestScene t = shadowScene(lights, {occluderSquare(1.0f)}, {0.0f, 7.0f, 6.0f});
    test::Rendered lit = render(t, {});
    std::uint32_t drawn = 0;
    const Surface& depth = lit.get("depth");
    for (std::uint32_t y = 0; y < kH; ++y)
        for (std::uint32_t x = 0; x < kW; ++x) drawn += depth.loadDepth(x, y) < 1.0f ? 1u : 0u;
    const std::array<std::uint32_t, 5> k = counters(lit);
    CHECK(k[3] == drawn);
    CHECK(k[4] == drawn * 72u);
    const MaskCheck c = checkMask(lit, t, 0.01f);
    CHECK(c.mismatches == 0);
    CHECK(c.shadowed > 1000);
    test::Rendered unlit = render(t, {{"shadowOverflow", "unlit"}});
    CHECK(sameBytes(lit.get("shadow.mask"), unlit.get("shadow.mask")));
    CHECK(!sameBytes(lit.back(), unlit.back()));  // the 72 lights past the mask are dropped
}

TEST_CASE("shadow rays: identical jobs, masks and images at 1, 2 and 7 threads") {
    std::vector<Light> lights;
    for (int i = 0; i < 40; ++i)
        lights.push_back(caster({std::cos(0.7f * float(i)) * 2.0f, 1.5f + 0.05f * float(i), std::sin(0.7f * float(i)) * 2.0f}, 8.0f,
                                glm::vec3(0.05f)));
    const test::TestScene t = shadowScene(lights, {occluderSquare(1.0f), occluderSquare(2.5f)}, {0.0f, 7.0f, 6.0f});
    test::Rendered one = render(t, {}, 1);
    test::Rendered two = render(t, {}, 2);
    test::Rendered seven = render(t, {}, 7);
    for (const char* name : {"shadow.jobs", "shadow.mask", "shadow.counters", "gbuffer.normal", kBackBufferName.data()}) {
        CAPTURE(name);
        CHECK(sameBytes(one.get(name), two.get(name)));
        CHECK(sameBytes(one.get(name), seven.get(name)));
    }
    CHECK(counters(one)[0] > 10000);
    CHECK(counters(one)[1] > 1000);
}

TEST_CASE("shadow rays: only what the scene asks for, and clear errors") {
    // Without a shadow-casting light (or with "shadows": "off") there are no shadow passes and
    // the image is forward-plus-amd's without shadows, bit for bit.
    Light plain = caster({0.0f, 3.0f, 0.0f}, 12.0f);
    plain.castsShadows = false;
    const test::TestScene none = shadowScene({plain}, {occluderSquare(1.5f)}, {0.0f, 7.0f, 6.0f});
    const test::TestScene with = shadowScene({caster({0.0f, 3.0f, 0.0f}, 12.0f)}, {occluderSquare(1.5f)}, {0.0f, 7.0f, 6.0f});
    test::Rendered a = render(none, {});
    test::Rendered b = render(with, {{"shadows", "off"}});
    test::Rendered c = render(with, {});
    CHECK(a.registry.find("shadow.mask") == nullptr);
    CHECK(a.registry.find("gbuffer.normal") == nullptr);
    CHECK(b.registry.find("shadow.mask") == nullptr);
    CHECK(sameBytes(a.back(), b.back()));
    CHECK(!sameBytes(a.back(), c.back()));
    const auto errorOf = [&](const nlohmann::json& options, std::uint32_t samples = 1) -> std::string {
        try {
            test::Rendered out;
            test::render(with, "forward-plus-amd", options, out, Precision::Exact, 2, {kW, kH}, {}, samples);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    // "on" where they cannot run is an error naming the reason; "auto" runs without them.
    CHECK(errorOf({{"shadows", "on"}, {"halfZ", true}}).find("/options/shadows: \"on\", but ray-cast shadows index") != std::string::npos);
    CHECK(errorOf({{"shadows", "on"}, {"shading", "3dgep"}}).find("\"shading\": \"amd\"") != std::string::npos);
    CHECK(errorOf({{"shadows", "on"}}, 4).find("1 sample per pixel") != std::string::npos);
    CHECK(errorOf({{"halfZ", true}}).empty());
    CHECK(errorOf({{"shading", "3dgep"}}).empty());
    CHECK(errorOf({}, 4).empty());
    CHECK(errorOf({{"shadows", "on"}}).empty());
    {
        test::Rendered out;
        CHECK_THROWS_AS(test::render(none, "forward-plus-amd", {{"shadows", "on"}}, out, Precision::Exact, 2, {kW, kH}), InputError);
    }
    CHECK(errorOf({{"shadowNormalOffset", -1}}).find("/options/shadowNormalOffset") != std::string::npos);
    CHECK(errorOf({{"shadowBackfaces", "skip"}}).find("/options/shadowBackfaces") != std::string::npos);
    CHECK(errorOf({{"shadows", "off"}, {"halfZ", true}}).empty());
}

} // namespace tessera_test::techniques_amd_shadows_test
