// Draws one triangle through an installed tessera and checks a covered and an uncovered pixel.
#include <cstdio>
#include <span>

#include <tessera/raster/device.h>

struct Vertex {
    glm::vec4 posClip;
};
struct Varyings {
    float unused;
};
struct VS {
    using Varyings = ::Varyings;
    tessera::VertexOutput<Varyings> operator()(const Vertex& v) const { return {v.posClip, {0.0f}}; }
};
struct PS {
    using Varyings = ::Varyings;
    static constexpr int kTargetCount = 1;
    void operator()(const tessera::PixelInput<Varyings>&, tessera::PixelOutput<1>& out) const { out.target[0] = glm::vec4(1.0f); }
};

int main() {
    tessera::Surface target(tessera::SurfaceDesc{8, 8, tessera::Format::R32_FLOAT, 1});
    tessera::Device device(tessera::DeviceConfig{8, 1});
    tessera::DrawState state;
    state.viewport = tessera::fullViewport(target);
    state.rasterizer.cullMode = tessera::CullMode::None;
    tessera::RenderTargets targets;
    targets.colors[0] = &target;
    // Covers the top-left half of the target (window (0,0), (8,0), (0,8)).
    const Vertex vertices[] = {{{-1, 1, 0.5f, 1}}, {{1, 1, 0.5f, 1}}, {{-1, -1, 0.5f, 1}}};
    device.draw(state, targets, std::span<const Vertex>(vertices), {}, VS{}, PS{});
    const bool ok = target.load(1, 1).x == 1.0f && target.load(6, 6).x == 0.0f;
    std::printf("consumer: %s\n", ok ? "ok" : "wrong pixels");
    return ok ? 0 : 1;
}
