// Built-in scene: view-space Lambert + ambient shading of a ground plane and three cubes
// under one directional light, then a translucent pane blended with SRC_ALPHA/INV_SRC_ALPHA.
// Geometry is generated here; the camera is a D3D-style left-handed perspective (z in 0..1).
#include <tessera/techniques/builtin_scene.h>

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
};

struct SceneVS {
    using Varyings = LitVaryings;
    glm::mat4 view, viewProj;
    VertexOutput<LitVaryings> operator()(const SceneVertex& v) const {
        const glm::vec3 nView = glm::vec3(view * glm::vec4(v.normalWorld, 0.0f));
        return {viewProj * glm::vec4(v.posWorld, 1.0f), {nView, v.color}};
    }
};

struct LambertPS {
    using Varyings = LitVaryings;
    static constexpr int kTargetCount = 1;
    glm::vec3 lightDirView;  // towards the light, normalized
    void operator()(const PixelInput<LitVaryings>& in, PixelOutput<1>& out) const {
        const glm::vec3 n = glm::normalize(in.varyings.normalView);
        const float diffuse = glm::max(glm::dot(n, lightDirView), 0.0f);
        const glm::vec3 rgb = glm::vec3(in.varyings.color) * (0.25f + 0.75f * diffuse);
        out.target[0] = glm::vec4(rgb, in.varyings.color.w);
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
    const LambertPS ps{glm::normalize(glm::vec3(view * glm::vec4(glm::normalize(glm::vec3(-0.4f, 1.0f, -0.6f)), 0.0f)))};
    const bool msaa = o.sampleCount > 1;
    const std::string colorName = msaa ? "backbuffer.msaa" : "backbuffer";

    frame.add({"clear", {}, {colorName, "depth"}, [=](BufferRegistry& reg) {
                   reg.create(colorName, {o.width, o.height, Format::R8G8B8A8_UNORM, o.sampleCount})
                       .clearColor(glm::vec4(0.08f, 0.09f, 0.12f, 1.0f));
                   reg.create("depth", {o.width, o.height, Format::D24_UNORM_S8_UINT, o.sampleCount})
                       .clearDepthStencil(true, 1.0f, true, 0);
               }});
    frame.add({"opaque", {colorName, "depth"}, {colorName, "depth"}, [=, &device, &stats](BufferRegistry& reg) {
                   std::vector<SceneVertex> verts;
                   addQuad(verts, {-6, 0, -6}, {-6, 0, 6}, {6, 0, 6}, {6, 0, -6}, {0, 1, 0}, {0.55f, 0.55f, 0.5f, 1});
                   addCube(verts, {-1.6f, 0.65f, 0.4f}, 0.6f, {0.85f, 0.25f, 0.2f, 1});
                   addCube(verts, {0.3f, 0.95f, 1.4f}, 0.9f, {0.2f, 0.55f, 0.85f, 1});
                   addCube(verts, {1.5f, 0.45f, -0.9f}, 0.4f, {0.3f, 0.75f, 0.3f, 1});
                   DrawState st;
                   st.viewport = Viewport{0, 0, float(o.width), float(o.height), 0, 1};
                   RenderTargets rt;
                   rt.colors[0] = &reg.get(colorName);
                   rt.depthStencil = &reg.get("depth");
                   stats += device.draw(st, rt, std::span<const SceneVertex>(verts), {}, vs, ps);
               }});
    frame.add({"transparent", {colorName, "depth"}, {colorName}, [=, &device, &stats](BufferRegistry& reg) {
                   std::vector<SceneVertex> verts;
                   addQuad(verts, {-2.5f, 0.0f, -1.2f}, {-2.5f, 2.2f, -1.2f}, {0.8f, 2.2f, -1.2f}, {0.8f, 0.0f, -1.2f},
                           {0, 0, -1}, {0.95f, 0.85f, 0.3f, 0.45f});
                   DrawState st;
                   st.viewport = Viewport{0, 0, float(o.width), float(o.height), 0, 1};
                   st.rasterizer.cullMode = CullMode::None;
                   st.depthStencil.depthWriteEnable = false;
                   st.blend.renderTarget[0] = kAlphaBlend;
                   RenderTargets rt;
                   rt.colors[0] = &reg.get(colorName);
                   rt.depthStencil = &reg.get("depth");
                   stats += device.draw(st, rt, std::span<const SceneVertex>(verts), {}, vs, ps);
               }});
    if (msaa) {
        frame.add({"resolve", {colorName}, {"backbuffer"}, [=](BufferRegistry& reg) {
                       Surface resolved = reg.get(colorName).resolve(Format::R8G8B8A8_UNORM);
                       Surface& out = reg.create("backbuffer", resolved.desc());
                       out = std::move(resolved);
                   }});
    }
    return frame;
}

} // namespace tessera
