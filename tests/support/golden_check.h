// Exact golden-image comparison shared by the golden tests: writes the actual image into the
// build's golden-out/ folder, compares its stored bytes with golden/<group>/<name>.png, and on
// a mismatch writes <name>.expected.png and <name>.diff.png (|a-e| x 16) beside it and reports
// the worst pixel. A missing golden fails. TESSERA_UPDATE_GOLDEN=1 copies actual over golden,
// except under CI (CI set), where it fails: CI compares, it never rewrites.
#pragma once

#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <tessera/io/image_writer.h>

namespace tessera::test {

inline void checkGolden(const Surface& actual, const std::string& group, const std::string& name) {
    const std::filesystem::path golden = std::filesystem::path(TESSERA_SOURCE_DIR) / "golden" / group / (name + ".png");
    const std::filesystem::path outDir = std::filesystem::path(TESSERA_TEST_OUTPUT_DIR) / "golden-out" / group;
    std::filesystem::create_directories(outDir);
    const std::string actualPath = (outDir / (name + ".actual.png")).string();
    writeSurface(actual, actualPath);
    if (const char* update = std::getenv("TESSERA_UPDATE_GOLDEN"); update && std::string(update) == "1") {
        const char* ci = std::getenv("CI");
        REQUIRE_MESSAGE((ci == nullptr || std::string(ci).empty() || std::string(ci) == "false"),
                        "TESSERA_UPDATE_GOLDEN=1 under CI: goldens are compared in CI, never rewritten");
        std::filesystem::create_directories(golden.parent_path());
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
    INFO(group << "/" << name << ": worst pixel (" << cmp.maxx << "," << cmp.maxy << ") channel " << cmp.maxc << " differs by "
               << cmp.maxerror * 255.0 << "/255; " << cmp.nfail << " channel values differ; images in " << outDir.string());
    CHECK(cmp.maxerror == 0.0);
}

} // namespace tessera::test
