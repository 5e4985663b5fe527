#!/usr/bin/env bash
# Makes scenes/sponza/ from the full-size Sponza glTF (../shared/scenes-external/Sponza): copies
# the glTF JSON, the .bin and the licence files unchanged, and halves each texture (box filter,
# OpenImageIO's oiiotool) until its larger side is at most 512 px, to keep the repository lean.
# Usage: scripts/shrink-sponza.sh [SOURCE_DIR] [MAX_SIZE]   (defaults: ../shared/scenes-external/Sponza, 512)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
src="${1:-$root/../shared/scenes-external/Sponza}"
max="${2:-512}"
dst="$root/scenes/sponza"
[ -f "$src/glTF/Sponza.gltf" ] || { echo "shrink-sponza: $src/glTF/Sponza.gltf not found" >&2; exit 2; }
command -v oiiotool >/dev/null || { echo "shrink-sponza: oiiotool missing (apt-get install openimageio-tools)" >&2; exit 2; }

rm -rf "$dst.tmp" && mkdir -p "$dst.tmp"
cp "$src/glTF/Sponza.gltf" "$src/glTF/Sponza.bin" "$dst.tmp/"
cp "$src/LICENSE.md" "$src/SponzaLicense.txt" "$dst.tmp/"
cp "$src/README.md" "$dst.tmp/README.upstream.md"
for img in "$src"/glTF/*.png "$src"/glTF/*.jpg; do
  name="$(basename "$img")"
  read -r w h < <(iinfo "$img" | sed -n 's/.*: *\([0-9]*\) x *\([0-9]*\),.*/\1 \2/p' | head -n1)
  tw=$w; th=$h
  while [ "$tw" -gt "$max" ] || [ "$th" -gt "$max" ]; do tw=$((tw / 2)); th=$((th / 2)); done
  if [ "$tw" -eq "$w" ] && [ "$th" -eq "$h" ]; then
    cp "$img" "$dst.tmp/$name"
  elif [ "${name##*.}" = "jpg" ]; then
    oiiotool "$img" --resize:filter=box "${tw}x${th}" --compression jpeg:90 -o "$dst.tmp/$name"
  else
    oiiotool "$img" --resize:filter=box "${tw}x${th}" -o "$dst.tmp/$name"
  fi
  echo "$name: ${w}x${h} -> ${tw}x${th}"
done
rm -rf "$dst" && mv "$dst.tmp" "$dst"
du -sh "$dst"
