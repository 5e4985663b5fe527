#!/usr/bin/env bash
# Thread scaling of the three Sponza frames of bench/RESULTS.md with binned passes and draw by draw
# (--draw-by-draw), one process per cell, alternating the two so host noise falls on both alike.
# Prints one line per (technique, threads, mode): per-pass and frame medians from `--stats`.
# Usage: bench/run_binned_scaling.sh TESSERA_BINARY [THREADS (default 1,2,4,8,16)] [REPEAT (default 3)]
set -euo pipefail
bin=$1 threads=${2:-1,2,4,8,16} repeat=${3:-3}
scenes=$(cd "$(dirname "$0")/../scenes" && pwd)
frames=("forward-plus sponza-small-lights" "deferred sponza-small-lights" "forward sponza-large-lights")
echo "| technique | threads | mode | passes (median ms) | frame ms |"
echo "|---|---:|---|---|---:|"
for f in "${frames[@]}"; do
  set -- $f
  for t in ${threads//,/ }; do
    for mode in binned draw-by-draw; do
      flag=(--binned); [[ $mode == draw-by-draw ]] && flag=(--draw-by-draw)  # --binned: the CLI draws draw by draw at 1 thread
      out=$("$bin" render "$scenes/$2.json" --technique "$1" --width 1280 --height 720 --threads "$t" \
            --repeat "$repeat" --warmup 1 --no-output --stats --quiet "${flag[@]}" 2>&1)
      passes=$(awk '/^pass /{l=$0; sub(/^pass +/, "", l); n=match(l, / +[0-9.]+ ms/); split(substr(l, n), a, " ");
                             printf "%s %s, ", substr(l, 1, n - 1), a[1]}' <<<"$out")
      frame=$(awk '/^frame /{print $2}' <<<"$out")
      echo "| $1 | $t | $mode | ${passes%, } | $frame |"
    done
  done
done
