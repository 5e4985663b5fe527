#!/usr/bin/env bash
# Builds oneTBB under ThreadSanitizer for the TSan pass of scripts/test.sh: Debian's libtbb is not
# instrumented, so TSan cannot see its scheduler's synchronisation and reports every capture of a
# parallel_for body as a race. Takes the source of the installed version from Debian (apt-get
# source, adding a deb-src entry when none is configured) and installs it into $1 (a prefix).
set -euo pipefail
prefix=$(realpath -m "${1:?usage: build-tbb-tsan.sh PREFIX}")
version=$(dpkg-query -W -f='${Version}' libtbb-dev)
if [ -f "$prefix/.version" ] && [ "$(cat "$prefix/.version")" = "$version" ]; then
  echo "build-tbb-tsan: $prefix holds oneTBB $version already"; exit 0
fi
if [ "$(id -u)" -eq 0 ]; then sudo=""; else sudo="sudo"; fi
if ! grep -rqsE '^(Types:.*deb-src|deb-src )' /etc/apt/sources.list /etc/apt/sources.list.d/; then
  echo "build-tbb-tsan: adding Debian's bookworm deb-src entry (/etc/apt/sources.list.d/tessera-deb-src.sources)"
  printf 'Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: bookworm\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' |
    $sudo tee /etc/apt/sources.list.d/tessera-deb-src.sources >/dev/null
  $sudo apt-get update -qq
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(cd "$work" && apt-get source --download-only -qq "onetbb=$version" 2>/dev/null || apt-get source --download-only -qq onetbb)
dsc=$(ls "$work"/onetbb_*.dsc)
case "$dsc" in
  *"_${version}.dsc") ;;
  *) echo "build-tbb-tsan: source $dsc does not match the installed libtbb-dev $version" >&2; exit 1 ;;
esac
tar -xf "$work"/onetbb_*.orig.tar.* -C "$work"
src=$(find "$work" -mindepth 1 -maxdepth 1 -type d | head -1)
flags="-fsanitize=thread -O1 -g1"
cmake -S "$src" -B "$work/build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_INSTALL_PREFIX="$prefix" \
      -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_SHARED_LINKER_FLAGS=-fsanitize=thread \
      -DTBB_TEST=OFF -DTBB_EXAMPLES=OFF -DTBBMALLOC_BUILD=OFF -DTBB_STRICT=OFF >/dev/null
cmake --build "$work/build" -j"$(nproc)" >/dev/null
cmake --install "$work/build" >/dev/null
echo "$version" > "$prefix/.version"
echo "build-tbb-tsan: oneTBB $version with -fsanitize=thread in $prefix"
