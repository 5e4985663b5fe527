// Tile frustums three ways, each exactly as its source builds it: 3dgep grid frustums (article
// §4.2), AMD Forward+ side planes (GPU Pro 4 §5.3.1, ForwardPlus11 CullLightsCS) and Intel's
// projection-derived planes (Intel 2010 sample ComputeShaderTile.hlsl; tile-frustum note), with
// their sphere tests and functions that express all three in one common convention for comparison.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

#include <tessera/culling/frustum.h>
#include <tessera/culling/plane.h>
#include <tessera/gbuffer/screen_to_view.h>

namespace tessera {

// Tiles covering a screen: ceil(screen / tile) per axis (3dgep article §4.2: 1280x720, 16 px -> 80x45).
inline glm::uvec2 tileCount(glm::uvec2 screenPx, std::uint32_t tileSizePx) {
    return (screenPx + glm::uvec2(tileSizePx - 1u)) / tileSizePx;
}

// ===== (a) 3dgep grid frustums ===================================================================
// Convention: right-handed view space (x right, y up, camera looks down -z); planes left, right,
// top, bottom with unit normals pointing INTO the tile; all pass through the eye (d = +-0).
//
// 3dgep article §4.2 CS_ComputeFrustums for the thread with SV_DispatchThreadID.xy = tileId (tile column,
// tile row counted from the TOP of the screen), as in the demo's ForwardPlusRendering.hlsl:
//   screenSpace[0] = float4(tileId * BLOCK_SIZE, -1, 1)           top-left
//   screenSpace[1] = float4((tileId.x + 1, tileId.y) * BLOCK_SIZE, -1, 1)   top-right
//   screenSpace[2] = float4((tileId.x, tileId.y + 1) * BLOCK_SIZE, -1, 1)   bottom-left
//   screenSpace[3] = float4((tileId.x + 1, tileId.y + 1) * BLOCK_SIZE, -1, 1) bottom-right
//   viewSpace[i] = ScreenToView(screenSpace[i]).xyz          (gbuffer/screen_to_view.h)
//   planes: Left (eye, v2, v0), Right (eye, v1, v3), Top (eye, v0, v1), Bottom (eye, v3, v2)
// The uint products tileId * BLOCK_SIZE are converted to float exactly (< 2^24). z = -1 is the
// article's "far plane" for a right-handed system; under the demo's GL-form projection it is the
// near plane (view z = -n, ERRATA #1); under the D3D form it lies between the eye and the near
// plane (view z = -n f / (2 f - n)); only the ray direction matters. With near 1e-21 the corners
// lie ~1e-21 from the eye and the planes rely on cullmath::unitCross's rescue.
inline Frustum gridFrustum3dgep(glm::uvec2 tileId, std::uint32_t blockSizePx, const glm::vec2& screenDimensions,
                                const glm::mat4& inverseProjection) {
    const auto corner = [&](std::uint32_t tx, std::uint32_t ty) {
        const glm::vec4 posScreen(static_cast<float>(tx * blockSizePx), static_cast<float>(ty * blockSizePx), -1.0f, 1.0f);
        return glm::vec3(screenToView(posScreen, screenDimensions, inverseProjection));
    };
    const glm::vec3 eyePos(0.0f);
    const std::array<glm::vec3, 4> viewSpace{corner(tileId.x, tileId.y), corner(tileId.x + 1, tileId.y),
                                             corner(tileId.x, tileId.y + 1), corner(tileId.x + 1, tileId.y + 1)};
    Frustum frustum;
    frustum.planes[0] = computePlane(eyePos, viewSpace[2], viewSpace[0]);  // left
    frustum.planes[1] = computePlane(eyePos, viewSpace[1], viewSpace[3]);  // right
    frustum.planes[2] = computePlane(eyePos, viewSpace[0], viewSpace[1]);  // top
    frustum.planes[3] = computePlane(eyePos, viewSpace[3], viewSpace[2]);  // bottom
    return frustum;
}

// An orthographic camera (which the 3dgep demo never had): its rays are parallel, so planes
// through the eye are not the tile's sides. gridFrustum3dgep's corners (NDC z = -1) lie at view
// z = f - 2n there, behind the eye: nearly right when f >> n, degenerate at f = 2n (NaN planes
// and 50 of 3072 pixels losing light in the extremes catalogue's "orthographic with far = 2 x
// near"). Each side plane here passes through the tile corner a on the near plane and the
// corners a, b on the far plane, NDC z = nearNdc and farNdc (orthographic cameras take the D3D
// form, 0 and 1, under either projection option), same corner order and normal direction as
// gridFrustum3dgep.
inline Frustum gridFrustumOrthographic(glm::uvec2 tileId, std::uint32_t blockSizePx, const glm::vec2& screenDimensions,
                                       const glm::mat4& inverseProjection, float nearNdc, float farNdc) {
    const auto corner = [&](std::uint32_t tx, std::uint32_t ty, float zNdc) {
        const glm::vec4 posScreen(static_cast<float>(tx * blockSizePx), static_cast<float>(ty * blockSizePx), zNdc, 1.0f);
        return glm::vec3(screenToView(posScreen, screenDimensions, inverseProjection));
    };
    const std::array<glm::uvec2, 4> c{tileId, tileId + glm::uvec2(1, 0), tileId + glm::uvec2(0, 1), tileId + glm::uvec2(1, 1)};
    const auto side = [&](std::size_t a, std::size_t b) {
        return computePlane(corner(c[a].x, c[a].y, nearNdc), corner(c[a].x, c[a].y, farNdc), corner(c[b].x, c[b].y, farNdc));
    };
    Frustum frustum;
    frustum.planes[0] = side(2, 0);  // left
    frustum.planes[1] = side(1, 3);  // right
    frustum.planes[2] = side(0, 1);  // top
    frustum.planes[3] = side(3, 2);  // bottom
    return frustum;
}

// ===== (b) AMD Forward+ side planes ==============================================================
// Convention: LEFT-handed view space (x right, y up, camera looks down +z, D3DX/XMMath); four unit
// normals through the origin with the positive half-space OUTSIDE the tile; order frustumEqn0..3
// = top, right, bottom, left (corners clockwise from the top-left).
//
// GPU Pro 4 ch. 5 §5.3.1: v[i] = projToView(corner i, depth 1); frustum[i] =
// createEquation(o, v[i], v[(i+1)&3]). The public ForwardPlus11 sample
// (ForwardPlus11Tiling.hlsl, CullLightsCS) spells it out:
//   frustumK = ConvertProjToView(float4(px / (float)Wdiv * 2 - 1, (Hdiv - py) / (float)Hdiv * 2 - 1, 1, 1))
//   CreatePlaneEquation(b, c) = normalize(cross(b, c));  eqn0 = (f0, f1) ... eqn3 = (f3, f0)
// with Wdiv = TILE_RES * GetNumTilesX(), GetNumTilesX() = (uint)((W + TILE_RES - 1) / (float)TILE_RES),
// i.e. the corners are mapped over the tile grid PADDED to whole tiles, not over the screen.
enum class AmdTileCorners : std::uint8_t {
    PaddedGrid,  // faithful to ForwardPlus11: NDC over TILE_RES * numTiles px. ERRATUM when the
                 // screen is not a multiple of TILE_RES (1080 / 16 = 67.5): tile frustums drift up
                 // to half a tile from their pixels, and lights touching only the uncovered rows are
                 // culled (test "AMD ForwardPlus11 padded-grid corners miss pixels at 1920x1080").
    Screen,      // corrected, and the reading of GPU Pro 4's projToView(pixel x, pixel y, depth):
                 // NDC over the screen's W x H px.
};

// ConvertProjToView (ForwardPlus11): p = mul(p, g_mProjectionInv); p /= p.w. `inverseProjection`
// is the glm (column-vector) matrix of the same transform: HLSL row-vector M._rc = m[r-1][c-1].
// Evaluated as clipToView (gbuffer/screen_to_view.h): dp4 rows in x, y, z, w order.
inline std::array<glm::vec3, 4> tileSidePlanesAmd(glm::uvec2 groupId, std::uint32_t tileRes, glm::uvec2 windowPx,
                                                  const glm::mat4& inverseProjection, AmdTileCorners corners) {
    const auto numTiles = [&](std::uint32_t size) {
        return static_cast<std::uint32_t>(static_cast<float>(size + tileRes - 1u) / static_cast<float>(tileRes));
    };
    const std::uint32_t widthGrid = corners == AmdTileCorners::PaddedGrid ? tileRes * numTiles(windowPx.x) : windowPx.x;
    const std::uint32_t heightGrid = corners == AmdTileCorners::PaddedGrid ? tileRes * numTiles(windowPx.y) : windowPx.y;
    const std::uint32_t pxm = tileRes * groupId.x, pym = tileRes * groupId.y;
    const std::uint32_t pxp = tileRes * (groupId.x + 1u), pyp = tileRes * (groupId.y + 1u);
    const auto corner = [&](std::uint32_t px, std::uint32_t py) {
        // (Hdiv - py) is a uint subtraction in the shader (py <= Hdiv there); in float here, exact
        // for integers < 2^24, so the corrected Screen mapping may pass py > H.
        const float xNdc = static_cast<float>(px) / static_cast<float>(widthGrid) * 2.0f - 1.0f;
        const float yNdc = (static_cast<float>(heightGrid) - static_cast<float>(py)) / static_cast<float>(heightGrid) * 2.0f - 1.0f;
        return glm::vec3(clipToView(glm::vec4(xNdc, yNdc, 1.0f, 1.0f), inverseProjection));
    };
    const std::array<glm::vec3, 4> f{corner(pxm, pym), corner(pxp, pym), corner(pxp, pyp), corner(pxm, pyp)};
    std::array<glm::vec3, 4> eqn{};
    for (std::size_t i = 0; i < 4; ++i) eqn[i] = cullmath::unitCross(f[i], f[(i + 1) & 3u]);
    return eqn;
}

// ForwardPlus11 CullLightsCS: TestFrustumSides (dot(eqn_i, c) < r for all four: the sphere is not
// entirely on the outer side of any plane) && `-c.z + minZ < r && c.z - maxZ < r` (the depth
// bounds, LH view z). posView: the light centre in AMD's left-handed view space.
inline bool sphereOverlapsTileAmd(const glm::vec3& posView, float radius, const std::array<glm::vec3, 4>& eqn,
                                  float minZ, float maxZ) {
    const bool sides = cullmath::dot(eqn[0], posView) < radius && cullmath::dot(eqn[1], posView) < radius &&
                       cullmath::dot(eqn[2], posView) < radius && cullmath::dot(eqn[3], posView) < radius;
    return sides && (-posView.z + minZ < radius && posView.z - maxZ < radius);
}

// ===== (c) Intel tiled deferred: planes from the projection's columns ===========================
// Convention: LEFT-handed view space (+z forward, y up); float4 planes (a, b, c, w) with the tile
// on the side dot(plane, float4(p, 1)) >= 0 (normals point INTO the frustum); planes[0..5] =
// -X side (right edge), +X side (left edge), bottom edge, top edge, near (z >= minTileZ), far
// (z <= maxTileZ). Projection: glm (column-vector) matrix, HLSL mCameraProj._rc = m[r-1][c-1]
// (_11 = m[0][0], _22 = m[1][1]); off-centre terms (_31, _32) are ignored, as Intel does.
//
// Intel 2010 sample ComputeShaderTile.hlsl (and the tile-frustum note):
//   tileScale = float2(mFramebufferDimensions.xy) * rcp(float(2 * COMPUTE_SHADER_TILE_GROUP_DIM))
//   tileBias  = tileScale - float2(groupId.xy)
//   c1 = (_11 * tileScale.x, 0, tileBias.x, 0); c2 = (0, -_22 * tileScale.y, tileBias.y, 0); c4 = (0, 0, 1, 0)
// In view space dot(c1, p) = z (tx - gx) with tx = (x_ndc + 1) * tileScale.x the position in tile
// units from the left, and dot(c2, p) = z (ty - gy) with ty = (1 - y_ndc) * tileScale.y from the
// top (derived from c1 and c2; tests/culling/tile_frustum_test.cpp), so tile g is tx in [g, g + 1].
struct IntelTileColumns {
    glm::vec2 tileScale{0.0f};  // tiles per half screen (600 px / (2 * 10 px) = 30 in the note's example)
    glm::vec2 tileBias{0.0f};   // tileScale - groupId
    glm::vec4 c1{0.0f}, c2{0.0f}, c4{0.0f};
};

inline IntelTileColumns intelTileColumns(glm::uvec2 groupId, std::uint32_t tileDim, glm::uvec2 framebufferPx,
                                         const glm::mat4& projection) {
    IntelTileColumns cols;
    const float rcpTwoDim = 1.0f / static_cast<float>(2u * tileDim);  // rcp: correctly rounded here
    cols.tileScale = glm::vec2(static_cast<float>(framebufferPx.x) * rcpTwoDim, static_cast<float>(framebufferPx.y) * rcpTwoDim);
    cols.tileBias = cols.tileScale - glm::vec2(static_cast<float>(groupId.x), static_cast<float>(groupId.y));
    cols.c1 = glm::vec4(projection[0][0] * cols.tileScale.x, 0.0f, cols.tileBias.x, 0.0f);
    cols.c2 = glm::vec4(0.0f, -projection[1][1] * cols.tileScale.y, cols.tileBias.y, 0.0f);
    cols.c4 = glm::vec4(0.0f, 0.0f, 1.0f, 0.0f);
    return cols;
}

enum class IntelSidePlanes : std::uint8_t {
    TileBounds,     // the tile-frustum note: c4 - c1, c1, c4 - c2, c2: exactly tile g (tx in [g, g + 1]).
    Sample2010,  // Intel's 2010 sample and its forks (ComputeShaderTile.hlsl): c4 - c1,
                 // c4 + c1, c4 - c2, c4 + c2. ERRATUM: c4 + c1 >= 0 is tx >= g - 1, so every tile
                 // frustum spans tiles g-1 .. g in x and in y (2x2 tiles, extending left and up):
                 // conservative but four times the area (test "Intel 2010 sample planes span 2x2
                 // tiles"). The scale / bias that would make c4 +- c1 bound tile g is 2 * tileScale
                 // and 2 * tileScale - 2g - 1.
};

// The four side planes before normalization (the note's frustumPlanes[0..3], as in its worked example).
inline std::array<glm::vec4, 4> intelSidePlanesRaw(const IntelTileColumns& cols, IntelSidePlanes form) {
    if (form == IntelSidePlanes::TileBounds) return {cols.c4 - cols.c1, cols.c1, cols.c4 - cols.c2, cols.c2};
    return {cols.c4 - cols.c1, cols.c4 + cols.c1, cols.c4 - cols.c2, cols.c4 + cols.c2};
}

// All six planes, the four sides scaled by rcp(length(plane.xyz)) (computed as 1 / sqrt, then a
// multiply of all four components, as `frustumPlanes[i] *= rcp(length(frustumPlanes[i].xyz))`),
// near (0, 0, 1, -minTileZ), far (0, 0, -1, maxTileZ). minTileZ / maxTileZ: LH view z (> 0).
inline std::array<glm::vec4, 6> tileFrustumPlanesIntel(glm::uvec2 groupId, std::uint32_t tileDim, glm::uvec2 framebufferPx,
                                                       const glm::mat4& projection, float minTileZ, float maxTileZ,
                                                       IntelSidePlanes form) {
    const std::array<glm::vec4, 4> sides = intelSidePlanesRaw(intelTileColumns(groupId, tileDim, framebufferPx, projection), form);
    std::array<glm::vec4, 6> planes{};
    for (std::size_t i = 0; i < 4; ++i) {
        const glm::vec3 n(sides[i]);
        const float scale = 1.0f / cullmath::length(n);
        planes[i] = sides[i] * scale;
    }
    planes[4] = glm::vec4(0.0f, 0.0f, 1.0f, -minTileZ);
    planes[5] = glm::vec4(0.0f, 0.0f, -1.0f, maxTileZ);
    return planes;
}

// Intel's point-light cull: d = dot(plane, float4(posView, 1)) (summed x, y, z, w left to right);
// in frustum iff d >= -radius for all six planes. posView: LH view space.
inline bool sphereInFrustumIntel(const glm::vec3& posView, float radius, const std::array<glm::vec4, 6>& planes) {
    bool inFrustum = true;
    for (const glm::vec4& plane : planes) {
        const float d = ((plane.x * posView.x + plane.y * posView.y) + plane.z * posView.z) + plane.w * 1.0f;
        inFrustum = inFrustum && (d >= -radius);
    }
    return inFrustum;
}

// ===== One common convention =====================================================================
// For comparing the three: 3dgep's right-handed view space (x right, y up, -z forward) and
// Plane{N, d} with N pointing INTO the tile (on the tile's side iff dot(N, X) - d >= 0), unit N,
// order left, right, top, bottom. A left-handed point maps as (x, y, z) -> (x, y, -z) (the same
// camera: only the z axis is flipped), and so do plane normals (the map is orthogonal).
using TileSidePlanes = std::array<Plane, 4>;

inline glm::vec3 viewRhFromViewLh(const glm::vec3& posViewLh) { return {posViewLh.x, posViewLh.y, -posViewLh.z}; }
inline glm::vec3 viewLhFromViewRh(const glm::vec3& posViewRh) { return {posViewRh.x, posViewRh.y, -posViewRh.z}; }

// 3dgep: already in the common convention.
inline TileSidePlanes commonSidePlanes(const Frustum& frustum3dgep) { return frustum3dgep.planes; }

// AMD (LH, outward, order top, right, bottom, left): N = -(flip z of eqn) = (-x, -y, z), d = 0.
inline TileSidePlanes commonSidePlanesFromAmd(const std::array<glm::vec3, 4>& eqn) {
    const auto inward = [](const glm::vec3& e) { return Plane{glm::vec3(-e.x, -e.y, e.z), 0.0f}; };
    return {inward(eqn[3]), inward(eqn[1]), inward(eqn[0]), inward(eqn[2])};
}

// Intel (LH, inward, (a, b, c, w) with a x + b y + c z + w >= 0, order -X side = right edge, left
// edge, bottom edge, top edge): N = (a, b, -c), d = -w.
inline TileSidePlanes commonSidePlanesFromIntel(const std::array<glm::vec4, 6>& planes) {
    const auto convert = [](const glm::vec4& p) { return Plane{glm::vec3(p.x, p.y, -p.z), -p.w}; };
    return {convert(planes[1]), convert(planes[0]), convert(planes[3]), convert(planes[2])};
}

}  // namespace tessera
