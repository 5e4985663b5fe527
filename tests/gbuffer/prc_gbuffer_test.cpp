// PR&C D3D11 ch. 11's G-buffer math (gbuffer/prc_gbuffer.h) and lighting (shading/prc_lighting.h)
// against values worked by hand from the printed listings, and against geometric truth: the
// sphere-map codec round-trips every normal but the two poles (NaN, which the chapter never
// mentions), Eq. 11.3's sign, linear depth, the scissor rectangle contains the sphere's projection.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include <tessera/buffers/surface.h>
#include <tessera/gbuffer/prc_gbuffer.h>
#include <tessera/shading/prc_lighting.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::gbuffer_prc_gbuffer_test {

using namespace tessera;

TEST_CASE("prc gbuffer: the sphere-map codec of Listing 11.8, worked values, round trip and NaN at the poles") {
    // normalize(n.xy) * sqrt(-n.z / 2 + 1/2):
    //   (0.6, 0, -0.8) -> (1, 0) * sqrt(0.9) = (0.9486833, 0); (0, 0.6, 0.8) -> (0, 1) * sqrt(0.1) = (0, 0.3162278);
    //   (0.48, 0.64, -0.6) -> (0.6, 0.8) * sqrt(0.8) = (0.5366563, 0.7155418); (1, 0, 0) -> (sqrt(0.5), 0).
    const auto check = [](glm::vec3 n, glm::vec2 want) {
        const glm::vec2 e = prcSpheremapEncode(n);
        CHECK(e.x == doctest::Approx(want.x).epsilon(1e-6));
        CHECK(e.y == doctest::Approx(want.y).epsilon(1e-6));
    };
    check({0.6f, 0.0f, -0.8f}, {0.9486833f, 0.0f});
    check({0.0f, 0.6f, 0.8f}, {0.0f, 0.3162278f});
    check({0.48f, 0.64f, -0.6f}, {0.5366563f, 0.7155418f});
    check({1.0f, 0.0f, 0.0f}, {0.7071068f, 0.0f});
    // Round trip: every unit normal off the z axis comes back within float rounding (the decode's
    // sqrt(l) with l = 1 - |e|^2 loses relative precision as n.z -> +1: 1e-3 covers |n.xy| >= 1e-3).
    std::mt19937 rng(4);
    std::normal_distribution<float> g;
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 n = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
        if (std::hypot(n.x, n.y) < 1e-3f) continue;
        const glm::vec3 back = prcSpheremapDecode(prcSpheremapEncode(n));
        CHECK(glm::length(back - n) < 1e-3f);
    }
    // The poles: normalize((0, 0)) is 0/0 -> NaN, and the decoded normal is NaN too.
    for (const float z : {1.0f, -1.0f}) {
        const glm::vec2 e = prcSpheremapEncode({0.0f, 0.0f, z});
        CHECK(std::isnan(e.x));
        CHECK(std::isnan(prcSpheremapDecode(e).z));
    }
}

TEST_CASE("prc gbuffer: at the poles the printed encoder's NaN, stored to R16G16_SNORM, decodes as +z: a head-on normal comes back facing away (ERRATA #29)") {
    Surface snorm({1, 1, Format::R16G16_SNORM, 1});
    const auto storeAndDecode = [&](glm::vec2 e) {
        snorm.store(0, 0, 0, glm::vec4(e, 0.0f, 0.0f));  // D3D11.3 §3.2.3.6: NaN -> 0
        return prcSpheremapDecode(glm::vec2(snorm.load(0, 0)));
    };
    // The camera looks down +z (left-handed view): a surface facing it has n = (0, 0, -1).
    const glm::vec3 printed = storeAndDecode(prcSpheremapEncode({0.0f, 0.0f, -1.0f}));
    CHECK(printed.z == 1.0f);  // flipped
    const glm::vec3 safe = storeAndDecode(prcSpheremapEncodeSafe({0.0f, 0.0f, -1.0f}));
    CHECK(safe.x == 0.0f);
    CHECK(safe.y == 0.0f);
    CHECK(safe.z == -1.0f);
    CHECK(storeAndDecode(prcSpheremapEncodeSafe({0.0f, 0.0f, 1.0f})).z == 1.0f);
    // Near the pole: |e| rounds to 16-bit SNORM codes whose |e|^2 exceeds 1, and the printed decode
    // takes sqrt of a negative number. Search the normals at 1e-4..1e-3 from -z for one.
    int nanPrinted = 0, nanSafe = 0;
    for (int i = 1; i <= 200; ++i) {
        const float t = float(i) * 5e-6f;
        const glm::vec3 m = glm::normalize(glm::vec3(t * 0.4f, t * 0.9f, -1.0f));
        snorm.store(0, 0, 0, glm::vec4(prcSpheremapEncode(m), 0.0f, 0.0f));
        const glm::vec2 code(snorm.load(0, 0));
        nanPrinted += std::isnan(prcSpheremapDecode(code).x) ? 1 : 0;
        const glm::vec3 d = prcSpheremapDecodeSafe(code);
        nanSafe += std::isnan(d.x) ? 1 : 0;
        CHECK(glm::dot(d, m) > 0.999f);  // the safe decode stays next to the true normal
    }
    CHECK(nanPrinted > 0);
    CHECK(nanSafe == 0);
    // Away from the poles the two encoders agree bit for bit.
    const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.2f, -0.9f));
    CHECK(prcSpheremapEncodeSafe(n) == prcSpheremapEncode(n));
}

TEST_CASE("prc gbuffer: Eq. 11.3 rebuilds z with the stored sign, and view-space normals do face +z (Fig. 11.5)") {
    CHECK(prcNormalFromXy({0.6f, 0.0f}, true).z == doctest::Approx(0.8f));
    CHECK(prcNormalFromXy({0.6f, 0.0f}, false).z == doctest::Approx(-0.8f));
    CHECK(prcNormalFromXy({0.6f, 0.8f + 1e-7f}, true).z == 0.0f);  // rounding past the unit circle: 0, not NaN
    // Why the sign must be stored: a surface seen at a grazing angle near the edge of a wide view
    // faces away from the view axis. Camera at the origin looking down +z (left-handed view), 90
    // degree FOV; a plane through (10, 0, 10) whose normal points (-1, 0, +0.2) towards the camera's
    // side: the pixel sees it (dot(normal, eye - p) > 0) while its view-space normal has z > 0.
    const glm::vec3 p(10.0f, 0.0f, 10.0f);
    const glm::vec3 n = glm::normalize(glm::vec3(-1.0f, 0.0f, 0.2f));
    CHECK(glm::dot(n, -p) > 0.0f);  // front-facing
    CHECK(n.z > 0.0f);              // yet +z: "z < 0 in view space" would flip it
}

TEST_CASE("prc gbuffer: ProjectionA/B linear depth of Listing 11.12") {
    // Near 1, far 100: A = 100/99 = 1.0101010, B = -100/99; B / (d - A) at d = 0, 0.5050505,
    // 0.9090909, 0.9898990, 1 gives 1, 2, 10, 50, 100 (the depths of view z = 1, 2, 10, 50, 100).
    const PrcProjectionAB ab = prcProjectionAB(1.0f, 100.0f);
    CHECK(ab.a == doctest::Approx(1.0101010f));
    CHECK(ab.b == doctest::Approx(-1.0101010f));
    const float depths[] = {0.0f, 0.5050505f, 0.9090909f, 0.9898990f, 1.0f};
    const float views[] = {1.0f, 2.0f, 10.0f, 50.0f, 100.0f};
    for (int i = 0; i < 5; ++i) CHECK(prcLinearDepth(depths[i], ab) == doctest::Approx(views[i]).epsilon(1e-4));
    // Against glm's left-handed D3D projection: z/w of view z back to view z.
    const glm::mat4 p = glm::perspectiveLH_ZO(glm::radians(60.0f), 1.5f, 1.0f, 100.0f);
    for (const float z : {1.5f, 7.0f, 33.0f, 99.0f}) {
        const glm::vec4 clip = p * glm::vec4(0.3f, -0.2f, z, 1.0f);
        CHECK(prcLinearDepth(clip.z / clip.w, ab) == doctest::Approx(z).epsilon(1e-4));
    }
}

TEST_CASE("prc gbuffer: the point-light scissor rectangle of Listing 11.14, worked values and containment") {
    // P(0,0) = 0.5625 (16:9 at 90 degrees vertical), P(1,1) = 1, near 1, far 100, 1280 x 720:
    //   centre (0, 0, 10), r 2: left/right points pushed to z 8: x = -+2 * 0.5625 / 8 = -+0.140625
    //   -> 550, 730; top/bottom +-2 / 8 = +-0.25 -> 270, 450.
    PrcScissorRect r = prcPointLightScissor({0.0f, 0.0f, 10.0f}, 2.0f, 0.5625f, 1.0f, 1.0f, 100.0f, 1280, 720);
    CHECK(r.left == 550);
    CHECK(r.top == 270);
    CHECK(r.right == 730);
    CHECK(r.bottom == 450);
    //   centre (5, -3, 20), r 4: 655, 337.5, 842.5, 517.5 truncated to 655, 337, 842, 517.
    r = prcPointLightScissor({5.0f, -3.0f, 20.0f}, 4.0f, 0.5625f, 1.0f, 1.0f, 100.0f, 1280, 720);
    CHECK(r.left == 655);
    CHECK(r.top == 337);
    CHECK(r.right == 842);
    CHECK(r.bottom == 517);
    //   the eye inside the sphere: the whole viewport.
    r = prcPointLightScissor({0.0f, 0.0f, 0.5f}, 3.0f, 0.5625f, 1.0f, 1.0f, 100.0f, 1280, 720);
    CHECK(r.left == 0);
    CHECK(r.top == 0);
    CHECK(r.right == 1280);
    CHECK(r.bottom == 720);
    // Containment: every projected point of the sphere's surface (in front of the near plane) lands
    // inside the rectangle, widened by the one pixel the truncation of right and bottom can cut.
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::normal_distribution<float> g;
    int points = 0;
    for (int s = 0; s < 50; ++s) {
        const glm::vec3 c(u(rng) * 10.0f, u(rng) * 6.0f, 12.0f + u(rng) * 8.0f);
        const float radius = 1.0f + std::abs(u(rng)) * 3.0f;
        const PrcScissorRect rect = prcPointLightScissor(c, radius, 0.5625f, 1.0f, 1.0f, 100.0f, 1280, 720);
        for (int i = 0; i < 200; ++i) {
            const glm::vec3 q = c + radius * glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
            if (q.z < 1.0f) continue;
            const float xPx = (q.x * 0.5625f / q.z * 0.5f + 0.5f) * 1280.0f;
            const float yPx = (1.0f - (q.y / q.z * 0.5f + 0.5f)) * 720.0f;
            if (xPx < 0.0f || xPx > 1280.0f || yPx < 0.0f || yPx > 720.0f) continue;
            CHECK(xPx >= float(rect.left));
            CHECK(xPx <= float(rect.right) + 1.0f);
            CHECK(yPx >= float(rect.top));
            CHECK(yPx <= float(rect.bottom) + 1.0f);
            ++points;
        }
    }
    CHECK(points > 5000);
}

TEST_CASE("prc gbuffer: truncating the scissor's right and bottom edges drops lit pixel centres, rounding out keeps them (ERRATA #28)") {
    // A pixel is shaded when its centre (i + 0.5) lies in [left, right). Worked case (found by a
    // sweep of 10^5 random spheres, 0.3 % of which lose a column this way): centre (-1.60647,
    // -0.02600, 5.59040), radius 1.61651, P(0,0) = 0.5625, 1280 px wide. Listing 11.14's right
    // edge: the point (cx + r, cz + r) (x < 0 pushes z away) gives x/z = 0.010012/7.20691 ->
    // 640.909 px, truncated to 640. The sphere's true silhouette in x: the tangent from the eye at
    // angle atan2(cx, cz) + asin(r / |(cx, cz)|) has slope 0.000919, i.e. 640.647 px: column 640's
    // centre (640.5) sees the sphere, yet the truncated rectangle [.., 640) excludes it.
    const glm::vec3 c(-1.6064667f, -0.0259954f, 5.5904042f);
    const float radius = 1.6165078f;
    const PrcScissorRect cut = prcPointLightScissor(c, radius, 0.5625f, 1.0f, 1.0f, 100.0f, 1280, 720);
    const PrcScissorRect out = prcPointLightScissor(c, radius, 0.5625f, 1.0f, 1.0f, 100.0f, 1280, 720, true);
    const double d = std::hypot(double(c.x), double(c.z));
    const double slope = std::tan(std::atan2(double(c.x), double(c.z)) + std::asin(double(radius) / d));
    const double silhouettePx = (slope * 0.5625 * 0.5 + 0.5) * 1280.0;
    CHECK(silhouettePx == doctest::Approx(640.647).epsilon(1e-5));
    CHECK(cut.right == 640);
    CHECK(silhouettePx > 640.5);  // column 640's centre lies inside the sphere's projection
    CHECK(out.right == 641);      // rounded out, the column is shaded
    // Rounding out never loses a covered centre: on random spheres (clear of the eye) the rounded
    // right edge exceeds every silhouette, as the listing's edge itself does (it is conservative).
    std::mt19937 rng(12);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int checked = 0;
    for (int s = 0; s < 2000; ++s) {
        const glm::vec3 cs(u(rng) * 10.0f, u(rng) * 6.0f, 12.0f + u(rng) * 8.0f);
        const float r = 1.0f + std::abs(u(rng)) * 3.0f;
        const double ds = std::hypot(double(cs.x), double(cs.z));
        if (ds <= double(r) + 1.0) continue;
        const double a = std::atan2(double(cs.x), double(cs.z)) + std::asin(double(r) / ds);
        const double px = (std::tan(a) * 0.5625 * 0.5 + 0.5) * 1280.0;
        if (!(a < 1.5) || px >= 1280.0) continue;
        const PrcScissorRect rect = prcPointLightScissor(cs, r, 0.5625f, 1.0f, 1.0f, 100.0f, 1280, 720, true);
        CHECK(double(rect.right) + 1e-3 >= px);
        ++checked;
    }
    CHECK(checked > 1000);
}

TEST_CASE("prc lighting: Listing 11.3's point light and the light pre-pass buffer, worked values") {
    // n (0, 1, 0) at the origin, light at (0, 3, 4) range 10 colour 1, albedos 1, power 16, camera
    // (0, 10, 0): d = 5 -> attenuation 0.5; L = (0, 0.6, 0.8) -> N.L 0.6; V unnormalized (0, 10, 0):
    // H = normalize(0, 10.6, 0.8) = (0, 0.997164, 0.075258); spec = 0.997164^16 x 0.6 = 0.5733470;
    // (0.6 + 0.5733470) x 0.5 = 0.5866735.
    PrcLight<double> light;
    light.position = {0.0, 3.0, 4.0};
    light.range = 10.0;
    const glm::dvec3 n(0.0, 1.0, 0.0), p(0.0), cam(0.0, 10.0, 0.0), one(1.0);
    const glm::dvec3 lit = prcClassicLighting(light, n, p, one, one, 16.0, cam);
    CHECK(lit.x == doctest::Approx(0.5866735).epsilon(1e-6));
    // With V normalized (Eq. 11.1's intent) H = normalize(0, 1.6, 0.8) = (0, 0.894427, 0.447214).
    const glm::dvec3 unitV = prcClassicLighting(light, n, p, one, one, 16.0, cam, true);
    CHECK(unitV.x == doctest::Approx((0.6 + std::pow(0.894427191, 16.0) * 0.6) * 0.5).epsilon(1e-6));
    // Light at (0, 5, 0), diffuse 0.5, specular 1, power 1: att 0.5, N.L 1, H = (0, 1, 0):
    // (0.5 + 1) x 0.5 = 0.75.
    light.position = {0.0, 5.0, 0.0};
    CHECK(prcClassicLighting(light, n, p, glm::dvec3(0.5), one, 1.0, cam).x == doctest::Approx(0.75));
    // Out of range: 0.
    light.position = {0.0, 12.0, 0.0};
    CHECK(prcClassicLighting(light, n, p, one, one, 16.0, cam) == glm::dvec3(0.0));
    // Spot: rho 0.95 between cos outer 0.9 and cos inner 1.0 -> 0.5.
    PrcLight<double> spot;
    spot.type = LightType::Spot;
    spot.position = {0.0, 1.0, 0.0};
    spot.direction = glm::normalize(glm::dvec3(std::sqrt(1.0 - 0.95 * 0.95), -0.95, 0.0));
    spot.cosInner = 1.0;
    spot.cosOuter = 0.9;
    spot.range = 1e9;
    CHECK(prcIncidence(spot, glm::dvec3(0.0)).attenuation == doctest::Approx(0.5 * (1.0 - 1.0 / 1e9)));
    // The light pre-pass buffer of the first case: (0.3, 0.3, 0.3, 0.2866735); the final pass with
    // albedos 1 sums to the classic result.
    light.position = {0.0, 3.0, 4.0};
    const glm::dvec4 texel = prcLightBufferTexel(light, n, 16.0, p, cam);
    CHECK(texel.x == doctest::Approx(0.3));
    CHECK(texel.w == doctest::Approx(0.2866735).epsilon(1e-6));
    CHECK(prcLightPrePassFinal(texel, one, one).x == doctest::Approx(0.5866735).epsilon(1e-6));
}

TEST_CASE("prc gbuffer: the four position reconstructions of §11.4.1 rebuild the same world points") {
    // A rotated camera; random points in front of it. Each variant gets what its G-buffer stores
    // and the ray its light geometry provides, and must return the point (1e-4 relative: float).
    const glm::vec3 eye(3.0f, 2.0f, -7.0f);
    const glm::mat4 viewLh = glm::lookAtLH(eye, glm::vec3(0.5f, 0.0f, 1.0f), glm::vec3(0, 1, 0));
    const glm::mat4 worldFromView = glm::inverse(viewLh);
    const glm::vec3 eyeZ = glm::normalize(glm::vec3(worldFromView[2]));  // the view's +z in world space
    const float nearZ = 1.0f, farZ = 100.0f;
    const glm::mat4 proj = glm::perspectiveLH_ZO(glm::radians(60.0f), 1.5f, nearZ, farZ);
    const PrcProjectionAB ab = prcProjectionAB(nearZ, farZ);
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u(-8.0f, 8.0f);
    int checked = 0;
    for (int i = 0; i < 300; ++i) {
        const glm::vec3 world(u(rng), u(rng), u(rng));
        const glm::vec3 view(viewLh * glm::vec4(world, 1.0f));
        if (view.z < 2.0f) continue;
        const float tol = 1e-4f * glm::length(view) + 1e-5f;
        // (a) distance along the world-space ray through the point (a volume vertex on that ray).
        CHECK(glm::length(prcPositionFromDistance(eye, world - eye, glm::length(view)) - world) <= tol);
        // (b) depth / far, with a volume vertex anywhere on the same view ray (here twice as far).
        const glm::vec3 b = prcPositionFromNormalizedDepth(view * 2.0f, farZ, view.z / farZ);
        CHECK(glm::length(b - view) <= tol);
        // (c) hardware depth through ProjectionA/B along (x/z, y/z, 1).
        const glm::vec4 clip = proj * glm::vec4(view, 1.0f);
        const float linear = prcLinearDepth(clip.z / clip.w, ab);
        const glm::vec3 c = glm::vec3(view.x / view.z, view.y / view.z, 1.0f) * linear;
        CHECK(glm::length(c - view) <= 10.0f * tol);  // depth precision near the far plane (Fig. 11.8)
        // (d) any space: the world ray and the eye's z axis.
        CHECK(glm::length(prcPositionAnySpace(eye, eyeZ, world - eye, view.z) - world) <= tol);
        ++checked;
    }
    CHECK(checked > 100);
}

} // namespace tessera_test::gbuffer_prc_gbuffer_test
