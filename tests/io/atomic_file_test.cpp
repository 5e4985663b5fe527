// Safe and reproducible image files: a full disk (simulated with RLIMIT_FSIZE) makes the write
// throw and keeps the previous file, concurrent writers to one path never collide, a failed
// rename reports its real cause, and the same surface always gives the same bytes.
#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include <sys/resource.h>

#include <OpenImageIO/imagebuf.h>

#include <tessera/io/atomic_file.h>
#include <tessera/io/image_writer.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::io_atomic_file_test {

using namespace tessera;
namespace fs = std::filesystem;

namespace {

fs::path scratchDir(const std::string& name) {
    // Per process: two builds' test runs at once must not share (and remove_all) each other's files.
    const fs::path dir = fs::path(TESSERA_TEST_OUTPUT_DIR) / ("atomic-file-test-" + std::to_string(::getpid())) / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::vector<unsigned char> readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<unsigned char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Files in `dir` whose name holds ".partial" (writeFileAtomically's temporaries).
int partialFiles(const fs::path& dir) {
    int count = 0;
    for (const auto& e : fs::directory_iterator(dir)) count += e.path().filename().string().find(".partial") != std::string::npos;
    return count;
}

// A surface of `format` whose texels depend on `seed`, so that writers of different seeds write
// different files.
Surface patterned(Format format, std::uint32_t seed, std::uint32_t w = 33, std::uint32_t h = 21) {
    Surface s(SurfaceDesc{w, h, format, 1});
    const FormatInfo& info = formatInfo(format);
    for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) {
            const std::uint32_t i = (y * w + x) * 2654435761u + seed * 40503u;
            if (info.kind == FormatKind::Uint || format == Format::D24_UNORM_S8_UINT) {  // every bit pattern is valid
                const std::uint32_t v[4] = {i, i >> 3, i ^ seed, 7};
                std::memcpy(s.texel(x, y), v, info.bytesPerTexel);
            } else {
                const auto c = [&](int k) { return float((i >> (k * 8)) & 0xFF) / 255.0f; };
                s.store(x, y, 0, glm::vec4(c(0), c(1), c(2), c(3)));
            }
        }
    return s;
}

// Lowers this process's soft RLIMIT_FSIZE (the hard limit stays, so it can be raised back) and
// ignores SIGXFSZ, so that a write past `bytes` fails with EFBIG as on a full disk; restores both.
class FileSizeLimit {
public:
    explicit FileSizeLimit(rlim_t bytes) {
        getrlimit(RLIMIT_FSIZE, &mSaved);
        mOldHandler = std::signal(SIGXFSZ, SIG_IGN);
        rlimit lowered = mSaved;
        lowered.rlim_cur = bytes;
        mOk = setrlimit(RLIMIT_FSIZE, &lowered) == 0;
    }
    ~FileSizeLimit() {
        setrlimit(RLIMIT_FSIZE, &mSaved);
        std::signal(SIGXFSZ, mOldHandler);
    }
    bool ok() const { return mOk; }

private:
    rlimit mSaved{};
    void (*mOldHandler)(int) = nullptr;
    bool mOk = false;
};

} // namespace

TEST_CASE("fnv1a64 matches the FNV reference vectors") {
    const auto hash = [](const std::string& s) {
        return fnv1a64(std::span(reinterpret_cast<const unsigned char*>(s.data()), s.size()));
    };
    CHECK(hash("") == 0xcbf29ce484222325ull);
    CHECK(hash("a") == 0xaf63dc4c8601ec8cull);
    CHECK(hash("foobar") == 0x85944171f73967e8ull);
    CHECK(hashHex(0xaf63dc4c8601ec8cull) == "af63dc4c8601ec8c");
    CHECK(hashHex(1) == "0000000000000001");
}

TEST_CASE("a full disk (RLIMIT_FSIZE, EFBIG) makes writeSurface throw and keeps the previous file intact") {
    const fs::path dir = scratchDir("full-disk");
    for (const char* name : {"image.png", "image.exr", "image.tif"}) {
        const fs::path target = dir / name;
        const bool rgba = target.extension() != ".exr";
        const Surface good = patterned(rgba ? Format::R8G8B8A8_UNORM : Format::R32G32B32A32_FLOAT, 1);
        const Surface next = patterned(rgba ? Format::R8G8B8A8_UNORM : Format::R32G32B32A32_FLOAT, 2);
        writeSurface(good, target);
        const std::vector<unsigned char> before = readBytes(target);
        REQUIRE(before.size() > 256);
        std::string message;
        {
            constexpr rlim_t kLimitBytes = 64;  // far below any of these files
            const FileSizeLimit limit(kLimitBytes);
            REQUIRE(limit.ok());
            try {
                writeSurface(next, target);
            } catch (const std::runtime_error& e) {
                message = e.what();
            }
        }  // limit lifted before any test output
        INFO(name << ": " << message);
        CHECK(message.find(target.string()) == 0);
        CHECK(message.find("File too large") != std::string::npos);
        CHECK(readBytes(target) == before);
        CHECK(partialFiles(dir) == 0);
    }
}

TEST_CASE("concurrent writers to one path all succeed and leave one complete image of one writer") {
    constexpr int kWriters = 6;  // threads writing at once
    constexpr int kRounds = 8;   // repetitions, to give the race a chance
    const fs::path dir = scratchDir("concurrent");
    for (const char* ext : {".png", ".exr"}) {
        const Format format = std::string(ext) == ".png" ? Format::R8G8B8A8_UNORM : Format::R16G16B16A16_FLOAT;
        std::vector<Surface> surfaces;
        std::vector<std::vector<unsigned char>> expected;
        for (int i = 0; i < kWriters; ++i) {
            surfaces.push_back(patterned(format, std::uint32_t(i + 10), 96, 64));
            const fs::path alone = dir / ("alone" + std::to_string(i) + ext);
            writeSurface(surfaces.back(), alone);
            expected.push_back(readBytes(alone));
        }
        const fs::path target = dir / (std::string("shared") + ext);
        for (int round = 0; round < kRounds; ++round) {
            std::vector<std::string> errors(kWriters);
            std::vector<std::thread> threads;
            for (int i = 0; i < kWriters; ++i)
                threads.emplace_back([&, i] {
                    try {
                        writeSurface(surfaces[std::size_t(i)], target);
                    } catch (const std::exception& e) {
                        errors[std::size_t(i)] = e.what();
                    }
                });
            for (std::thread& t : threads) t.join();
            for (const std::string& e : errors) CHECK_MESSAGE(e.empty(), e);
            const std::vector<unsigned char> got = readBytes(target);
            CHECK(std::find(expected.begin(), expected.end(), got) != expected.end());
            CHECK(partialFiles(dir) == 0);
        }
        OIIO::ImageBuf back(target.string());
        CHECK(back.read(0, 0, true, OIIO::TypeDesc::FLOAT));
    }
}

TEST_CASE("a failed rename reports its real cause and removes the temporary file") {
    const fs::path dir = scratchDir("rename");
    const fs::path target = dir / "taken.png";  // an existing, non-empty directory: rename(2) fails
    fs::create_directories(target / "inside");
    std::string message;
    try {
        writeSurface(patterned(Format::R8G8B8A8_UNORM, 3), target);
    } catch (const std::runtime_error& e) {
        message = e.what();
    }
    INFO(message);
    CHECK(message.find(target.string() + ": cannot rename into place: ") == 0);
    CHECK(message.find("Success") == std::string::npos);
    CHECK((message.find("Is a directory") != std::string::npos || message.find("Directory not empty") != std::string::npos));
    CHECK(partialFiles(dir) == 0);
    CHECK(fs::is_directory(target / "inside"));
}

TEST_CASE("the same surface gives byte-identical files a second later, and SOURCE_DATE_EPOCH fixes the DateTime") {
    const fs::path dir = scratchDir("reproducible");
    struct Case { Format format; const char* ext; };
    const Case cases[] = {{Format::R8G8B8A8_UNORM, ".png"}, {Format::R8G8B8A8_UNORM, ".tif"}, {Format::R32G32_UINT, ".tif"},
                          {Format::R32G32B32A32_FLOAT, ".exr"}, {Format::D24_UNORM_S8_UINT, ".exr"}};
    ::unsetenv("SOURCE_DATE_EPOCH");
    std::vector<std::vector<unsigned char>> first;
    for (std::size_t i = 0; i < std::size(cases); ++i) {
        const fs::path path = dir / ("a" + std::to_string(i) + cases[i].ext);
        const std::uint64_t hash = writeSurface(patterned(cases[i].format, 4), path);
        first.push_back(readBytes(path));
        CHECK(hash == fnv1a64(first.back()));
    }
    writeStencil(patterned(Format::D24_UNORM_S8_UINT, 4), dir / "a.stencil.png");
    // Timestamps have a resolution of 1 s: wait past the next second.
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    for (std::size_t i = 0; i < std::size(cases); ++i) {
        CAPTURE(formatInfo(cases[i].format).name);
        CAPTURE(cases[i].ext);
        const fs::path path = dir / ("b" + std::to_string(i) + cases[i].ext);
        writeSurface(patterned(cases[i].format, 4), path);
        CHECK(readBytes(path) == first[i]);
        OIIO::ImageBuf back(path.string());
        REQUIRE(back.init_spec(path.string(), 0, 0));
        CHECK(back.spec().get_string_attribute("DateTime") == "");
    }
    writeStencil(patterned(Format::D24_UNORM_S8_UINT, 4), dir / "b.stencil.png");
    CHECK(readBytes(dir / "a.stencil.png") == readBytes(dir / "b.stencil.png"));

    ::setenv("SOURCE_DATE_EPOCH", "1700000000", 1);  // 2023-11-14 22:13:20 UTC
    for (const char* ext : {".exr", ".tif"}) {
        const fs::path path = dir / (std::string("epoch") + ext);
        writeSurface(patterned(std::string(ext) == ".exr" ? Format::R32_FLOAT : Format::R32_UINT, 5), path);
        OIIO::ImageBuf back(path.string());
        REQUIRE(back.init_spec(path.string(), 0, 0));
        CHECK(back.spec().get_string_attribute("DateTime") == "2023:11:14 22:13:20");
    }
    ::unsetenv("SOURCE_DATE_EPOCH");
}

} // namespace tessera_test::io_atomic_file_test
