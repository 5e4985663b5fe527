// The `preview` technique: an inspection view of a loaded scene with no light model. Base
// colour (factor x sRGB texture) lit by a head light, |dot(N, V)| * 0.8 + 0.2, plus emissive;
// MASK materials discard below alphaCutoff; BLEND materials follow in a second pass with
// SRC_ALPHA / INV_SRC_ALPHA blending and no depth writes, in scene order (not sorted).
#pragma once

#include <array>

#include <tessera/techniques/technique.h>

namespace tessera {

// What each pass does (TechniqueInfo::passes; "clear", "transparent", "resolve" are shared).
inline constexpr std::array<PassCaption, 1> kPreviewPassCaptions{{
    {"opaque", "Every opaque draw: base colour x a head light, |N.V| x 0.8 + 0.2, plus emissive; MASK materials "
               "discard below alphaCutoff (an inspection view, no light model)."},
}};

// Buffers: "backbuffer" (R8G8B8A8_UNORM_SRGB: shading in linear space, encoded on write),
// "depth" (D32_FLOAT, reversed: no; 0 near, 1 far).
Frame buildPreview(const TechniqueContext& context);

// The D3D-style projection every scene technique starts from: right-handed view space (camera
// looks down -Z, as glTF), clip z in [0, w] (glm::perspectiveRH_ZO / orthoRH_ZO).
glm::mat4 projectionD3D(const Camera& camera, float aspect);

} // namespace tessera
