// The Cookbook's light functions (shading/cookbook_lighting.h) against their closed forms:
// the squared linear falloff's end points, Lambert and Blinn at known angles, the spot's squared
// cone ramp, the capsule's nearest segment point, the hemispheric ambient's two poles.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include <tessera/shading/cookbook_lighting.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::shading_cookbook_lighting_test {

using namespace tessera;

namespace {

CookbookMaterial<double> matte(glm::dvec3 normal) {
    CookbookMaterial<double> m;
    m.normal = glm::normalize(normal);
    m.diffuseColor = {0.5, 0.25, 1.0};
    m.specPow = 16.0;
    m.specIntensity = 0.0;  // diffuse only unless a test sets it
    return m;
}

} // namespace

TEST_CASE("cookbook lighting: point light falloff (1 - d/R)^2, Lambert diffuse, Blinn specular at the mirror angle") {
    const glm::dvec3 p(0.0), eye(0.0, 0.0, 10.0), color(1.0, 1.0, 1.0);
    const CookbookMaterial<double> m = matte({0.0, 0.0, 1.0});
    // Light straight above at distance d, range 4: diffuse = colour x 1 x (1 - d/4)^2.
    for (const double d : {0.0001, 1.0, 2.0, 3.0, 3.999}) {
        const CookbookTerms<double> t = cookbookPoint<double>(p, eye, m, {0.0, 0.0, d}, 1.0 / 4.0, color);
        CHECK(t.distance == doctest::Approx(d));
        CHECK(t.nDotL == doctest::Approx(1.0));
        CHECK(t.attenuation == doctest::Approx((1.0 - d / 4.0) * (1.0 - d / 4.0)));
        CHECK(t.color.x == doctest::Approx(0.5 * t.attenuation));
    }
    // At and past the range: exactly 0 (saturate), so a volume may stop there.
    CHECK(cookbookPoint<double>(p, eye, m, {0.0, 0.0, 4.0}, 0.25, color).color == glm::dvec3(0.0));
    CHECK(cookbookPoint<double>(p, eye, m, {0.0, 0.0, 9.0}, 0.25, color).color == glm::dvec3(0.0));
    // 60 degrees off the normal: N.L = 0.5.
    const CookbookTerms<double> slanted = cookbookPoint<double>(p, eye, m, {std::sqrt(3.0), 0.0, 1.0}, 0.0, color);
    CHECK(slanted.nDotL == doctest::Approx(0.5));
    CHECK(slanted.color.z == doctest::Approx(0.5));  // diffuse 1.0 x 0.5, no falloff (range rcp 0)
    // Behind the surface: no diffuse (saturate), the Blinn term alone.
    CHECK(cookbookPoint<double>(p, eye, m, {0.0, 0.0, -1.0}, 0.0, color).color == glm::dvec3(0.0));
    // Blinn: light and eye both along the normal -> H = N, pow(1, p) = 1, x intensity (not x diffuse).
    CookbookMaterial<double> shiny = m;
    shiny.specIntensity = 0.25;
    const CookbookTerms<double> mirror = cookbookPoint<double>(p, eye, shiny, {0.0, 0.0, 1.0}, 0.0, color);
    CHECK(mirror.color.x == doctest::Approx(0.5 + 0.25));
    CHECK(mirror.color.y == doctest::Approx(0.25 + 0.25));
}

TEST_CASE("cookbook lighting: the spot's cone ramp is squared between the outer and inner cosines") {
    const glm::dvec3 p(0.0), eye(0.0, 0.0, 10.0), color(1.0);
    const CookbookMaterial<double> m = matte({0.0, 0.0, 1.0});
    const double cosOuter = std::cos(0.5), cosInner = std::cos(0.25);
    // The spot at (0, 0, 1) pointing down -z; the surface point moves off the axis.
    for (const double angle : {0.0, 0.2, 0.3, 0.4, 0.49, 0.6}) {
        const glm::dvec3 lightPos = glm::dvec3(-std::tan(angle), 0.0, 1.0);  // the point is `angle` off the axis
        const CookbookTerms<double> t =
            cookbookSpot<double>(p, eye, m, lightPos, 0.0, color, {0.0, 0.0, 1.0}, cosOuter, cosInner - cosOuter);
        const double ramp = std::clamp((std::cos(angle) - cosOuter) / (cosInner - cosOuter), 0.0, 1.0);
        CHECK(t.cone == doctest::Approx(ramp * ramp));
    }
}

TEST_CASE("cookbook lighting: a capsule lights from the nearest point of its segment") {
    const glm::dvec3 eye(0.0, 0.0, 10.0), color(1.0);
    const CookbookMaterial<double> m = matte({0.0, 0.0, 1.0});
    // Segment from (-2, 0, 1) to (2, 0, 1): surface points under it see the light at height 1,
    // points beyond its ends see the end point.
    const glm::dvec3 start(-2.0, 0.0, 1.0), dir(1.0, 0.0, 0.0);
    for (const double x : {-1.5, 0.0, 1.9})
        CHECK(cookbookCapsule<double>({x, 0.0, 0.0}, eye, m, start, dir, 4.0, 0.0, color).distance == doctest::Approx(1.0));
    const CookbookTerms<double> beyond = cookbookCapsule<double>({5.0, 0.0, 0.0}, eye, m, start, dir, 4.0, 0.0, color);
    CHECK(beyond.distance == doctest::Approx(std::sqrt(9.0 + 1.0)));  // to (2, 0, 1)
    // Equal to a point light at the nearest point.
    const CookbookTerms<double> under = cookbookCapsule<double>({0.7, 0.0, 0.0}, eye, m, start, dir, 4.0, 0.2, color);
    const CookbookTerms<double> point = cookbookPoint<double>({0.7, 0.0, 0.0}, eye, m, {0.7, 0.0, 1.0}, 0.2, color);
    CHECK(under.color.x == doctest::Approx(point.color.x));
}

TEST_CASE("cookbook lighting: hemispheric ambient is the lower colour facing down and the upper facing up, directional multiplies by the colour") {
    const glm::dvec3 down(0.1, 0.2, 0.3), up(0.5, 0.6, 0.7), base(1.0, 0.5, 0.25);
    const glm::dvec3 a = cookbookAmbient<double>({0.0, -1.0, 0.0}, base, down, up - down);
    const glm::dvec3 b = cookbookAmbient<double>({0.0, 1.0, 0.0}, base, down, up - down);
    const glm::dvec3 c = cookbookAmbient<double>({1.0, 0.0, 0.0}, base, down, up - down);
    CHECK(a.x == doctest::Approx(0.1));
    CHECK(b.y == doctest::Approx(0.6 * 0.5));
    CHECK(c.z == doctest::Approx(0.5 * 0.25));  // the mean, on the horizon
    // CalcDirectional: (colour x N.L + colour x Blinn) x diffuse: 45 degrees, no specular.
    const CookbookMaterial<double> m = matte({0.0, 1.0, 0.0});
    const glm::dvec3 lit = cookbookDirectional<double>({0.0, 0.0, 0.0}, {0.0, 5.0, 5.0}, m,
                                                       glm::normalize(glm::dvec3(1.0, 1.0, 0.0)), {2.0, 2.0, 2.0});
    CHECK(lit.x == doctest::Approx(2.0 * std::sqrt(0.5) * 0.5));
    CHECK(lit.z == doctest::Approx(2.0 * std::sqrt(0.5) * 1.0));
}

} // namespace tessera_test::shading_cookbook_lighting_test
