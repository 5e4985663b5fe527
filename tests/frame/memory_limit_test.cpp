// Memory limits: BufferRegistry refuses a buffer past its byte limit before allocating it, and
// estimateFrameMemory's four-probe fit predicts every technique's buffer bytes (checked against
// the bytes a real frame holds), so a render can be refused before its frame is built.
#include <doctest/doctest.h>

#include <algorithm>

#include <tessera/frame/memory_limit.h>
#include <tessera/frame/buffer_registry.h>

#include "support/room_scene.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::frame_memory_limit_test {

using namespace tessera;
using namespace tessera::test;

TEST_CASE("memory: BufferRegistry refuses a buffer past its limit before allocating it") {
    BufferRegistry registry;
    registry.setByteLimit(1000, "--memory-limit");
    registry.create("small", {10, 10, Format::R8G8B8A8_UNORM, 1});  // 400 B
    CHECK(registry.bytes() == 400);
    CHECK_THROWS_WITH_AS(registry.create("big", {20, 20, Format::R8G8B8A8_UNORM, 1}),  // 1600 B
                         "buffer 'big' (20x20, R8G8B8A8_UNORM, 1.6 KiB) would take the frame's buffers to 2.0 KiB, past the "
                         "memory limit of 1000 B (--memory-limit)",
                         MemoryLimitError);
    CHECK_FALSE(registry.contains("big"));
    CHECK(registry.bytes() == 400);
    registry.create("exact", {15, 10, Format::R8G8B8A8_UNORM, 1});  // 600 B: exactly the limit
    CHECK(registry.bytes() == 1000);
    CHECK(&registry.create("small", {10, 10, Format::R8G8B8A8_UNORM, 1}) == registry.find("small"));  // existing: no new bytes
    CHECK(registry.bytes() == 1000);
}

// The command renders each --repeat run into a cleared registry; clearing must not lift the
// limit (it once did: the runs replaced the registry with a default one, which has none).
TEST_CASE("memory: a cleared BufferRegistry holds no buffer and keeps its limit") {
    BufferRegistry registry;
    registry.setByteLimit(1000, "--memory-limit");
    registry.create("small", {10, 10, Format::R8G8B8A8_UNORM, 1});  // 400 B
    registry.clear();
    CHECK(registry.bytes() == 0);
    CHECK(registry.names().empty());
    CHECK_FALSE(registry.contains("small"));
    registry.create("exact", {25, 10, Format::R8G8B8A8_UNORM, 1});  // 1000 B: exactly the limit, allowed again
    CHECK(registry.bytes() == 1000);
    CHECK_THROWS_WITH_AS(registry.create("one more", {1, 1, Format::R8G8B8A8_UNORM, 1}),  // 4 B past it
                         "buffer 'one more' (1x1, R8G8B8A8_UNORM, 4 B) would take the frame's buffers to 1004 B, past the "
                         "memory limit of 1000 B (--memory-limit)",
                         MemoryLimitError);
}

TEST_CASE("memory: a cleared BufferRegistry reuses its buffers' storage, zeroed, and keeps at most one frame's spare") {
    const SurfaceDesc a{10, 10, Format::R8G8B8A8_UNORM, 1}, b{5, 5, Format::R32_FLOAT, 1};  // 400 B, 100 B
    BufferRegistry registry;
    Surface& first = registry.create("color", a);
    std::byte* const storage = first.bytes().data();
    first.clearColor(glm::vec4(1.0f));
    registry.create("other", b);
    registry.clear();
    CHECK(registry.spareBytes() == 500);
    CHECK(registry.bytes() == 0);
    // Frame 2: same desc under another name: the same storage, every byte zero as a new buffer's.
    Surface& again = registry.create("accumulation", a);
    CHECK(again.bytes().data() == storage);
    CHECK(std::all_of(again.bytes().begin(), again.bytes().end(), [](std::byte v) { return v == std::byte{0}; }));
    CHECK(registry.spareBytes() == 100);
    CHECK(registry.bytes() == 400);
    registry.clear();
    // The 5x5 spare was kept at the first clear and not reused by frame 2: freed now.
    CHECK(registry.spareBytes() == 400);
    registry.create("small", {2, 2, Format::R8G8B8A8_UNORM, 1});  // no spare of this desc: fresh
    CHECK(registry.spareBytes() == 400);
    registry.clear();
    CHECK(registry.spareBytes() == 16);
}

TEST_CASE("memory: a BufferRegistry's spare storage never takes it past its limit") {
    BufferRegistry registry;
    registry.setByteLimit(1000, "--memory-limit");
    registry.create("a", {10, 10, Format::R8G8B8A8_UNORM, 1});  // 400 B
    registry.clear();
    CHECK(registry.spareBytes() == 400);
    registry.create("b", {15, 10, Format::R8G8B8A8_UNORM, 1});  // 600 B: 600 + 400 spare = the limit, kept
    CHECK(registry.spareBytes() == 400);
    registry.clear();  // the 400 B spare was not reused: freed; the 600 B kept
    CHECK(registry.spareBytes() == 600);
    registry.create("c", {5, 5, Format::R8G8B8A8_UNORM, 1});  // 100 B: 100 + 600 spare fits, kept
    CHECK(registry.spareBytes() == 600);
    registry.create("d", {16, 5, Format::R8G8B8A8_UNORM, 1});  // 320 B: 420 live + 600 spare > 1000, spares freed
    CHECK(registry.spareBytes() == 0);
    CHECK(registry.bytes() == 420);
}

TEST_CASE("memory: the default limit is three quarters of what the process may use") {
    const std::uint64_t available = availableMemoryBytes();
    CHECK(available > (std::uint64_t{1} << 28));  // any machine that runs the suite has 256 MiB
    CHECK(defaultMemoryLimitBytes() == available / 4 * 3);
    CHECK(formatBytes(1536.0) == "1.5 KiB");
    CHECK(formatBytes(11.25 * 1024 * 1024 * 1024) == "11.2 GiB");  // %.1f of 11.25: round-half-even in printf
}

TEST_CASE("memory: estimateFrameMemory predicts each technique's buffer bytes") {
    // 96 lights: beyond the probes' 32 and 64, so the light terms are extrapolated too.
    std::vector<Light> lights;
    for (int i = 0; i < 96; ++i)
        lights.push_back(makeLight(i % 2 ? LightType::Point : LightType::Spot, {-8.0f + 0.17f * float(i), 1.0f, -4.0f + 0.09f * float(i)},
                                   {0.1f, -1.0f, 0.0f}, 2.5f, {0.5f, 0.4f, 0.3f}, 30.0f));
    const TestScene t = makeScene(lights);
    const SceneResources resources(t.scene, {}, TexturePolicy::AllLinear);
    for (const TechniqueInfo& info : techniques()) {
        if (!info.build) continue;
        for (const std::uint32_t samples : {1u, 4u}) {
            if (samples > 1 && (!info.msaa || info.id == std::string_view("preview"))) continue;
            CAPTURE(info.id);
            CAPTURE(samples);
            Device device(DeviceConfig{32, 2});
            TechniqueContext ctx;
            ctx.device = &device;
            ctx.resources = &resources;
            ctx.camera = t.camera;
            ctx.width = 192;  // px: not a probe size, 3 x 2 probes of 64 x 64
            ctx.height = 128;
            ctx.sampleCount = samples;
            ctx.sceneFile = "memory.json";
            const FrameMemoryEstimate e = estimateFrameMemory(info.id, ctx, ctx.sceneFile);
            BufferRegistry registry;
            buildTechnique(info.id, ctx, ctx.sceneFile).run(registry);
            const double actual = double(registry.bytes());
            MESSAGE(info.id << " x" << samples << ": estimate " << e.bytes << " B, actual " << actual << " B");
            // Never short; over by at most 10% (tile light lists depend on where the lights fall
            // in the probes' tiles) plus the spare rows of 16384 x 4 B given to each structured
            // buffer (at most 4 per technique here: 256 KiB).
            CHECK(e.bytes >= actual);
            CHECK(e.bytes <= 1.10 * actual + 4.0 * 65536.0);
        }
    }
}

TEST_CASE("memory: a 16384x16384 deferred frame with float G-buffer targets is estimated above 11 GB") {
    // Its buffers per pixel: back buffer R8G8B8A8 4 B; accumulation and gbuffer.diffuse,
    // .specular, .normal R32G32B32A32_FLOAT 4 x 16 B; depth and depth.copy D32_FLOAT_S8X24 2 x 8 B:
    // 84 B x 2^28 px = 22.5 GB, past the 11 GB the frame reached before std::bad_alloc.
    // Estimated without building it.
    const TestScene t = makeScene(defaultLights());
    const SceneResources resources(t.scene, {}, TexturePolicy::AllLinear);
    Device device(DeviceConfig{32, 2});
    TechniqueContext ctx;
    ctx.device = &device;
    ctx.resources = &resources;
    ctx.camera = t.camera;
    ctx.width = 16384;
    ctx.height = 16384;
    ctx.options = {{"gbuffer", "float"}};
    ctx.sceneFile = "memory.json";
    const FrameMemoryEstimate e = estimateFrameMemory("deferred", ctx, ctx.sceneFile);
    MESSAGE("deferred 16384^2 gbuffer float: " << formatBytes(e.bytes) << ", " << e.bytesPerPixel << " B/px");
    CHECK(e.bytesPerPixel == doctest::Approx(84.0));
    CHECK(e.bytes == doctest::Approx(84.0 * 16384.0 * 16384.0).epsilon(1e-4));
}

} // namespace tessera_test::frame_memory_limit_test
