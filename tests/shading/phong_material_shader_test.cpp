// The 3dgep pixel shader's material gathering (tessera/shading/phong_material_shader.h): the
// texture rule, the specular gate, alpha test, normal and bump mapping (texel-offset taps in the
// sampled mip, negated binormal, no re-normalization), and the variant chosen per material.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include <tessera/shading/phong_material_shader.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::shading_phong_material_shader_test {

using namespace tessera;

namespace {

SamplerState pointSampler() {
    SamplerState s;
    s.minFilter = s.magFilter = s.mipFilter = Filter::Point;
    s.addressU = s.addressV = AddressMode::Wrap;
    return s;
}

// One pixel at view position (0,0,-1) facing the eye, TBN = identity, UV set 0 at `uv`.
PixelInput<PhongVaryings> pixel(glm::vec2 uv = {0.5f, 0.5f}, glm::vec2 texelsPerPixel = {0.0f, 0.0f}) {
    PixelInput<PhongVaryings> in{};
    in.varyings.posView = {0.0f, 0.0f, -1.0f};
    in.varyings.uv0 = uv;
    in.varyings.tangentView = {1.0f, 0.0f, 0.0f};
    in.varyings.binormalView = {0.0f, 1.0f, 0.0f};
    in.varyings.normalView = {0.0f, 0.0f, 1.0f};
    in.ddx.uv0 = {texelsPerPixel.x, 0.0f};
    in.ddy.uv0 = {0.0f, texelsPerPixel.y};
    return in;
}

PhongShaderData<float> plainData() {
    PhongShaderData<float> d;
    d.globalAmbient = {1.0f, 1.0f, 1.0f, 1.0f};
    d.ambientColor = {0.0f, 0.0f, 0.0f, 1.0f};
    d.emissiveColor = {0.0f, 0.0f, 0.0f, 1.0f};
    d.diffuseColor = {1.0f, 1.0f, 1.0f, 1.0f};
    d.specularColor = {0.0f, 0.0f, 0.0f, 1.0f};
    return d;
}

glm::vec4 shade(std::uint32_t features, const PhongShaderData<float>& d, const PixelInput<PhongVaryings>& in,
                bool* kept = nullptr) {
    Vec4<float> color(-1.0f);
    const bool k = selectPhongVariant<float>(features).exact(d, in, color);
    if (kept) *kept = k;
    return color;
}

ViewLight<float> directional(glm::vec3 towardsLight) {
    ViewLight<float> l;
    l.type = LightType::Directional;
    l.directionView = {-towardsLight.x, -towardsLight.y, -towardsLight.z, 0.0f};
    return l;
}

} // namespace

TEST_CASE("material texture rule: any(colour.rgb) ? colour * texel : texel, alpha included") {
    const Texture2D tex = Texture2D::fromFloatRgba(1, 1, std::vector<float>{0.2f, 0.4f, 0.6f, 0.5f}, "texel");
    const SamplerState s = pointSampler();
    PhongShaderData<float> d = plainData();
    d.ambientTexture = d.diffuseTexture = BoundTexture{&tex, &s, 0};
    // No lights: output rgb = ambient (x GlobalAmbient 1) + emissive 0 + diffuse x (0,0,0,1); alpha = diffuse.a.
    d.ambientColor = {0.0f, 0.0f, 0.0f, 1.0f};        // black: replaced by the texel
    d.diffuseColor = {0.0f, 0.0f, 0.0f, 0.25f};       // black rgb: replaced, alpha too
    glm::vec4 c = shade(kPhongAmbientTexture | kPhongDiffuseTexture, d, pixel());
    CHECK(c == glm::vec4(0.2f, 0.4f, 0.6f, 0.5f));
    d.ambientColor = {0.5f, 1.0f, 0.0f, 1.0f};        // not black: modulates (0 * 0.6 = 0 in blue)
    d.diffuseColor = {1.0f, 0.0f, 0.0f, 0.5f};        // alpha 0.5 * 0.5
    c = shade(kPhongAmbientTexture | kPhongDiffuseTexture, d, pixel());
    CHECK(c == glm::vec4(0.1f, 0.4f, 0.0f, 0.25f));
    // GlobalAmbient multiplies ambient after the rule.
    d.globalAmbient = {0.5f, 0.5f, 0.5f, 1.0f};
    CHECK(shade(kPhongAmbientTexture | kPhongDiffuseTexture, d, pixel()).y == 0.2f);
    // glTF OPAQUE: alpha forced to 1 before x Opacity.
    d.ignoreDiffuseAlpha = true;
    d.opacity = 0.75f;
    CHECK(shade(kPhongAmbientTexture | kPhongDiffuseTexture, d, pixel()).w == 0.75f);
}

TEST_CASE("specular is added only when SpecularPower > 1, opacity texture .r, alpha test discards") {
    // Light along N, V = N: lit.Diffuse = lit.Specular = 1. diffuse 0.25 + specular 0.5.
    const std::vector<ViewLight<float>> lights{directional({0.0f, 0.0f, 1.0f})};
    PhongShaderData<float> d = plainData();
    d.diffuseColor = {0.25f, 0.25f, 0.25f, 1.0f};
    d.specularColor = {0.5f, 0.5f, 0.5f, 1.0f};
    d.lights = lights;
    d.specularPower = 1.0f;
    CHECK(shade(0, d, pixel()).x == 0.25f);
    d.specularPower = 2.0f;
    CHECK(shade(0, d, pixel()).x == 0.75f);

    const Texture2D opacity = Texture2D::fromFloatRgba(1, 1, std::vector<float>{0.05f, 1.0f, 1.0f, 1.0f}, "opacity");
    const SamplerState s = pointSampler();
    d.opacityTexture = BoundTexture{&opacity, &s, 0};
    d.alphaThreshold = 0.1f;
    bool kept = true;
    CHECK(shade(kPhongOpacityTexture, d, pixel(), &kept).w == 0.05f);  // no alpha test: .r is the alpha
    CHECK(kept);
    shade(kPhongOpacityTexture | kPhongAlphaTest, d, pixel(), &kept);  // 0.05 * 1 < 0.1: discarded
    CHECK_FALSE(kept);
}

TEST_CASE("normal mapping: normalize(mul(texel * 2 - 1, TBN))") {
    const std::vector<ViewLight<float>> lights{directional({1.0f, 0.0f, 0.0f})};  // light along the tangent
    PhongShaderData<float> d = plainData();
    d.lights = lights;
    const SamplerState s = pointSampler();
    // Texel (1, 0.5, 0.5) expands to (1, 0, 0): N = T, so N.L = 1.
    const Texture2D towardsTangent = Texture2D::fromFloatRgba(1, 1, std::vector<float>{1.0f, 0.5f, 0.5f, 1.0f}, "n");
    d.normalTexture = BoundTexture{&towardsTangent, &s, 0};
    CHECK(shade(kPhongNormalMap, d, pixel()).x == 1.0f);
    // Texel (0.5, 0.5, 1) expands to (0, 0, 1): N = the vertex normal, N.L = 0.
    const Texture2D flat = Texture2D::fromFloatRgba(1, 1, std::vector<float>{0.5f, 0.5f, 1.0f, 1.0f}, "flat");
    d.normalTexture = BoundTexture{&flat, &s, 0};
    CHECK(shade(kPhongNormalMap, d, pixel()).x == 0.0f);
}

TEST_CASE("sampleWithTexelOffset: the offset counts texels of the sampled mip level") {
    // 4x4 float texture with R = x: level 1 (2x2) averages pairs, R = 0.5 and 2.5.
    std::vector<float> rgba;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) rgba.insert(rgba.end(), {float(x), float(y), 0.0f, 1.0f});
    const Texture2D tex = Texture2D::fromFloatRgba(4, 4, rgba, "grid");
    const SamplerState s = pointSampler();
    // LOD 0 (one texel per pixel): u = 1.5/4 is texel 1; +1 texel -> texel 2.
    CHECK(sampleWithTexelOffset(tex, s, {0.375f, 0.375f}, {0.25f, 0.0f}, {0.0f, 0.25f}, {1, 0}).x == 2.0f);
    CHECK(sampleWithTexelOffset(tex, s, {0.375f, 0.375f}, {0.25f, 0.0f}, {0.0f, 0.25f}, {0, 0}).x == 1.0f);
    // LOD 1 (two texels per pixel): u = 0.125 is level-1 texel 0 (R 0.5); +1 level-1 texel -> texel 1
    // (R 2.5). Adding 1/width(0) = 0.25 to u instead would stay in texel 0.
    CHECK(sampleWithTexelOffset(tex, s, {0.125f, 0.125f}, {0.5f, 0.0f}, {0.0f, 0.5f}, {1, 0}).x == 2.5f);
    CHECK(sampleWithTexelOffset(tex, s, {0.125f, 0.125f}, {0.5f, 0.0f}, {0.0f, 0.5f}, {0, 1}).y == 2.5f);
    // Wrap: texel 3 + 1 -> texel 0.
    CHECK(sampleWithTexelOffset(tex, s, {0.875f, 0.875f}, {0.25f, 0.0f}, {0.0f, 0.25f}, {1, 0}).x == 0.0f);
}

TEST_CASE("bump mapping: heights at +1 texel in U and V, negated binormal, result not normalized") {
    // R = 0.1 (x + y): at texel (1,1) h = 0.2, hU = hV = 0.3; x BumpIntensity 5: 1, 1.5, 1.5.
    // pU - p = (1, 0, 0.5), pV - p = (0, 1, 0.5); normalized, crossed:
    // (-0.5, -0.5, 1) / (sqrt(1.25) sqrt(1.25)) = (-0.4, -0.4, 0.8), length sqrt(0.96) (not 1).
    // mul with rows T = (1,0,0), B = -binormal = (0,-1,0), N = (0,0,1): (-0.4, 0.4, 0.8).
    std::vector<float> rgba;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) rgba.insert(rgba.end(), {0.1f * float(x + y), 0.0f, 0.0f, 1.0f});
    const Texture2D bump = Texture2D::fromFloatRgba(4, 4, rgba, "bump");
    const SamplerState s = pointSampler();
    PhongShaderData<float> d = plainData();
    d.bumpTexture = BoundTexture{&bump, &s, 0};
    std::vector<ViewLight<float>> lights{directional({0.0f, 0.0f, 1.0f})};
    d.lights = lights;
    const PixelInput<PhongVaryings> in = pixel({0.375f, 0.375f}, {0.25f, 0.25f});
    CHECK(shade(kPhongBumpMap, d, in).x == doctest::Approx(0.8f).epsilon(1e-5));  // normalized would be 0.8165
    lights[0] = directional({0.0f, 1.0f, 0.0f});
    CHECK(shade(kPhongBumpMap, d, in).x == doctest::Approx(0.4f).epsilon(1e-5));  // +0.4: the binormal was negated
}

TEST_CASE("shader variants: chosen per material, specialized or generic, same bits either way") {
    PhongMaterial m;
    CHECK(phongFeatures(m, false) == 0u);
    CHECK(selectPhongVariant<float>(0).name == "exact:none");
    m.diffuseTexture.texture = 0;
    m.ambientTexture.texture = 0;
    m.normalTexture.texture = 1;
    m.bumpTexture.texture = 2;  // normal map wins
    CHECK(phongFeatures(m, false) == (kPhongAmbientTexture | kPhongDiffuseTexture | kPhongNormalMap));
    CHECK(selectPhongVariant<float>(phongFeatures(m, false)).name == "exact:ambient+diffuse+normal");
    CHECK_FALSE(selectPhongVariant<float>(phongFeatures(m, false)).mayDiscard);
    // Alpha test only where it can reject: MASK-like materials (alpha not forced to 1).
    CHECK((phongFeatures(m, true) & kPhongAlphaTest) != 0u);
    m.ignoreDiffuseAlpha = true;
    CHECK((phongFeatures(m, true) & kPhongAlphaTest) == 0u);
    CHECK(selectPhongVariant<float>(kPhongAlphaTest).mayDiscard);
    // Specular textures are not among the specialized axes: the generic variant.
    m.specularTexture.texture = 3;
    CHECK(selectPhongVariant<float>(phongFeatures(m, false)).name == "exact:generic(ambient+diffuse+specular+normal)");
    CHECK(selectPhongVariant<double>(0).name == "reference:generic(none)");

    // Specialized and generic give the same bits (the generic variant checks each slot).
    const Texture2D tex = Texture2D::fromFloatRgba(1, 1, std::vector<float>{0.3f, 0.6f, 0.9f, 0.7f}, "t");
    const SamplerState s = pointSampler();
    const std::vector<ViewLight<float>> lights{directional({0.3f, 0.4f, 0.866f})};
    PhongShaderData<float> d = plainData();
    d.ambientTexture = d.diffuseTexture = BoundTexture{&tex, &s, 0};
    d.specularColor = {0.5f, 0.5f, 0.5f, 1.0f};
    d.specularPower = 20.0f;
    d.lights = lights;
    const glm::vec4 specialized = shade(kPhongAmbientTexture | kPhongDiffuseTexture, d, pixel());
    const glm::vec4 generic = shade(kPhongAmbientTexture | kPhongDiffuseTexture | kPhongSpecularTexture, d, pixel());
    CHECK(specialized == generic);
}

} // namespace tessera_test::shading_phong_material_shader_test
