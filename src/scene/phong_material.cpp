// The glTF metallic-roughness -> 3dgep Phong material mapping (table in
// include/tessera/scene/phong_material.h): binary32, +, -, *, / only.
#include <tessera/scene/phong_material.h>

#include <algorithm>

namespace tessera {

namespace {
bool isBlack(const glm::vec3& c) { return c.x == 0.0f && c.y == 0.0f && c.z == 0.0f; }

// p = 2 / a^2 - 2, a = r^2 (Walter et al. 2007, eq. 33), clamped to [0, 2^10.5].
float specularPowerFromRoughness(float roughness) {
    const float r = std::clamp(roughness, 0.0f, 1.0f);
    const float a = r * r;
    const float aSquared = a * a;
    // 2 / aSquared - 2 > max  <=>  aSquared < 2 / (max + 2); also catches aSquared == 0.
    if (aSquared < 2.0f / (kPhongMaxSpecularPower + 2.0f)) return kPhongMaxSpecularPower;
    const float p = 2.0f / aSquared - 2.0f;
    return std::clamp(p, 0.0f, kPhongMaxSpecularPower);
}
}

PhongMaterial phongFromGltf(const Material& material) {
    PhongMaterial phong;
    const glm::vec3 base{material.baseColorFactor};
    AlphaMode mode = material.alphaMode;
    if (mode == AlphaMode::Mask && !(material.alphaCutoff > 0.0f)) mode = AlphaMode::Opaque;  // cuts nothing

    phong.ambientColor = glm::vec4(base, 1.0f);
    phong.diffuseColor = mode == AlphaMode::Mask ? material.baseColorFactor : glm::vec4(base, 1.0f);
    if (!isBlack(base)) {
        phong.ambientTexture = material.baseColorTexture;
        phong.diffuseTexture = material.baseColorTexture;
    }
    phong.emissiveColor = glm::vec4(material.emissiveFactor, 1.0f);
    if (!isBlack(material.emissiveFactor)) phong.emissiveTexture = material.emissiveTexture;

    // lerp(0.04, base, metallic) = 0.04 + (base - 0.04) * metallic, per channel.
    const float metallic = std::clamp(material.metallicFactor, 0.0f, 1.0f);
    const glm::vec3 dielectric{kDielectricSpecular};
    const glm::vec3 specular = dielectric + (base - dielectric) * metallic;
    phong.specularColor = glm::vec4(specular, 1.0f);
    phong.specularPower = specularPowerFromRoughness(material.roughnessFactor);

    phong.normalTexture = material.normalTexture;
    phong.doubleSided = material.doubleSided;
    phong.reverseBackFaceNormals = reversesBackFaceNormals(material);

    switch (mode) {
    case AlphaMode::Opaque:
        phong.ignoreDiffuseAlpha = true;
        break;
    case AlphaMode::Mask:
        phong.alphaThreshold = material.alphaCutoff;
        break;
    case AlphaMode::Blend:
        phong.opacity = material.baseColorFactor.w;
        phong.alphaThreshold = 0.0f;
        phong.diffuseTextureHasAlpha = phong.diffuseTexture.present();
        break;
    }
    return phong;
}

} // namespace tessera
