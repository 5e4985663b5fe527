// Image output: every surface format round-trips through its lossless file type (read back with
// OpenImageIO and compared code by code), EXR carries the format's channels by name, half EXR
// rounds as binary16 does, and refused pairings or failed writes leave no file behind.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>

#include <tessera/io/image_writer.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::io_image_writer_test {

using namespace tessera;
namespace fs = std::filesystem;

namespace {

// One folder per test process: ctest runs these cases as parallel processes, and a shared folder
// let one case see another's temporary ".partial" file (noPartialFiles).
fs::path scratch(const std::string& name) {
    const fs::path dir = fs::path(TESSERA_TEST_OUTPUT_DIR) / ("image-writer-test-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir / name;
}

// A surface whose texels run through many distinct codes: value of texel i = (i * 37 mod 251) / 250.
Surface rampSurface(Format format, std::uint32_t w = 17, std::uint32_t h = 9) {
    Surface s(SurfaceDesc{w, h, format, 1});
    for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) {
            const float i = float(y * w + x);
            const auto v = [&](float k) { return float(int(i * 37.0f + k) % 251) / 250.0f; };
            s.store(x, y, 0, glm::vec4(v(0), v(60), v(120), v(180)) * (formatInfo(format).kind == FormatKind::Snorm ? -1.0f : 1.0f));
        }
    return s;
}

OIIO::ImageBuf readBack(const fs::path& path) {
    OIIO::ImageBuf buf(path.string());
    REQUIRE(buf.read(0, 0, true, OIIO::TypeDesc::FLOAT));
    return buf;
}

bool noPartialFiles() {
    for (const auto& e : fs::directory_iterator(scratch("x").parent_path()))
        if (e.path().string().find(".partial") != std::string::npos) return false;
    return true;
}

} // namespace

TEST_CASE("float formats written as float EXR load back to the same shader-visible values") {
    for (const Format f : {Format::R32_FLOAT, Format::R16G16_SNORM, Format::R11G11B10_FLOAT, Format::R16G16B16A16_FLOAT,
                           Format::R10G10B10A2_UNORM, Format::R32G32B32A32_FLOAT}) {
        CAPTURE(formatInfo(f).name);
        const Surface s = rampSurface(f);
        const fs::path path = scratch(std::string(formatInfo(f).name) + ".exr");
        writeSurface(s, path);
        const OIIO::ImageBuf back = readBack(path);
        const std::uint32_t channels = formatInfo(f).channels;
        REQUIRE(back.spec().nchannels == int(channels));
        const char* names[] = {"R", "G", "B", "A"};
        for (std::uint32_t c = 0; c < channels; ++c) CHECK(back.spec().channelnames[c] == names[c]);
        int mismatches = 0;
        for (std::uint32_t y = 0; y < s.height(); ++y)
            for (std::uint32_t x = 0; x < s.width(); ++x)
                for (std::uint32_t c = 0; c < channels; ++c)
                    mismatches += back.getchannel(int(x), int(y), 0, int(c)) != s.load(x, y)[int(c)];
        CHECK(mismatches == 0);
        // Lossless in the strong sense: storing the read-back value reproduces the stored bytes.
        Surface again(s.desc());
        for (std::uint32_t y = 0; y < s.height(); ++y)
            for (std::uint32_t x = 0; x < s.width(); ++x) {
                glm::vec4 v(0.0f);
                for (std::uint32_t c = 0; c < channels; ++c) v[int(c)] = back.getchannel(int(x), int(y), 0, int(c));
                if (channels < 4) v.w = s.load(x, y).w;
                again.store(x, y, 0, v);
            }
        CHECK(std::equal(s.bytes().begin(), s.bytes().end(), again.bytes().begin()));
    }
}

TEST_CASE("half EXR stores binary16: 1/3 becomes 0x3555 = 0.333251953125") {
    // 1/3 = 1.0101...b x 2^-2; binary16 keeps 10 fraction bits: 0101010101 (round to nearest,
    // the next bits 0101... are below half) -> 0x3555 = (1 + 341/1024) / 4 = 0.333251953125.
    Surface s(SurfaceDesc{2, 1, Format::R32_FLOAT, 1});
    s.store(0, 0, 0, glm::vec4(1.0f / 3.0f));
    s.store(1, 0, 0, glm::vec4(65504.0f));  // largest finite half: exact
    const fs::path path = scratch("half.exr");
    writeSurface(s, path, ExrPixelType::Half);
    const OIIO::ImageBuf back = readBack(path);
    CHECK(back.nativespec().format == OIIO::TypeDesc::HALF);
    CHECK(back.getchannel(0, 0, 0, 0) == 0.333251953125f);
    CHECK(back.getchannel(1, 0, 0, 0) == 65504.0f);
}

TEST_CASE("RGBA8 goes to PNG as stored bytes, UINT data to uint32 TIFF, depth to EXR channel Z") {
    Surface rgba(SurfaceDesc{3, 2, Format::R8G8B8A8_UNORM_SRGB, 1});
    for (std::uint32_t i = 0; i < 6; ++i)
        for (int c = 0; c < 4; ++c) rgba.texel(i % 3, i / 3)[c] = std::byte(i * 40 + std::uint32_t(c) * 7);
    writeSurface(rgba, scratch("rgba.png"));
    // Read unassociated, as the bytes are stored (OIIO premultiplies PNG alpha on read by default).
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    OIIO::ImageBuf png(scratch("rgba.png").string(), 0, 0, nullptr, &config);
    REQUIRE(png.read(0, 0, true, OIIO::TypeDesc::UINT8));
    for (std::uint32_t i = 0; i < 6; ++i)
        for (int c = 0; c < 4; ++c)
            CHECK(std::lround(png.getchannel(int(i % 3), int(i / 3), 0, c) * 255.0f) == long(i * 40 + std::uint32_t(c) * 7));

    Surface grid(SurfaceDesc{4, 1, Format::R32G32_UINT, 1});
    const std::uint32_t values[4][2] = {{0, 1}, {0xFFFFFFFFu, 7}, {123456789u, 0x80000000u}, {42, 16777217u}};
    for (std::uint32_t x = 0; x < 4; ++x) std::memcpy(grid.texel(x, 0), values[x], 8);
    writeSurface(grid, scratch("grid.tif"));
    OIIO::ImageBuf tif(scratch("grid.tif").string());
    REQUIRE(tif.read(0, 0, true, OIIO::TypeDesc::UINT32));
    CHECK(tif.nativespec().format == OIIO::TypeDesc::UINT32);
    std::vector<std::uint32_t> px(8);
    REQUIRE(tif.get_pixels(tif.roi(), OIIO::TypeDesc::UINT32, px.data()));
    for (std::uint32_t x = 0; x < 4; ++x) {
        CHECK(px[x * 2] == values[x][0]);
        CHECK(px[x * 2 + 1] == values[x][1]);
    }

    Surface depth(SurfaceDesc{2, 2, Format::D32_FLOAT_S8X24_UINT, 1});
    depth.clearDepthStencil(true, 0.25f, true, 9);
    writeSurface(depth, scratch("depth.exr"));
    const OIIO::ImageBuf z = readBack(scratch("depth.exr"));
    CHECK(z.spec().nchannels == 1);
    CHECK(z.spec().channelnames[0] == "Z");
    CHECK(z.getchannel(1, 1, 0, 0) == 0.25f);
    writeStencil(depth, scratch("depth.stencil.png"));
    OIIO::ImageBuf st(scratch("depth.stencil.png").string());
    REQUIRE(st.read(0, 0, true, OIIO::TypeDesc::UINT8));
    CHECK(std::lround(st.getchannel(0, 0, 0, 0) * 255.0f) == 9);
}

TEST_CASE("lossy or impossible pairings are refused and failed writes leave nothing behind") {
    const Surface f = rampSurface(Format::R32_FLOAT);
    CHECK_THROWS_WITH_AS(writeSurface(f, scratch("f.png")), doctest::Contains("without loss (use .exr)"), std::runtime_error);
    const Surface u(SurfaceDesc{2, 2, Format::R32_UINT, 1});
    CHECK_THROWS_WITH_AS(writeSurface(u, scratch("u.exr")), doctest::Contains("write it as .tif"), std::runtime_error);
    CHECK_THROWS_WITH_AS(writeSurface(f, scratch("f.exr"), ExrPixelType::Float, 1), doctest::Contains("sample 1"), std::runtime_error);
    CHECK_THROWS_AS(writeStencil(f, scratch("f.stencil.png")), std::runtime_error);
    const fs::path missingDir = scratch("no-such-dir") / "out.exr";
    CHECK_THROWS_WITH_AS(writeSurface(f, missingDir), doctest::Contains("no-such-dir"), std::runtime_error);
    CHECK_FALSE(fs::exists(missingDir));
    CHECK(noPartialFiles());
    CHECK(losslessExtension(Format::R8G8B8A8_UNORM) == ".png");
    CHECK(losslessExtension(Format::R32G32_UINT) == ".tif");
    CHECK(losslessExtension(Format::D24_UNORM_S8_UINT) == ".exr");
}

TEST_CASE("withOpaqueAlpha sets alpha to 1 as a swap chain presents it and keeps colour bits") {
    Surface rgba(SurfaceDesc{2, 1, Format::R8G8B8A8_UNORM, 1});
    for (int c = 0; c < 4; ++c) rgba.texel(0, 0)[c] = std::byte(10 + c);
    const Surface opaque = withOpaqueAlpha(rgba);
    CHECK(opaque.texel(0, 0)[0] == std::byte{10});
    CHECK(opaque.texel(0, 0)[2] == std::byte{12});
    CHECK(opaque.texel(0, 0)[3] == std::byte{255});
    CHECK(opaque.texel(1, 0)[3] == std::byte{255});
    Surface half(SurfaceDesc{1, 1, Format::R16G16B16A16_FLOAT, 1});
    half.store(0, 0, 0, glm::vec4(0.25f, -2.0f, 65504.0f, 0.0f));
    CHECK(withOpaqueAlpha(half).load(0, 0) == glm::vec4(0.25f, -2.0f, 65504.0f, 1.0f));
    const Surface r32 = rampSurface(Format::R32_FLOAT);
    CHECK(std::equal(r32.bytes().begin(), r32.bytes().end(), withOpaqueAlpha(r32).bytes().begin()));
}

} // namespace tessera_test::io_image_writer_test
