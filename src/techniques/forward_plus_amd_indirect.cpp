// forward-plus-amd's one-bounce indirect light (GPU Pro 4 ch. 5 §5.5): the "rsm" pass renders a
// reflective shadow map (Dachsbacher and Stamminger 2005) from the indirect light, the "vpl" pass
// turns it into N x N virtual point lights appended to the light table.
#include "forward_plus_amd_detail.h"

#include <tessera/raster/draw_batch.h>

namespace tessera::forward_plus_amd_detail {
namespace {

// The RSM's three targets (Dachsbacher and Stamminger 2005): world position (w = 1), unit world
// normal (w = 1), reflected flux = DiffuseTex.rgb x the light's colour x intensity (w = 1).
// PhongVS with worldFromObject as its "view": posView / normalView are world space.
struct RsmPS {
    using Varyings = PhongVaryings;
    static constexpr int kTargetCount = 3;
    const PhongShaderData<float>* material = nullptr;
    glm::vec3 lightColor{1.0f};
    void operator()(const PixelInput<PhongVaryings>& in, PixelOutput<3>& out) const {
        glm::vec4 diffuseTex = material->diffuseColor;
        if (material->diffuseTexture.bound()) diffuseTex = phong_detail::textureRule(diffuseTex, material->diffuseTexture.sample(in));
        out.target[0] = glm::vec4(in.varyings.posView, 1.0f);
        // glTF 2.0 §3.9.5: a double-sided back face seen by the light reflects along its reversed normal.
        out.target[1] = glm::vec4(hlsl::normalize(facingVaryings(in.varyings, in.isFrontFace, material->reverseBackFaceNormals).normalView), 1.0f);
        out.target[2] = glm::vec4(glm::vec3(diffuseTex) * lightColor, 1.0f);
    }
};

} // namespace

// The "rsm" pass: the opaque draw items from the indirect light (rsmView), depth LESS with
// writes into "rsm.depth" (D32_FLOAT), each material's culling, precision exact.
void drawRsm(const AmdState& st, Device& device, const SceneResources& res, BufferRegistry& reg, DrawStats* stats) {
    const std::uint32_t size = st.options.vpl.rsmSize;
    RenderTargets rt;
    rt.colors[0] = &reg.create("rsm.position", {size, size, Format::R32G32B32A32_FLOAT, 1});
    rt.colors[1] = &reg.create("rsm.normal", {size, size, Format::R32G32B32A32_FLOAT, 1});
    rt.colors[2] = &reg.create("rsm.color", {size, size, Format::R32G32B32A32_FLOAT, 1});
    for (int i = 0; i < 3; ++i) rt.colors[i]->clearColor(glm::vec4(0.0f));
    rt.depthStencil = &reg.create("rsm.depth", {size, size, Format::D32_FLOAT, 1});
    rt.depthStencil->clearDepthStencil(true, 1.0f, false, 0);
    const glm::vec3 lightColor = st.indirectLight.color * st.indirectLight.intensity;
    DrawBatch batch(device);  // every opaque item binned together (raster/draw_batch.h)
    for (const DrawItem& item : res.drawItems()) {
        const PhongMaterial material = phongFromGltf(res.material(item.material));
        if (material.isTransparent()) continue;
        DrawState ds;
        ds.viewport = Viewport{0.0f, 0.0f, float(size), float(size), 0.0f, 1.0f};
        ds.rasterizer.frontCounterClockwise = item.frontCounterClockwise;
        ds.rasterizer.cullMode = material.doubleSided ? CullMode::None : CullMode::Back;
        const PhongVS vs{st.rsm.clipFromWorld * item.worldFromObject, item.worldFromObject};
        const PrimitiveBuffer& prim = res.primitives()[item.primitive];
        const PhongShaderData<float>& data = batch.keep(makePhongShaderData<float>(material, *st.setup->textures, {}));
        batch.draw(ds, rt, std::span<const SceneVertex>(prim.vertices), prim.indices, vs, RsmPS{&data, lightColor});
    }
    batch.runInto(stats);
}

// The "vpl" pass (§5.1 step 2): N x N VPLs from the RSM, appended after the scene's lights to the
// culling spheres, the shading table and the casters (they cast no shadows); "vpl.position"
// (w = 1 valid, 0 empty texel), "vpl.direction" (w = cos of the cone), "vpl.color" (w = range).
void makeVpls(AmdState& st, BufferRegistry& reg) {
    const VplOptions& o = st.options.vpl;
    const std::vector<Vpl> vpls = vplsFromRsm(reg.get("rsm.position"), reg.get("rsm.normal"), reg.get("rsm.color"), st.rsm, o);
    std::vector<Light> lights;
    lights.reserve(vpls.size());
    for (const Vpl& v : vpls) lights.push_back(vplLight(v, o));
    const std::vector<ViewLight<float>> view = viewLights<float>(lights, st.setup->viewFromWorld);
    const std::size_t first = st.sceneLightCount, n = first + vpls.size();
    st.spheresViewLh.resize(n);
    st.table.kind.resize(first);  // a frame that runs again starts from the scene's lights
    st.table.kind.resize(n, AmdKind::None);
    st.table.points.resize(n);
    st.table.spots.resize(n);
    st.casters.resize(first);
    st.casters.resize(n);
    for (std::size_t i = 0; i < vpls.size(); ++i) convertLight(st, first + i, view[i], lights[i]);
    const std::uint32_t grid = o.grid;
    Surface& position = reg.create("vpl.position", {grid, grid, Format::R32G32B32A32_FLOAT, 1});
    Surface& direction = reg.create("vpl.direction", {grid, grid, Format::R32G32B32A32_FLOAT, 1});
    Surface& color = reg.create("vpl.color", {grid, grid, Format::R32G32B32A32_FLOAT, 1});
    const float cosCone = detCos(hlsl::radians(o.coneDeg));
    for (std::uint32_t j = 0; j < grid; ++j)
        for (std::uint32_t i = 0; i < grid; ++i) {
            const Vpl& v = vpls[std::size_t{j} * grid + i];
            const glm::vec4 values[3] = {glm::vec4(v.positionWorld, v.valid ? 1.0f : 0.0f), glm::vec4(v.directionWorld, cosCone),
                                         glm::vec4(v.color, o.range)};
            std::memcpy(position.texel(i, j), &values[0], sizeof(glm::vec4));
            std::memcpy(direction.texel(i, j), &values[1], sizeof(glm::vec4));
            std::memcpy(color.texel(i, j), &values[2], sizeof(glm::vec4));
        }
}

} // namespace tessera::forward_plus_amd_detail
