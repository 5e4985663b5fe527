// Tests of the 3dgep material: the demo's defaults, its IsTransparent rule, and the glTF ->
// Phong mapping of include/tessera/scene/phong_material.h with hand-computed values.
#include <tessera/scene/phong_material.h>

#include <doctest/doctest.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::scene_phong_material_test {

using tessera::AlphaMode;
using tessera::Material;
using tessera::PhongMaterial;
using tessera::TextureRef;

namespace {
TextureRef texture(int index) {
    TextureRef t;
    t.texture = index;
    return t;
}
bool equal(const glm::vec4& a, const glm::vec4& b) { return a.x == b.x && a.y == b.y && a.z == b.z && a.w == b.w; }
} // namespace

TEST_CASE("PhongMaterial has the demo's defaults (Material.h MaterialProperties)") {
    const PhongMaterial m;
    CHECK(equal(m.globalAmbient, {0.1f, 0.1f, 0.15f, 1.0f}));
    CHECK(equal(m.ambientColor, {0.0f, 0.0f, 0.0f, 1.0f}));
    CHECK(equal(m.emissiveColor, {0.0f, 0.0f, 0.0f, 1.0f}));
    CHECK(equal(m.diffuseColor, {1.0f, 1.0f, 1.0f, 1.0f}));
    CHECK(equal(m.specularColor, {0.0f, 0.0f, 0.0f, 1.0f}));
    CHECK(equal(m.reflectance, {0.0f, 0.0f, 0.0f, 0.0f}));
    CHECK(m.opacity == 1.0f);
    CHECK(m.specularPower == -1.0f);
    CHECK(m.indexOfRefraction == -1.0f);
    CHECK(m.bumpIntensity == 5.0f);
    CHECK(m.specularScale == 128.0f);
    CHECK(m.alphaThreshold == 0.1f);
    CHECK_FALSE(m.diffuseTexture.present());
    CHECK_FALSE(m.isTransparent());
}

TEST_CASE("isTransparent is the demo's rule: opacity < 1, opacity texture, diffuse alpha, threshold <= 0") {
    PhongMaterial m;
    m.opacity = 0.99f;
    CHECK(m.isTransparent());
    m = PhongMaterial{};
    m.opacityTexture = texture(0);
    CHECK(m.isTransparent());
    m = PhongMaterial{};
    m.diffuseTextureHasAlpha = true;  // without a diffuse texture this means nothing
    CHECK_FALSE(m.isTransparent());
    m.diffuseTexture = texture(1);
    CHECK(m.isTransparent());
    m = PhongMaterial{};
    m.alphaThreshold = 0.0f;
    CHECK(m.isTransparent());
}

TEST_CASE("phongFromGltf: an OPAQUE metallic-roughness material") {
    Material g;
    g.baseColorFactor = {0.5f, 0.25f, 1.0f, 0.3f};
    g.baseColorTexture = texture(2);
    g.metallicFactor = 0.5f;
    g.roughnessFactor = 0.5f;
    g.normalTexture = texture(3);
    g.normalTexture.scale = 0.75f;
    g.emissiveFactor = {0.0f, 0.0f, 0.0f};
    g.emissiveTexture = texture(4);
    g.doubleSided = true;
    const PhongMaterial m = tessera::phongFromGltf(g);

    CHECK(equal(m.globalAmbient, {0.1f, 0.1f, 0.15f, 1.0f}));
    CHECK(equal(m.ambientColor, {0.5f, 0.25f, 1.0f, 1.0f}));
    CHECK(m.ambientTexture.texture == 2);
    CHECK(equal(m.diffuseColor, {0.5f, 0.25f, 1.0f, 1.0f}));  // OPAQUE: alpha ignored
    CHECK(m.diffuseTexture.texture == 2);
    // lerp(0.04, base, 0.5): 0.04 + 0.46 * 0.5 = 0.27, 0.04 + 0.21 * 0.5 = 0.145, 0.04 + 0.96 * 0.5 = 0.52.
    CHECK(m.specularColor.x == doctest::Approx(0.27).epsilon(1e-6));
    CHECK(m.specularColor.y == doctest::Approx(0.145).epsilon(1e-6));
    CHECK(m.specularColor.z == doctest::Approx(0.52).epsilon(1e-6));
    CHECK(m.specularColor.w == 1.0f);
    // roughness 0.5: a = 0.25, p = 2 / 0.0625 - 2 = 30 (exact in binary32).
    CHECK(m.specularPower == 30.0f);
    // emissiveFactor 0: the texture is dropped (glTF gives black; the demo would show the texel).
    CHECK(equal(m.emissiveColor, {0.0f, 0.0f, 0.0f, 1.0f}));
    CHECK_FALSE(m.emissiveTexture.present());
    CHECK(m.normalTexture.texture == 3);
    CHECK(m.normalTexture.scale == 0.75f);
    CHECK(m.opacity == 1.0f);
    CHECK(m.alphaThreshold == 0.1f);
    CHECK(m.ignoreDiffuseAlpha);
    CHECK_FALSE(m.diffuseTextureHasAlpha);
    CHECK(m.doubleSided);
    CHECK_FALSE(m.isTransparent());
    CHECK_FALSE(m.bumpTexture.present());
    CHECK_FALSE(m.opacityTexture.present());
    CHECK_FALSE(m.specularTexture.present());
    CHECK_FALSE(m.specularPowerTexture.present());
}

TEST_CASE("phongFromGltf: MASK keeps the factor's alpha in the diffuse colour and cuts at alphaCutoff") {
    Material g;
    g.baseColorFactor = {1.0f, 1.0f, 1.0f, 0.8f};
    g.baseColorTexture = texture(0);
    g.alphaMode = AlphaMode::Mask;
    g.alphaCutoff = 0.25f;
    const PhongMaterial m = tessera::phongFromGltf(g);
    CHECK(equal(m.diffuseColor, {1.0f, 1.0f, 1.0f, 0.8f}));
    CHECK(m.alphaThreshold == 0.25f);
    CHECK(m.opacity == 1.0f);
    CHECK_FALSE(m.ignoreDiffuseAlpha);
    CHECK_FALSE(m.diffuseTextureHasAlpha);
    CHECK_FALSE(m.isTransparent());

    g.alphaCutoff = 0.0f;  // cuts nothing: mapped as OPAQUE
    const PhongMaterial o = tessera::phongFromGltf(g);
    CHECK(o.ignoreDiffuseAlpha);
    CHECK(o.alphaThreshold == 0.1f);
    CHECK(o.diffuseColor.w == 1.0f);
    CHECK_FALSE(o.isTransparent());
}

TEST_CASE("phongFromGltf: BLEND is transparent with opacity = baseColorFactor.a") {
    Material g;
    g.baseColorFactor = {0.2f, 0.4f, 0.6f, 0.5f};
    g.alphaMode = AlphaMode::Blend;
    g.metallicFactor = 0.0f;
    g.roughnessFactor = 1.0f;
    PhongMaterial m = tessera::phongFromGltf(g);
    CHECK(equal(m.diffuseColor, {0.2f, 0.4f, 0.6f, 1.0f}));
    CHECK(m.opacity == 0.5f);
    CHECK(m.alphaThreshold == 0.0f);
    CHECK_FALSE(m.diffuseTextureHasAlpha);  // no texture
    CHECK(m.isTransparent());
    CHECK(equal(m.specularColor, {0.04f, 0.04f, 0.04f, 1.0f}));  // dielectric
    CHECK(m.specularPower == 0.0f);                             // roughness 1: no specular (p <= 1)

    g.baseColorFactor.w = 1.0f;  // fully opaque factor: still transparent (BLEND)
    g.baseColorTexture = texture(5);
    m = tessera::phongFromGltf(g);
    CHECK(m.opacity == 1.0f);
    CHECK(m.diffuseTextureHasAlpha);
    CHECK(m.isTransparent());
}

TEST_CASE("phongFromGltf: specular power from roughness, metals, emissive and a black base colour") {
    Material g;
    g.roughnessFactor = 0.25f;  // a = 1/16, a^2 = 1/256: p = 512 - 2 = 510
    CHECK(tessera::phongFromGltf(g).specularPower == 510.0f);
    g.roughnessFactor = 0.0f;   // a mirror: clamped to 2^10.5 (the G-buffer packing's maximum)
    CHECK(tessera::phongFromGltf(g).specularPower == tessera::kPhongMaxSpecularPower);
    g.roughnessFactor = 1.0f;
    CHECK(tessera::phongFromGltf(g).specularPower == 0.0f);
    g.roughnessFactor = 2.0f;   // outside glTF's [0, 1]: clamped to 1
    CHECK(tessera::phongFromGltf(g).specularPower == 0.0f);

    g = Material{};
    g.baseColorFactor = {0.75f, 0.5f, 0.25f, 1.0f};
    g.metallicFactor = 1.0f;    // a metal: specular colour = base colour
    CHECK(equal(tessera::phongFromGltf(g).specularColor, {0.75f, 0.5f, 0.25f, 1.0f}));

    g = Material{};
    g.emissiveFactor = {1.0f, 0.5f, 0.0f};
    g.emissiveTexture = texture(7);
    PhongMaterial m = tessera::phongFromGltf(g);
    CHECK(equal(m.emissiveColor, {1.0f, 0.5f, 0.0f, 1.0f}));
    CHECK(m.emissiveTexture.texture == 7);

    g = Material{};
    g.baseColorFactor = {0.0f, 0.0f, 0.0f, 1.0f};
    g.baseColorTexture = texture(1);
    m = tessera::phongFromGltf(g);  // black x texture = black: the texture is dropped
    CHECK_FALSE(m.diffuseTexture.present());
    CHECK_FALSE(m.ambientTexture.present());
    CHECK(equal(m.diffuseColor, {0.0f, 0.0f, 0.0f, 1.0f}));
}

} // namespace tessera_test::scene_phong_material_test
