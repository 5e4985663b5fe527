#!/usr/bin/env bash
# Installs the Debian 12 packages tessera needs. `install-deps.sh render`: what building and
# running `tessera` needs (the README's first command, scripts/run.sh); `install-deps.sh` (all):
# also the tests, benchmarks, llvmpipe peer, report browser and plots (the second command,
# scripts/test.sh, and .ci/run). Installs only what is missing; runs apt-get as root or through
# sudo. Set TESSERA_DEPS_EXTRA="clang-14 ..." to add more packages.
set -euo pipefail

mode=${1:-all}
if [ "$mode" != render ] && [ "$mode" != all ]; then
  echo "install-deps: unknown set '$mode' (render, all)" >&2
  exit 2
fi
packages=(
  cmake ninja-build g++ pkg-config
  libglm-dev libopenimageio-dev libtbb-dev libtinygltf-dev nlohmann-json3-dev libstb-dev
  # OpenImageIO's CMake package imports its tools (OpenImageIO::iconvert, idiff, ...) and fails
  # find_package(OpenImageIO CONFIG) when their executables are absent: needed to configure at all
  openimageio-tools
  # portable SIMD with runtime dispatch (the vectorised pixel pipeline)
  libhwy-dev
  # ray casting for forward-plus-amd's many-light shadows (GPU Pro 4 ch. 5 §5.6.2): Intel Embree 3
  libembree-dev
  # `tessera serve`: the HTTP server of the frame inspector
  libcpp-httplib-dev
)
if [ "$mode" = all ]; then
  packages+=(
    # tests and benchmarks
    doctest-dev libbenchmark-dev
    # glTF loader tests: malformed glTF cases in /usr/share/assimp/models/glTF2/
    assimp-testmodels
    # bench/plot.py: the speed/accuracy charts of bench/RESULTS.md (run it with /usr/bin/python3)
    python3-matplotlib
    # tests/report: the teaching report opened by headless Chromium
    chromium
    # llvmpipe peer (conformance test and benchmark): EGL surfaceless + desktop GL headers
    libegl-dev libopengl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  )
fi
# shellcheck disable=SC2206
packages+=(${TESSERA_DEPS_EXTRA:-})

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then sudo=""; elif command -v sudo >/dev/null; then sudo="sudo"; else
  echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
