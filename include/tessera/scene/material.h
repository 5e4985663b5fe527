// A glTF 2.0 material as the file states it (metallic-roughness core plus alphaMode,
// alphaCutoff, doubleSided, normal/occlusion/emissive textures). Shading models do not read
// this directly: each declares its own material type and maps from this one in one place
// (e.g. scene/phong_material.h for the 3dgep shading model).
#pragma once

#include <string>

#include <glm/glm.hpp>

namespace tessera {

enum class AlphaMode { Opaque, Mask, Blend };

// A reference to Scene::textures; texture < 0 means "none".
struct TextureRef {
    int texture = -1;
    int texCoord = 0;     // TEXCOORD_n set (0 or 1)
    float scale = 1.0f;   // normalTexture.scale, occlusionTexture.strength; 1 otherwise
    bool present() const { return texture >= 0; }
};

struct Material {
    std::string name;
    glm::vec4 baseColorFactor{1.0f};  // linear RGBA
    TextureRef baseColorTexture;      // sRGB
    float metallicFactor = 1.0f;
    float roughnessFactor = 1.0f;
    TextureRef metallicRoughnessTexture;  // linear; G = roughness, B = metallic
    TextureRef normalTexture;             // linear, tangent space
    TextureRef occlusionTexture;          // linear, R
    TextureRef emissiveTexture;           // sRGB
    glm::vec3 emissiveFactor{0.0f};       // linear RGB
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f;             // MASK only
    bool doubleSided = false;
    // glTF 2.0 §3.9.5 (Double Sided): back faces of a double-sided material are shaded with their
    // normals reversed. false keeps the interpolated normal on back faces (`tessera render
    // --double-sided-normals keep`), for comparison only; read through reversesBackFaceNormals.
    bool reverseBackFaceNormals = true;
};

// Whether a pixel shader negates the normal and tangent frame of `m`'s back faces (SV_IsFrontFace
// false): only double-sided materials have visible back faces (single-sided ones are culled).
inline bool reversesBackFaceNormals(const Material& m) { return m.doubleSided && m.reverseBackFaceNormals; }

} // namespace tessera
