// Built-in scene: view-space Lambert + ambient shading of a ground plane and three cubes
// under one directional light, then a translucent pane blended with SRC_ALPHA/INV_SRC_ALPHA.
// Geometry is generated here; the camera is a D3D-style left-handed perspective (z in 0..1).
#include <tessera/techniques/builtin_scene.h>

#include <tessera/buffers/conversion.h>

#include <array>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

namespace tessera {
namespace {

struct SceneVertex {
    glm::vec3 posWorld{0.0f};
    glm::vec3 normalWorld{0.0f, 1.0f, 0.0f};
    glm::vec4 color{1.0f};
};

struct LitVaryings {
    glm::vec3 normalView;
    glm::vec4 color;
    static constexpr std::array<VaryingField, 2> kFields{{{"normalView", 3}, {"color", 4}}};
};

struct SceneVS {
    using Varyings = LitVaryings;
    glm::mat4 view, viewProj;
    VertexOutput<LitVaryings> operator()(const SceneVertex& v) const {
        const glm::vec3 nView = glm::vec3(view * glm::vec4(v.normalWorld, 0.0f));
        return {viewProj * glm::vec4(v.posWorld, 1.0f), {nView, v.color}};
    }
};

// T = float: exact and fast; T = double: reference, written to both targets (the back buffer
// and its float copy).
template <class T, int kTargets>
struct LambertPS {
    using Varyings = LitVaryings;
    static constexpr int kTargetCount = kTargets;
    glm::vec3 lightDirView;  // towards the light, normalized
    void operator()(const PixelInput<LitVaryings>& in, PixelOutput<kTargets>& out) const {
        using V3 = glm::vec<3, T, glm::defaultp>;
        const V3 n = glm::normalize(V3(in.varyings.normalView));
        const T diffuse = glm::max(glm::dot(n, V3(lightDirView)), T(0));
        const V3 rgb = V3(glm::vec3(in.varyings.color)) * (T(0.25) + T(0.75) * diffuse);
        out.target[0] = glm::vec4(glm::vec3(rgb), in.varyings.color.w);
        if constexpr (kTargets == 2) out.target[1] = convert::clampUnorm(out.target[0]);  // as the UNORM target clamps
    }
};

void addQuad(std::vector<SceneVertex>& v, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 n, glm::vec4 col) {
    // Two triangles a-b-c, a-c-d, made clockwise seen from the side `n` points to (D3D front
    // faces): in a left-handed frame that means cross(b - a, c - a) points along n.
    if (glm::dot(glm::cross(b - a, c - a), n) < 0.0f) std::swap(b, d);
    for (const glm::vec3& p : {a, b, c, a, c, d}) v.push_back({p, n, col});
}

void addCube(std::vector<SceneVertex>& v, glm::vec3 centre, float half, glm::vec4 col) {
    const glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int axis = 0; axis < 3; ++axis)
        for (const float sign : {1.0f, -1.0f}) {
            const glm::vec3 n = axes[axis] * sign;
            const glm::vec3 u = axes[(axis + 1) % 3] * half, w = axes[(axis + 2) % 3] * half;
            const glm::vec3 f = centre + n * half;
            addQuad(v, f - u - w, f - u + w, f + u + w, f + u - w, n, col);
        }
}

} // namespace

Frame buildBuiltinScene(Device& device, const BuiltinSceneOptions& o, DrawStats& stats) {
    Frame frame;
    const float aspect = float(o.width) / float(o.height);
    const glm::mat4 view = glm::lookAtLH(glm::vec3(4.5f, 3.5f, -6.0f), glm::vec3(0.0f, 0.6f, 0.0f), glm::vec3(0, 1, 0));
    const glm::mat4 proj = glm::perspectiveLH_ZO(glm::radians(45.0f), aspect, 0.1f, 100.0f);
    const SceneVS vs{view, proj * view};
    const glm::vec3 lightDirView =
        glm::normalize(glm::vec3(view * glm::vec4(glm::normalize(glm::vec3(-0.4f, 1.0f, -0.6f)), 0.0f)));
    const bool msaa = o.sampleCount > 1;
    const bool reference = o.precision == Precision::Reference;
    const std::string colorName = msaa ? "backbuffer.msaa" : "backbuffer";
    const std::string referenceName = msaa ? "backbuffer.reference.msaa" : "backbuffer.reference";
    const std::vector<std::string> colors = reference ? std::vector<std::string>{colorName, referenceName}
                                                      : std::vector<std::string>{colorName};
    std::vector<std::string> colorsDepth = colors;
    colorsDepth.emplace_back("depth");
    constexpr glm::vec4 kClear{0.08f, 0.09f, 0.12f, 1.0f};
    const auto draw = [&device, &stats, colorName, referenceName, reference, lightDirView, precision = o.precision](
                          BufferRegistry& reg, const DrawState& state, const std::vector<SceneVertex>& verts, const SceneVS& shader) {
        DrawState st = state;
        st.precision = precision;
        RenderTargets rt;
        rt.colors[0] = &reg.get(colorName);
        rt.depthStencil = &reg.get("depth");
        if (reference) {
            rt.colors[1] = &reg.get(referenceName);
            stats += device.draw(st, rt, std::span<const SceneVertex>(verts), {}, shader, LambertPS<double, 2>{lightDirView});
        } else {
            stats += device.draw(st, rt, std::span<const SceneVertex>(verts), {}, shader, LambertPS<float, 1>{lightDirView});
        }
    };

    frame.add({"clear", {}, colorsDepth, [=](BufferRegistry& reg) {
                   reg.create(colorName, {o.width, o.height, Format::R8G8B8A8_UNORM, o.sampleCount}).clearColor(kClear);
                   if (reference)
                       reg.create(referenceName, {o.width, o.height, Format::R32G32B32A32_FLOAT, o.sampleCount}).clearColor(kClear);
                   reg.create("depth", {o.width, o.height, Format::D24_UNORM_S8_UINT, o.sampleCount})
                       .clearDepthStencil(true, 1.0f, true, 0);
               }});
    frame.add({"opaque", colorsDepth, colorsDepth, [=](BufferRegistry& reg) {
                   std::vector<SceneVertex> verts;
                   addQuad(verts, {-6, 0, -6}, {-6, 0, 6}, {6, 0, 6}, {6, 0, -6}, {0, 1, 0}, {0.55f, 0.55f, 0.5f, 1});
                   addCube(verts, {-1.6f, 0.65f, 0.4f}, 0.6f, {0.85f, 0.25f, 0.2f, 1});
                   addCube(verts, {0.3f, 0.95f, 1.4f}, 0.9f, {0.2f, 0.55f, 0.85f, 1});
                   addCube(verts, {1.5f, 0.45f, -0.9f}, 0.4f, {0.3f, 0.75f, 0.3f, 1});
                   DrawState st;
                   st.viewport = Viewport{0, 0, float(o.width), float(o.height), 0, 1};
                   draw(reg, st, verts, vs);
               }});
    frame.add({"transparent", colorsDepth, colors, [=](BufferRegistry& reg) {
                   std::vector<SceneVertex> verts;
                   addQuad(verts, {-2.5f, 0.0f, -1.2f}, {-2.5f, 2.2f, -1.2f}, {0.8f, 2.2f, -1.2f}, {0.8f, 0.0f, -1.2f},
                           {0, 0, -1}, {0.95f, 0.85f, 0.3f, 0.45f});
                   DrawState st;
                   st.viewport = Viewport{0, 0, float(o.width), float(o.height), 0, 1};
                   st.rasterizer.cullMode = CullMode::None;
                   st.depthStencil.depthWriteEnable = false;
                   st.blend.renderTarget[0] = kAlphaBlend;
                   draw(reg, st, verts, vs);
               }});
    if (msaa) {
        std::vector<std::string> resolved{"backbuffer"};
        if (reference) resolved.emplace_back("backbuffer.reference");
        frame.add({"resolve", colors, resolved, [=](BufferRegistry& reg) {
                       Surface back = reg.get(colorName).resolve(Format::R8G8B8A8_UNORM);
                       Surface& out = reg.create("backbuffer", back.desc());
                       out = std::move(back);
                       if (reference) {
                           Surface ref = reg.get(referenceName).resolve(Format::R32G32B32A32_FLOAT);
                           Surface& outRef = reg.create("backbuffer.reference", ref.desc());
                           outRef = std::move(ref);
                       }
                   }});
    }
    return frame;
}

} // namespace tessera
