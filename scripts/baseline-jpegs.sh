#!/usr/bin/env bash
# Rewrites progressive JPEGs under scenes/ as baseline JPEGs, losslessly: jpegtran (Debian's
# libjpeg-turbo-progs) re-encodes the entropy coding only, so every DCT coefficient and therefore
# every decoded texel is unchanged; the script checks that with djpeg before replacing a file.
# Why: a progressive JPEG is decoded through whole-image coefficient buffers that libjpeg
# allocates and zeroes in jpeg_start_decompress, which OpenImageIO also calls to read the header,
# so the default scene's three 2048 x 2048 progressive textures made every `tessera render
# default` spend about 40% of its time there (perf, on 2 cores; a baseline file decodes ~6x faster).
# Usage: scripts/baseline-jpegs.sh [FILE.jpg ...]   (default: every progressive *.jpg under scenes/)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
for tool in jpegtran djpeg; do
  command -v "$tool" >/dev/null || { echo "baseline-jpegs: $tool missing (apt-get install libjpeg-turbo-progs)" >&2; exit 2; }
done
if [ $# -gt 0 ]; then files=("$@"); else mapfile -t files < <(find "$root/scenes" -name '*.jpg' | sort); fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for f in "${files[@]}"; do
  [ -f "$f" ] || { echo "baseline-jpegs: $f: no such file" >&2; exit 2; }
  file -b "$f" | grep -q progressive || continue
  jpegtran -copy all -optimize -outfile "$tmp/new.jpg" "$f"
  djpeg -ppm "$f" > "$tmp/old.ppm"
  djpeg -ppm "$tmp/new.jpg" > "$tmp/new.ppm"
  cmp -s "$tmp/old.ppm" "$tmp/new.ppm" || { echo "baseline-jpegs: $f decodes differently as baseline; left unchanged" >&2; exit 1; }
  mv "$tmp/new.jpg" "$f"
  echo "$f: progressive -> baseline, texels identical"
done
