// A downstream program built against an installed tessera (tests/package): draws through the
// public pipeline API and evaluates the header-only math (plane construction, 3dgep tile
// frustums, the rasteriser's interpolation, a shader's arithmetic), writing every result's bits
// to argv[1]. run_consumer.cmake builds it with the defaults and with -O3 -march=x86-64-v3 and
// requires identical files: the exported target must carry the flags the bits depend on.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <span>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <tessera/culling/plane.h>
#include <tessera/culling/tile_frustum.h>
#include <tessera/raster/device.h>

namespace {

struct Vertex {
    glm::vec4 posClip;
    glm::vec3 normalView;
};
struct Varyings {
    glm::vec3 normalView;
};
struct VS {
    using Varyings = ::Varyings;
    glm::mat4 clipFromObject;
    tessera::VertexOutput<Varyings> operator()(const Vertex& v) const { return {clipFromObject * v.posClip, {v.normalView}}; }
};
// Lambert and Blinn-like terms: products summed, the pattern a compiler fuses into FMAs when allowed.
struct PS {
    using Varyings = ::Varyings;
    static constexpr int kTargetCount = 1;
    void operator()(const tessera::PixelInput<Varyings>& in, tessera::PixelOutput<1>& out) const {
        const glm::vec3 n = tessera::cullmath::normalize(in.varyings.normalView);
        const glm::vec3 l(0.267261f, 0.534522f, -0.801784f);
        const float nDotL = n.x * l.x + n.y * l.y + n.z * l.z;
        out.target[0] = glm::vec4(nDotL, n.x * in.posWindow.x + n.y * in.posWindow.y, in.posWindow.z * 3.1f + 0.7f, in.posWindow.w);
    }
};

// A fixed pseudo-random sequence (LCG, Numerical Recipes constants) of floats in [-8, 8).
struct Sequence {
    std::uint32_t state = 12345u;
    float next() {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24) * 16.0f - 8.0f;
    }
};

void put(std::vector<std::uint32_t>& bits, float v) {
    std::uint32_t u;
    std::memcpy(&u, &v, sizeof u);
    bits.push_back(u);
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: consumer OUT.bin\n");
        return 2;
    }
    std::vector<std::uint32_t> bits;

    // Plane construction through three points (3dgep ComputePlane).
    Sequence seq;
    for (int i = 0; i < 64; ++i) {
        const glm::vec3 p0(seq.next(), seq.next(), seq.next()), p1(seq.next(), seq.next(), seq.next()),
            p2(seq.next(), seq.next(), seq.next());
        const tessera::Plane plane = tessera::computePlane(p0, p1, p2);
        put(bits, plane.N.x), put(bits, plane.N.y), put(bits, plane.N.z), put(bits, plane.d);
    }

    // Every 3dgep grid frustum of a 1280x720 screen with 16 px tiles.
    const glm::mat4 clipFromView = glm::perspective(glm::radians(45.0f), 1280.0f / 720.0f, 0.1f, 1000.0f);
    const glm::mat4 viewFromClip = glm::inverse(clipFromView);
    const glm::uvec2 tiles = tessera::tileCount({1280, 720}, 16);
    for (std::uint32_t y = 0; y < tiles.y; ++y)
        for (std::uint32_t x = 0; x < tiles.x; ++x) {
            const tessera::Frustum f = tessera::gridFrustum3dgep({x, y}, 16, {1280.0f, 720.0f}, viewFromClip);
            for (const tessera::Plane& p : f.planes) put(bits, p.N.x), put(bits, p.N.y), put(bits, p.N.z), put(bits, p.d);
        }

    // A rendered float target: perspective-correct interpolation and the pixel shader above.
    tessera::Surface target(tessera::SurfaceDesc{64, 64, tessera::Format::R32G32B32A32_FLOAT, 1});
    tessera::Device device(tessera::DeviceConfig{16, 2});
    tessera::DrawState state;
    state.viewport = tessera::fullViewport(target);
    state.rasterizer.cullMode = tessera::CullMode::None;
    tessera::RenderTargets targets;
    targets.colors[0] = &target;
    std::vector<Vertex> vertices;
    for (int i = 0; i < 24; ++i)
        vertices.push_back({{seq.next() * 0.2f, seq.next() * 0.2f, -3.0f + seq.next() * 0.1f, 1.0f},
                            {seq.next(), seq.next(), seq.next()}});
    const glm::mat4 clipFromObject = glm::perspective(glm::radians(60.0f), 1.0f, 0.5f, 10.0f);
    device.draw(state, targets, std::span<const Vertex>(vertices), {}, VS{clipFromObject}, PS{});
    std::uint32_t covered = 0;
    for (std::uint32_t y = 0; y < 64; ++y)
        for (std::uint32_t x = 0; x < 64; ++x) {
            const glm::vec4 v = target.load(x, y);
            covered += v != glm::vec4(0.0f);
            for (int c = 0; c < 4; ++c) put(bits, v[c]);
        }

    std::FILE* out = std::fopen(argv[1], "wb");
    if (!out || std::fwrite(bits.data(), sizeof(std::uint32_t), bits.size(), out) != bits.size() || std::fclose(out) != 0) {
        std::fprintf(stderr, "consumer: cannot write %s\n", argv[1]);
        return 1;
    }
    std::printf("consumer: %zu values, %u of 4096 pixels covered\n", bits.size(), covered);
    // The draw must reach the target, or the comparison would compare clear colours.
    return covered > 256 ? 0 : 1;
}
