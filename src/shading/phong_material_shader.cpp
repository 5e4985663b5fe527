// The 3dgep pixel shader (3dgep article §2.3, the demo's ForwardRendering.hlsl PS_main) as one template
// over the scalar and the material's feature mask, its variant table, the texel-offset Sample of
// the bump-mapping path, the UNORM texture set and the view-space light conversion.
#include <tessera/shading/phong_material_shader.h>
#include <tessera/shading/phong_surface.h>

#include <array>
#include <cmath>
#include <cstring>
#include <set>
#include <utility>

#include <tbb/parallel_for.h>

namespace tessera {
namespace {

// D3D11.3 §3.1 min: a NaN operand yields the other operand.
inline float d3dMin(float a, float b) {
    if (a != a) return b;
    if (b != b) return a;
    return b < a ? b : a;
}


inline std::uint32_t loadUint32(const std::byte* base, std::size_t element) {
    std::uint32_t value;
    std::memcpy(&value, base + element * sizeof(std::uint32_t), sizeof(value));
    return value;
}

// The Forward+ PS_main light loop over the pixel's tile list (TileLightList; the light grid
// read with out-of-bounds Load = 0, the index list with out-of-bounds reads = 0).
template <class T, bool kFast>
LightingResult<T> doLightingTile(const PhongShaderData<T>& d, const glm::vec4& posWindow, T specularPower,
                                 const Vec4<T>& posView, const Vec4<T>& normalView) {
    const TileLightList& list = *d.tileLights;
    const float blockSize = float(list.tileSizePx);
    const auto tileX = std::uint32_t(std::floor(posWindow.x / blockSize));
    const auto tileY = std::uint32_t(std::floor(posWindow.y / blockSize));
    std::uint32_t startOffset = 0, lightCount = 0;
    if (tileX < list.gridWidth && tileY < list.gridHeight) {
        const std::size_t texel = std::size_t(tileY) * list.gridWidth + tileX;
        startOffset = loadUint32(list.grid, texel * 2);
        lightCount = loadUint32(list.grid, texel * 2 + 1);
    }
    const auto lightIndexAt = [&](std::uint32_t i) {
        const std::uint32_t at = startOffset + i;  // uint arithmetic, wraps as in HLSL
        return at < list.indexCount ? loadUint32(list.indices, at) : 0u;
    };
    return doLightingListed<T, kFast>(d.lights, lightCount, lightIndexAt, specularPower, posView, normalView, specularPower > T(1));
}

template <class T, std::uint32_t F, bool kFast = false>
bool shadePhong(const PhongShaderData<T>& d, const PixelInput<PhongVaryings>& in, Vec4<T>& color) {
    PhongSurface<T> s;
    if (!gatherPhongSurface<T, F>(d, in, s)) return false;
    const Vec4<T> posView(Vec3<T>(in.varyings.posView), T(1));
    LightingResult<T> lit;
    if constexpr (kFast && std::is_same_v<T, float>) {
        if (d.fastLights && !d.tileLights) {
            lit = fastLighting(*d.fastLights, s.specularPower, in.varyings.posView, glm::vec3(s.normalView), s.specularPower > 1.0f);
        } else {
            lit = d.tileLights ? doLightingTile<T, kFast>(d, in.posWindow, s.specularPower, posView, s.normalView)
                               : doLighting<T, kFast>(d.lights, s.specularPower, posView, s.normalView, s.specularPower > T(1));
        }
    } else {
        lit = d.tileLights ? doLightingTile<T, kFast>(d, in.posWindow, s.specularPower, posView, s.normalView)
                           : doLighting<T, kFast>(d.lights, s.specularPower, posView, s.normalView, s.specularPower > T(1));
    }

    const Vec4<T> diffuse = s.diffuse * Vec4<T>(lit.diffuse.x, lit.diffuse.y, lit.diffuse.z, T(1));  // lighting alpha discarded
    // specular ignored for power <= 1
    const Vec4<T> specular = s.specularPower > T(1) ? s.specular * lit.specular : Vec4<T>(T(0));
    const Vec4<T> ambient = s.ambient, emissive = s.emissive;
    const T alpha = s.alpha;
    const Vec4<T> sum = ((ambient + emissive) + diffuse) + specular;
    color = Vec4<T>(sum.x, sum.y, sum.z, alpha * d.opacity);
    return true;
}


template <std::size_t... I>
constexpr std::array<PhongShadeFn<float>, sizeof...(I)> makeExactTable(std::index_sequence<I...>) {
    return {&shadePhong<float, phongVariantMask(I)>...};
}
constexpr auto kExactTable = makeExactTable(std::make_index_sequence<kPhongVariantCount>{});
template <std::size_t... I>
constexpr std::array<PhongShadeFn<float>, sizeof...(I)> makeFastTable(std::index_sequence<I...>) {
    return {&shadePhong<float, phongVariantMask(I), true>...};
}
constexpr auto kFastTable = makeFastTable(std::make_index_sequence<kPhongVariantCount>{});

} // namespace

glm::vec4 sampleWithTexelOffset(const Texture2D& texture, const SamplerState& sampler, glm::vec2 uv, glm::vec2 ddxUv,
                                glm::vec2 ddyUv, glm::ivec2 offsetTexels) {
    if (offsetTexels == glm::ivec2(0)) return texture.sample(sampler, uv, ddxUv, ddyUv);
    if (texture.levels() == 0) return glm::vec4(0.0f);  // unbound slot
    // As Sample (texture/sampling.h steps 1-4): LOD, bias, MinLOD/MaxLOD, magnify on <= 0.
    const float lod = texture.calculateLevelOfDetailUnclamped(ddxUv, ddyUv);
    const float clamped = hlsl::max(sampler.minLod, d3dMin(sampler.maxLod, lod + sampler.mipLodBias));
    const Filter filter = clamped > 0.0f ? sampler.minFilter : sampler.magFilter;
    const float limited = d3dMin(clamped > 0.0f ? clamped : 0.0f, float(texture.levels() - 1));
    const float levelFloor = std::floor(limited);
    const int level = int(levelFloor);
    const float fraction = limited - levelFloor;
    const auto sampleOneLevel = [&](int l) {
        SamplerState single = sampler;
        single.minFilter = single.magFilter = filter;
        single.mipFilter = Filter::Point;
        single.mipLodBias = 0.0f;
        single.minLod = single.maxLod = float(l);
        const glm::vec2 shifted =
            uv + glm::vec2(offsetTexels) / glm::vec2(float(texture.width(l)), float(texture.height(l)));
        return texture.sampleLevel(single, shifted, float(l));
    };
    if (sampler.mipFilter == Filter::Point) return sampleOneLevel(level + (fraction >= 0.5f ? 1 : 0));
    const glm::vec4 nearer = sampleOneLevel(level);
    if (fraction == 0.0f) return nearer;
    return nearer + (sampleOneLevel(level + 1) - nearer) * fraction;
}

std::string phongFeatureNames(std::uint32_t features) {
    static constexpr std::array<const char*, 9> kNames{"ambient", "emissive", "diffuse", "specular", "specularPower",
                                                       "normal", "bump", "opacity", "alphaTest"};
    std::string names;
    for (std::size_t b = 0; b < kNames.size(); ++b) {
        if ((features & (1u << b)) == 0) continue;
        if (!names.empty()) names += '+';
        names += kNames[b];
    }
    return names.empty() ? std::string("none") : names;
}

std::uint32_t phongFeatures(const PhongMaterial& m, bool alphaTest) {
    std::uint32_t f = 0;
    if (m.ambientTexture.present()) f |= kPhongAmbientTexture;
    if (m.emissiveTexture.present()) f |= kPhongEmissiveTexture;
    if (m.diffuseTexture.present()) f |= kPhongDiffuseTexture;
    if (m.specularTexture.present()) f |= kPhongSpecularTexture;
    if (m.specularPowerTexture.present()) f |= kPhongSpecularPowerTexture;
    if (m.normalTexture.present()) f |= kPhongNormalMap;
    else if (m.bumpTexture.present()) f |= kPhongBumpMap;
    if (m.opacityTexture.present()) f |= kPhongOpacityTexture;
    // alpha is forced to 1 (OPAQUE) and no opacity texture: alpha * opacity < threshold is constant.
    const bool alphaVaries = !m.ignoreDiffuseAlpha || m.opacityTexture.present();
    if (alphaTest && m.alphaThreshold > 0.0f && (alphaVaries || m.opacity < m.alphaThreshold)) f |= kPhongAlphaTest;
    return f;
}

template <>
PhongVariant selectPhongVariant<float>(std::uint32_t features) {
    PhongVariant v;
    v.mayDiscard = (features & kPhongAlphaTest) != 0;
    if ((features & ~kPhongSpecializedAxes) == 0) {
        v.exact = kExactTable[phongVariantIndex(features)];
        v.fast = kFastTable[phongVariantIndex(features)];
        v.name = "exact:";
        v.name += phongFeatureNames(features);
        v.fastName = "fast:" + phongFeatureNames(features);
    } else {
        // The generic variant checks every texture slot at run time; the alpha test stays a
        // compile-time choice (it cannot be detected from a bound slot).
        v.exact = v.mayDiscard ? &shadePhong<float, kPhongAllFeatures> : &shadePhong<float, kPhongAllFeatures & ~kPhongAlphaTest>;
        v.fast = v.mayDiscard ? &shadePhong<float, kPhongAllFeatures, true>
                              : &shadePhong<float, kPhongAllFeatures & ~kPhongAlphaTest, true>;
        v.name = "exact:generic(";
        v.name += phongFeatureNames(features);
        v.name += ')';
        v.fastName = "fast" + v.name.substr(5);
    }
    return v;
}

template <>
PhongVariant selectPhongVariant<double>(std::uint32_t features) {
    PhongVariant v;
    v.mayDiscard = (features & kPhongAlphaTest) != 0;
    v.reference =
        v.mayDiscard ? &shadePhong<double, kPhongAllFeatures> : &shadePhong<double, kPhongAllFeatures & ~kPhongAlphaTest>;
    v.name = "reference:generic(";
    v.name += phongFeatureNames(features);
    v.name += ')';
    return v;
}

PhongTextureSet::PhongTextureSet(const SceneResources& resources, PhongSamplerChoice samplers)
    : mResources(&resources), mSamplers(samplers) {
    // The demo's LinearRepeatSampler: MinLinear, MagLinear, MipLinear, wrap (3dgep demo's main.cpp).
    mDemoSampler.minFilter = mDemoSampler.magFilter = mDemoSampler.mipFilter = Filter::Linear;
    mDemoSampler.addressU = mDemoSampler.addressV = AddressMode::Wrap;
    const Scene& scene = resources.scene();
    std::set<int> images;
    const auto want = [&](const TextureRef& ref) {
        if (!ref.present() || std::size_t(ref.texture) >= scene.textures.size()) return;
        if (resources.texture(ref, TexelEncoding::Linear)) return;
        const int image = scene.textures[std::size_t(ref.texture)].image;
        if (image >= 0 && std::size_t(image) < scene.images.size() && !scene.images[std::size_t(image)].rgba8.empty())
            images.insert(image);
    };
    for (const Material& m : scene.materials) {
        const PhongMaterial p = phongFromGltf(m);
        for (const TextureRef* ref : {&p.ambientTexture, &p.emissiveTexture, &p.diffuseTexture, &p.specularTexture,
                                      &p.specularPowerTexture, &p.normalTexture, &p.bumpTexture, &p.opacityTexture})
            want(*ref);
    }
    const std::vector<int> list(images.begin(), images.end());
    std::vector<Texture2D> decoded(list.size());
    tbb::parallel_for(std::size_t(0), list.size(), [&](std::size_t i) {
        decoded[i] = Texture2D::fromImage(scene.images[std::size_t(list[i])], TexelEncoding::Linear);
    });
    for (std::size_t i = 0; i < list.size(); ++i) mOwnLinear.emplace(list[i], std::move(decoded[i]));
}

BoundTexture PhongTextureSet::bind(const TextureRef& ref) const {
    BoundTexture b;
    b.texture = mResources->texture(ref, TexelEncoding::Linear);
    if (!b.texture && ref.present()) {
        const Scene& scene = mResources->scene();
        if (std::size_t(ref.texture) < scene.textures.size()) {
            const auto it = mOwnLinear.find(scene.textures[std::size_t(ref.texture)].image);
            if (it != mOwnLinear.end()) b.texture = &it->second;
        }
    }
    b.sampler = mSamplers == PhongSamplerChoice::Demo ? &mDemoSampler : &mResources->sampler(ref);
    b.texCoord = ref.texCoord;
    return b;
}

template <class T>
PhongShaderData<T> makePhongShaderData(const PhongMaterial& m, const PhongTextureSet& textures,
                                       std::span<const ViewLight<T>> lights) {
    PhongShaderData<T> d;
    d.globalAmbient = Vec4<T>(m.globalAmbient);
    d.ambientColor = Vec4<T>(m.ambientColor);
    d.emissiveColor = Vec4<T>(m.emissiveColor);
    d.diffuseColor = Vec4<T>(m.diffuseColor);
    d.specularColor = Vec4<T>(m.specularColor);
    d.opacity = T(m.opacity);
    d.specularPower = T(m.specularPower);
    d.bumpIntensity = T(m.bumpIntensity);
    d.specularScale = T(m.specularScale);
    d.alphaThreshold = T(m.alphaThreshold);
    d.ignoreDiffuseAlpha = m.ignoreDiffuseAlpha;
    d.reverseBackFaceNormals = m.reverseBackFaceNormals;
    d.ambientTexture = textures.bind(m.ambientTexture);
    d.emissiveTexture = textures.bind(m.emissiveTexture);
    d.diffuseTexture = textures.bind(m.diffuseTexture);
    d.specularTexture = textures.bind(m.specularTexture);
    d.specularPowerTexture = textures.bind(m.specularPowerTexture);
    d.normalTexture = textures.bind(m.normalTexture);
    d.bumpTexture = textures.bind(m.bumpTexture);
    d.opacityTexture = textures.bind(m.opacityTexture);
    d.lights = lights;
    return d;
}

template <class T>
std::vector<ViewLight<T>> viewLights(std::span<const Light> lights, const glm::mat4& viewFromWorld) {
    using Mat4 = glm::mat<4, 4, T, glm::defaultp>;
    const Mat4 view(viewFromWorld);
    std::vector<ViewLight<T>> out;
    out.reserve(lights.size());
    for (const Light& l : lights) {
        ViewLight<T> v;
        v.positionView = view * Vec4<T>(Vec3<T>(l.positionWorld), T(1));
        // glm::normalize as the demo's UpdateLights calls it: v * inversesqrt(dot(v, v)).
        v.directionView = glm::normalize(view * Vec4<T>(Vec3<T>(l.directionWorld), T(0)));
        v.color = Vec4<T>(Vec3<T>(l.color), T(1));
        v.spotlightAngleDeg = T(l.spotHalfAngleDeg);
        v.range = T(l.range);
        v.intensity = T(l.intensity);
        v.enabled = l.enabled && l.type != LightType::Capsule;  // the 3dgep model has no capsule lights
        v.type = l.type;
        cacheSpotCone(v);  // per-frame constants of DoSpotCone (same bits as per pixel)
        out.push_back(v);
    }
    return out;
}

template PhongShaderData<float> makePhongShaderData<float>(const PhongMaterial&, const PhongTextureSet&,
                                                           std::span<const ViewLight<float>>);
template PhongShaderData<double> makePhongShaderData<double>(const PhongMaterial&, const PhongTextureSet&,
                                                             std::span<const ViewLight<double>>);
template std::vector<ViewLight<float>> viewLights<float>(std::span<const Light>, const glm::mat4&);
template std::vector<ViewLight<double>> viewLights<double>(std::span<const Light>, const glm::mat4&);

} // namespace tessera
