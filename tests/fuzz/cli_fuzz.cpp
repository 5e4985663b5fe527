// libFuzzer entry point for `tessera render`'s arguments, one per line (parseRenderArgs); the harness is in
// fuzz_harness.cpp, shared with the corpus replay test (fuzz_regressions_test.cpp).
#include "fuzz_harness.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return tessera::fuzz::fuzzCli(data, size);
}
