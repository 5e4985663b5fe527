#!/usr/bin/env bash
# One remote command for a GPU host: (1) same_frame_bench with --gl-platform device (the Sponza
# frames through tessera at each thread count and once through the GPU's OpenGL driver, headless
# via EGL_EXT_platform_device: per-pass GL_TIME_ELAPSED times, their ratio to tessera's, and the
# GPU image's difference from tessera's), then (2) the tessera CLI's thread scaling sweep
# (forward-plus with 1024 lights and deferred with 256 on sponza-small-lights, 1280x720).
#
# Usage: bench/run_same_frame_gpu.sh SCALEDIST OUT_DIR
#   SCALEDIST  folder with bin/same_frame_bench, bin/tessera and lib/ (their non-system shared
#              libraries; run with LD_LIBRARY_PATH=SCALEDIST/lib). It must not carry libEGL,
#              libOpenGL or libGLdispatch from elsewhere: those come from the host or from .gl/.
#   OUT_DIR    created; gets:
#     env.txt                 host, GPU (nvidia-smi), EGL vendor files, what was set up
#     same_frame_gpu.md/.csv  same_frame_bench's tables (stderr: same_frame_gpu.err: GL_VENDOR,
#                             GL_RENDERER, GL_VERSION, the EGL devices seen)
#     cli/<technique>-t<T>[-r<run>].txt   each `tessera render --stats` output
#     cli_scaling.csv         technique,threads,pass,ms: per-pass medians and the frame median
#                             ("frame"), as the CLI prints them with --repeat 5 --warmup 1; a CLI
#                             without --repeat/--warmup is run 3 times and the middle value taken
# Environment (all optional):
#   REPO=<repo root>          default: this script's ../ (scenes: $REPO/scenes as TESSERA_SCENES)
#   GL_DEBS=<folder>          .deb files of the GL loaders (libegl1, libopengl0, libglvnd0, ...),
#                             unpacked into / when present (default: $REPO/.gl)
#   THREADS="1 2 4 8 12 16"   thread counts of both parts
#   SF_ITERATIONS=5           same_frame_bench's timed frames (after 1 warm-up)
#   SF_TECHNIQUES=forward,forward-plus,deferred
#   SF_GL_DEVICE=N            pass --gl-device N (default: the first non-software EGL device)
#   SF_DUMP=1                 also write the images (OUT_DIR/images; ~5 MB per row)
set -uo pipefail

if [ $# -ne 2 ]; then
  echo "usage: bench/run_same_frame_gpu.sh SCALEDIST OUT_DIR (see the comment at its top)" >&2
  exit 2
fi
dist=$(cd "$1" && pwd) || { echo "run_same_frame_gpu: no folder $1" >&2; exit 2; }
mkdir -p "$2" && out=$(cd "$2" && pwd) || exit 2
repo=${REPO:-$(cd "$(dirname "$0")/.." && pwd)}
debs=${GL_DEBS:-$repo/.gl}
threads=${THREADS:-1 2 4 8 12 16}
status=0
: > "$out/env.txt"

log() { echo "run_same_frame_gpu: $*" | tee -a "$out/env.txt" >&2; }

for b in same_frame_bench tessera; do
  [ -x "$dist/bin/$b" ] || { log "missing $dist/bin/$b"; status=1; }
done
[ -d "$repo/scenes" ] || { log "no scenes folder in $repo (set REPO)"; exit 2; }

# --- GL loaders and the NVIDIA EGL vendor -------------------------------------------------------
{
  echo "date: $(date -u +%FT%TZ)"; echo "host: $(uname -a)"; echo "cpus: $(nproc)"
  grep -m1 'model name' /proc/cpuinfo 2>/dev/null
  command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv 2>&1
} >> "$out/env.txt"
shopt -s nullglob
deb_files=("$debs"/*.deb)
if [ ${#deb_files[@]} -gt 0 ]; then
  for f in "${deb_files[@]}"; do dpkg -x "$f" / || log "dpkg -x $f failed"; done
  ldconfig
  log "unpacked ${#deb_files[@]} .deb file(s) from $debs"
fi
vendor_files=(/usr/share/glvnd/egl_vendor.d/*.json /etc/glvnd/egl_vendor.d/*.json)
nvidia_vendor=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
use_nvidia_vendor() {
  export __EGL_VENDOR_LIBRARY_FILENAMES=$nvidia_vendor
  for d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib; do  # where its libEGL_nvidia.so.0 lives
    [ -d "$d" ] && case ":${LD_LIBRARY_PATH:-}:" in *":$d:"*) ;; *) export LD_LIBRARY_PATH=${LD_LIBRARY_PATH:+$LD_LIBRARY_PATH:}$d ;; esac
  done
  log "__EGL_VENDOR_LIBRARY_FILENAMES=$__EGL_VENDOR_LIBRARY_FILENAMES"
}
if [ -z "${__EGL_VENDOR_LIBRARY_FILENAMES:-}" ] && ! grep -qil nvidia "${vendor_files[@]}" /dev/null 2>/dev/null \
   && [ -f "$nvidia_vendor" ]; then
  use_nvidia_vendor
fi
shopt -u nullglob
echo "EGL vendor files: ${vendor_files[*]:-none} ${__EGL_VENDOR_LIBRARY_FILENAMES:+(override: $__EGL_VENDOR_LIBRARY_FILENAMES)}" >> "$out/env.txt"
export LD_LIBRARY_PATH=$dist/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export TESSERA_SCENES=$repo/scenes
echo "LD_LIBRARY_PATH=$LD_LIBRARY_PATH" >> "$out/env.txt"
echo "same_frame_bench libraries:" >> "$out/env.txt"
ldd "$dist/bin/same_frame_bench" 2>&1 | grep -Ei 'egl|opengl|gldispatch|not found' >> "$out/env.txt"

# --- (1) same-frame benchmark on the GPU ---------------------------------------------------------
sf_threads=$(echo $threads | tr ' ' ,)
sf_args=(--gl-platform device --tessera-threads "$sf_threads" --iterations "${SF_ITERATIONS:-5}"
         --techniques "${SF_TECHNIQUES:-forward,forward-plus,deferred}" --csv "$out/same_frame_gpu.csv")
[ -n "${SF_GL_DEVICE:-}" ] && sf_args+=(--gl-device "$SF_GL_DEVICE")
[ "${SF_DUMP:-0}" = 1 ] && sf_args+=(--dump "$out/images")
run_sf() {
  log "same_frame_bench ${sf_args[*]}"
  "$dist/bin/same_frame_bench" "${sf_args[@]}" > "$out/same_frame_gpu.md" 2> "$out/same_frame_gpu.err"
}
run_sf; rc=$?
if [ $rc -ne 0 ] && [ -z "${__EGL_VENDOR_LIBRARY_FILENAMES:-}" ] && [ -f "$nvidia_vendor" ] \
   && grep -q 'no hardware EGL device\|EGL_EXT_platform_device\|EGL_EXT_device' "$out/same_frame_gpu.err"; then
  mv "$out/same_frame_gpu.err" "$out/same_frame_gpu.first.err"
  log "no GPU EGL device with the default vendor files: retrying with NVIDIA's"
  use_nvidia_vendor
  run_sf; rc=$?
fi
if [ $rc -ne 0 ]; then
  log "same_frame_bench failed (rc $rc):"; tail -5 "$out/same_frame_gpu.err" >&2; status=1
else
  grep -E '^GL_(VENDOR|RENDERER|VERSION)' "$out/same_frame_gpu.err" | sort -u | tee -a "$out/env.txt" >&2
fi

# --- (2) tessera CLI thread scaling ----------------------------------------------------------------
mkdir -p "$out/cli"
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
cli=$dist/bin/tessera
help=$("$cli" render --help 2>&1)
if grep -q -- '--repeat' <<<"$help" && grep -q -- '--warmup' <<<"$help"; then repeat=1; else repeat=0; fi
# --no-output (a CLI built without OpenImageIO cannot write the image); older CLIs write a scratch PNG.
if grep -q -- '--no-output' <<<"$help"; then outArgs=(--no-output); else outArgs=(--out "$tmp/x.png"); fi
log "tessera CLI: $([ $repeat = 1 ] && echo '--repeat 5 --warmup 1' || echo 'no --repeat/--warmup: 3 runs, middle value')"
# "pass NAME MS ms [(lo..hi)]" and "frame MS ms ..." lines of --stats as "pass,ms" rows.
parse_stats() { awk '$1 == "pass" && $4 == "ms" { print $2 "," $3 } $1 == "frame" && $3 == "ms" { print "frame," $2 }' "$1"; }
echo "technique,threads,pass,ms" > "$out/cli_scaling.csv"
for spec in forward-plus:1024 deferred:256; do
  technique=${spec%%:*} lights=${spec##*:}
  for t in $threads; do
    args=(render sponza-small-lights --technique "$technique" --lights "$lights" --width 1280 --height 720
          --threads "$t" --stats "${outArgs[@]}")
    if [ $repeat = 1 ]; then
      f=$out/cli/$technique-t$t.txt
      "$cli" "${args[@]}" --repeat 5 --warmup 1 > "$f" 2>&1 || { log "tessera ${args[*]} failed: $(tail -1 "$f")"; status=1; continue; }
      parse_stats "$f" | sed "s/^/$technique,$t,/" >> "$out/cli_scaling.csv"
    else
      : > "$tmp/rows"
      for r in 1 2 3; do
        f=$out/cli/$technique-t$t-r$r.txt
        "$cli" "${args[@]}" > "$f" 2>&1 || { log "tessera ${args[*]} failed: $(tail -1 "$f")"; status=1; continue 2; }
        parse_stats "$f" | awk -F, -v r=$r '{ print NR "," $1 "," $2 }' >> "$tmp/rows"  # order,pass,ms
      done
      # the middle of the 3 values per pass, passes in the order they ran
      sort -t, -k1,1n -k3,3g "$tmp/rows" | awk -F, -v pre="$technique,$t" \
        '{ n[$1]++; if (n[$1] == 2) { name[$1] = $2; ms[$1] = $3 } } END { for (i = 1; i in name; i++) print pre "," name[i] "," ms[i] }' \
        >> "$out/cli_scaling.csv"
    fi
  done
done
log "wrote $out/same_frame_gpu.md, $out/same_frame_gpu.csv, $out/cli_scaling.csv (status $status)"
exit $status
