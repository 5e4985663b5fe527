// GLSL 4.50 ports of the shaders of "Forward vs Deferred vs Forward+ Rendering with DirectX 11"
// (van Oosten, 3dgep 2015) as tessera implements them: Phong VS/PS, G-buffer, deferred lighting,
// light volumes, Forward+ frustum / culling / heat-map compute. Operation order follows tessera's
// headers (dot summed left to right, glm's matrix-vector order); y is negated on output.
#pragma once

namespace tessera::samefr::glsl {

// Shared maths and the article's lighting functions (include/tessera/shading/phong_lighting.h).
inline constexpr const char* kCommon = R"(
struct Light {
    vec4 positionView;
    vec4 directionView;
    vec4 color;
    float spotlightAngleDeg;
    float range;
    float intensity;
    uint enabled;
    uint type;          // 0 point, 1 spot, 2 directional
    float minCos;       // cos(radians(SpotlightAngle)), tessera's detCos, computed on the CPU
    float coneRadius;   // tan(radians(SpotlightAngle)) * Range, tessera's detTan (culling)
    float pad;
};
layout(std430, binding = 0) readonly buffer LightBuffer { Light lights[]; };
uniform uint uLightCount;

float dot3(vec3 a, vec3 b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
float dot4(vec4 a, vec4 b) { return ((a.x * b.x + a.y * b.y) + a.z * b.z) + a.w * b.w; }
vec3 cross3(vec3 a, vec3 b) { return vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x); }
vec3 normalize3(vec3 v) { float len = sqrt(dot3(v, v)); return vec3(v.x / len, v.y / len, v.z / len); }
vec4 normalize4(vec4 v) { return v / sqrt(dot4(v, v)); }
float saturate1(float x) { return x > 0.0 ? (x < 1.0 ? x : 1.0) : 0.0; }
float smoothstep1(float a, float b, float x) { float t = saturate1((x - a) / (b - a)); return t * t * (3.0 - 2.0 * t); }
// glm's mat4 * vec4: (m0 x + m1 y) + (m2 z + m3 w).
vec4 mulPoint(mat4 m, vec4 v) { return (m[0] * v.x + m[1] * v.y) + (m[2] * v.z + m[3] * v.w); }
// glm's mat3 * vec3: (m0 x + m1 y) + m2 z.
vec3 mulUpper(mat4 m, vec3 v) { return (m[0].xyz * v.x + m[1].xyz * v.y) + m[2].xyz * v.z; }

struct Lit { vec4 diffuse; vec4 specular; };

vec4 doDiffuse(Light light, vec4 lightDirView, vec4 normalView) { return light.color * max(dot4(normalView, lightDirView), 0.0); }
// Phong: R = normalize(reflect(-L, N)), reflect(i, n) = i - (2 dot(n, i)) n.
vec4 doSpecular(Light light, float power, vec4 viewDirView, vec4 lightDirView, vec4 normalView) {
    vec4 incidentView = -lightDirView;
    vec4 reflectedView = normalize4(incidentView - (2.0 * dot4(normalView, incidentView)) * normalView);
    float rDotV = max(dot4(reflectedView, viewDirView), 0.0);
    return light.color * pow(rDotV, power);
}
float doAttenuation(Light light, float d) { return 1.0 - smoothstep1(light.range * 0.75, light.range, d); }
float doSpotCone(Light light, vec4 lightDirView) {
    float minCos = light.minCos;
    float maxCos = minCos + 0.5 * (1.0 - minCos);   // lerp(minCos, 1, 0.5)
    float cosAngle = dot4(light.directionView, -lightDirView);
    return smoothstep1(minCos, maxCos, cosAngle);
}
Lit doPointLight(Light light, float power, vec4 viewDirView, vec4 posView, vec4 normalView, bool withSpecular) {
    vec4 lightDirView = light.positionView - posView;
    float distance = sqrt(dot4(lightDirView, lightDirView));
    lightDirView = lightDirView / distance;
    float attenuation = doAttenuation(light, distance);
    Lit r;
    r.diffuse = doDiffuse(light, lightDirView, normalView) * attenuation * light.intensity;
    r.specular = withSpecular ? doSpecular(light, power, viewDirView, lightDirView, normalView) * attenuation * light.intensity
                              : vec4(0.0);
    return r;
}
Lit doSpotLight(Light light, float power, vec4 viewDirView, vec4 posView, vec4 normalView, bool withSpecular) {
    vec4 lightDirView = light.positionView - posView;
    float distance = sqrt(dot4(lightDirView, lightDirView));
    lightDirView = lightDirView / distance;
    float attenuation = doAttenuation(light, distance);
    float spotIntensity = doSpotCone(light, lightDirView);
    Lit r;
    r.diffuse = doDiffuse(light, lightDirView, normalView) * attenuation * spotIntensity * light.intensity;
    r.specular = withSpecular ? doSpecular(light, power, viewDirView, lightDirView, normalView) * attenuation * spotIntensity *
                                    light.intensity
                              : vec4(0.0);
    return r;
}
Lit doDirectionalLight(Light light, float power, vec4 viewDirView, vec4 normalView, bool withSpecular) {
    vec4 lightDirView = normalize4(-light.directionView);
    Lit r;
    r.diffuse = doDiffuse(light, lightDirView, normalView) * light.intensity;
    r.specular = withSpecular ? doSpecular(light, power, viewDirView, lightDirView, normalView) * light.intensity : vec4(0.0);
    return r;
}
// DoLighting's loop body: skip disabled lights and lights farther than Range (strict), then sum.
void accumulateLight(inout Lit total, uint index, float power, vec4 viewDirView, vec4 posView, vec4 normalView,
                     bool withSpecular) {
    // The skips read only the fields they test; the whole light is loaded after them.
    if (lights[index].enabled == 0u) return;
    uint type = lights[index].type;
    if (type != 2u) {
        vec4 toLightView = lights[index].positionView - posView;
        if (sqrt(dot4(toLightView, toLightView)) > lights[index].range) return;
    }
    Light light = lights[index];
    Lit r;
    if (type == 2u) r = doDirectionalLight(light, power, viewDirView, normalView, withSpecular);
    else if (type == 0u) r = doPointLight(light, power, viewDirView, posView, normalView, withSpecular);
    else r = doSpotLight(light, power, viewDirView, posView, normalView, withSpecular);
    total.diffuse += r.diffuse;
    total.specular += r.specular;
}

// ScreenToView / ClipToView (include/tessera/gbuffer/screen_to_view.h): rows as dp4 in x, y, z, w order.
uniform mat4 uInverseProjection;
uniform vec2 uScreenDimensions;
vec4 clipToView(vec4 posClip) {
    mat4 m = uInverseProjection;
    vec4 posView;
    for (int row = 0; row < 4; ++row)
        posView[row] = ((m[0][row] * posClip.x + m[1][row] * posClip.y) + m[2][row] * posClip.z) + m[3][row] * posClip.w;
    float w = posView.w;
    return vec4(posView.x / w, posView.y / w, posView.z / w, posView.w / w);
}
// posScreen: x, y in window px (y down), z the depth-buffer value, w = 1.
vec4 screenToView(vec4 posScreen) {
    float u = posScreen.x / uScreenDimensions.x, v = posScreen.y / uScreenDimensions.y;
    float xNdc = u * 2.0 - 1.0;
    float yNdc = (1.0 - v) * 2.0 - 1.0;
    return clipToView(vec4(xNdc, yNdc, posScreen.z, posScreen.w));
}
)";

// VS_main (include/tessera/shading/phong_material_shader.h PhongVS).
inline constexpr const char* kPhongVertex = R"(
layout(location = 0) in vec3 aPosObject;
layout(location = 1) in vec3 aNormalObject;
layout(location = 2) in vec4 aTangentObject;
layout(location = 3) in vec2 aUv0;
layout(location = 4) in vec2 aUv1;
uniform mat4 uClipFromObject;
uniform mat4 uViewFromObject;
out PhongVaryings {
    vec3 posView;
    vec2 uv0;
    vec2 uv1;
    vec3 tangentView;
    vec3 binormalView;
    vec3 normalView;
} vOut;
invariant gl_Position;
void main() {
    vec3 tangentObject = aTangentObject.xyz;
    precise vec3 binormalObject = cross3(aNormalObject, tangentObject) * aTangentObject.w;
    precise vec4 posClip = mulPoint(uClipFromObject, vec4(aPosObject, 1.0));
    gl_Position = vec4(posClip.x, -posClip.y, posClip.z, posClip.w);   // D3D row r -> GL row r
    precise vec3 posView = mulPoint(uViewFromObject, vec4(aPosObject, 1.0)).xyz;
    precise vec3 tangentView = mulUpper(uViewFromObject, tangentObject);
    precise vec3 binormalView = mulUpper(uViewFromObject, binormalObject);
    precise vec3 normalView = mulUpper(uViewFromObject, aNormalObject);
    vOut.posView = posView;
    vOut.uv0 = aUv0;
    vOut.uv1 = aUv1;
    vOut.tangentView = tangentView;
    vOut.binormalView = binormalView;
    vOut.normalView = normalView;
}
)";

// gatherPhongSurface (include/tessera/shading/phong_surface.h) for the slots glTF materials fill
// (ambient, emissive, diffuse, normal) with the optional alpha test.
inline constexpr const char* kPhongSurface = R"(
in PhongVaryings {
    vec3 posView;
    vec2 uv0;
    vec2 uv1;
    vec3 tangentView;
    vec3 binormalView;
    vec3 normalView;
} vIn;
layout(binding = 0) uniform sampler2D uAmbientTexture;
layout(binding = 1) uniform sampler2D uEmissiveTexture;
layout(binding = 2) uniform sampler2D uDiffuseTexture;
layout(binding = 3) uniform sampler2D uNormalTexture;
uniform ivec4 uHasTexture;     // ambient, emissive, diffuse, normal bound
uniform ivec4 uTexCoordSet;    // TEXCOORD_0 or _1 per slot
uniform vec4 uGlobalAmbient, uAmbientColor, uEmissiveColor, uDiffuseColor, uSpecularColor;
uniform float uOpacity, uSpecularPower, uAlphaThreshold;
uniform int uIgnoreDiffuseAlpha, uAlphaTest;

vec2 uvFor(int slot) { return uTexCoordSet[slot] == 1 ? vIn.uv1 : vIn.uv0; }

#if EMULATED_SAMPLING
// Diagnostic (--sampler emulated): tessera's Texture2D::sample in GLSL (texture/sampling.h, the
// D3D11.3 rules for a trilinear wrap sampler) from texelFetch, instead of llvmpipe's sampler:
// LOD = 0.5 log2(max(|ddx|^2, |ddy|^2)) in level-0 texels from the coarse quad derivatives,
// clamped to [0, levels - 1]; per level wrap, s = u size - 0.5, a + (b - a) w along U, then V,
// then between the two levels.
vec4 fetchWrapped(sampler2D t, ivec2 size, int x, int y, int level) {
    // x, y in [-1, size] here; GLSL leaves % of negative operands undefined, so shift first.
    return texelFetch(t, ivec2((x + size.x) % size.x, (y + size.y) % size.y), level);
}
vec4 bilinearLevel(sampler2D t, vec2 uv, int level) {
    // Level sizes from level 0 (D3D11.3 §5.3.6): llvmpipe's textureSize takes one lod per SIMD
    // vector, so a per-pixel level there gives some pixels another level's size.
    ivec2 size = max(textureSize(t, 0) >> level, ivec2(1));
    float u = uv.x - floor(uv.x), v = uv.y - floor(uv.y);
    float su = u * float(size.x) - 0.5, sv = v * float(size.y) - 0.5;
    float fu = floor(su), fv = floor(sv);
    float wu = su - fu, wv = sv - fv;
    int x0 = int(fu), y0 = int(fv);
    vec4 a = fetchWrapped(t, size, x0, y0, level), b = fetchWrapped(t, size, x0 + 1, y0, level);
    vec4 c = fetchWrapped(t, size, x0, y0 + 1, level), d = fetchWrapped(t, size, x0 + 1, y0 + 1, level);
    vec4 top = a + (b - a) * wu;
    vec4 bottom = c + (d - c) * wu;
    return top + (bottom - top) * wv;
}
vec4 sampleSlot(sampler2D t, vec2 uv) {
    vec2 dx = dFdxCoarse(uv), dy = dFdyCoarse(uv);
    vec2 size0 = vec2(textureSize(t, 0));
    float dxU = dx.x * size0.x, dxV = dx.y * size0.y, dyU = dy.x * size0.x, dyV = dy.y * size0.y;
    float lod = 0.5 * log2(max(dxU * dxU + dxV * dxV, dyU * dyU + dyV * dyV));
    float limited = min(lod > 0.0 ? lod : 0.0, float(textureQueryLevels(t) - 1));
    float levelFloor = floor(limited);
    int level = int(levelFloor);
    float fraction = limited - levelFloor;
    vec4 nearer = bilinearLevel(t, uv, level);
    if (fraction == 0.0) return nearer;
    return nearer + (bilinearLevel(t, uv, level + 1) - nearer) * fraction;
}
#else
vec4 sampleSlot(sampler2D t, vec2 uv) { return texture(t, uv); }
#endif
vec4 textureRule(vec4 color, vec4 texel) {
    bool anyColor = color.x != 0.0 || color.y != 0.0 || color.z != 0.0;
    return anyColor ? color * texel : texel;
}
struct Surface { vec4 diffuse; float alpha; vec4 ambient; vec4 emissive; float specularPower; vec4 specular; vec4 normalView; };

// false: the alpha test discards the pixel.
bool gatherSurface(out Surface s) {
    // Sample every bound slot first, under uniform conditions only: implicit derivatives need
    // uniform control flow (tessera samples the same slots; the alpha test comes after).
    vec4 ambientTexel = vec4(0.0), emissiveTexel = vec4(0.0), diffuseTexel = vec4(0.0), normalTexel = vec4(0.0);
    if (uHasTexture.x != 0) ambientTexel = sampleSlot(uAmbientTexture, uvFor(0));
    if (uHasTexture.y != 0) emissiveTexel = sampleSlot(uEmissiveTexture, uvFor(1));
    if (uHasTexture.z != 0) diffuseTexel = sampleSlot(uDiffuseTexture, uvFor(2));
    if (uHasTexture.w != 0) normalTexel = sampleSlot(uNormalTexture, uvFor(3));
    vec4 diffuse = uDiffuseColor;
    if (uHasTexture.z != 0) diffuse = textureRule(diffuse, diffuseTexel);
    float alpha = uIgnoreDiffuseAlpha != 0 ? 1.0 : diffuse.w;
    s.diffuse = diffuse;
    s.alpha = alpha;
    if (uAlphaTest != 0 && alpha * uOpacity < uAlphaThreshold) return false;
    vec4 ambient = uAmbientColor;
    if (uHasTexture.x != 0) ambient = textureRule(ambient, ambientTexel);
    ambient *= uGlobalAmbient;
    vec4 emissive = uEmissiveColor;
    if (uHasTexture.y != 0) emissive = textureRule(emissive, emissiveTexel);
    vec4 normalView;
    if (uHasTexture.w != 0) {
        vec3 t = normalize3(vIn.tangentView);
        vec3 b = normalize3(vIn.binormalView);
        vec3 n = normalize3(vIn.normalView);
        vec3 expanded = normalTexel.xyz * 2.0 - 1.0;
        normalView = normalize4(vec4((t * expanded.x + b * expanded.y) + n * expanded.z, 0.0));
    } else {
        normalView = normalize4(vec4(vIn.normalView, 0.0));
    }
    s.ambient = ambient;
    s.emissive = emissive;
    s.specularPower = uSpecularPower;
    s.specular = uSpecularPower > 1.0 ? uSpecularColor : vec4(0.0);
    s.normalView = normalView;
    return true;
}
)";

// ForwardRendering.hlsl PS_main (forward) and ForwardPlusRendering.hlsl PS_main (uTiled != 0:
// the tile's light list from the light grid).
inline constexpr const char* kPhongFragment = R"(
layout(std430, binding = 1) readonly buffer LightGrid { uvec2 lightGrid[]; };
layout(std430, binding = 2) readonly buffer LightIndexList { uint lightIndexList[]; };
uniform int uTiled;
uniform uvec2 uGridSize;        // tiles
uniform uint uIndexCapacity;    // entries of the light index list
uniform float uTileSizePx;
layout(location = 0) out vec4 oColor;
void main() {
    Surface s;
    if (!gatherSurface(s)) discard;
    vec4 posView = vec4(vIn.posView, 1.0);
    vec4 viewDirView = normalize4(vec4(0.0, 0.0, 0.0, 1.0) - posView);
    bool withSpecular = s.specularPower > 1.0;
    Lit lit;
    lit.diffuse = vec4(0.0);
    lit.specular = vec4(0.0);
    if (uTiled != 0) {
        uvec2 tile = uvec2(floor(gl_FragCoord.xy / uTileSizePx));
        uint startOffset = 0u, lightCount = 0u;
        if (tile.x < uGridSize.x && tile.y < uGridSize.y) {
            uvec2 cell = lightGrid[tile.y * uGridSize.x + tile.x];
            startOffset = cell.x;
            lightCount = cell.y;
        }
        for (uint i = 0u; i < lightCount; ++i) {
            uint at = startOffset + i;
            uint index = at < uIndexCapacity ? lightIndexList[at] : 0u;
            if (index >= uLightCount) continue;
            accumulateLight(lit, index, s.specularPower, viewDirView, posView, s.normalView, withSpecular);
        }
    } else {
        for (uint i = 0u; i < uLightCount; ++i)
            accumulateLight(lit, i, s.specularPower, viewDirView, posView, s.normalView, withSpecular);
    }
    vec4 diffuse = s.diffuse * vec4(lit.diffuse.xyz, 1.0);
    vec4 specular = s.specularPower > 1.0 ? s.specular * lit.specular : vec4(0.0);
    vec4 sum = ((s.ambient + s.emissive) + diffuse) + specular;
    precise vec4 color = vec4(sum.xyz, s.alpha * uOpacity);
    oColor = color;
}
)";

// The depth pre-pass: the Phong VS alone (the FS writes nothing).
inline constexpr const char* kEmptyFragment = R"(
void main() {}
)";

// DeferredRendering.hlsl PS_Geometry: RT0 ambient + emissive, RT1 diffuse, RT2 (specular.rgb,
// log2(p) / 10.5), RT3 view normal. The packed power is per material (tessera's
// packSpecularPower, computed on the CPU).
inline constexpr const char* kGBufferFragment = R"(
uniform float uPackedSpecularPower;
layout(location = 0) out vec4 oLightAccumulation;
layout(location = 1) out vec4 oDiffuse;
layout(location = 2) out vec4 oSpecular;
layout(location = 3) out vec4 oNormalView;
void main() {
    Surface s;
    if (!gatherSurface(s)) discard;
    precise vec4 ambientEmissive = s.ambient + s.emissive;
    oLightAccumulation = ambientEmissive;
    oDiffuse = s.diffuse;
    oSpecular = vec4(s.specular.xyz, uPackedSpecularPower);
    oNormalView = s.normalView;
}
)";

// The light volume (and far-plane quad) VS: position only.
inline constexpr const char* kVolumeVertex = R"(
layout(location = 0) in vec3 aPosObject;
uniform mat4 uClipFromObject;
invariant gl_Position;
void main() {
    precise vec4 posClip = mulPoint(uClipFromObject, vec4(aPosObject, 1.0));
    gl_Position = vec4(posClip.x, -posClip.y, posClip.z, posClip.w);
}
)";

// DeferredRendering.hlsl PS_DeferredLighting for light uLightIndex: P reconstructed at the
// pixel's integer corner from the depth copy, the G-buffer loaded, no range or Enabled test;
// specular power exp2(a * 10.5) from a 256-entry table of tessera's unpackSpecularPower.
inline constexpr const char* kDeferredLightingFragment = R"(
layout(binding = 0) uniform sampler2D uDepthCopy;
layout(binding = 1) uniform sampler2D uGDiffuse;
layout(binding = 2) uniform sampler2D uGSpecular;
layout(binding = 3) uniform sampler2D uGNormal;
uniform uint uLightIndex;
uniform float uUnpackedSpecularPower[256];
layout(location = 0) out vec4 oColor;
void main() {
    ivec2 pxWindow = ivec2(gl_FragCoord.xy);   // int2(SV_Position.xy): truncation to the corner
    float depth = texelFetch(uDepthCopy, pxWindow, 0).r;
    vec4 posView = screenToView(vec4(float(pxWindow.x), float(pxWindow.y), depth, 1.0));
    vec4 viewDirView = normalize4(vec4(0.0, 0.0, 0.0, 1.0) - posView);
    vec4 diffuse = texelFetch(uGDiffuse, pxWindow, 0);
    vec4 specular = texelFetch(uGSpecular, pxWindow, 0);
    vec4 normalView = texelFetch(uGNormal, pxWindow, 0);
    float power = uUnpackedSpecularPower[int(round(specular.w * 255.0))];
    Light light = lights[uLightIndex];
    Lit lit;
    if (light.type == 2u) lit = doDirectionalLight(light, power, viewDirView, normalView, true);
    else if (light.type == 0u) lit = doPointLight(light, power, viewDirView, posView, normalView, true);
    else lit = doSpotLight(light, power, viewDirView, posView, normalView, true);
    precise vec4 color = diffuse * lit.diffuse + specular * lit.specular;
    oColor = color;
}
)";

// ForwardPlusRendering.hlsl CS_ComputeFrustums: one thread per tile, planes left, right, top,
// bottom through the eye (include/tessera/culling/tile_frustum.h gridFrustum3dgep).
inline constexpr const char* kFrustumCompute = R"(
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 1) writeonly buffer Frustums { vec4 frustumPlanes[]; };
uniform uvec2 uTiles;
uniform uint uBlockSizePx;
vec3 cornerView(uint tx, uint ty) {
    return screenToView(vec4(float(tx * uBlockSizePx), float(ty * uBlockSizePx), -1.0, 1.0)).xyz;
}
vec4 computePlane(vec3 p0, vec3 p1, vec3 p2) {
    vec3 v0 = p1 - p0;
    vec3 v2 = p2 - p0;
    vec3 N = normalize3(cross3(v0, v2));
    return vec4(N, dot3(N, p0));
}
void main() {
    uvec2 id = gl_GlobalInvocationID.xy;
    if (id.x >= uTiles.x || id.y >= uTiles.y) return;
    vec3 eyeView = vec3(0.0);
    vec3 v0 = cornerView(id.x, id.y), v1 = cornerView(id.x + 1u, id.y), v2 = cornerView(id.x, id.y + 1u),
         v3 = cornerView(id.x + 1u, id.y + 1u);
    uint base = (id.x + id.y * uTiles.x) * 4u;
    precise vec4 left = computePlane(eyeView, v2, v0);
    precise vec4 right = computePlane(eyeView, v1, v3);
    precise vec4 top = computePlane(eyeView, v0, v1);
    precise vec4 bottom = computePlane(eyeView, v3, v2);
    frustumPlanes[base + 0u] = left;
    frustumPlanes[base + 1u] = right;
    frustumPlanes[base + 2u] = top;
    frustumPlanes[base + 3u] = bottom;
}
)";

// ForwardPlusRendering.hlsl CS_main: the tile's depth range by atomic min/max over asuint, the
// strided light loop with SphereInsideFrustum / ConeInsideFrustum (the article's cone test) and
// the opaque minPlane, group-shared lists of 1024 with atomic counters, the global offsets by
// atomic add, the light grids and the copy to the global lists. One addition: each group-shared
// list is sorted by light index before the copy (a rank sort), so the lists hold tessera's
// order (ascending index) rather than the order the atomics happened to run in.
inline constexpr const char* kCullCompute = R"(
layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D uDepth;
layout(std430, binding = 1) readonly buffer Frustums { vec4 frustumPlanes[]; };
layout(std430, binding = 2) buffer Counters { uint oLightIndexCounter; uint tLightIndexCounter; };
layout(std430, binding = 3) writeonly buffer OIndex { uint oLightIndexList[]; };
layout(std430, binding = 4) writeonly buffer TIndex { uint tLightIndexList[]; };
layout(std430, binding = 5) writeonly buffer OGrid { uvec2 oLightGrid[]; };
layout(std430, binding = 6) writeonly buffer TGrid { uvec2 tLightGrid[]; };
uniform uvec2 uTiles;
uniform ivec2 uScreenPx;
uniform uint uCapacity;         // entries of each global list

const uint kLocalCapacity = 1024u;
shared uint sMinDepth, sMaxDepth;
shared uint sOCount, sTCount, sOOffset, sTOffset;
shared uint sOList[1024], sTList[1024], sOSorted[1024], sTSorted[1024];

bool pointInsidePlane(vec3 p, vec4 plane) { return dot3(plane.xyz, p) - plane.w < 0.0; }
bool sphereInsidePlane(vec3 c, float r, vec4 plane) { return dot3(plane.xyz, c) - plane.w < -r; }
bool coneInsidePlane(vec3 T, float h, vec3 d, float r, vec4 plane) {
    vec3 m = cross3(cross3(plane.xyz, d), d);
    vec3 Q = (T + d * h) - m * r;
    return pointInsidePlane(T, plane) && pointInsidePlane(Q, plane);
}

void main() {
    uvec2 groupId = gl_WorkGroupID.xy;
    uint localIndex = gl_LocalInvocationIndex;
    ivec2 pxWindow = ivec2(gl_GlobalInvocationID.xy);
    // Threads past the screen load 0 (a D3D11 out-of-range Load), as in tessera's kernel.
    float depth = (pxWindow.x < uScreenPx.x && pxWindow.y < uScreenPx.y) ? texelFetch(uDepth, pxWindow, 0).r : 0.0;
    uint uDepthBits = floatBitsToUint(depth);
    if (localIndex == 0u) {
        sMinDepth = 0xFFFFFFFFu;
        sMaxDepth = 0u;
        sOCount = 0u;
        sTCount = 0u;
    }
    barrier();
    atomicMin(sMinDepth, uDepthBits);
    atomicMax(sMaxDepth, uDepthBits);
    barrier();
    precise float minDepthVS = screenToView(vec4(0.0, 0.0, uintBitsToFloat(sMinDepth), 1.0)).z;
    precise float maxDepthVS = screenToView(vec4(0.0, 0.0, uintBitsToFloat(sMaxDepth), 1.0)).z;
    precise float nearClipVS = screenToView(vec4(0.0, 0.0, 0.0, 1.0)).z;
    vec4 minPlane = vec4(0.0, 0.0, -1.0, -minDepthVS);
    vec4 nearPlane = vec4(0.0, 0.0, -1.0, -nearClipVS);
    vec4 farPlane = vec4(0.0, 0.0, 1.0, maxDepthVS);
    uint tile = groupId.x + groupId.y * uTiles.x;
    vec4 planes[4] = vec4[4](frustumPlanes[tile * 4u], frustumPlanes[tile * 4u + 1u], frustumPlanes[tile * 4u + 2u],
                             frustumPlanes[tile * 4u + 3u]);

    for (uint i = localIndex; i < uLightCount; i += 256u) {
        Light light = lights[i];
        if (light.enabled == 0u) continue;
        bool opaqueToo = false;
        if (light.type == 0u) {
            vec3 centreView = light.positionView.xyz;
            float r = light.range;
            if (centreView.z - r > nearClipVS || centreView.z + r < maxDepthVS) continue;
            bool inside = true;
            for (int p = 0; p < 4 && inside; ++p)
                if (sphereInsidePlane(centreView, r, planes[p])) inside = false;
            if (!inside) continue;
            opaqueToo = !sphereInsidePlane(centreView, r, minPlane);
        } else if (light.type == 1u) {
            vec3 T = light.positionView.xyz;
            float h = light.range;
            vec3 d = light.directionView.xyz;
            float r = light.coneRadius;
            if (coneInsidePlane(T, h, d, r, nearPlane) || coneInsidePlane(T, h, d, r, farPlane)) continue;
            bool inside = true;
            for (int p = 0; p < 4 && inside; ++p)
                if (coneInsidePlane(T, h, d, r, planes[p])) inside = false;
            if (!inside) continue;
            opaqueToo = !coneInsidePlane(T, h, d, r, minPlane);
        } else {
            opaqueToo = true;
        }
        uint t = atomicAdd(sTCount, 1u);
        if (t < kLocalCapacity) sTList[t] = i;
        if (opaqueToo) {
            uint o = atomicAdd(sOCount, 1u);
            if (o < kLocalCapacity) sOList[o] = i;
        }
    }
    barrier();
    uint oStored = min(sOCount, kLocalCapacity), tStored = min(sTCount, kLocalCapacity);
    for (uint e = localIndex; e < oStored; e += 256u) {
        uint v = sOList[e], rank = 0u;
        for (uint j = 0u; j < oStored; ++j) rank += sOList[j] < v ? 1u : 0u;
        sOSorted[rank] = v;
    }
    for (uint e = localIndex; e < tStored; e += 256u) {
        uint v = sTList[e], rank = 0u;
        for (uint j = 0u; j < tStored; ++j) rank += sTList[j] < v ? 1u : 0u;
        sTSorted[rank] = v;
    }
    if (localIndex == 0u) {
        sOOffset = atomicAdd(oLightIndexCounter, sOCount);
        oLightGrid[tile] = uvec2(sOOffset, sOCount);
        sTOffset = atomicAdd(tLightIndexCounter, sTCount);
        tLightGrid[tile] = uvec2(sTOffset, sTCount);
    }
    barrier();
    for (uint i = localIndex; i < sOCount; i += 256u) {
        uint at = sOOffset + i;
        if (at < uCapacity) oLightIndexList[at] = i < kLocalCapacity ? sOSorted[i] : 0u;
    }
    for (uint i = localIndex; i < sTCount; i += 256u) {
        uint at = sTOffset + i;
        if (at < uCapacity) tLightIndexList[at] = i < kLocalCapacity ? sTSorted[i] : 0u;
    }
}
)";

// The demo's DebugTexture (tessera's "heatmap" pass, forward_plus.h): tile borders, then the
// opaque light count through the 5-texel gradient (forwardPlusHeatMapColor).
inline constexpr const char* kHeatMapCompute = R"(
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 5) readonly buffer OGrid { uvec2 oLightGrid[]; };
layout(binding = 0, rgba32f) uniform writeonly image2D uHeatMap;
uniform uvec2 uTiles;
uniform ivec2 uScreenPx;
const vec4 kGradient[5] = vec4[5](vec4(0, 0, 1, 1), vec4(0, 1, 1, 1), vec4(0, 1, 0, 1), vec4(1, 1, 0, 1), vec4(1, 0, 0, 1));
void main() {
    ivec2 pxWindow = ivec2(gl_GlobalInvocationID.xy);
    if (pxWindow.x >= uScreenPx.x || pxWindow.y >= uScreenPx.y) return;
    uvec2 local = gl_LocalInvocationID.xy;
    uint count = oLightGrid[gl_WorkGroupID.x + gl_WorkGroupID.y * uTiles.x].y;
    vec4 color;
    if (local.x == 0u || local.y == 0u) color = vec4(0.0, 0.0, 0.0, 0.9);
    else if (local.x == 1u || local.y == 1u) color = vec4(1.0, 1.0, 1.0, 0.5);
    else if (count == 0u) color = vec4(0.0, 0.0, 0.0, 1.0);
    else {
        float t = clamp(float(count) / 50.0 * 5.0 - 0.5, 0.0, 4.0);
        float base = floor(t);
        int i0 = int(base);
        int i1 = min(i0 + 1, 4);
        color = kGradient[i0] + (kGradient[i1] - kGradient[i0]) * (t - base);
    }
    imageStore(uHeatMap, pxWindow, color);
}
)";

} // namespace tessera::samefr::glsl
