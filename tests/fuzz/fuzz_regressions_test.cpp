// Replays the fuzz inputs kept in the tree through the fuzz harnesses in every build (GCC too,
// without libFuzzer): the seed corpus of each target and every input that once crashed one,
// each of which must now be accepted or refused with the documented error.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_harness.h"

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::fuzz_fuzz_regressions_test {

namespace {

namespace fs = std::filesystem;
using Harness = int (*)(const std::uint8_t*, std::size_t);

const fs::path kFuzzDir = fs::path(TESSERA_SOURCE_DIR) / "tests" / "fuzz";

// The files of tests/fuzz/<kind>/<target>/, sorted (absent folder: none).
std::vector<fs::path> inputs(const std::string& kind, const std::string& target) {
    std::vector<fs::path> files;
    const fs::path dir = kFuzzDir / kind / target;
    if (!fs::is_directory(dir)) return files;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.is_regular_file()) files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    return files;
}

std::string bytesOf(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    REQUIRE_MESSAGE(in, "cannot read " << file.string());
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Every corpus and regression input of `target` through `harness`; returns how many ran.
std::size_t replay(const std::string& target, Harness harness) {
    std::size_t count = 0;
    for (const char* kind : {"corpus", "regressions"}) {
        for (const fs::path& file : inputs(kind, target)) {
            INFO(file.string());
            const std::string bytes = bytesOf(file);
            CHECK_NOTHROW(CHECK(harness(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()) == 0));
            ++count;
        }
    }
    return count;
}

} // namespace

TEST_CASE("fuzz inputs: scene files are accepted or refused with InputError") {
    CHECK(replay("scene_file", tessera::fuzz::fuzzSceneFile) > 0);  // the seed corpus is there
}

TEST_CASE("fuzz inputs: glTF files are accepted or refused with InputError") {
    CHECK(replay("gltf", tessera::fuzz::fuzzGltf) > 0);  // the seed corpus is there
}

TEST_CASE("fuzz inputs: render arguments are accepted or refused with UsageError") {
    CHECK(replay("cli", tessera::fuzz::fuzzCli) > 0);  // the seed corpus is there
}

} // namespace tessera_test::fuzz_fuzz_regressions_test
