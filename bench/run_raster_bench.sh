#!/usr/bin/env bash
# Builds tessera in Release (build-bench/) and runs the rasterizer benchmark: tessera and the
# llvmpipe peer on the same workloads at 1 and 2 threads, then a summary table with ratios.
# Usage: bench/run_raster_bench.sh [extra google-benchmark flags, e.g. --benchmark_filter=tessera]
# Run it alone on the machine: compiles or other jobs on the same cores distort the timings.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${TESSERA_BENCH_BUILD:-$root/build-bench}"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DTESSERA_WERROR=ON >/dev/null
cmake --build "$build" --target raster_bench
exec "$build/bench/raster_bench" --benchmark_color=false "$@"
