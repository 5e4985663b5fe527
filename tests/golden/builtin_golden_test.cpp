// Golden image of the built-in scene (the README's picture): rendered at 1, 2 and 7 threads,
// compared exactly with golden/builtin/<name>.png. A missing golden fails. On a mismatch the
// test writes <name>.actual.png, <name>.expected.png and <name>.diff.png (|a-e| x 16) into
// the build's golden-out/ folder and prints the worst pixel. To accept new output on
// purpose: TESSERA_UPDATE_GOLDEN=1 ctest -R golden (then review and commit the PNGs).
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <vector>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "builtin_scene.h"
#include <tessera/io/image_writer.h>

using namespace tessera;

namespace {

Surface renderBuiltin(std::uint32_t threads, std::uint32_t samples) {
    Device device(DeviceConfig{64, threads});
    DrawStats stats;
    BufferRegistry registry;
    cli::BuiltinSceneOptions opt;
    opt.sampleCount = samples;
    cli::buildBuiltinScene(device, opt, stats).run(registry);
    return registry.get("backbuffer");
}

void checkGolden(const Surface& actual, const std::string& name) {
    const std::filesystem::path golden = std::filesystem::path(TESSERA_SOURCE_DIR) / "golden" / "builtin" / (name + ".png");
    const std::filesystem::path outDir = std::filesystem::current_path() / "golden-out";
    std::filesystem::create_directories(outDir);
    const std::string actualPath = (outDir / (name + ".actual.png")).string();
    writeSurface(actual, actualPath);
    if (const char* update = std::getenv("TESSERA_UPDATE_GOLDEN"); update && std::string(update) == "1") {
        std::filesystem::copy_file(actualPath, golden, std::filesystem::copy_options::overwrite_existing);
        MESSAGE("updated " << golden.string());
        return;
    }
    REQUIRE_MESSAGE(std::filesystem::exists(golden), "missing golden " << golden.string());
    // Compare the stored bytes: read alpha unassociated (OIIO premultiplies PNG on read by default).
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    OIIO::ImageBuf expected(golden.string(), 0, 0, nullptr, &config), got(actualPath, 0, 0, nullptr, &config);
    REQUIRE(expected.read(0, 0, true, OIIO::TypeDesc::UINT8));
    REQUIRE(got.read(0, 0, true, OIIO::TypeDesc::UINT8));
    REQUIRE(expected.spec().width == got.spec().width);
    REQUIRE(expected.spec().height == got.spec().height);
    const auto cmp = OIIO::ImageBufAlgo::compare(got, expected, 0.0f, 0.0f);
    if (cmp.maxerror > 0.0) {
        std::filesystem::copy_file(golden, outDir / (name + ".expected.png"), std::filesystem::copy_options::overwrite_existing);
        OIIO::ImageBuf diff = OIIO::ImageBufAlgo::absdiff(got, expected);
        diff = OIIO::ImageBufAlgo::mul(diff, 16.0f);
        diff.write((outDir / (name + ".diff.png")).string());
    }
    INFO(name << ": worst pixel (" << cmp.maxx << "," << cmp.maxy << ") channel " << cmp.maxc << " differs by "
              << cmp.maxerror * 255.0 << "/255; " << cmp.nfail << " channel values differ; images in " << outDir.string());
    CHECK(cmp.maxerror == 0.0);
}

} // namespace

TEST_CASE("golden: built-in scene, 1 sample, identical at 1, 2 and 7 threads") {
    const Surface one = renderBuiltin(1, 1);
    checkGolden(one, "forward");
    for (const std::uint32_t threads : {2u, 7u}) {
        const Surface other = renderBuiltin(threads, 1);
        CHECK(std::equal(one.bytes().begin(), one.bytes().end(), other.bytes().begin(), other.bytes().end()));
    }
}

TEST_CASE("golden: built-in scene, 4x MSAA resolved") {
    checkGolden(renderBuiltin(2, 4), "forward-msaa4");
}
