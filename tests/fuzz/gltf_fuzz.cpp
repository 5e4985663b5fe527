// libFuzzer entry point for glTF files (.gltf and .glb, through loadGltfFromMemory); the harness is in
// fuzz_harness.cpp, shared with the corpus replay test (fuzz_regressions_test.cpp).
#include "fuzz_harness.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return tessera::fuzz::fuzzGltf(data, size);
}
