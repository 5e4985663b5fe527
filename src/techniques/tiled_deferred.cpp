// The `tiled-deferred` technique (Intel 2010 sample, ComputeShaderTile.hlsl): clear -> G-buffer
// (deferred's pass) -> one compute dispatch, a group per tile: view-z range, Intel tile planes,
// light culling into the tile's list, shading of the tile's pixels -> present -> transparent
// (forward). Options and buffers are documented in include/tessera/techniques/tiled_deferred.h.
#include <tessera/techniques/tiled_deferred.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <tessera/buffers/conversion.h>
#include <tessera/buffers/target_reader.h>
#include <tessera/compute/dispatch.h>
#include <tessera/errors/input_error.h>
#include <tessera/gbuffer/specular_power_packing.h>
#include <tessera/culling/tile_depth_range.h>
#include <tessera/shading/phong_lighting.h>
#include <tessera/techniques/deferred.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/technique_options.h>

#include "gbuffer_pass.h"
#include "msaa_deferred.h"

namespace tessera {

// ----- Intel's shading and G-buffer math (public, tiled_deferred.h) -----------------------------

float intelLinstep(float minValue, float maxValue, float v) { return hlsl::saturate((v - minValue) / (maxValue - minValue)); }

namespace {

// Intel's functions generic over the scalar: T = float is the sample's (exact; kFast uses
// fastmath's pow), T = double the reference.
template <class T>
T linstep(T minValue, T maxValue, T v) {
    return hlsl::saturate((v - minValue) / (maxValue - minValue));
}

// AccumulatePhongBRDF (Rendering.hlsl): `lightContrib` already includes the attenuation.
template <class T, bool kFast = false>
void intelPhong(const Vec3<T>& normal, const Vec3<T>& lightDir, const Vec3<T>& viewDir, const Vec3<T>& lightContrib,
                T specularPower, Vec3<T>& litDiffuse, Vec3<T>& litSpecular) {
    const T nDotL = hlsl::dot(normal, lightDir);
    if (nDotL > T(0)) {
        // reflect(i, n) = i - 2 * dot(n, i) * n
        const Vec3<T> r = lightDir - (T(2) * hlsl::dot(normal, lightDir)) * normal;
        const T rDotV = hlsl::max(T(0), hlsl::dot(r, viewDir));
        const T specular = lightingPow<T, kFast>(rDotV, specularPower);
        litDiffuse += lightContrib * nDotL;
        litSpecular += lightContrib * specular;
    }
}

// lit += albedo * (litDiffuse + specularAmount * litSpecular) for one light direction.
template <class T, bool kFast = false>
void intelAccumulate(const Vec3<T>& normalView, const Vec3<T>& lightDir, const Vec3<T>& viewDir, const Vec3<T>& contrib,
                     const Vec3<T>& albedo, T specularAmount, T specularPower, Vec3<T>& lit) {
    Vec3<T> litDiffuse(T(0)), litSpecular(T(0));
    intelPhong<T, kFast>(normalView, lightDir, viewDir, contrib, specularPower, litDiffuse, litSpecular);
    lit += albedo * (litDiffuse + specularAmount * litSpecular);
}

template <class T>
Vec3<T> normalize3(const Vec3<T>& v) {
    return v / std::sqrt(hlsl::dot(v, v));
}

// AccumulateBRDF's point-light body (public float version: intelAccumulateBrdf).
template <class T, bool kFast = false>
void accumulateBrdf(const Vec3<T>& posView, const Vec3<T>& normalView, const Vec3<T>& albedo, T specularAmount,
                    T specularPower, const IntelPointLight& light, Vec3<T>& lit) {
    const Vec3<T> lightPos(light.positionView);
    Vec3<T> directionToLight = lightPos - posView;
    const T distanceToLight = std::sqrt(hlsl::dot(directionToLight, directionToLight));
    if (distanceToLight < T(light.attenuationEnd)) {
        const T attenuation = linstep(T(light.attenuationEnd), T(light.attenuationBegin), distanceToLight);
        directionToLight *= T(1) / distanceToLight;  // rcp: correctly rounded here
        intelAccumulate<T, kFast>(normalView, directionToLight, normalize3(posView), attenuation * Vec3<T>(light.color), albedo,
                                  specularAmount, specularPower, lit);
    }
}

} // namespace

void intelAccumulateBrdf(const glm::vec3& posView, const glm::vec3& normalView, const glm::vec3& albedo,
                         float specularAmount, float specularPower, const IntelPointLight& light, glm::vec3& lit) {
    accumulateBrdf<float>(posView, normalView, albedo, specularAmount, specularPower, light, lit);
}

glm::vec3 positionViewFromDepthIntel(std::uint32_t pxX, std::uint32_t pxY, float zBuffer, glm::uvec2 framebufferPx,
                                     const glm::mat4& projectionLh) {
    const glm::vec2 screenPixelOffset = glm::vec2(2.0f, -2.0f) / glm::vec2(framebufferPx);
    const glm::vec2 positionScreen = (glm::vec2(float(pxX), float(pxY)) + 0.5f) * screenPixelOffset + glm::vec2(-1.0f, 1.0f);
    const float viewSpaceZ = projectionLh[3][2] / (zBuffer - projectionLh[2][2]);  // _43 / (z - _33)
    const glm::vec2 screenSpaceRay(positionScreen.x / projectionLh[0][0], positionScreen.y / projectionLh[1][1]);
    return {screenSpaceRay.x * viewSpaceZ, screenSpaceRay.y * viewSpaceZ, viewSpaceZ};
}

glm::mat4 projectionLhFromRh(const glm::mat4& projectionRh) {
    glm::mat4 p = projectionRh;
    p[2] = -p[2];
    return p;
}

glm::vec3 intelSpheremapRoundTrip(const glm::vec3& n) {
    const float oneMinusZ = 1.0f - n.z;
    const float p = std::sqrt((n.x * n.x + n.y * n.y) + oneMinusZ * oneMinusZ);
    glm::vec2 e = glm::vec2(n.x, n.y) / p * 0.5f + 0.5f;
    e = glm::vec2(convert::halfToFloat(convert::floatToHalf(e.x)), convert::halfToFloat(convert::floatToHalf(e.y)));  // R16G16B16A16_FLOAT
    const glm::vec2 tmp = e - e * e;
    const float f = tmp.x + tmp.y;
    const float m = std::sqrt(4.0f * f - 1.0f);
    const glm::vec2 xy = m * (e * 4.0f - 2.0f);
    return {xy.x, xy.y, 3.0f - 8.0f * f};
}

namespace {

constexpr std::uint32_t kIndicesRow = 16384;  // "tiles.lightIndices" row length (kMaxSurfaceDimension)
constexpr std::uint32_t kUnbounded = 0xFFFFFFFFu;

enum class Shading { Intel, Dgep };

struct TiledOptions {
    Shading shading = Shading::Intel;
    bool floatTargets = false;
    bool positionFromGBuffer = false;
    bool spheremap = true;
    IntelSidePlanes planes = IntelSidePlanes::Sample2010;
    std::uint32_t tileSize = kIntelTileDim;
    std::uint32_t capacity = kIntelMaxLights;
    PhongSamplerChoice sampler = PhongSamplerChoice::Demo;
    bool alphaTest = false;
    EdgeDetector edges = EdgeDetector::DepthNormal;  // MSAA: RequiresPerSampleShading
};

TiledOptions parseOptions(const nlohmann::json& j, const std::string& file) {
    const OptionReader r(j, kTiledDeferredOptions, file);
    TiledOptions o;
    o.shading = r.is("shading", "3dgep") ? Shading::Dgep : Shading::Intel;
    o.floatTargets = r.is("gbuffer", "float");
    o.positionFromGBuffer = r.is("position", "gbuffer");
    o.spheremap = r.is("normals", "spheremap");
    o.planes = r.is("tilePlanes", "tile") ? IntelSidePlanes::TileBounds : IntelSidePlanes::Sample2010;
    (void)r.word("projection");  // checked: "d3d" is its only value
    o.sampler = r.is("sampler", "gltf") ? PhongSamplerChoice::Gltf : PhongSamplerChoice::Demo;
    o.alphaTest = r.flag("alphaTest");
    o.edges = gbuffer_detail::parseEdgeDetector(r);
    o.tileSize = std::uint32_t(r.integer("tileSize"));
    // IntegerOrWord: "unbounded", or an integer in 1..2^32 - 2 (the table's bound; 2^32 - 1 is kUnbounded).
    o.capacity = r.is("tileListCapacity", "unbounded")
                     ? kUnbounded
                     : std::uint32_t(r.integer("tileListCapacity"));
    return o;
}

// A PS output value converted for an R8G8B8A8_UNORM target without blending: NaN -> 0, clamp to
// [0, 1] (D3D11.3 §3.2.3.6), rounded by the surface's encoder.
void storeUnorm8(Surface& target, std::uint32_t x, std::uint32_t y, glm::vec4 v, std::uint32_t sample = 0) {
    for (int c = 0; c < 4; ++c) v[c] = v[c] == v[c] ? std::min(std::max(v[c], 0.0f), 1.0f) : 0.0f;
    target.store(x, y, sample, v);
}

// One scene light as the culling loop sees it (left-handed view space, Intel's convention).
struct CullLight {
    enum Kind : std::uint8_t { Sphere, Always, Never };
    glm::vec3 posViewLh{0.0f};
    float radius = 0.0f;  // attenuationEnd = range, view units
    Kind kind = Never;
};

// One scene light for Intel's shading: a PointLight, or a light without falloff (directional:
// lightDirLh = normalize(-direction); infinite-range point / spot: attenuation 1).
struct IntelLight {
    IntelPointLight point;
    bool directional = false, infinite = false;
    glm::vec3 lightDirLh{0.0f};        // directional: normalize(-DirectionVS), left-handed
    const ViewLight<float>* spot = nullptr;  // spot lights: the cone of 3dgep's DoSpotCone (RH view)
};

// What the dispatch reads and writes for one frame.
struct TiledSetup {
    TiledOptions options;
    std::shared_ptr<ForwardPassSetup> forward;
    std::uint32_t width = 0, height = 0;
    glm::uvec2 tiles{0u};
    glm::mat4 projectionLh{1.0f};
    float cameraNear = 0.0f, cameraFar = 0.0f;  // mCameraNearFar
    std::vector<CullLight> cull;
    std::vector<IntelLight> intelLights;
    // Bound by the dispatch pass:
    std::vector<float> depth;  // the depth buffer as Load returns it (D24 decoded), sample 0
    DepthImageView depthView;
    // MSAA: every sample's depth image (sampleViews[0] is depthView), the edge detectors' inputs
    // and outputs, and per tile the pixels and samples shaded (DrawStats' compute counters).
    std::uint32_t samples = 1;
    std::vector<std::vector<float>> sampleDepth;
    std::vector<DepthImageView> sampleViews;
    TargetReader edgeSurface, edgeCoverage;
    Surface* edges = nullptr;
    std::vector<std::uint64_t> shadedPixels, shadedSamples, edgePixels;
    TargetReader accumulation, diffuse, specular, normal, position;
    Surface* back = nullptr;
    Surface* reference = nullptr;  // precision reference: the float copy of the back buffer
    Surface* lit = nullptr;
    Surface* heat = nullptr;
    // Per tile (row-major), each written by its own group only:
    std::vector<std::vector<std::uint32_t>> lists;
    std::vector<std::uint32_t> appended;  // sTileNumLights after the loop (may exceed the capacity)
    std::vector<TileDepthBits> ranges;
    PixelWatch* watch = nullptr;  // Device::pixelWatch during the dispatch (tessera probe)
};

// Pixel (x, y) of the tile: 3dgep's DoLighting over the tile's lights and forward's final
// expression (deferred.h ComposePS), where the G-buffer has geometry.
// With MSAA `i` is the sample (Intel's ComputeSurfaceDataFromGBufferSample: the sample's G-buffer
// and depth, the position along the pixel centre's ray).
template <class T, bool kFast>
void shadePixelDgep(const TiledSetup& s, std::span<const ViewLight<T>> lights, std::uint32_t x, std::uint32_t y, std::uint32_t i = 0) {
    const float zBuffer = s.sampleViews[i].load(x, y);
    if (!(zBuffer < 1.0f)) return;  // the cleared depth: no geometry, the clear colour stays
    const TiledOptions& o = s.options;
    glm::vec4 posViewStored;
    if (o.positionFromGBuffer) {
        posViewStored = s.position.load(x, y, i);
    } else {
        const glm::vec3 lh = positionViewFromDepthIntel(x, y, zBuffer, {s.width, s.height}, s.projectionLh);
        posViewStored = glm::vec4(lh.x, lh.y, -lh.z, 1.0f);
    }
    const Vec4<T> posView(posViewStored);
    const Vec4<T> normalView(s.normal.load(x, y, i));
    const glm::vec4 specularStored = s.specular.load(x, y, i);
    const T specularPower = T(o.floatTargets ? specularStored.w : unpackSpecularPower(specularStored.w));
    const LightingResult<T> lit = doLighting<T, kFast>(lights, specularPower, posView, normalView, specularPower > T(1));
    const Vec4<T> ambientEmissive(s.accumulation.load(x, y, i));
    Vec4<T> diffuse(s.diffuse.load(x, y, i));
    diffuse *= Vec4<T>(lit.diffuse.x, lit.diffuse.y, lit.diffuse.z, T(1));
    Vec4<T> specular(T(0));
    if (specularPower > T(1)) specular = Vec4<T>(T(specularStored.x), T(specularStored.y), T(specularStored.z), T(0)) * lit.specular;
    const Vec4<T> sum = (ambientEmissive + diffuse) + specular;
    const glm::vec4 color(float(sum.x), float(sum.y), float(sum.z), float(ambientEmissive.w));
    storeUnorm8(*s.back, x, y, color, i);
    if (s.reference) s.reference->store(x, y, i, convert::clampUnorm(color));
}

// Pixel (x, y): Intel's per-pixel body of ComputeShaderTileCS (MSAA 1): SurfaceData from the
// G-buffer, AccumulateBRDF over the tile's list, WriteSample(float4(lit, 1)) or 0 with no lights.
// T = double (reference): the same from the G-buffer's float values; the reference buffer gets
// what the present pass makes of it without the half-float "lit" and the 8-bit rounding.
// The scene's spot cone on Intel's light (3dgep's DoSpotCone: tessera's spot lights under Intel
// shading); directionToLight is the normalised left-handed L, flipped to the right-handed -L.
template <class T, bool kFast>
T intelSpotCone(const IntelLight& light, const Vec3<T>& directionToLight) {
    ViewLight<T> spot;
    spot.directionView = Vec4<T>(light.spot->directionView);
    spot.spotlightAngleDeg = T(light.spot->spotlightAngleDeg);
    if constexpr (std::is_same_v<T, float>) {  // the per-frame cone constants (viewLights)
        spot.spotMinCos = light.spot->spotMinCos;
        spot.spotMaxCos = light.spot->spotMaxCos;
    }
    return doSpotCone<T, kFast>(spot, Vec4<T>(directionToLight.x, directionToLight.y, -directionToLight.z, T(0)));
}

// What one light added at the watched pixel under Intel's shading (AccumulateBRDF adds one colour
// per light, albedo included: LightTerm::combined), with the distance and falloff it used.
template <class T, bool kFast>
LightTerm describeIntelLight(std::uint32_t index, const IntelLight& light, const Vec3<T>& posViewLh, const Vec3<T>& normalLh,
                             const Vec3<T>& added) {
    LightTerm term;
    term.light = index;
    term.combined = true;
    term.diffuse = glm::vec4(glm::vec3(added), 0.0f);
    if (light.directional) {
        term.nDotL = float(hlsl::dot(normalLh, Vec3<T>(light.lightDirLh)));
        return term;
    }
    const Vec3<T> toLight = Vec3<T>(light.point.positionView) - posViewLh;
    const T distance = std::sqrt(hlsl::dot(toLight, toLight));
    term.distance = float(distance);
    term.nDotL = float(hlsl::dot(normalLh, toLight / distance));
    if (light.infinite) return term;  // no falloff and no cone (shadePixelIntel)
    if (light.spot) term.cone = float(intelSpotCone<T, kFast>(light, Vec3<T>(toLight * (T(1) / distance))));
    term.range = light.point.attenuationEnd;
    if (distance < T(light.point.attenuationEnd))
        term.falloff = float(linstep(T(light.point.attenuationEnd), T(light.point.attenuationBegin), distance));
    else term.skip = LightTerm::Skip::OutOfRange;
    return term;
}

template <class T, bool kFast>
void shadePixelIntel(const TiledSetup& s, std::span<const std::uint32_t> list, std::uint32_t x, std::uint32_t y, std::uint32_t i = 0) {
    const float zBuffer = s.sampleViews[i].load(x, y);
    const bool sky = !(zBuffer < 1.0f);  // the present pass keeps the clear colour there
    if (list.empty()) {
        s.lit->store(x, y, i, glm::vec4(0.0f));
        if (s.reference && !sky) s.reference->store(x, y, i, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
        return;
    }
    const TiledOptions& o = s.options;
    glm::vec3 posViewLhStored;
    if (o.positionFromGBuffer) {
        const glm::vec4 p = s.position.load(x, y, i);
        posViewLhStored = glm::vec3(p.x, p.y, -p.z);
    } else {
        posViewLhStored = positionViewFromDepthIntel(x, y, zBuffer, {s.width, s.height}, s.projectionLh);
    }
    const Vec3<T> posViewLh(posViewLhStored);
    const glm::vec4 n = s.normal.load(x, y, i);
    glm::vec3 normalLhStored(n.x, n.y, -n.z);
    if (o.spheremap) normalLhStored = intelSpheremapRoundTrip(normalLhStored);
    const Vec3<T> normalLh(normalLhStored);
    const Vec3<T> albedo(glm::vec3(s.diffuse.load(x, y, i)));
    const T specularAmount(kIntelSpecularAmount), specularPower(kIntelSpecularPower);
    Vec3<T> lit(T(0));
    std::vector<LightTerm>* const trace = watchedLightTerms();
    for (const std::uint32_t index : list) {
        const IntelLight& light = s.intelLights[index];
        const Vec3<T> litBefore = lit;
        const Vec3<T> color(light.point.color);
        if (light.directional) {
            intelAccumulate<T, kFast>(normalLh, Vec3<T>(light.lightDirLh), normalize3(posViewLh), color, albedo, specularAmount,
                                      specularPower, lit);
        } else if (light.infinite) {
            Vec3<T> directionToLight = Vec3<T>(light.point.positionView) - posViewLh;
            const T distanceToLight = std::sqrt(hlsl::dot(directionToLight, directionToLight));
            directionToLight *= T(1) / distanceToLight;
            intelAccumulate<T, kFast>(normalLh, directionToLight, normalize3(posViewLh), color, albedo, specularAmount,
                                      specularPower, lit);
        } else if (light.spot) {
            // AccumulateBRDF with the contribution scaled by the scene's cone (tessera: Intel has no
            // spot lights); DoSpotCone reads the right-handed -L, the flip of the left-handed one.
            Vec3<T> directionToLight = Vec3<T>(light.point.positionView) - posViewLh;
            const T distanceToLight = std::sqrt(hlsl::dot(directionToLight, directionToLight));
            if (distanceToLight < T(light.point.attenuationEnd)) {
                const T attenuation = linstep(T(light.point.attenuationEnd), T(light.point.attenuationBegin), distanceToLight);
                directionToLight *= T(1) / distanceToLight;
                const T cone = intelSpotCone<T, kFast>(light, directionToLight);
                intelAccumulate<T, kFast>(normalLh, directionToLight, normalize3(posViewLh), attenuation * color * cone, albedo,
                                          specularAmount, specularPower, lit);
            }
        } else {
            accumulateBrdf<T, kFast>(posViewLh, normalLh, albedo, specularAmount, specularPower, light.point, lit);
        }
        if (trace) [[unlikely]] trace->push_back(describeIntelLight<T, kFast>(index, light, posViewLh, normalLh, lit - litBefore));
    }
    s.lit->store(x, y, i, glm::vec4(glm::vec3(lit), 1.0f));
    if (s.reference && !sky) s.reference->store(x, y, i, convert::clampUnorm(glm::vec4(glm::vec3(lit), 1.0f)));
}

// The watched pixel's shading as a compute event: the target it writes before and after, and the
// terms the light loop left (3dgep shading loops over the gathered lights: its indices are the
// list's positions, mapped back to scene indices here).
template <class Shade>
void watchPixel(const TiledSetup& f, std::span<const std::uint32_t> list, std::uint32_t x, std::uint32_t y, Shade&& shade) {
    PixelDrawEvent ev;
    ev.compute = true;
    ev.coverage = ev.passed = 1;
    ev.shaded = true;
    ev.posWindow = glm::vec4(float(x) + 0.5f, float(y) + 0.5f, f.depthView.load(x, y), 1.0f);
    const Surface* target = f.options.shading == Shading::Intel ? f.lit : f.back;
    ev.colorFormat = target->format();
    const std::size_t bytes = formatInfo(target->format()).bytesPerTexel;
    std::memcpy(ev.colorBefore.data(), target->texel(x, y), bytes);
    setWatchedLightTerms(&ev.lights);
    setWatchedSurface(&ev.surface);
    shade();
    setWatchedLightTerms(nullptr);
    setWatchedSurface(nullptr);
    std::memcpy(ev.colorAfter.data(), target->texel(x, y), bytes);
    ev.output = target->load(x, y);
    if (f.options.shading == Shading::Dgep)
        for (LightTerm& term : ev.lights) term.light = term.light < list.size() ? list[term.light] : term.light;
    f.watch->events.push_back(std::move(ev));
}

// RequiresPerSampleShading (or the chosen detector) from the G-buffer pass's EdgeSample targets.
bool edgePixel(const TiledSetup& f, std::uint32_t x, std::uint32_t y) {
    return gbuffer_detail::edgePixelAt(f.options.edges, f.edgeSurface, f.edgeCoverage, f.samples, x, y);
}

// A one-surface pixel: sample 0's results written to its other samples (the sample's
// WriteSample loop over every sample with one value).
void copySampleZero(const TiledSetup& f, std::uint32_t x, std::uint32_t y) {
    const auto copy = [&](Surface* s) {
        if (!s) return;
        const std::size_t bytes = s->bytesPerTexel();
        for (std::uint32_t i = 1; i < f.samples; ++i) std::memcpy(s->texel(x, y, i), s->texel(x, y, 0), bytes);
    };
    copy(f.options.shading == Shading::Intel ? f.lit : f.back);
    copy(f.reference);
}

// ComputeShaderTileCS, one group per tile of kDim x kDim pixels (one thread each).
template <std::uint32_t kDim>
struct TileKernel {
    static constexpr glm::uvec3 groupSize{kDim, kDim, 1};
    struct Shared {
        std::uint32_t minZ, maxZ;  // sMinZ, sMaxZ (asuint of view z)
        std::uint32_t numLights;   // sTileNumLights
    };
    TiledSetup* s = nullptr;

    void operator()(compute::GroupContext<Shared>& g) const {
        TiledSetup& f = *s;
        Shared& sh = g.shared();
        const glm::uvec2 groupId(g.groupId());
        const std::size_t tile = std::size_t(groupId.y) * f.tiles.x + groupId.x;

        // Per-thread view z, valid near <= z < far, InterlockedMin / Max over asuint, initialised
        // to FLT_MAX / 0: tile_depth_range.h reduces the tile's pixels with the same result.
        // With MSAA every sample's view z joins the reduction (the sample's per-sample loop).
        g.forOneThread(0, [&](const compute::ThreadIds&) {
            TileDepthBits bits = tileViewZBitsIntel(f.depthView, groupId, kDim, f.projectionLh, f.cameraNear, f.cameraFar);
            for (std::uint32_t i = 1; i < f.samples; ++i) {
                const TileDepthBits b = tileViewZBitsIntel(f.sampleViews[i], groupId, kDim, f.projectionLh, f.cameraNear, f.cameraFar);
                bits.minBits = std::min(bits.minBits, b.minBits);
                bits.maxBits = std::max(bits.maxBits, b.maxBits);
            }
            sh.minZ = bits.minBits;
            sh.maxZ = bits.maxBits;
            sh.numLights = 0;
        });
        f.ranges[tile] = TileDepthBits{sh.minZ, sh.maxZ};
        const std::array<glm::vec4, 6> planes =
            tileFrustumPlanesIntel(groupId, kDim, {f.width, f.height}, f.projectionLh, std::bit_cast<float>(sh.minZ),
                                   std::bit_cast<float>(sh.maxZ), f.options.planes);

        // for (lightIndex = groupIndex; lightIndex < totalLights; lightIndex += GROUP_SIZE):
        // appends in ascending light index (dispatch.h order rule 2).
        std::vector<std::uint32_t>& list = f.lists[tile];
        list.clear();
        g.forEachStrided(std::uint32_t(f.cull.size()), [&](const compute::ThreadIds&, std::uint32_t lightIndex) {
            const CullLight& light = f.cull[lightIndex];
            const bool inFrustum = light.kind == CullLight::Always ||
                                   (light.kind == CullLight::Sphere && sphereInFrustumIntel(light.posViewLh, light.radius, planes));
            if (!inFrustum) return;
            const std::uint32_t listIndex = sh.numLights++;  // InterlockedAdd(sTileNumLights, 1, listIndex)
            if (listIndex < f.options.capacity) list.push_back(lightIndex);
        });
        f.appended[tile] = sh.numLights;

        const Precision precision = f.forward->precision;
        thread_local std::vector<ViewLight<float>> gathered;
        thread_local std::vector<ViewLight<double>> gatheredReference;
        if (f.options.shading == Shading::Dgep) {
            gathered.clear();
            gatheredReference.clear();
            for (const std::uint32_t index : list) {
                if (precision == Precision::Reference) gatheredReference.push_back(f.forward->lightsReference[index]);
                else gathered.push_back(f.forward->lightsExact[index]);
            }
        }
        const glm::vec4 heat(float(sh.numLights) / 255.0f);  // visualizeLightCount
        // MSAA (DEFER_PER_SAMPLE): sample 0 of every pixel, copied to the others where the pixel is
        // one surface; edge pixels (RequiresPerSampleShading) shaded per sample after the tile's
        // first loop (the sample's LDS list of y << 16 | x, here in the same row-major order).
        std::vector<std::uint32_t> deferred;
        std::uint64_t pixelsShaded = 0;
        const auto shadeSample = [&](std::uint32_t x, std::uint32_t y, std::uint32_t i) {
            if (f.options.shading == Shading::Intel) {
                if (precision == Precision::Reference) shadePixelIntel<double, false>(f, list, x, y, i);
                else if (precision == Precision::Fast) shadePixelIntel<float, true>(f, list, x, y, i);
                else shadePixelIntel<float, false>(f, list, x, y, i);
            } else if (precision == Precision::Reference) shadePixelDgep<double, false>(f, gatheredReference, x, y, i);
            else if (precision == Precision::Fast) shadePixelDgep<float, true>(f, gathered, x, y, i);
            else shadePixelDgep<float, false>(f, gathered, x, y, i);
        };
        g.forEachThread([&](const compute::ThreadIds& t) {
            const std::uint32_t x = t.dispatchThreadId.x, y = t.dispatchThreadId.y;
            if (x >= f.width || y >= f.height) return;  // only onscreen pixels
            storeUnorm8(*f.heat, x, y, heat);
            const auto shadePixel = [&] { shadeSample(x, y, 0); };
            if (f.watch && x == f.watch->x && y == f.watch->y) [[unlikely]] watchPixel(f, list, x, y, shadePixel);
            else shadePixel();
            ++pixelsShaded;
            if (f.samples > 1) {
                if (edgePixel(f, x, y)) deferred.push_back(y << 16 | x);
                else copySampleZero(f, x, y);
            }
        });
        for (const std::uint32_t packed : deferred) {
            const std::uint32_t x = packed & 0xFFFFu, y = packed >> 16;
            for (std::uint32_t i = 1; i < f.samples; ++i) shadeSample(x, y, i);
            for (std::uint32_t i = 0; i < f.samples; ++i) f.edges->store(x, y, i, glm::vec4(1.0f, 0.0f, 0.0f, 0.0f));
        }
        f.shadedPixels[tile] = pixelsShaded;
        f.edgePixels[tile] = deferred.size();
        f.shadedSamples[tile] = deferred.size() * (f.samples - 1);
    }
};

template <std::uint32_t kDim>
void dispatchTiles(TiledSetup& s, Device& device) {
    s.watch = device.pixelWatch();
    const TileKernel<kDim> kernel{&s};
    compute::DispatchDesc desc;
    desc.order = compute::GroupOrder::Parallel;  // groups write only their own tile's pixels and lists
    device.execute([&] { compute::dispatch(kernel, glm::uvec3(s.tiles.x, s.tiles.y, 1u), desc); });
}

// Lights to view space once per frame (the sample's per-frame light buffer upload).
void lightsToView(const TechniqueContext& ctx, TiledSetup* setup) {
    const std::vector<Light>& lights = ctx.lights();
    const std::vector<ViewLight<float>>& viewLights = setup->forward->lightsExact;
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const ViewLight<float>& v = viewLights[i];
        CullLight c;
        IntelLight il;
        il.point.positionView = glm::vec3(v.positionView.x, v.positionView.y, -v.positionView.z);
        il.point.color = glm::vec3(v.color) * v.intensity;
        il.point.attenuationEnd = v.range;
        il.point.attenuationBegin = kIntelAttenuationBeginRatio * v.range;
        il.directional = v.type == LightType::Directional;
        il.infinite = !il.directional && !std::isfinite(v.range);
        if (v.type == LightType::Spot && !il.infinite) il.spot = &v;
        if (il.directional) {
            const glm::vec3 toLight = normalize3<float>(glm::vec3(-v.directionView.x, -v.directionView.y, -v.directionView.z));
            il.lightDirLh = glm::vec3(toLight.x, toLight.y, -toLight.z);
        }
        c.posViewLh = il.point.positionView;
        c.radius = v.range;
        c.kind = !v.enabled ? CullLight::Never : (il.directional || il.infinite) ? CullLight::Always : CullLight::Sphere;
        setup->cull.push_back(c);
        setup->intelLights.push_back(il);
    }
}

// The "tiles" pass up to its outputs: the G-buffer, depth and targets bound, the dispatch at the
// tile size, then the shaded-pixel counts and the overflow note.
void runTiles(TiledSetup& s, Device* device, DrawStats* stats, const std::string& back, const std::string& backReference,
              BufferRegistry& reg) {
    const Surface& depth = reg.get("depth");
    s.sampleDepth.resize(s.samples);
    s.sampleViews.resize(s.samples);
    for (std::uint32_t i = 0; i < s.samples; ++i) {
        std::vector<float>& d = i == 0 ? s.depth : s.sampleDepth[i];
        d.resize(std::size_t(s.width) * s.height);
        for (std::uint32_t y = 0; y < s.height; ++y)
            for (std::uint32_t x = 0; x < s.width; ++x) d[std::size_t(y) * s.width + x] = depth.loadDepth(x, y, i);
        s.sampleViews[i] = DepthImageView{d, s.width, s.height};
    }
    s.depthView = s.sampleViews[0];
    if (s.samples > 1) {
        s.edgeSurface = TargetReader(reg.get(std::string(gbuffer_detail::kEdgeSurfaceTarget)));
        s.edgeCoverage = TargetReader(reg.get(std::string(gbuffer_detail::kEdgeCoverageTarget)));
        s.edges = &reg.get(std::string(gbuffer_detail::kEdgesBuffer));
    }
    const std::size_t tileCountTotal = s.lists.size();
    s.shadedPixels.assign(tileCountTotal, 0);
    s.shadedSamples.assign(tileCountTotal, 0);
    s.edgePixels.assign(tileCountTotal, 0);
    s.accumulation = TargetReader(reg.get("accumulation"));
    s.diffuse = TargetReader(reg.get("gbuffer.diffuse"));
    s.specular = TargetReader(reg.get("gbuffer.specular"));
    s.normal = TargetReader(reg.get("gbuffer.normal"));
    if (s.options.positionFromGBuffer) s.position = TargetReader(reg.get("gbuffer.position"));
    s.back = &reg.get(back);
    s.reference = s.forward->precision == Precision::Reference ? &reg.get(backReference) : nullptr;
    s.heat = &reg.get("heatmap");
    s.lit = s.options.shading == Shading::Intel ? &reg.get("lit") : nullptr;
    switch (s.options.tileSize) {
    case 8: dispatchTiles<8>(s, *device); break;
    case 32: dispatchTiles<32>(s, *device); break;
    default: dispatchTiles<16>(s, *device); break;
    }
    if (stats) {
        DrawStats counted;
        for (std::size_t t = 0; t < tileCountTotal; ++t) {
            counted.computeShadedPixels += s.shadedPixels[t];
            counted.computeShadedSamples += s.shadedSamples[t];
            counted.edgePixels += s.edgePixels[t];
        }
        if (s.samples > 1) counted.edgeTestedPixels = std::uint64_t(s.width) * s.height;
        *stats += counted;
    }
    if (FrameNotes* notes = s.forward->notes) {
        std::uint64_t dropped = 0;
        for (std::size_t t = 0; t < s.lists.size(); ++t)
            if (s.appended[t] > s.lists[t].size()) dropped += s.appended[t] - s.lists[t].size();
        notes->add({"light-list-overflow", "tile light-list entries past the tile list's capacity dropped", dropped, 16,
                    "--option tileListCapacity=unbounded", true});
    }
}

// The "tiles" pass's buffers.
void writeTileBuffers(const TiledSetup& s, BufferRegistry& reg) {
    // The lists, row-major by tile, the grid (offset, stored count) and the appended counts.
    std::size_t total = 0;
    for (const auto& l : s.lists) total += l.size();
    const std::uint32_t n = std::uint32_t(std::max<std::size_t>(total, 1));
    Surface& grid = reg.create("tiles.grid", {s.tiles.x, s.tiles.y, Format::R32G32_UINT, 1});
    Surface& counts = reg.create("tiles.lightCount", {s.tiles.x, s.tiles.y, Format::R32_UINT, 1});
    Surface& ranges = reg.create("tiles.depthRange", {s.tiles.x, s.tiles.y, Format::R32G32_UINT, 1});
    Surface& indices =
        reg.create("tiles.lightIndices", {std::min(n, kIndicesRow), (n + kIndicesRow - 1) / kIndicesRow, Format::R32_UINT, 1});
    indices.clearUint(glm::uvec4(0u));
    std::uint32_t offset = 0;
    for (std::uint32_t ty = 0; ty < s.tiles.y; ++ty)
        for (std::uint32_t tx = 0; tx < s.tiles.x; ++tx) {
            const std::size_t tile = std::size_t(ty) * s.tiles.x + tx;
            encodeTexelUint(Format::R32G32_UINT, glm::uvec4(offset, std::uint32_t(s.lists[tile].size()), 0u, 0u),
                            grid.texel(tx, ty));
            encodeTexelUint(Format::R32_UINT, glm::uvec4(s.appended[tile], 0u, 0u, 0u), counts.texel(tx, ty));
            encodeTexelUint(Format::R32G32_UINT, glm::uvec4(s.ranges[tile].minBits, s.ranges[tile].maxBits, 0u, 0u),
                            ranges.texel(tx, ty));
            for (const std::uint32_t index : s.lists[tile]) {
                encodeTexelUint(Format::R32_UINT, glm::uvec4(index, 0u, 0u, 0u),
                                indices.texel(offset % kIndicesRow, offset / kIndicesRow));
                ++offset;
            }
        }
}

} // namespace

Frame buildTiledDeferred(const TechniqueContext& ctx) {
    const std::string file = ctx.errorFile();
    if (ctx.camera.projection == ProjectionKind::Orthographic)
        throw inputError(file, "/camera", "tiled-deferred needs a perspective camera (Intel's tile planes and view-z reconstruction)");
    auto setup = std::make_shared<TiledSetup>();
    setup->options = parseOptions(ctx.options, file);
    if (ctx.precision == Precision::Reference) setup->options.floatTargets = true;  // reference keeps the G-buffer unquantized
    const TiledOptions& opt = setup->options;
    setup->forward = makeForwardPassSetup(ctx, ProjectionConvention::D3d, opt.sampler, opt.alphaTest);
    setup->width = ctx.width;
    setup->height = ctx.height;
    setup->tiles = tileCount({ctx.width, ctx.height}, opt.tileSize);
    setup->projectionLh = projectionLhFromRh(setup->forward->clipFromView);
    setup->cameraNear = ctx.camera.nearZ;
    setup->cameraFar = ctx.camera.farZ;
    const std::size_t tileTotal = std::size_t(setup->tiles.x) * setup->tiles.y;
    setup->lists.resize(tileTotal);
    setup->appended.resize(tileTotal);
    setup->ranges.resize(tileTotal);

    lightsToView(ctx, setup.get());

    const Format colorFormat = opt.floatTargets ? Format::R32G32B32A32_FLOAT : Format::R8G8B8A8_UNORM;
    const Format depthFormat = opt.floatTargets ? Format::D32_FLOAT_S8X24_UINT : Format::D24_UNORM_S8_UINT;
    // With MSAA every buffer has `samples` samples and the image is resolved last (technique.h).
    const std::uint32_t samples = ctx.sampleCount;
    const bool msaa = samples > 1;
    setup->samples = samples;
    const std::string back = backBufferTarget(samples), backReference = referenceBufferTarget(samples);
    std::vector<std::string> gbufferTargets{"accumulation", "gbuffer.diffuse", "gbuffer.specular", "gbuffer.normal"};
    if (opt.positionFromGBuffer) gbufferTargets.emplace_back("gbuffer.position");
    std::vector<std::string> created = gbufferTargets;
    created.push_back(back);
    if (ctx.precision == Precision::Reference) created.push_back(backReference);
    created.emplace_back("depth");
    created.emplace_back("heatmap");
    if (opt.shading == Shading::Intel) created.emplace_back("lit");
    if (msaa) {
        created.emplace_back(gbuffer_detail::kEdgeSurfaceTarget);
        created.emplace_back(gbuffer_detail::kEdgeCoverageTarget);
        created.emplace_back(gbuffer_detail::kEdgesBuffer);
    }

    Frame frame;
    frame.add({"clear", {}, created, [setup, colorFormat, depthFormat, samples, back, backReference](BufferRegistry& reg) {
                   const TiledOptions& o = setup->options;
                   const std::uint32_t w = setup->width, h = setup->height;
                   // the demo's clear, also tessera's stand-in for Intel's sky box
                   reg.create(back, {w, h, Format::R8G8B8A8_UNORM, samples}).clearColor(kDemoClearColor);
                   if (setup->forward->precision == Precision::Reference)
                       reg.create(backReference, {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(kDemoClearColor);
                   reg.create("accumulation", {w, h, colorFormat, samples}).clearColor(kDemoClearColor);
                   reg.create("gbuffer.diffuse", {w, h, colorFormat, samples}).clearColor(kDemoClearColor);
                   reg.create("gbuffer.specular", {w, h, colorFormat, samples}).clearColor(kDemoClearColor);
                   reg.create("gbuffer.normal", {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(kDemoClearColor);
                   if (o.positionFromGBuffer)
                       reg.create("gbuffer.position", {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(kDemoClearColor);
                   reg.create("depth", {w, h, depthFormat, samples}).clearDepthStencil(true, 1.0f, true, 0);
                   reg.create("heatmap", {w, h, Format::R8G8B8A8_UNORM, 1}).clearColor(glm::vec4(0.0f));
                   if (o.shading == Shading::Intel)
                       reg.create("lit", {w, h, Format::R16G16B16A16_FLOAT, samples}).clearColor(glm::vec4(0.0f));
                   if (samples > 1) gbuffer_detail::createEdgeTargets(reg, w, h, samples);
               }});

    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;

    // RT0 alpha = alpha * Opacity: forward's output alpha for the 3dgep compose.
    frame.add(gbuffer_detail::deferredGBufferPass(setup->forward, ctx, gbufferTargets, opt.floatTargets, true));

    std::vector<std::string> tileReads = gbufferTargets;
    tileReads.emplace_back("depth");
    std::vector<std::string> tileWrites{"heatmap", "tiles.grid", "tiles.lightCount", "tiles.lightIndices", "tiles.depthRange"};
    std::vector<std::string> inspection = tileWrites;  // the tiles' lists, bounds and heat map: no later pass reads them
    tileWrites.push_back(opt.shading == Shading::Intel ? std::string("lit") : back);
    if (ctx.precision == Precision::Reference) tileWrites.push_back(backReference);
    if (msaa) {
        tileReads.emplace_back(gbuffer_detail::kEdgeSurfaceTarget);
        tileReads.emplace_back(gbuffer_detail::kEdgeCoverageTarget);
        tileWrites.emplace_back(gbuffer_detail::kEdgesBuffer);
        inspection.emplace_back(gbuffer_detail::kEdgesBuffer);  // the edge pixels the tiles shaded per sample
    }
    frame.add({"tiles", tileReads, tileWrites, [setup, device, stats, back, backReference](BufferRegistry& reg) {
                   TiledSetup& s = *setup;
                   runTiles(s, device, stats, back, backReference, reg);
                   writeTileBuffers(s, reg);
               },
               inspection});

    if (opt.shading == Shading::Intel) {
        // SkyboxToneMapPS with MSAA_SAMPLES 1: the sky where depth is the cleared value (tessera: the
        // clear colour instead of a sky box texture), else the lit value; identity tone map, alpha 1.
        // With MSAA per sample (the MSAA_SAMPLES loop before the resolve).
        frame.add({"present", {"lit", "depth"}, {back}, [back](BufferRegistry& reg) {
                       const Surface& lit = reg.get("lit");
                       const Surface& depth = reg.get("depth");
                       Surface& backbuffer = reg.get(back);
                       for (std::uint32_t y = 0; y < backbuffer.height(); ++y)
                           for (std::uint32_t x = 0; x < backbuffer.width(); ++x)
                               for (std::uint32_t i = 0; i < backbuffer.sampleCount(); ++i) {
                                   if (!(depth.loadDepth(x, y, i) < 1.0f)) continue;  // sky: keeps the clear colour
                                   const glm::vec4 v = lit.load(x, y, i);
                                   storeUnorm8(backbuffer, x, y, glm::vec4(v.x, v.y, v.z, 1.0f), i);
                               }
                   }});
    }

    // Transparent geometry: Intel's sample has none; tessera draws it as deferred does, with
    // forward's TransparentPass (3dgep shading, every light) over the image and the G-buffer depth.
    frame.add(gbuffer_detail::forwardTransparentPass(setup->forward, ctx));
    if (msaa) frame.add(resolveBackBufferPass(samples, ctx.precision));
    return frame;
}

} // namespace tessera
