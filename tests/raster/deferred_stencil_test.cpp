// The deferred light-volume stencil sequences run through the real Device on a 64x48 D24S8
// target: 3dgep (stencil 1, unmark front faces GREATER / DECR_SAT, shade back faces
// GREATER_EQUAL / EQUAL 1 with depth clip off) and Killzone 2 (stencil 0, mark, count with an
// occlusion query, shade), with a tess-4 sphere volume against analytic scene planes. The shaded
// mask is compared with geometric truth: the pixel centre's scene point inside the polyhedron.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include <glm/ext/matrix_clip_space.hpp>

#include <tessera/raster/device.h>
#include <tessera/techniques/deferred_states.h>
#include <tessera/techniques/light_volumes.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::raster_deferred_stencil_test {

using namespace tessera;

namespace {

constexpr std::uint32_t kWidth = 64, kHeight = 48;
constexpr float kFovYDeg = 45.0f, kNear = 0.1f;

struct PosVertex {
    glm::vec3 posObject;
};

// VS: SV_Position = ModelViewProjection * position (3dgep article §2.1), no varyings.
struct VolumeVS {
    glm::mat4 clipFromObject{1.0f};
    using Varyings = NoVaryings;
    VertexOutput<NoVaryings> operator()(const PosVertex& v) const {
        return {clipFromObject * glm::vec4(v.posObject, 1.0f), {}};
    }
};

// The shade passes' stand-in for the lighting PS: writes 1, so the additively blended R32_FLOAT
// target counts how often each pixel was shaded.
struct OnePS {
    using Varyings = NoVaryings;
    static constexpr int kTargetCount = 1;
    void operator()(const PixelInput<NoVaryings>&, PixelOutput<1>& out) const { out.target[0] = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f); }
};

// "<what>x,y" built piecewise (GCC 12 -O3 misfires -Wrestrict on "literal" + std::string).
std::string describe(const char* what, std::uint32_t x, std::uint32_t y) {
    std::string s(what);
    s += std::to_string(x);
    s += ',';
    s += std::to_string(y);
    return s;
}

// A scene plane in view space (camera at the origin looking down -Z): point and normal.
struct ScenePlane {
    glm::dvec3 point, normal;
};

enum class Truth { Outside, Inside, Ambiguous };

struct PlaneD {
    glm::dvec3 n;
    double offset;  // inside: n . p <= offset
};

class StencilScene {
public:
    StencilScene(float farZ, const ScenePlane& plane, const Light& light)
        : mProj(glm::perspectiveRH_NO(glm::radians(kFovYDeg), float(kWidth) / float(kHeight), kNear, farZ)),
          mProjD(mProj), mInvProjD(glm::inverse(glm::dmat4(mProj))), mPlane(plane), mLight(light),
          mDepth(SurfaceDesc{kWidth, kHeight, Format::D24_UNORM_S8_UINT, 1}),
          mMask(SurfaceDesc{kWidth, kHeight, Format::R32_FLOAT, 1}), mDevice(DeviceConfig{16, 2}) {
        mWorldFromObject = mVolumes.worldFromObject(light);  // view = world here (camera at origin)
        for (const glm::vec3& p : mVolumes.sphere().positions) mVolumeVertices.push_back({p});
        const glm::dmat4 m(mWorldFromObject);
        const VolumeMesh& mesh = mVolumes.sphere();
        for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
            const glm::dvec3 a(m * glm::dvec4(glm::dvec3(mesh.positions[mesh.indices[i]]), 1.0));
            const glm::dvec3 b(m * glm::dvec4(glm::dvec3(mesh.positions[mesh.indices[i + 1]]), 1.0));
            const glm::dvec3 c(m * glm::dvec4(glm::dvec3(mesh.positions[mesh.indices[i + 2]]), 1.0));
            const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
            mPlanesView.push_back({n, glm::dot(n, a)});
        }
    }

    const Surface& depth() const { return mDepth; }
    const Surface& mask() const { return mMask; }

    // G-buffer pass: the scene plane's depth (the plane as a quad through the frustum corners
    // at NDC +-1.5, drawn counter-clockwise as seen from the camera).
    void drawScene() {
        mDepth.clearDepthStencil(true, 1.0f, true, 0);
        std::vector<PosVertex> quad;
        const glm::dvec2 cornersNdc[4] = {{-1.5, -1.5}, {1.5, -1.5}, {1.5, 1.5}, {-1.5, 1.5}};
        for (const glm::dvec2& c : cornersNdc) {
            const glm::dvec3 ray(c.x / mProjD[0][0], c.y / mProjD[1][1], -1.0);
            const double t = glm::dot(mPlane.normal, mPlane.point) / glm::dot(mPlane.normal, ray);
            REQUIRE(t > 0.0);
            quad.push_back({glm::vec3(ray * t)});
        }
        const std::vector<std::uint32_t> indices{0, 1, 2, 0, 2, 3};
        RenderTargets rt;
        rt.depthStencil = &mDepth;
        const DrawStats stats = mDevice.draw(makeDrawState(kDeferredGBufferPass, fullViewport(mDepth)), rt,
                                             std::span<const PosVertex>(quad), indices, VolumeVS{mProj}, NoPixelShader{});
        REQUIRE(stats.samplesPassed == std::uint64_t(kWidth) * kHeight);  // the plane covers the screen
    }

    // One 3dgep light: stencil <- 1, unmark, shade (DeferredLightingPass.cpp). `shadeOverride`
    // replaces the shade state (for counterfactuals). Returns the stencil after unmarking.
    std::vector<std::uint8_t> run3dgep(const PassState& shade = kDeferredShadePass) {
        mMask.clearColor(glm::vec4(0.0f));
        mDepth.clearDepthStencil(false, 0.0f, true, kDeferredStencilClear);
        drawVolume(kDeferredUnmarkPass, false, nullptr);
        std::vector<std::uint8_t> stencil = readStencil();
        drawVolume(shade, true, nullptr);
        return stencil;
    }

    // One Killzone 2 light: stencil <- 0, mark, count (occlusion query), shade if the count
    // exceeds the threshold. Returns the query's count.
    std::uint64_t runKillzone() {
        mMask.clearColor(glm::vec4(0.0f));
        mDepth.clearDepthStencil(false, 0.0f, true, kKillzoneStencilClear);
        drawVolume(kKillzoneMarkPass, false, nullptr);
        OcclusionQuery query;
        query.begin();
        drawVolume(kKillzoneCountPass, false, &query);
        query.end();
        if (killzoneShouldShade(query.samplesPassed())) drawVolume(kKillzoneShadePass, true, nullptr);
        return query.samplesPassed();
    }

    // Geometric truth at pixel (x, y): the scene point on the pixel-centre ray at the stored
    // depth (reconstructed in double), tested against the polyhedron's face planes. Ambiguous
    // when it lies within eps of the boundary: eps = 1/16 of the pixel footprint at its
    // distance (vertex snapping is 1/256 px) + 16 D24 steps in view units (d^2 / |B| per unit
    // of depth, GL form B = P[3][2]).
    Truth truth(std::uint32_t x, std::uint32_t y) const {
        const double depth = mDepth.loadDepth(x, y);
        const double xNdc = (x + 0.5) / kWidth * 2.0 - 1.0, yNdc = 1.0 - (y + 0.5) / kHeight * 2.0;
        const glm::dvec4 h = mInvProjD * glm::dvec4(xNdc, yNdc, depth, 1.0);
        const glm::dvec3 posView = glm::dvec3(h) / h.w;
        const double d = -posView.z;
        const double pxFootprint = 2.0 * d * std::tan(glm::radians(double(kFovYDeg)) * 0.5) / kHeight;
        const double depthStep = d * d / std::fabs(mProjD[3][2]) / 16777215.0;
        const double eps = pxFootprint / 16.0 + 16.0 * depthStep;
        double excess = -1e300;
        for (const PlaneD& pl : mPlanesView) excess = std::max(excess, glm::dot(pl.n, posView) - pl.offset);
        if (excess < -eps) return Truth::Inside;
        if (excess > eps) return Truth::Outside;
        return Truth::Ambiguous;
    }

    struct Comparison {
        int inside = 0, outside = 0, ambiguous = 0;
        int shadedInside = 0, shadedOutside = 0, unshadedInside = 0, shadedTwice = 0;
        std::string firstMismatch;
    };
    Comparison compareMaskWithTruth() const {
        Comparison c;
        for (std::uint32_t y = 0; y < kHeight; ++y)
            for (std::uint32_t x = 0; x < kWidth; ++x) {
                const float shade = mMask.load(x, y).x;
                c.shadedTwice += shade > 1.0f;
                const bool shaded = shade > 0.0f;
                switch (truth(x, y)) {
                case Truth::Inside:
                    ++c.inside;
                    if (shaded) ++c.shadedInside;
                    else {
                        ++c.unshadedInside;
                        if (c.firstMismatch.empty()) c.firstMismatch = describe("unshaded inside at ", x, y);
                    }
                    break;
                case Truth::Outside:
                    ++c.outside;
                    if (shaded) {
                        ++c.shadedOutside;
                        if (c.firstMismatch.empty()) c.firstMismatch = describe("shaded outside at ", x, y);
                    }
                    break;
                case Truth::Ambiguous: ++c.ambiguous; break;
                }
            }
        return c;
    }

    int shadedCount() const {
        int n = 0;
        for (std::uint32_t y = 0; y < kHeight; ++y)
            for (std::uint32_t x = 0; x < kWidth; ++x) n += mMask.load(x, y).x > 0.0f;
        return n;
    }

private:
    void drawVolume(const PassState& pass, bool withShader, OcclusionQuery* query) {
        RenderTargets rt;
        rt.depthStencil = &mDepth;
        const DrawState st = makeDrawState(pass, fullViewport(mDepth));
        const VolumeVS vs{mProj * mWorldFromObject};  // ModelViewProjection, view = identity
        const std::span<const PosVertex> vertices(mVolumeVertices);
        const std::span<const std::uint32_t> indices(mVolumes.sphere().indices);
        if (withShader) {
            rt.colors[0] = &mMask;
            mDevice.draw(st, rt, vertices, indices, vs, OnePS{}, query);
        } else {
            mDevice.draw(st, rt, vertices, indices, vs, NoPixelShader{}, query);
        }
    }

    std::vector<std::uint8_t> readStencil() const {
        std::vector<std::uint8_t> s;
        for (std::uint32_t y = 0; y < kHeight; ++y)
            for (std::uint32_t x = 0; x < kWidth; ++x) s.push_back(mDepth.loadStencil(x, y));
        return s;
    }

    glm::mat4 mProj;
    glm::dmat4 mProjD, mInvProjD;
    ScenePlane mPlane;
    Light mLight;
    LightVolumes mVolumes;
    glm::mat4 mWorldFromObject{1.0f};
    std::vector<PosVertex> mVolumeVertices;
    std::vector<PlaneD> mPlanesView;
    Surface mDepth, mMask;
    Device mDevice;
};

Light pointLight(glm::vec3 posView, float range) {
    Light l;
    l.type = LightType::Point;
    l.positionWorld = posView;
    l.range = range;
    return l;
}

ScenePlane plane(glm::dvec3 point, glm::dvec3 normal) { return {point, glm::normalize(normal)}; }

int countEqual(const std::vector<std::uint8_t>& v, std::uint8_t value) {
    int n = 0;
    for (std::uint8_t s : v) n += s == value;
    return n;
}

#define CHECK_MATCHES_TRUTH(c)                                                                                     \
    do {                                                                                                           \
        INFO("inside " << (c).inside << " outside " << (c).outside << " ambiguous " << (c).ambiguous << "; "   \
                       << (c).firstMismatch);                                                                       \
        CHECK((c).shadedOutside == 0);                                                                             \
        CHECK((c).unshadedInside == 0);                                                                            \
        CHECK((c).shadedTwice == 0);                                                                               \
        CHECK((c).ambiguous * 20 < (c).inside + (c).outside);                                                      \
    } while (false)

} // namespace

TEST_CASE("deferred states are the seed's and the demo's") {
    // 3dgep unmark: front faces, GREATER, no write, ALWAYS / DECR_SAT on depth pass, ref 1.
    static_assert(kDeferredUnmarkPass.rasterizer.cullMode == CullMode::Back);
    static_assert(kDeferredUnmarkPass.rasterizer.depthClipEnable);
    static_assert(kDeferredUnmarkPass.rasterizer.frontCounterClockwise);
    static_assert(kDeferredUnmarkPass.depthStencil.depthEnable && !kDeferredUnmarkPass.depthStencil.depthWriteEnable);
    static_assert(kDeferredUnmarkPass.depthStencil.depthFunc == ComparisonFunc::Greater);
    static_assert(kDeferredUnmarkPass.depthStencil.stencilEnable && kDeferredUnmarkPass.stencilRef == 1);
    static_assert(kDeferredUnmarkPass.depthStencil.stencilReadMask == 0xFF && kDeferredUnmarkPass.depthStencil.stencilWriteMask == 0xFF);
    static_assert(kDeferredUnmarkPass.depthStencil.frontFace.func == ComparisonFunc::Always);
    static_assert(kDeferredUnmarkPass.depthStencil.frontFace.passOp == StencilOp::DecrSat);
    static_assert(kDeferredUnmarkPass.depthStencil.frontFace.failOp == StencilOp::Keep);
    static_assert(kDeferredUnmarkPass.depthStencil.frontFace.depthFailOp == StencilOp::Keep);
    static_assert(kDeferredUnmarkPass.depthStencil.backFace.passOp == StencilOp::Keep);
    static_assert(!kDeferredUnmarkPass.blend.renderTarget[0].blendEnable);
    // 3dgep shade: back faces, no depth clip, GREATER_EQUAL, no write, back-face EQUAL 1, ONE+ONE.
    static_assert(kDeferredShadePass.rasterizer.cullMode == CullMode::Front);
    static_assert(!kDeferredShadePass.rasterizer.depthClipEnable);
    static_assert(kDeferredShadePass.depthStencil.depthFunc == ComparisonFunc::GreaterEqual);
    static_assert(!kDeferredShadePass.depthStencil.depthWriteEnable);
    static_assert(kDeferredShadePass.depthStencil.backFace.func == ComparisonFunc::Equal);
    static_assert(kDeferredShadePass.depthStencil.backFace.passOp == StencilOp::Keep);
    static_assert(kDeferredShadePass.depthStencil.frontFace.func == ComparisonFunc::Always);
    static_assert(kDeferredShadePass.stencilRef == 1);
    static_assert(kDeferredShadePass.blend.renderTarget[0].blendEnable);
    static_assert(kDeferredShadePass.blend.renderTarget[0].srcBlend == Blend::One);
    static_assert(kDeferredShadePass.blend.renderTarget[0].destBlend == Blend::One);
    static_assert(kDeferredShadePass.blend.renderTarget[0].blendOp == BlendOp::Add);
    // Directional: depth GREATER, no write, no stencil, additive.
    static_assert(kDeferredDirectionalPass.depthStencil.depthFunc == ComparisonFunc::Greater);
    static_assert(!kDeferredDirectionalPass.depthStencil.depthWriteEnable && !kDeferredDirectionalPass.depthStencil.stencilEnable);
    static_assert(kDeferredDirectionalPass.blend.renderTarget[0].blendEnable);
    // G-buffer: LESS with writes, no stencil.
    static_assert(kDeferredGBufferPass.depthStencil.depthFunc == ComparisonFunc::Less);
    static_assert(kDeferredGBufferPass.depthStencil.depthWriteEnable && !kDeferredGBufferPass.depthStencil.stencilEnable);
    // Killzone: mark back faces GREATER_EQUAL REPLACE; count front faces LESS_EQUAL EQUAL 1.
    static_assert(kKillzoneMarkPass.rasterizer.cullMode == CullMode::Front);
    static_assert(kKillzoneMarkPass.depthStencil.depthFunc == ComparisonFunc::GreaterEqual);
    static_assert(kKillzoneMarkPass.depthStencil.backFace.func == ComparisonFunc::Always);
    static_assert(kKillzoneMarkPass.depthStencil.backFace.passOp == StencilOp::Replace);
    static_assert(kKillzoneMarkPass.stencilRef == 1);
    static_assert(kKillzoneCountPass.rasterizer.cullMode == CullMode::Back);
    static_assert(kKillzoneCountPass.depthStencil.depthFunc == ComparisonFunc::LessEqual);
    static_assert(kKillzoneCountPass.depthStencil.frontFace.func == ComparisonFunc::Equal);
    static_assert(kKillzoneCountPass.depthStencil.frontFace.passOp == StencilOp::Keep);
    static_assert(kKillzoneShadePass.blend.renderTarget[0].blendEnable);
    static_assert(kDeferredStencilClear == 1 && kKillzoneStencilClear == 0);
    CHECK(killzoneShouldShade(1));
    CHECK_FALSE(killzoneShouldShade(0));
    CHECK_FALSE(killzoneShouldShade(5, 5));
    const DrawState st = makeDrawState(kDeferredShadePass, Viewport{0, 0, 8, 8, 0, 1});
    CHECK(st.stencilRef == 1);
    CHECK(st.viewport.width == 8.0f);
    CHECK_FALSE(st.rasterizer.scissorEnable);
}

// Light: point light at view (0, 0, -10), Range 3 (volume spans view z -13 .. -7).
TEST_CASE("(a) geometry in front of the volume: unmark clears the stencil, nothing is shaded") {
    StencilScene scene(100.0f, plane({0, 0, -5}, {0.1, 0.2, 1.0}), pointLight({0.0f, 0.0f, -10.0f}, 3.0f));
    scene.drawScene();
    const auto stencil = scene.run3dgep();
    // The whole volume lies behind the scene, so every front-face fragment passes GREATER and
    // DECR_SATs its pixel: stencil 0 over the volume's silhouette, 1 elsewhere.
    const int zeros = countEqual(stencil, 0), ones = countEqual(stencil, 1);
    MESSAGE("(a) stencil after unmark: " << zeros << " pixels 0, " << ones << " pixels 1");
    CHECK(zeros > 200);
    CHECK(zeros + ones == int(kWidth * kHeight));
    CHECK(scene.shadedCount() == 0);
    CHECK_MATCHES_TRUTH(scene.compareMaskWithTruth());
    CHECK(scene.runKillzone() == 0);
    CHECK(scene.shadedCount() == 0);
}

TEST_CASE("(b) geometry inside the volume: exactly the pixels whose scene point is inside are shaded") {
    // A tilted plane through the light: part of it inside the sphere, part outside.
    StencilScene scene(100.0f, plane({0, 0, -10}, {0.5, 0.3, 1.0}), pointLight({0.0f, 0.0f, -10.0f}, 3.0f));
    scene.drawScene();
    const auto stencil = scene.run3dgep();
    CHECK(countEqual(stencil, 1) + countEqual(stencil, 0) == int(kWidth * kHeight));
    const auto c = scene.compareMaskWithTruth();
    MESSAGE("(b) 3dgep: inside " << c.inside << ", outside " << c.outside << ", ambiguous " << c.ambiguous
                                 << ", shaded " << scene.shadedCount());
    CHECK(c.inside > 200);
    CHECK(c.outside > 200);
    CHECK_MATCHES_TRUTH(c);
    // Killzone gives the same mask here, and its query counts exactly the shaded pixels.
    const int shaded3dgep = scene.shadedCount();
    const std::uint64_t counted = scene.runKillzone();
    CHECK(counted == std::uint64_t(shaded3dgep));
    CHECK(scene.shadedCount() == shaded3dgep);
    CHECK_MATCHES_TRUTH(scene.compareMaskWithTruth());
}

TEST_CASE("(c) geometry behind the volume: the stencil stays 1 but the shade pass's depth test fails") {
    StencilScene scene(100.0f, plane({0, 0, -15}, {-0.2, 0.1, 1.0}), pointLight({0.0f, 0.0f, -10.0f}, 3.0f));
    scene.drawScene();
    const auto stencil = scene.run3dgep();
    CHECK(countEqual(stencil, 1) == int(kWidth * kHeight));  // front faces in front of the scene: GREATER fails
    CHECK(scene.shadedCount() == 0);                           // back faces in front too: GREATER_EQUAL fails
    CHECK_MATCHES_TRUTH(scene.compareMaskWithTruth());
    CHECK(scene.runKillzone() == 0);
    CHECK(scene.shadedCount() == 0);
}

TEST_CASE("(d) eye inside the volume: 3dgep shades the inside pixels, Killzone 2 counts 0 and shades nothing") {
    // Light at (0, 0, -1) with Range 3 contains the eye; the tilted plane around z = -3.5 is
    // inside the sphere near the screen centre and outside towards the corners.
    StencilScene scene(100.0f, plane({0, 0, -3.5}, {0.2, -0.1, 1.0}), pointLight({0.0f, 0.0f, -1.0f}, 3.0f));
    scene.drawScene();
    const auto stencil = scene.run3dgep();
    // Every visible face is a back face (the eye is inside): nothing is unmarked.
    CHECK(countEqual(stencil, 1) == int(kWidth * kHeight));
    const auto c = scene.compareMaskWithTruth();
    MESSAGE("(d) 3dgep: inside " << c.inside << ", outside " << c.outside << ", ambiguous " << c.ambiguous
                                 << ", shaded " << scene.shadedCount());
    CHECK(c.inside > 200);
    CHECK(c.outside > 100);
    CHECK_MATCHES_TRUTH(c);
    // Killzone 2: the front faces are behind the eye (w < 0) and clipped, so the count pass
    // passes no sample, the query reads 0 and the light is skipped (3dgep article §3.2.1.2, §3.3).
    const std::uint64_t counted = scene.runKillzone();
    MESSAGE("(d) Killzone 2: query " << counted << ", shaded " << scene.shadedCount());
    CHECK(counted == 0);
    CHECK(scene.shadedCount() == 0);
}

TEST_CASE("(e) volume crossing the far plane: shaded thanks to depthClipEnable = false") {
    // far = 20; the sphere at z = -19 with Range 3 reaches z = -22. The scene plane at z = -19.5
    // lies inside; most of its pixels see the volume's back face beyond the far plane.
    StencilScene scene(20.0f, plane({0, 0, -19.5}, {0.0, 0.0, 1.0}), pointLight({0.0f, 0.0f, -19.0f}, 3.0f));
    scene.drawScene();
    scene.run3dgep();
    const auto c = scene.compareMaskWithTruth();
    const int shaded = scene.shadedCount();
    MESSAGE("(e) 3dgep: inside " << c.inside << ", outside " << c.outside << ", ambiguous " << c.ambiguous
                                 << ", shaded " << shaded);
    CHECK(c.inside > 200);
    CHECK_MATCHES_TRUTH(c);
    // Counterfactual: the same shade pass with depth clipping on loses every pixel whose back
    // face lies beyond z = -20 (lateral radius < sqrt(3^2 - 1^2) = 2.83 of the light's axis).
    PassState clipped = kDeferredShadePass;
    clipped.rasterizer.depthClipEnable = true;
    scene.run3dgep(clipped);
    const int shadedClipped = scene.shadedCount();
    MESSAGE("(e) with depth clip on: shaded " << shadedClipped << " of " << shaded);
    CHECK(shadedClipped * 4 < shaded);
    // The Killzone mark pass (depth clip on) likewise never marks those pixels.
    scene.runKillzone();
    const int shadedKillzone = scene.shadedCount();
    MESSAGE("(e) Killzone 2 (mark pass depth-clipped): shaded " << shadedKillzone << " of " << shaded);
    CHECK(shadedKillzone * 4 < shaded);
}

TEST_CASE("directional pass: the full-screen quad at depth 1 lights geometry pixels, not the cleared background") {
    // DeferredLightingPass.cpp: CreateScreenQuad(-1, 1, -1, 1, -1) under glm::ortho(-1, 1, -1, 1,
    // 0, 1) (GL form): z_ndc = -2/(f-n) * (-1) - (f+n)/(f-n) = 1, the far plane; depth GREATER.
    Surface depth(SurfaceDesc{kWidth, kHeight, Format::D24_UNORM_S8_UINT, 1});
    Surface mask(SurfaceDesc{kWidth, kHeight, Format::R32_FLOAT, 1});
    depth.clearDepthStencil(true, 1.0f, true, 0);
    mask.clearColor(glm::vec4(0.0f));
    Device device(DeviceConfig{16, 2});
    const std::vector<std::uint32_t> quadIndices{0, 1, 2, 0, 2, 3};  // counter-clockwise seen from +Z
    // Geometry: the left half of the screen at NDC depth 0.5 (identity transform).
    const std::vector<PosVertex> leftHalf{{{-1.0f, -1.0f, 0.5f}}, {{0.0f, -1.0f, 0.5f}}, {{0.0f, 1.0f, 0.5f}}, {{-1.0f, 1.0f, 0.5f}}};
    RenderTargets depthOnly;
    depthOnly.depthStencil = &depth;
    device.draw(makeDrawState(kDeferredGBufferPass, fullViewport(depth)), depthOnly, std::span<const PosVertex>(leftHalf),
                quadIndices, VolumeVS{}, NoPixelShader{});
    const std::vector<PosVertex> screenQuad{{{-1.0f, -1.0f, -1.0f}}, {{1.0f, -1.0f, -1.0f}}, {{1.0f, 1.0f, -1.0f}}, {{-1.0f, 1.0f, -1.0f}}};
    const glm::mat4 ortho = glm::orthoRH_NO(-1.0f, 1.0f, -1.0f, 1.0f, 0.0f, 1.0f);
    CHECK((ortho * glm::vec4(0.0f, 0.0f, -1.0f, 1.0f)).z == 1.0f);
    RenderTargets rt;
    rt.colors[0] = &mask;
    rt.depthStencil = &depth;
    device.draw(makeDrawState(kDeferredDirectionalPass, fullViewport(depth)), rt, std::span<const PosVertex>(screenQuad),
                quadIndices, VolumeVS{ortho}, OnePS{});
    int wrong = 0;
    for (std::uint32_t y = 0; y < kHeight; ++y)
        for (std::uint32_t x = 0; x < kWidth; ++x) wrong += (mask.load(x, y).x == 1.0f) != (x < kWidth / 2);
    CHECK(wrong == 0);
}

#undef CHECK_MATCHES_TRUTH

} // namespace tessera_test::raster_deferred_stencil_test
