// The `deferred-cookbook` technique (techniques/deferred_cookbook.h; HLSL Development Cookbook ch. 2):
// clear -> G-buffer (PackGBuffer) -> lights (directional + ambient quad, then one tessellated
// volume per point, spot and capsule light, additive) -> [present] -> forward's transparent pass.
#include <tessera/techniques/deferred_cookbook.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <tessera/buffers/target_reader.h>
#include <tessera/gbuffer/cookbook_gbuffer.h>
#include <tessera/math/det_math.h>
#include <tessera/raster/draw_batch.h>
#include <tessera/shading/cookbook_lighting.h>
#include <tessera/shading/phong_surface.h>
#include <tessera/techniques/cookbook_volumes.h>
#include <tessera/techniques/deferred_states.h>
#include <tessera/techniques/forward.h>
#include <tessera/techniques/technique_options.h>

#include "gbuffer_pass.h"
#include "msaa_deferred.h"

namespace tessera {
namespace {

struct CookbookOptions {
    bool printedUnpack = true;      // specPowerUnpack printed
    bool cullBack = true;           // volumeCull table
    bool bookSpot = true;           // spotVolume book
    bool vertexCpPos = true;        // cpPos vertex
    bool stencil = false;           // background stencil
    EdgeDetector edges = EdgeDetector::DepthNormal;  // MSAA (the recipe has none): Intel's test
    bool padded = true;             // volumeScale padded
    bool quads = false;             // lightGeometry quads
    PhongSamplerChoice sampler = PhongSamplerChoice::Demo;
    bool alphaTest = false;
};

CookbookOptions parseOptions(const TechniqueContext& ctx, const std::string& file) {
    const OptionReader r(ctx.options, kDeferredCookbookOptions, file);
    CookbookOptions o;
    o.printedUnpack = r.is("specPowerUnpack", "printed");
    o.cullBack = r.is("volumeCull", "table");
    o.bookSpot = r.is("spotVolume", "book");
    o.vertexCpPos = r.is("cpPos", "vertex");
    o.stencil = r.is("background", "stencil");
    o.padded = r.is("volumeScale", "padded");
    o.quads = r.is("lightGeometry", "quads");
    o.sampler = r.is("sampler", "gltf") ? PhongSamplerChoice::Gltf : PhongSamplerChoice::Demo;
    o.alphaTest = r.flag("alphaTest");
    o.edges = gbuffer_detail::parseEdgeDetector(r);
    return o;
}

// One light as the lighting pixel shader reads it (cbDirLight, cbPointLightPixel, cbSpotLightPixel,
// CapsuleLightConstants), world space.
struct CookbookLight {
    LightType type = LightType::Directional;
    std::uint32_t index = 0;         // scene light index (pixel watch)
    bool ambient = false;            // the first directional draw adds CalcAmbient
    glm::vec3 color{0.0f};           // colour x intensity
    glm::vec3 dirToLight{0.0f};      // directional: -direction; spot: SpotDirToLight = -direction
    glm::vec3 position{0.0f};        // point, spot; capsule: the segment's start
    glm::vec3 direction{0.0f};       // capsule: the segment's unit direction
    float length = 0.0f;             // capsule
    float range = 0.0f;              // +inf: no falloff volume
    float rangeRcp = 0.0f;
    float cosOuter = 0.0f, cosConeAttRange = 0.0f;  // spot
};

// What every lighting draw reads: the G-buffer, the unpack constants and the choices.
struct CookbookShared {
    TargetReader color, normal, specPow;
    const Surface* depth = nullptr;
    CookbookPerspectiveValues pv;
    glm::mat4 worldFromViewLh{1.0f};
    glm::dmat4 worldFromViewLhDouble{1.0};
    glm::vec3 eyeWorld{0.0f};       // EyePosition = ViewInv[3].xyz
    glm::vec2 screenPx{1.0f};
    bool printedUnpack = true, vertexCpPos = true;
};

struct CookbookVaryings {
    glm::vec2 cpPos;  // Output.cpPos = Output.Position.xy / Output.Position.w (per vertex)
    static constexpr std::array<VaryingField, 1> kFields{{{"cpPos", 2}}};
};

struct LocalVertex {
    glm::vec3 posLocal;
};

// The domain shader's last lines: Position = mul(posLS, LightProjection); cpPos = Position.xy / w.
struct CookbookVolumeVS {
    using Varyings = CookbookVaryings;
    glm::mat4 clipFromLocal{1.0f};
    VertexOutput<CookbookVaryings> operator()(const LocalVertex& v) const {
        const glm::vec4 posClip = clipFromLocal * glm::vec4(v.posLocal, 1.0f);
        return {posClip, {glm::vec2(posClip) / posClip.w}};
    }
};

// The G-buffer PS: the Phong surface gather (the material mapping every 3dgep-based technique
// uses), then PackGBuffer(BaseColor, normalize(Normal), SpecIntensity, SpecPower) with the world
// normal. SpecIntensity is the mean of the specular colour (0 when the material has none).
struct CookbookEncoder {
    static constexpr int kTargetCount = 3;
    glm::mat3 worldFromView{1.0f};
    template <class Out>
    void encode(const PhongSurface<float>& s, const PixelInput<PhongVaryings>&, Out& out) const {
        const glm::vec3 normalWorld = hlsl::normalize(worldFromView * glm::vec3(s.normalView));
        const float specIntensity = ((s.specular.x + s.specular.y) + s.specular.z) / 3.0f;
        out.target[0] = glm::vec4(glm::vec3(s.diffuse), specIntensity);                    // ColorSpecInt
        out.target[1] = glm::vec4(packCookbookNormal(normalWorld), 0.0f);                  // Normal
        out.target[2] = glm::vec4(packCookbookSpecPower(s.specularPower), 0.0f, 0.0f, 0.0f);  // SpecPow
    }
};
template <bool D> using CookbookGBufferPS = gbuffer_detail::GBufferShader<CookbookEncoder, D>;
template <bool D> using CookbookGBufferMsaaPS = gbuffer_detail::GBufferShader<CookbookEncoder, D, true>;

// DirLightPS / PointLightPS / SpotLightPS / CapsuleLightPS: UnpackGBuffer at the pixel,
// MaterialFromGBuffer, CalcWorldPos, Calc*. T = float (exact, fast with kFast), double (reference:
// the G-buffer's values shaded in double).
template <class T, bool kFast>
struct CookbookLightPS {
    using Varyings = CookbookVaryings;
    static constexpr int kTargetCount = 1;
    const CookbookShared* shared = nullptr;
    const CookbookLight* light = nullptr;
    void operator()(const PixelInput<CookbookVaryings>& in, PixelOutput<1>& out) const {
        const CookbookShared& g = *shared;
        // UnpackGBuffer_Loc(In.Position.xy): Load at the integer pixel; with MSAA the shader's
        // sample (0 per pixel; SV_Position and cpPos at the sample when it runs per sample).
        const auto x = std::uint32_t(in.posWindow.x), y = std::uint32_t(in.posWindow.y);
        const std::uint32_t i = in.sampleIndex;
        const T linearDepth = cookbookLinearDepth<T>(T(g.depth->loadDepth(x, y, i)), g.pv);
        const glm::vec4 colorSpecInt = g.color.load(x, y, i);
        CookbookMaterial<T> m;
        m.diffuseColor = Vec3<T>(glm::vec3(colorSpecInt));
        m.specIntensity = T(colorSpecInt.w);
        const Vec3<T> stored(glm::vec3(g.normal.load(x, y, i)));
        m.normal = hlsl::normalize(stored * T(2) - T(1));
        const float specPowNorm = g.specPow.load(x, y, i).x;
        m.specPow = T(g.printedUnpack ? unpackCookbookSpecPowerAsPrinted(specPowNorm) : unpackCookbookSpecPower(specPowNorm));
        // cpPos: the interpolated per-vertex value, or the pixel centre's clip-space xy.
        glm::vec<2, T> cpPos;
        if (g.vertexCpPos) {
            cpPos = glm::vec<2, T>(in.varyings.cpPos);
        } else {
            cpPos = glm::vec<2, T>(T(in.posWindow.x) / T(g.screenPx.x) * T(2) - T(1),
                                   T(1) - T(in.posWindow.y) / T(g.screenPx.y) * T(2));
        }
        Vec3<T> posWorld;
        if constexpr (std::is_same_v<T, double>) posWorld = cookbookWorldPosition<T>(cpPos, linearDepth, g.pv, g.worldFromViewLhDouble);
        else posWorld = cookbookWorldPosition<T>(cpPos, linearDepth, g.pv, g.worldFromViewLh);
        const Vec3<T> eye(g.eyeWorld);
        const CookbookLight& l = *light;
        Vec3<T> color(T(0));
        CookbookTerms<T> terms;
        switch (l.type) {
        case LightType::Directional:
            if (l.ambient) color = cookbookAmbient<T>(m.normal, m.diffuseColor, Vec3<T>(kCookbookAmbientDown),
                                                      Vec3<T>(kCookbookAmbientUp) - Vec3<T>(kCookbookAmbientDown));
            color += cookbookDirectional<T, kFast>(posWorld, eye, m, Vec3<T>(l.dirToLight), Vec3<T>(l.color));
            terms.color = color;
            terms.nDotL = hlsl::dot(Vec3<T>(l.dirToLight), m.normal);
            break;
        case LightType::Point:
            terms = cookbookPoint<T, kFast>(posWorld, eye, m, Vec3<T>(l.position), T(l.rangeRcp), Vec3<T>(l.color));
            color = terms.color;
            break;
        case LightType::Spot:
            terms = cookbookSpot<T, kFast>(posWorld, eye, m, Vec3<T>(l.position), T(l.rangeRcp), Vec3<T>(l.color),
                                           Vec3<T>(l.dirToLight), T(l.cosOuter), T(l.cosConeAttRange));
            color = terms.color;
            break;
        case LightType::Capsule:
            terms = cookbookCapsule<T, kFast>(posWorld, eye, m, Vec3<T>(l.position), Vec3<T>(l.direction), T(l.length),
                                              T(l.rangeRcp), Vec3<T>(l.color));
            color = terms.color;
            break;
        }
        if (std::vector<LightTerm>* trace = watchedLightTerms()) [[unlikely]] {
            LightTerm term;
            term.light = l.index;
            term.combined = true;
            term.distance = float(terms.distance);
            term.range = l.range;
            term.nDotL = float(terms.nDotL);
            term.falloff = float(terms.attenuation);
            term.cone = float(terms.cone);
            term.diffuse = glm::vec4(glm::vec3(color), 0.0f);
            trace->push_back(term);
        }
        out.target[0] = glm::vec4(glm::vec3(color), 1.0f);  // float4(finalColor, 1.0)
    }
};

// A light's draw: its mesh in local space and the matrix to clip space.
struct LightDraw {
    CookbookLight light;
    std::vector<LocalVertex> vertices;
    std::vector<std::uint32_t> indices;
    glm::mat4 clipFromLocal{1.0f};
    bool quad = false;  // the full-screen quad (directional, infinite range)
};

struct CookbookSetup {
    CookbookOptions options;
    std::shared_ptr<ForwardPassSetup> forward;
    CookbookShared shared;
    glm::mat3 worldFromView{1.0f};
    std::vector<LightDraw> draws;  // in drawing order: directional (first with ambient), then the rest
    std::function<void(std::size_t, std::string_view, const BufferRegistry&)> afterLightStep;
};

// DirLightVS's arrBasePos as a triangle strip (-1, 1), (1, 1), (-1, -1), (1, -1): two triangles,
// clockwise on screen (D3D11's front face), at z = 0, w = 1.
void setQuad(LightDraw& d) {
    d.quad = true;
    d.vertices.clear();
    for (const glm::vec3& p : gbuffer_detail::kQuadClip) d.vertices.push_back({p});
    d.indices.assign(gbuffer_detail::kQuadIndices.begin(), gbuffer_detail::kQuadIndices.end());
    d.clipFromLocal = glm::mat4(1.0f);
}

void setMesh(LightDraw& d, const CookbookVolumeMesh& mesh, const glm::mat4& clipFromLocal) {
    d.vertices.clear();
    for (const glm::vec3& p : mesh.positions) d.vertices.push_back({p});
    d.indices = mesh.indices;
    d.clipFromLocal = clipFromLocal;
}

// Local -> left-handed view frame for a light along dirLh at posLh: columns right, up, dir
// (the companion code's construction: up = (0, 0, dir.y) when |dir.y| > 0.9, else (0, 1, 0);
// right = normalize(up x dir); up = normalize(dir x right)), built in view space.
glm::mat4 frameAlong(const glm::vec3& posLh, const glm::vec3& dirLh) {
    glm::vec3 up = (dirLh.y > 0.9f || dirLh.y < -0.9f) ? glm::vec3(0.0f, 0.0f, dirLh.y) : glm::vec3(0.0f, 1.0f, 0.0f);
    const glm::vec3 right = glm::normalize(glm::cross(up, dirLh));
    up = glm::normalize(glm::cross(dirLh, right));
    glm::mat4 m(1.0f);
    m[0] = glm::vec4(right, 0.0f);
    m[1] = glm::vec4(up, 0.0f);
    m[2] = glm::vec4(dirLh, 0.0f);
    m[3] = glm::vec4(posLh, 1.0f);
    return m;
}

std::vector<LightDraw> planDraws(const std::vector<Light>& lights, const CookbookOptions& o, const glm::mat4& viewLh,
                                 const glm::mat4& projectionLh) {
    std::vector<LightDraw> directional, volumes;
    // The unit point volume and its enlargement are the same for every point light, and a spot's
    // enlargement depends only on its angle: built once each, not per light.
    const CookbookVolumeMesh pointMesh = cookbookPointVolume();
    const float pointPad = o.padded ? cookbookPointPadding() : 1.0f;
    std::map<float, CookbookSpotPadding> spotPads;
    const auto toViewLh = [&](const glm::vec3& p) { return glm::vec3(viewLh * glm::vec4(p, 1.0f)); };
    const auto dirViewLh = [&](const glm::vec3& d) { return glm::normalize(glm::vec3(viewLh * glm::vec4(d, 0.0f))); };
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const Light& src = lights[i];
        if (!src.enabled) continue;
        LightDraw d;
        CookbookLight& l = d.light;
        l.type = src.type;
        l.index = std::uint32_t(i);
        l.color = src.color * src.intensity;
        l.position = src.positionWorld;
        l.range = src.type == LightType::Directional ? std::numeric_limits<float>::infinity() : src.range;
        l.rangeRcp = 1.0f / l.range;  // 0 for an infinite range: no falloff
        if (src.type == LightType::Directional) {
            l.dirToLight = -src.directionWorld;
            setQuad(d);
            directional.push_back(std::move(d));
            continue;
        }
        const bool finite = std::isfinite(src.range);
        if (src.type == LightType::Point) {
            if (finite) {
                // S(range) T(L View) P: the unit sphere around the light's view position, its axes the
                // view's ("the volume will always face the camera").
                const float s = src.range * pointPad;
                const glm::mat4 viewFromLocal = glm::translate(glm::mat4(1.0f), toViewLh(src.positionWorld)) *
                                                glm::scale(glm::mat4(1.0f), glm::vec3(s));
                setMesh(d, pointMesh, projectionLh * viewFromLocal);
            }
        } else if (src.type == LightType::Spot) {
            const float outer = float(hlsl::radians(double(src.spotHalfAngleDeg)));
            const float inner = float(hlsl::radians(double(src.spotInnerHalfAngleDeg)));
            l.dirToLight = -src.directionWorld;
            l.cosOuter = detCos(outer);
            l.cosConeAttRange = detCos(inner) - l.cosOuter;
            if (finite) {
                const glm::mat4 frame = frameAlong(toViewLh(src.positionWorld), dirViewLh(src.directionWorld));
                if (o.bookSpot) {
                    // ScaleXY = LightRange * tan(angle) / sqrt(1/2), ScaleZ = LightRange, with the
                    // domain shader's SinAngle = CosAngle = sqrt(1/2) (the unit cone of 45 degrees).
                    constexpr float kSqrtHalf = 0.70710678f;
                    const float scaleXy = src.range * detTan(outer) / kSqrtHalf;
                    setMesh(d, cookbookSpotVolume(kSqrtHalf, kSqrtHalf),
                            projectionLh * frame * glm::scale(glm::mat4(1.0f), glm::vec3(scaleXy, scaleXy, src.range)));
                } else {
                CookbookSpotPadding pad{outer, 1.0f};
                if (o.padded) {
                    const auto it = spotPads.find(outer);
                    pad = it != spotPads.end() ? it->second : spotPads.emplace(outer, cookbookSpotPadding(outer)).first->second;
                }
                    setMesh(d, cookbookSpotVolume(std::sin(pad.halfAngle), std::cos(pad.halfAngle)),
                            projectionLh * frame * glm::scale(glm::mat4(1.0f), glm::vec3(src.range * pad.scale)));
                }
            }
        } else {  // capsule
            l.direction = src.directionWorld;
            l.length = src.length;
            if (finite) {
                const float half = 0.5f * src.length;
                const glm::vec3 centreWorld = src.positionWorld + src.directionWorld * half;
                const glm::mat4 frame = frameAlong(toViewLh(centreWorld), dirViewLh(src.directionWorld));
                const float capsuleRange = o.padded ? cookbookCapsulePaddedRange(half, src.range) : src.range;
                setMesh(d, cookbookCapsuleVolume(half, capsuleRange), projectionLh * frame);
            }
        }
        if (!finite || o.quads) setQuad(d);  // no falloff, or the quads baseline: every pixel
        volumes.push_back(std::move(d));
    }
    if (directional.empty()) {  // the ambient still needs its full-screen pass: a black directional light
        LightDraw d;
        d.light.type = LightType::Directional;
        d.light.index = kAmbientLightTerm;
        d.light.dirToLight = glm::vec3(0.0f, 1.0f, 0.0f);
        d.light.range = std::numeric_limits<float>::infinity();
        setQuad(d);
        directional.push_back(std::move(d));
    }
    directional.front().light.ambient = true;
    directional.insert(directional.end(), std::make_move_iterator(volumes.begin()), std::make_move_iterator(volumes.end()));
    return directional;
}

// The pass states. G-buffer: depth LESS with writes (stencil REPLACE 1 in stencil mode).
PassState gbufferState(bool stencil) {
    PassState p;
    p.rasterizer.cullMode = CullMode::Back;
    p.depthStencil.depthEnable = true;
    p.depthStencil.depthWriteEnable = true;
    p.depthStencil.depthFunc = ComparisonFunc::Less;
    if (stencil) gbuffer_detail::stencilReplaceOne(p);
    return p;
}


// The full-screen quad: book: no depth-stencil view (depth disabled), the first draw without
// blending; stencil: depth LESS without writes, stencil EQUAL 1. Later quads add.
PassState quadState(const CookbookOptions& o, bool first) {
    PassState p;
    p.rasterizer.cullMode = CullMode::Back;
    p.depthStencil.depthEnable = o.stencil;
    p.depthStencil.depthWriteEnable = false;
    p.depthStencil.depthFunc = ComparisonFunc::Less;
    if (o.stencil) gbuffer_detail::stencilEqualOne(p);
    if (!first) p.blend.renderTarget[0] = kAdditiveBlend;
    return p;
}

// The volumes: depth GREATER_EQUAL without writes, depth clip off, cull BACK (the table) or FRONT,
// additive blending ("rest ... zero": FrontCounterClockwise FALSE).
PassState volumeState(const CookbookOptions& o) {
    PassState p;
    p.rasterizer.cullMode = o.cullBack ? CullMode::Back : CullMode::Front;
    p.rasterizer.frontCounterClockwise = false;
    p.rasterizer.depthClipEnable = false;
    p.depthStencil.depthEnable = true;
    p.depthStencil.depthWriteEnable = false;
    p.depthStencil.depthFunc = ComparisonFunc::GreaterEqual;
    if (o.stencil) gbuffer_detail::stencilEqualOne(p);
    p.blend.renderTarget[0] = kAdditiveBlend;
    return p;
}

const char* typeName(LightType t) {
    switch (t) {
    case LightType::Point: return "point";
    case LightType::Spot: return "spot";
    case LightType::Directional: return "directional";
    case LightType::Capsule: return "capsule";
    }
    return "?";
}

template <class T, bool kFast>
void runLights(const CookbookSetup& setup, Device& device, BufferRegistry& reg, Surface& target, DrawStats* stats,
               std::map<std::string, std::uint64_t>* variantCounts) {
    const ForwardPassSetup& fwd = *setup.forward;
    const Viewport viewport{0.0f, 0.0f, float(fwd.width), float(fwd.height), 0.0f, 1.0f};
    Surface& depth = reg.get("depth");
    // Every light binned together (raster/draw_batch.h): additive draws that read the G-buffer and
    // the depth-stencil (bound read-only) and write only `target`, in light order in each tile.
    DrawBatch batch(device);
    const auto runBatch = [&] { batch.runInto(stats); };
    for (std::size_t k = 0; k < setup.draws.size(); ++k) {
        const LightDraw& d = setup.draws[k];
        const PassState pass = d.quad ? quadState(setup.options, k == 0) : volumeState(setup.options);
        RenderTargets rt;
        rt.colors[0] = &target;
        // The book's quad binds no depth-stencil view; every other draw binds it read-only. With
        // MSAA every draw binds it for the edge bit (the quad's depth test stays off).
        const bool msaa = fwd.sampleCount > 1;
        if (!(d.quad && !setup.options.stencil) || msaa) rt.depthStencil = &depth;
        const CookbookVolumeVS vs{d.clipFromLocal};
        const CookbookLightPS<T, kFast> ps{&setup.shared, &d.light};
        const auto drawWith = [&](const PassState& p, const auto& shader) {
            DrawState state = makeDrawState(p, viewport);
            state.precision = fwd.precision;
            batch.draw(state, rt, std::span<const LocalVertex>(d.vertices), d.indices, vs, shader);
        };
        gbuffer_detail::drawPerPixelThenEdgeSamples(msaa, pass, ps, drawWith);
        if (variantCounts) ++(*variantCounts)[std::string("cookbook-light:") + typeName(d.light.type) + (d.quad ? "(quad)" : "")];
        if (setup.afterLightStep && d.light.index != kAmbientLightTerm) {
            runBatch();  // the step's buffers as they stand after it
            setup.afterLightStep(d.light.index, "shade", reg);
        }
    }
    runBatch();
}

} // namespace

Frame buildDeferredCookbook(const TechniqueContext& ctx) {
    const std::string file = ctx.errorFile();
    auto setup = std::make_shared<CookbookSetup>();
    setup->options = parseOptions(ctx, file);
    const CookbookOptions& opt = setup->options;
    setup->afterLightStep = ctx.afterLightStep;
    // The book's D3D projection (perspective, depth 0 at the near plane), as forward with "d3d".
    setup->forward = makeForwardPassSetup(ctx, ProjectionConvention::D3d, opt.sampler, opt.alphaTest);
    const ForwardPassSetup& fwd = *setup->forward;
    // Left-handed view: z flipped (tessera's view space looks down -z; the book's down +z).
    const glm::mat4 flipZ = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 1.0f, -1.0f));
    const glm::mat4 viewLh = flipZ * fwd.viewFromWorld;
    const glm::mat4 projectionLh = fwd.clipFromView * flipZ;
    CookbookShared& g = setup->shared;
    g.pv = cookbookPerspectiveValues(projectionLh);
    g.worldFromViewLh = glm::inverse(viewLh);
    g.worldFromViewLhDouble = glm::inverse(glm::dmat4(viewLh));
    g.eyeWorld = glm::vec3(g.worldFromViewLh[3]);
    g.screenPx = glm::vec2(float(ctx.width), float(ctx.height));
    g.printedUnpack = opt.printedUnpack;
    g.vertexCpPos = opt.vertexCpPos;
    setup->worldFromView = glm::transpose(glm::mat3(fwd.viewFromWorld));  // the view is rigid
    setup->draws = planDraws(ctx.lights(), opt, viewLh, projectionLh);

    const bool reference = ctx.precision == Precision::Reference;
    // With MSAA every buffer has `samples` samples and the image is resolved last (technique.h).
    const std::uint32_t samples = ctx.sampleCount;
    const bool msaa = samples > 1;
    const std::string back = backBufferTarget(samples), backReference = referenceBufferTarget(samples);
    std::vector<std::string> created{back, "gbuffer.color", "gbuffer.normal", "gbuffer.specpow", "depth"};
    if (reference) {
        created.emplace_back("accumulation");
        created.push_back(backReference);
    }
    if (msaa) {
        created.emplace_back(gbuffer_detail::kEdgeSurfaceTarget);
        created.emplace_back(gbuffer_detail::kEdgeCoverageTarget);
        created.emplace_back(gbuffer_detail::kEdgesBuffer);
    }
    Frame frame;
    frame.add({"clear", {}, created, [setup, reference, samples, back, backReference](BufferRegistry& reg) {
                   const std::uint32_t w = setup->forward->width, h = setup->forward->height;
                   reg.create(back, {w, h, Format::R8G8B8A8_UNORM, samples}).clearColor(kDemoClearColor);
                   // "clear depth to 1, the others to black"
                   reg.create("gbuffer.color", {w, h, Format::R8G8B8A8_UNORM, samples}).clearColor(glm::vec4(0.0f));
                   reg.create("gbuffer.normal", {w, h, Format::R11G11B10_FLOAT, samples}).clearColor(glm::vec4(0.0f));
                   reg.create("gbuffer.specpow", {w, h, Format::R8G8B8A8_UNORM, samples}).clearColor(glm::vec4(0.0f));
                   reg.create("depth", {w, h, Format::D24_UNORM_S8_UINT, samples}).clearDepthStencil(true, 1.0f, true, 0);
                   if (samples > 1) gbuffer_detail::createEdgeTargets(reg, w, h, samples);
                   if (reference) {
                       reg.create("accumulation", {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(kDemoClearColor);
                       reg.create(backReference, {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(kDemoClearColor);
                   }
               }});

    Device* device = ctx.device;
    DrawStats* stats = ctx.stats;
    std::map<std::string, std::uint64_t>* variantCounts = ctx.variantCounts;
    const SceneResources* res = ctx.resources;
    const std::vector<std::string> gbuffer{"gbuffer.color", "gbuffer.normal", "gbuffer.specpow", "depth"};
    std::vector<std::string> gbufferOut = gbuffer;
    if (msaa) {
        gbufferOut.emplace_back(gbuffer_detail::kEdgeSurfaceTarget);
        gbufferOut.emplace_back(gbuffer_detail::kEdgeCoverageTarget);
    }
    frame.add({"gbuffer", gbuffer, gbufferOut, [setup, device, stats, variantCounts, res, samples](BufferRegistry& reg) {
                   RenderTargets rt;
                   rt.colors[0] = &reg.get("gbuffer.color");
                   rt.colors[1] = &reg.get("gbuffer.normal");
                   rt.colors[2] = &reg.get("gbuffer.specpow");
                   rt.depthStencil = &reg.get("depth");
                   const auto configure = [&](auto& ps) {
                       ps.worldFromView = setup->worldFromView;
                       ps.sampleCount = samples;
                   };
                   const PassState state = gbufferState(setup->options.stencil);
                   if (samples == 1) {
                       gbuffer_detail::drawOpaqueGBuffer<CookbookGBufferPS>(*setup->forward, *device, *res, rt, state, "cookbook-gbuffer",
                                                                            configure, stats, variantCounts);
                   } else {
                       gbuffer_detail::bindEdgeTargets(rt, reg, 3);
                       gbuffer_detail::drawOpaqueGBuffer<CookbookGBufferMsaaPS>(*setup->forward, *device, *res, rt, state,
                                                                                "cookbook-gbuffer", configure, stats, variantCounts);
                   }
               }});
    if (msaa) frame.add(gbuffer_detail::edgePass(device, stats, opt.edges));

    const std::vector<std::string> lightReads{"gbuffer.color", "gbuffer.normal", "gbuffer.specpow", "depth"};
    const std::string lightTarget = reference ? "accumulation" : back;
    std::vector<std::string> lightReadsAll = lightReads;
    lightReadsAll.push_back(lightTarget);
    frame.add({"lights", lightReadsAll, {lightTarget}, [setup, device, stats, variantCounts, lightTarget](BufferRegistry& reg) {
                   CookbookShared& shared = setup->shared;
                   shared.color = TargetReader(reg.get("gbuffer.color"));
                   shared.normal = TargetReader(reg.get("gbuffer.normal"));
                   shared.specPow = TargetReader(reg.get("gbuffer.specpow"));
                   shared.depth = &reg.get("depth");
                   Surface& target = reg.get(lightTarget);
                   switch (setup->forward->precision) {
                   case Precision::Reference: runLights<double, false>(*setup, *device, reg, target, stats, variantCounts); break;
                   case Precision::Fast: runLights<float, true>(*setup, *device, reg, target, stats, variantCounts); break;
                   case Precision::Exact: runLights<float, false>(*setup, *device, reg, target, stats, variantCounts); break;
                   }
               }});
    if (reference) frame.add(gbuffer_detail::presentAccumulationPass(ctx.precision, samples));
    frame.add(gbuffer_detail::forwardTransparentPass(setup->forward, ctx));
    if (msaa) frame.add(resolveBackBufferPass(samples, ctx.precision));
    return frame;
}

} // namespace tessera
