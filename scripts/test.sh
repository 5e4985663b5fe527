#!/usr/bin/env bash
# The whole test suite for a fresh Debian 12 clone (what CI runs): install what is missing, then
# three passes, each building the library optimised and the tests at -O1 with -Werror:
#   1. GCC 12 at -O2, every test (and the benchmarks compiled);  2. clang 14 under AddressSanitizer
#      + UBSan at -O1, every test (goldens too), plus the libFuzzer targets (TESSERA_FUZZ=ON, each
#      fuzzed for TESSERA_FUZZ_SECONDS, 60 by default, and its past crashes replayed; ctest label
#      fuzz);  3. GCC 12 under ThreadSanitizer, the determinism and compute tests.
# Two compilers, every test under each, the sanitizers on the second (docs/testing.md, "CI passes").
# Golden images are compared, never rewritten here, and golden/ must still match the commit
# (ctest golden/tree_matches_commit, in every pass).
# TESSERA_SKIP_SANITIZE=1 (the clang 14 ASan + UBSan pass) / TESSERA_SKIP_TSAN=1 skip passes (quick local runs).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ -n "${TESSERA_UPDATE_GOLDEN:-}" ]; then
  echo "test.sh: TESSERA_UPDATE_GOLDEN is set; the test suite compares goldens and never rewrites them" >&2
  exit 2
fi
# libclang-rt-14-dev: libFuzzer and the sanitizer runtimes (clang-14 only recommends it).
TESSERA_DEPS_EXTRA="clang-14 libclang-rt-14-dev" bash scripts/install-deps.sh
jobs=2   # CI machines have 2 cores
started=$SECONDS
passStarted=$SECONDS
minSec() { echo "$(( $1 / 60 )) min $(( $1 % 60 )) s"; }
# Each pass's own time (build + tests) and the running total, so a slow pass shows in CI's log.
stamp() {
  echo "test.sh: $1 took $(minSec $(( SECONDS - passStarted ))), done at $(minSec $(( SECONDS - started )))"
  passStarted=$SECONDS
}

# Tests write only under their build folders (TESSERA_TEST_OUTPUT_DIR): after each pass the
# source tree must be as it was before the run (nothing written, changed or deleted outside the
# ignored /build*/ folders).
treeBefore=$(git status --porcelain --untracked-files=all 2>/dev/null || true)
checkTree() {
  local now
  now=$(git status --porcelain --untracked-files=all 2>/dev/null || true)
  if [ "$now" != "$treeBefore" ]; then
    echo "test.sh: the $1 changed the source tree (tests must write under the build folder):" >&2
    diff <(echo "$treeBefore") <(echo "$now") >&2 || true
    exit 1
  fi
}

# Every pass: -Werror. The GCC pass also compiles the benchmarks (not run: timings are not tests,
# bench/RESULTS.md), so that bench/ cannot rot; the other passes leave them out.
common=(-G Ninja -DTESSERA_WERROR=ON -DTESSERA_BUILD_BENCH=OFF)

# Release at -O2, not CMake's -O3: the technique sources (the rasterizer instantiated per pixel
# shader) compile about 40% faster, and no bit depends on the optimiser (-ffp-contract=off, IEEE
# binary32/64 everywhere; tests/package builds a consumer at -O3 -march=x86-64-v3 and compares).
release=(-DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O2 -DNDEBUG")

cmake -S . -B build-ci -G Ninja -DTESSERA_WERROR=ON -DTESSERA_BUILD_BENCH=ON "${release[@]}"
cmake --build build-ci -j"$jobs"
ctest --test-dir build-ci -j"$jobs" --output-on-failure
checkTree "GCC pass"
stamp "GCC pass"

if [ "${TESSERA_SKIP_SANITIZE:-0}" != 1 ]; then
  # clang 14 with ASan + UBSan: the second compiler's build of every target (-Werror) and every
  # test, sanitised. -O1 -g1 for the library too: line tables are enough for sanitizer reports, and
  # -O1 keeps the Sponza-sized goldens fast under ASan while compiling much faster than -O2 with
  # full debug info. The fuzz targets add libFuzzer's coverage to the parsers (tests/fuzz).
  cmake -S . -B build-asan "${common[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DTESSERA_SANITIZE=address \
        -DCMAKE_CXX_COMPILER=clang++-14 -DTESSERA_FUZZ=ON
  cmake --build build-asan -j"$jobs"
  # llvmpipe's own JIT is not instrumented; its allocations are not ours to judge.
  ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build-asan -j"$jobs" --output-on-failure
  checkTree "clang 14 ASan + UBSan pass"
  stamp "clang 14 ASan + UBSan pass"
fi

if [ "${TESSERA_SKIP_TSAN:-0}" != 1 ]; then
  # Only the executables that run threads against shared buffers: the tile-parallel draws and the
  # compute dispatches (TSan slows them 10-50x). oneTBB itself is rebuilt with TSan from Debian's
  # source (scripts/build-tbb-tsan.sh), so its scheduler's synchronisation is visible. Debian's
  # Embree is not instrumented (nor is the oneTBB code inlined into it): its BVH build is committed
  # from a thread of its own, and tests/tsan.supp suppresses only reports whose stacks name
  # libembree3 (the file says why).
  bash scripts/build-tbb-tsan.sh build-tbb-tsan
  cmake -S . -B build-tsan "${common[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DTESSERA_SANITIZE=thread -DTESSERA_LLVMPIPE=OFF \
        -DCMAKE_PREFIX_PATH="$PWD/build-tbb-tsan"
  cmake --build build-tsan -j"$jobs" --target tests_determinism tests_compute
  loaded=$(ldd build-tsan/tests/tests_compute)   # (not piped into grep -q: pipefail + SIGPIPE)
  [[ $loaded == *"$PWD/build-tbb-tsan/lib/libtbb"* ]] ||
    { echo "test.sh: the TSan tests do not load the instrumented oneTBB" >&2; exit 1; }
  TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 suppressions=$PWD/tests/tsan.supp" \
    ctest --test-dir build-tsan -j"$jobs" --output-on-failure -L 'determinism|compute'
  checkTree "ThreadSanitizer pass"
  stamp "ThreadSanitizer pass"
fi

echo "test.sh: every pass passed in $(minSec $(( SECONDS - started )))"
