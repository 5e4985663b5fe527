// The bundled-scene helpers compiled once for every test executable: the scene list (checked
// non-empty) and the opaque shading points, whose draw instantiates the rasteriser for the Phong
// varyings here rather than in each test that uses it.
#include "support/bundled_scene.h"

namespace tessera::test {
namespace {

struct ShadingPointPS {
    using Varyings = PhongVaryings;
    static constexpr int kTargetCount = 1;
    void operator()(const PixelInput<PhongVaryings>& in, PixelOutput<1>& out) const {
        out.target[0] = glm::vec4(in.varyings.posView, in.posWindow.z);
    }
};

} // namespace

std::vector<std::string> bundledSceneNames() {
    std::vector<std::string> names;
    const std::filesystem::path dir = std::filesystem::path(TESSERA_SOURCE_DIR) / "scenes";
    for (const auto& entry : std::filesystem::directory_iterator(dir))
        if (entry.path().extension() == ".json" && entry.path().filename() != "scene.schema.json")
            names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    for (const char* expected : {"default", "sponza-large-lights", "sponza-small-lights"})
        REQUIRE_MESSAGE(std::find(names.begin(), names.end(), expected) != names.end(),
                        "bundled scene '" << expected << "' missing from " << dir.string());
    return names;
}

Surface opaqueShadingPoints(const SceneResources& res, const ForwardPassSetup& setup, Device& device,
                            std::uint32_t width, std::uint32_t height) {
    Surface position({width, height, Format::R32G32B32A32_FLOAT, 1});
    position.clearColor(glm::vec4(0.0f, 0.0f, 0.0f, -1.0f));
    Surface depth({width, height, Format::D24_UNORM_S8_UINT, 1});
    depth.clearDepthStencil(true, 1.0f, true, 0);
    RenderTargets rt;
    rt.colors[0] = &position;
    rt.depthStencil = &depth;
    for (const DrawItem& item : res.drawItems()) {
        const PhongMaterial material = phongFromGltf(res.material(item.material));
        if (material.isTransparent()) continue;
        DrawState st;
        st.viewport = Viewport{0.0f, 0.0f, float(width), float(height), 0.0f, 1.0f};
        st.rasterizer.frontCounterClockwise = item.frontCounterClockwise;
        st.rasterizer.cullMode = material.doubleSided ? CullMode::None : CullMode::Back;
        const glm::mat4 viewFromObject = setup.viewFromWorld * item.worldFromObject;
        const PhongVS vs{setup.clipFromView * viewFromObject, viewFromObject};
        const PrimitiveBuffer& prim = res.primitives()[item.primitive];
        device.draw(st, rt, std::span<const SceneVertex>(prim.vertices), prim.indices, vs, ShadingPointPS{});
    }
    return position;
}

} // namespace tessera::test
