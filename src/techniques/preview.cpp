// The `preview` technique: head-lit base colour for inspecting loaded scenes (camera, geometry,
// winding, textures, mips, alpha modes) before any light model is involved. Two passes after
// the clear: opaque + mask, then blend.
#include <tessera/techniques/preview.h>

#include <tessera/buffers/conversion.h>
#include <tessera/raster/draw_batch.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace tessera {
namespace {

struct PreviewVaryings {
    glm::vec3 posWorld;
    glm::vec3 normalWorld;
    glm::vec2 uv0;
    glm::vec2 uv1;
    static constexpr std::array<VaryingField, 4> kFields{{{"posWorld", 3}, {"normalWorld", 3}, {"uv0", 2}, {"uv1", 2}}};
};

struct PreviewVS {
    using Varyings = PreviewVaryings;
    glm::mat4 clipFromObject;
    glm::mat4 worldFromObject;
    glm::mat3 normalWorldFromObject;
    VertexOutput<PreviewVaryings> operator()(const SceneVertex& v) const {
        const glm::vec4 posWorld = worldFromObject * glm::vec4(v.posObject, 1.0f);
        return {clipFromObject * glm::vec4(v.posObject, 1.0f),
                {glm::vec3(posWorld), normalWorldFromObject * v.normalObject, v.uv0, v.uv1}};
    }
};

// One bound texture: null `texture` = slot empty.
struct BoundTexture {
    const Texture2D* texture = nullptr;
    const SamplerState* sampler = nullptr;
    int texCoord = 0;
    glm::vec4 sample(const PixelInput<PreviewVaryings>& in) const {
        const bool second = texCoord == 1;
        return texture->sample(*sampler, second ? in.varyings.uv1 : in.varyings.uv0, second ? in.ddx.uv1 : in.ddx.uv0,
                               second ? in.ddy.uv1 : in.ddy.uv0);
    }
};

// T = float: exact and fast; T = double: reference (the head light and sums in double, written
// to the sRGB back buffer and, clamped as that target clamps, to the float copy: kTargets = 2).
template <bool kMask, class T = float, int kTargets = 1>
struct PreviewPS {
    using Varyings = PreviewVaryings;
    static constexpr int kTargetCount = kTargets;
    static constexpr bool kMayDiscard = kMask;
    glm::vec4 baseColorFactor;
    BoundTexture baseColor;
    glm::vec3 emissiveFactor;
    BoundTexture emissive;
    float alphaCutoff;
    bool opaque;  // OPAQUE: alpha forced to 1 (glTF 2.0 §3.9.4)
    glm::vec3 eyeWorld;
    void operator()(const PixelInput<PreviewVaryings>& in, PixelOutput<kTargets>& out) const {
        using V3 = glm::vec<3, T, glm::defaultp>;
        glm::vec4 color = baseColorFactor;
        if (baseColor.texture) color *= baseColor.sample(in);
        if constexpr (kMask) {
            if (color.w < alphaCutoff) {
                out.discard();
                return;
            }
        }
        const V3 n = glm::normalize(V3(in.varyings.normalWorld));
        const V3 v = glm::normalize(V3(eyeWorld) - V3(in.varyings.posWorld));
        const T headLight = T(0.2) + T(0.8) * glm::abs(glm::dot(n, v));
        V3 rgb = V3(glm::vec3(color)) * headLight;
        glm::vec3 glow = emissiveFactor;
        if (emissive.texture) glow *= glm::vec3(emissive.sample(in));
        rgb += V3(glow);
        out.target[0] = glm::vec4(glm::vec3(rgb), opaque || kMask ? 1.0f : color.w);
        if constexpr (kTargets == 2) out.target[1] = convert::clampUnorm(out.target[0]);
    }
};

BoundTexture bind(const SceneResources& res, const TextureRef& ref, TexelEncoding enc) {
    return {res.texture(ref, enc), &res.sampler(ref), ref.texCoord};
}

} // namespace

glm::mat4 projectionD3D(const Camera& camera, float aspect) {
    const float a = camera.aspect > 0.0f ? camera.aspect : aspect;
    if (camera.projection == ProjectionKind::Orthographic)
        return glm::orthoRH_ZO(-camera.xMag, camera.xMag, -camera.yMag, camera.yMag, camera.nearZ, camera.farZ);
    if (!std::isfinite(camera.farZ)) {
        // perspectiveRH_ZO with far -> infinity (glm 0.9.9 has no ZO infinite form): z_clip = -z_view - near,
        // w_clip = -z_view, so depth = 1 + near / z_view runs from 0 at the near plane towards 1.
        const float f = 1.0f / std::tan(glm::radians(camera.fovYDeg) * 0.5f);
        glm::mat4 p(0.0f);
        p[0][0] = f / a;
        p[1][1] = f;
        p[2][2] = -1.0f;
        p[2][3] = -1.0f;
        p[3][2] = -camera.nearZ;
        return p;
    }
    return glm::perspectiveRH_ZO(glm::radians(camera.fovYDeg), a, camera.nearZ, camera.farZ);
}

Frame buildPreview(const TechniqueContext& ctx) {
    Frame frame;
    const std::uint32_t w = ctx.width, h = ctx.height;
    const glm::mat4 viewFromWorld = ctx.camera.viewFromWorld();
    const glm::mat4 clipFromWorld = projectionD3D(ctx.camera, float(w) / float(h)) * viewFromWorld;
    const glm::vec3 eyeWorld = glm::vec3(glm::inverse(viewFromWorld)[3]);
    const SceneResources& res = *ctx.resources;
    Device& device = *ctx.device;
    DrawStats* stats = ctx.stats;

    const Precision precision = ctx.precision;
    const bool reference = precision == Precision::Reference;
    // With MSAA the multisampled targets, resolved last (technique.h).
    const std::uint32_t samples = ctx.sampleCount;
    const std::string back = backBufferTarget(samples), backReference = referenceBufferTarget(samples);
    const auto targets = [&](std::vector<std::string> names) {
        return withBackBufferTargets(withReferenceBuffer(std::move(names), precision), samples);
    };
    frame.add({"clear", {}, targets({std::string(kBackBufferName), "depth"}), [w, h, reference, samples, back, backReference](BufferRegistry& reg) {
                   constexpr glm::vec4 kClear{0.02f, 0.02f, 0.025f, 1.0f};
                   reg.create(back, {w, h, Format::R8G8B8A8_UNORM_SRGB, samples}).clearColor(kClear);
                   if (reference) reg.create(backReference, {w, h, Format::R32G32B32A32_FLOAT, samples}).clearColor(kClear);
                   reg.create("depth", {w, h, Format::D32_FLOAT, samples}).clearDepthStencil(true, 1.0f, false, 0);
               }});
    auto drawPass = [=, &res, &device](bool blendPass) {
        return [=, &res, &device](BufferRegistry& reg) {
            RenderTargets rt;
            rt.colors[0] = &reg.get(back);
            if (reference) rt.colors[1] = &reg.get(backReference);
            rt.depthStencil = &reg.get("depth");
            DrawBatch batch(device);  // the pass's draws binned together (raster/draw_batch.h)
            for (const DrawItem& item : res.drawItems()) {
                const Material& m = res.material(item.material);
                if ((m.alphaMode == AlphaMode::Blend) != blendPass) continue;
                const PrimitiveBuffer& prim = res.primitives()[item.primitive];
                DrawState st;
                st.viewport = Viewport{0, 0, float(w), float(h), 0, 1};
                st.rasterizer.cullMode = m.doubleSided ? CullMode::None : CullMode::Back;
                st.rasterizer.frontCounterClockwise = item.frontCounterClockwise;
                st.precision = precision;
                if (blendPass) {
                    st.depthStencil.depthWriteEnable = false;
                    st.blend.renderTarget[0] = kAlphaBlend;
                }
                const PreviewVS vs{clipFromWorld * item.worldFromObject, item.worldFromObject, item.normalWorldFromObject};
                auto draw = [&](const auto& ps) {
                    batch.draw(st, rt, std::span<const SceneVertex>(prim.vertices), prim.indices, vs, ps);
                };
                const BoundTexture base = bind(res, m.baseColorTexture, TexelEncoding::Srgb);
                const BoundTexture glow = bind(res, m.emissiveTexture, TexelEncoding::Srgb);
                const bool opaque = m.alphaMode == AlphaMode::Opaque;
                const bool mask = m.alphaMode == AlphaMode::Mask;
                if (reference) {
                    if (mask) draw(PreviewPS<true, double, 2>{m.baseColorFactor, base, m.emissiveFactor, glow, m.alphaCutoff, opaque, eyeWorld});
                    else draw(PreviewPS<false, double, 2>{m.baseColorFactor, base, m.emissiveFactor, glow, m.alphaCutoff, opaque, eyeWorld});
                } else {
                    if (mask) draw(PreviewPS<true>{m.baseColorFactor, base, m.emissiveFactor, glow, m.alphaCutoff, opaque, eyeWorld});
                    else draw(PreviewPS<false>{m.baseColorFactor, base, m.emissiveFactor, glow, m.alphaCutoff, opaque, eyeWorld});
                }
            }
            batch.runInto(stats);
        };
    };
    const std::string backName(kBackBufferName);
    frame.add({"opaque", targets({backName, "depth"}), targets({backName, "depth"}), drawPass(false)});
    frame.add({"transparent", targets({backName, "depth"}), targets({backName}), drawPass(true)});
    if (samples > 1) frame.add(resolveBackBufferPass(samples, precision));
    return frame;
}

} // namespace tessera
