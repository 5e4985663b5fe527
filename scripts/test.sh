#!/usr/bin/env bash
# The whole test suite for a fresh Debian 12 clone: install what is missing, build with
# -Werror (GCC), run ctest; then the suite under AddressSanitizer + UBSan (GCC), and a clang 14
# -Werror build.
# The GCC pass runs every test; the sanitizer pass runs every label but `golden`, and the golden
# tests of the default and built-in scenes (every technique end to end); the clang pass builds the
# library and the command: this keeps the whole script under CI's 30 minutes on 2 cores.
# TESSERA_SKIP_SANITIZE=1 / TESSERA_SKIP_CLANG=1 skip those passes (for quick local runs).
set -euo pipefail
cd "$(dirname "$0")/.."
TESSERA_DEPS_EXTRA="clang-14" bash scripts/install-deps.sh
jobs=2   # CI machines have 2 cores

cmake -S . -B build-ci -G Ninja -DCMAKE_BUILD_TYPE=Release -DTESSERA_WERROR=ON
cmake --build build-ci -j"$jobs"
ctest --test-dir build-ci -j"$jobs" --output-on-failure

if [ "${TESSERA_SKIP_SANITIZE:-0}" != 1 ]; then
  # RelWithDebInfo keeps -O2 so the exhaustive conversion sweeps stay fast under ASan; -g1 (line
  # tables, enough for sanitizer reports) compiles much faster than full debug information.
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTESSERA_WERROR=ON \
        -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DTESSERA_SANITIZE=ON -DTESSERA_BUILD_BENCH=OFF
  cmake --build build-asan -j"$jobs"
  # llvmpipe's own JIT is not instrumented; its allocations are not ours to judge.
  export ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  ctest --test-dir build-asan -j"$jobs" --output-on-failure -LE golden
  ctest --test-dir build-asan -j"$jobs" --output-on-failure -L golden -R "default scene|built-in scene"
  unset ASAN_OPTIONS UBSAN_OPTIONS
fi

if [ "${TESSERA_SKIP_CLANG:-0}" != 1 ]; then
  # The library and the command (tests and benchmarks are GCC-built above; building them with
  # clang too would take CI past its 30 minutes), then one render as a smoke test.
  cmake -S . -B build-clang -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++-14 \
        -DTESSERA_WERROR=ON -DTESSERA_BUILD_TESTS=OFF -DTESSERA_BUILD_BENCH=OFF -DTESSERA_LLVMPIPE=OFF
  cmake --build build-clang -j"$jobs"
  ./build-clang/tessera render --out build-clang/default.png --width 160 --height 90 --quiet
fi
