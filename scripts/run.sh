#!/usr/bin/env bash
# The main job for a fresh Debian 12 clone: install what is missing, build (Release), and
# render the default scene to tessera.png (pass extra `tessera render` options after it).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DTESSERA_BUILD_BENCH=OFF
cmake --build build -j2 --target tessera_cli
./build/tessera render --out tessera.png --stats "$@"
