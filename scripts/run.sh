#!/usr/bin/env bash
# The main job for a fresh Debian 12 clone: install what is missing, build (Release), and
# render the default scene to tessera.png (pass extra `tessera render` options after it).
set -euo pipefail
cd "$(dirname "$0")/.."
# Only what rendering needs: no test, benchmark or llvmpipe-peer packages, and only the command
# and its library are configured and built (scripts/test.sh builds everything).
bash scripts/install-deps.sh render
# -O2: the image is the same at any optimisation level, and the technique sources compile about
# 40% faster than at CMake's Release default -O3 (benchmarks keep -O3).
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O2 -DNDEBUG" -DTESSERA_BUILD_TESTS=OFF \
      -DTESSERA_BUILD_BENCH=OFF -DTESSERA_LLVMPIPE=OFF
cmake --build build -j2 --target tessera_cli
./build/tessera render --out tessera.png --stats "$@"
