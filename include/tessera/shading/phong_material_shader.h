// The 3dgep vertex shader and the material-gathering + lighting pixel shader (3dgep article §2.1–§2.3;
// the demo's ForwardRendering.hlsl), shared by forward and (later) deferred. Pixel shading is
// specialized at compile time by the material features it uses (a bitmask template parameter);
// a dispatcher picks the instantiation per material at run time and names it for --stats.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include <tessera/buffers/conversion.h>

#include <tessera/scene/phong_material.h>
#include <tessera/scene/scene.h>
#include <tessera/shaders/shader_stages.h>
#include <tessera/shading/fast_lighting.h>
#include <tessera/shading/phong_lighting.h>
#include <tessera/scene/scene_resources.h>
#include <tessera/texture/texture2d.h>

namespace tessera {

// VertexShaderOutput of the 3dgep article §2.1, plus TEXCOORD_1 for glTF materials that use it.
struct PhongVaryings {
    glm::vec3 posView;        // mul(ModelView, float4(position, 1)).xyz
    glm::vec2 uv0, uv1;       // TEXCOORD_0, TEXCOORD_1
    glm::vec3 tangentView;    // mul((float3x3)ModelView, tangent)
    glm::vec3 binormalView;   // mul((float3x3)ModelView, binormal)
    glm::vec3 normalView;     // mul((float3x3)ModelView, normal): upper 3x3, NOT the inverse transpose
    static constexpr std::array<VaryingField, 6> kFields{
        {{"posView", 3}, {"uv0", 2}, {"uv1", 2}, {"tangentView", 3}, {"binormalView", 3}, {"normalView", 3}}};
};

// VS_main (3dgep article §2.1). The article's vertex has a BINORMAL attribute; glTF gives tangent.w, so
// binormalObject = cross(normalObject, tangentObject.xyz) * tangentObject.w (glTF 2.0 §3.7.2.1).
// Matrix-vector products are glm's (column combination m[0]*v.x + m[1]*v.y + ..., summed left
// to right; HLSL's mul(M, v) leaves its dp4 order to the hardware).
struct PhongVS {
    using Varyings = PhongVaryings;
    glm::mat4 clipFromObject;   // ModelViewProjection = Projection * View * World
    glm::mat4 viewFromObject;   // ModelView = View * World
    VertexOutput<PhongVaryings> operator()(const SceneVertex& v) const {
        const glm::mat3 upper(viewFromObject);
        const glm::vec3 tangent(v.tangentObject);
        const glm::vec3 binormalObject = glm::cross(v.normalObject, tangent) * v.tangentObject.w;
        VertexOutput<PhongVaryings> out;
        out.posClip = clipFromObject * glm::vec4(v.posObject, 1.0f);
        out.varyings.posView = glm::vec3(viewFromObject * glm::vec4(v.posObject, 1.0f));
        out.varyings.uv0 = v.uv0;
        out.varyings.uv1 = v.uv1;
        out.varyings.tangentView = upper * tangent;
        out.varyings.binormalView = upper * binormalObject;
        out.varyings.normalView = upper * v.normalObject;
        return out;
    }
};

// HLSL Texture2D.Sample(s, uv, int2 offset): the offset is in texels of the mip level being
// sampled (D3D11.3 §22.4.15 "aoffimmi"), so it cannot be folded into uv once for all levels.
// tessera takes the LOD exactly as Sample does (bias, MinLOD/MaxLOD, min/mag decision on the
// clamped LOD, mip filter), then samples each contributing level L alone at uv + offset / size(L)
// and blends the levels as Sample does. The offset is exact in texels up to the float rounding
// of uv + offset / size(L) (exact whenever that sum is representable, e.g. power-of-two sizes
// and uv with few bits). Offset (0, 0) is exactly Texture2D::sample.
glm::vec4 sampleWithTexelOffset(const Texture2D& texture, const SamplerState& sampler, glm::vec2 uv, glm::vec2 ddxUv,
                                glm::vec2 ddyUv, glm::ivec2 offsetTexels);

// One material slot as the pixel shader sees it: texture (null = slot empty), sampler, UV set.
struct BoundTexture {
    const Texture2D* texture = nullptr;
    const SamplerState* sampler = nullptr;
    int texCoord = 0;
    bool bound() const { return texture != nullptr; }
    glm::vec4 sample(const PixelInput<PhongVaryings>& in) const {
        const bool second = texCoord == 1;
        return texture->sample(*sampler, second ? in.varyings.uv1 : in.varyings.uv0, second ? in.ddx.uv1 : in.ddx.uv0,
                               second ? in.ddy.uv1 : in.ddy.uv0);
    }
    glm::vec4 sample(const PixelInput<PhongVaryings>& in, glm::ivec2 offsetTexels) const {
        const bool second = texCoord == 1;
        return sampleWithTexelOffset(*texture, *sampler, second ? in.varyings.uv1 : in.varyings.uv0,
                                     second ? in.ddx.uv1 : in.ddx.uv0, second ? in.ddy.uv1 : in.ddy.uv0, offsetTexels);
    }
};

// Material features; a shader variant is a mask of them. Normal mapping wins over bump mapping
// when a material has both (3dgep article §2.3.1.5: "if HasNormalTexture ... else if HasBumpTexture").
enum PhongFeature : std::uint32_t {
    kPhongAmbientTexture = 1u << 0,
    kPhongEmissiveTexture = 1u << 1,
    kPhongDiffuseTexture = 1u << 2,
    kPhongSpecularTexture = 1u << 3,
    kPhongSpecularPowerTexture = 1u << 4,
    kPhongNormalMap = 1u << 5,
    kPhongBumpMap = 1u << 6,
    kPhongOpacityTexture = 1u << 7,
    kPhongAlphaTest = 1u << 8,   // discard when alpha * Opacity < AlphaThreshold (opt-in for forward)
    kPhongAllFeatures = (1u << 9) - 1u,
};

// "diffuse+normal", "none", ...: the features of a mask, in PhongFeature order.
std::string phongFeatureNames(std::uint32_t features);

// The features a material uses. `alphaTest`: the technique applies AlphaThreshold; the feature
// is set only when the test can reject something (threshold > 0 and alpha not forced to 1).
std::uint32_t phongFeatures(const PhongMaterial& material, bool alphaTest);

// Compile-time variants. T = float (exact): every combination of the features glTF materials
// produce through phongFromGltf — ambient, emissive and diffuse textures, normal map, alpha test
// (2^5 = 32 instantiations); any other mask (specular, specular-power, bump or opacity textures:
// OBJ-style materials) runs the generic variant, which compiles every texture feature in and
// checks each slot at run time (with and without the alpha test: 2 more). T = double (reference) always runs the generic variant: reference is the
// accuracy yardstick, not a speed mode. Results are identical bit for bit between a specialized
// variant and the generic one (the same code with the branches folded).
inline constexpr std::uint32_t kPhongSpecializedAxes =
    kPhongAmbientTexture | kPhongEmissiveTexture | kPhongDiffuseTexture | kPhongNormalMap | kPhongAlphaTest;

// The Forward+ light grid and light index list one pass binds (3dgep article §4.6; the demo's
// ForwardPlusRendering.hlsl PS_main: `Texture2D<uint2> LightGrid : t10`, `StructuredBuffer<uint>
// LightIndexList : t9`), read as the PS does: tileIndex = uint2(floor(SV_Position.xy /
// BLOCK_SIZE)); (startOffset, lightCount) = LightGrid[tileIndex] (0 outside the grid: D3D11
// out-of-bounds Load); lightIndex = LightIndexList[startOffset + i] (0 past the end). The bytes
// are the named buffers' (R32G32_UINT grid, R32_UINT list; techniques/forward_plus.h).
struct TileLightList {
    const std::byte* grid = nullptr;          // gridWidth x gridHeight texels of (offset, count)
    std::uint32_t gridWidth = 0, gridHeight = 0;  // tiles
    const std::byte* indices = nullptr;       // indexCount uint32 light indices
    std::uint32_t indexCount = 0;             // entries (the buffer's element count)
    std::uint32_t tileSizePx = 16;            // BLOCK_SIZE, px
};

// Everything the pixel shader reads for one draw: the Material constant buffer in T, the bound
// textures and the view-space lights (3dgep article §2.2.1 Material, §2.2.3 Light).
template <class T>
struct PhongShaderData {
    Vec4<T> globalAmbient, ambientColor, emissiveColor, diffuseColor, specularColor;
    T opacity = T(1), specularPower = T(-1), bumpIntensity = T(5), specularScale = T(128), alphaThreshold = T(0.1);
    bool ignoreDiffuseAlpha = false;  // glTF OPAQUE: alpha = 1 before x Opacity (phong_material.h)
    bool reverseBackFaceNormals = false;  // glTF 2.0 §3.9.5: back faces negate N, T, B (facingVaryings)
    BoundTexture ambientTexture, emissiveTexture, diffuseTexture, specularTexture, specularPowerTexture, normalTexture,
        bumpTexture, opacityTexture;
    std::span<const ViewLight<T>> lights;
    // Forward+: loop over this tile list instead of every light (null: every light, forward).
    const TileLightList* tileLights = nullptr;
    // Precision fast, every light (no tile list): the SIMD light loop over these (fast_lighting.h).
    const FastLightSet* fastLights = nullptr;
};

// The tangent frame a pixel shader lights with (glTF 2.0 §3.9.5, Double Sided: "back-facing sides
// ... have their normals reversed before the lighting equation is evaluated"): on a back face
// (SV_IsFrontFace false) of a material with `reverse`, normalView, tangentView and binormalView
// negated, so the normal-mapped N = T x + B y + N z is negated as a whole (and the bump-mapped one
// too); every other case (every front face, every single-sided material) the varyings unchanged.
// Negation is exact, so a reversed back face shades exactly as the mirrored normal would.
inline PhongVaryings facingVaryings(const PhongVaryings& v, bool isFrontFace, bool reverse) {
    if (isFrontFace || !reverse) return v;
    PhongVaryings r = v;
    r.normalView = -v.normalView;
    r.tangentView = -v.tangentView;
    r.binormalView = -v.binormalView;
    return r;
}

// Returns false when the pixel is discarded; otherwise `color` is PS_main's return value.
template <class T>
using PhongShadeFn = bool (*)(const PhongShaderData<T>&, const PixelInput<PhongVaryings>&, Vec4<T>& color);

struct PhongVariant {
    PhongShadeFn<float> exact = nullptr;    // set for T = float
    PhongShadeFn<float> fast = nullptr;     // set for T = float: the same variant with fastmath (phong_lighting.h)
    PhongShadeFn<double> reference = nullptr;  // set for T = double
    bool mayDiscard = false;
    std::string name;                       // "exact:diffuse+normal", "exact:generic(specular+bump)", ...
    std::string fastName;                   // "fast:diffuse+normal", ... (T = float)
};

// The variant a material with `features` runs at precision T (float or double).
template <class T>
PhongVariant selectPhongVariant(std::uint32_t features);
template <>
PhongVariant selectPhongVariant<float>(std::uint32_t features);
template <>
PhongVariant selectPhongVariant<double>(std::uint32_t features);

// The pixel shader handed to Device::draw: calls the selected variant through a pointer (one
// indirect call per pixel; the shading behind it is specialized) and writes the colour to every
// target (exact: the back buffer; reference: the back buffer and the float copy).
template <class T, bool kDiscard, int kTargets>
struct PhongPS {
    using Varyings = PhongVaryings;
    static constexpr int kTargetCount = kTargets;
    static constexpr bool kMayDiscard = kDiscard;
    PhongShadeFn<T> shade = nullptr;
    const PhongShaderData<T>* data = nullptr;
    void operator()(const PixelInput<PhongVaryings>& in, PixelOutput<kTargets>& out) const {
        Vec4<T> color;
        if (!shade(*data, in, color)) {
            out.discard();
            return;
        }
        out.target[0] = glm::vec4(color);
        // The float copy of precision reference holds what the UNORM back buffer holds before
        // its 8-bit rounding: the output merger's clamp to [0, 1] (NaN -> 0) applied here.
        if constexpr (kTargets == 2) out.target[1] = convert::clampUnorm(glm::vec4(color));
    }
};

// How the 3dgep techniques read textures.
enum class PhongSamplerChoice {
    Demo,  // the demo's LinearRepeatSampler for every slot: trilinear, wrap (3dgep demo's main.cpp)
    Gltf   // each texture's glTF sampler
};

// Texture2Ds for the Phong slots. The demo creates its 8-bit textures as R8G8B8A8_UNORM and
// writes R8G8B8A8_UNORM, so colours stay in the images' own (gamma) encoding end to end: every
// slot, base colour included, is read as Linear (UNORM, no sRGB decode, mips box-filtered on the
// codes). SceneResources decodes base colour and emissive images as sRGB only, so this set
// decodes the Linear versions of those images itself (in parallel, once per frame build).
class PhongTextureSet {
public:
    PhongTextureSet(const SceneResources& resources, PhongSamplerChoice samplers);
    BoundTexture bind(const TextureRef& ref) const;

private:
    const SceneResources* mResources;
    PhongSamplerChoice mSamplers;
    SamplerState mDemoSampler;
    std::map<int, Texture2D> mOwnLinear;  // image index -> Linear texture not in SceneResources
};

// The Material constant buffer of a PhongMaterial with its textures bound, in T.
template <class T>
PhongShaderData<T> makePhongShaderData(const PhongMaterial& material, const PhongTextureSet& textures,
                                       std::span<const ViewLight<T>> lights);

// Scene lights (world space) to the article's view-space lights, in scene order:
// PositionVS = View * (PositionWS, 1), DirectionVS = normalize(View * (DirectionWS, 0)), both in
// T from the float view matrix; Color = (color, 1); a light with non-finite range (KHR: absent =
// infinite) keeps it (never skipped by the range test).
template <class T>
std::vector<ViewLight<T>> viewLights(std::span<const Light> lights, const glm::mat4& viewFromWorld);

} // namespace tessera
