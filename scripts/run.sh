#!/usr/bin/env bash
# The main job for a fresh Debian 12 clone: install what is missing, build (Release), and
# render the default scene to tessera.png (pass extra `tessera render` options after it).
set -euo pipefail
cd "$(dirname "$0")/.."
# Only what rendering needs: no test, benchmark or llvmpipe-peer packages, and only the command
# and its library are configured and built (scripts/test.sh builds everything).
bash scripts/install-deps.sh render
# -O1 by default (TESSERA_OPT overrides): the first image comes in about 3 minutes on 2 cores
# instead of 4 (measured on a fresh clone: the command and its library compile in 181 s at -O1,
# about 250 s at -O2). Every image is the same at any optimisation level (-ffp-contract=off,
# IEEE binary32/64; tests/package compares -O3 -march=x86-64-v3 bit for bit); frames render
# about 18% slower than at -O2 (Sponza, forward-plus: 1.98 s against 1.68 s for the whole
# command). Timings belong to the benchmarks' own build (bench/RESULTS.md).
opt=${TESSERA_OPT:--O1}
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=$opt -DNDEBUG" -DTESSERA_BUILD_TESTS=OFF \
      -DTESSERA_BUILD_BENCH=OFF -DTESSERA_LLVMPIPE=OFF
cmake --build build -j2 --target tessera_cli
./build/tessera render --out tessera.png --stats "$@"
