#!/usr/bin/env bash
# The light-culling and scaling sweeps on a many-core host, as recorded in bench/RESULTS.md: (1) light culling of
# forward-plus by tile size and forward-plus-amd with 2.5D on and off (culling_bench, each process
# pinned to 2 cores, 1 and 2 threads), then (2) per-pass frame times of the tiled techniques
# (technique_sweep.py). Usage: bench/run_device_sweep.sh BIN_DIR OUT_DIR
set -uo pipefail
bin=$1 out=$2
mkdir -p "$out"
cores=$(nproc)
lights=1,2,4,8,16,32,64,128,256,512,1024,2048,4096,8192,16384
slot=0
run_pinned() {  # run_pinned NAME ARGS...: on cores slot, slot+1
  local name=$1; shift
  taskset -c $slot,$((slot + 1)) "$bin/culling_bench" "$@" > "$out/$name.md" 2> "$out/$name.err" &
  slot=$(( (slot + 2) % cores ))
}
for scenario in large small; do
  max=$([ $scenario = large ] && echo 512 || echo 16384)
  list=$(echo $lights | tr , '\n' | awk -v m=$max '$1 <= m' | paste -sd,)
  for tile in 8 16 32; do
    run_pinned "cull-fp-$scenario-$tile" --techniques forward-plus --scenario $scenario --lights $list \
      --tile-sizes $tile --threads 1,2 --frames 5 --warmup 1 --through culling
  done
  run_pinned "cull-amd-$scenario" --techniques forward-plus-amd --scenario $scenario --lights $list \
    --threads 1,2 --frames 3 --warmup 1 --through culling --fp off --option 'culling=depth-mask|min-max'
done
wait
python3 "$(dirname "$0")/technique_sweep.py" --bench "$bin/technique_bench" --cores "$cores" --scenario both \
  --techniques forward-plus,tiled-deferred,forward-plus-amd --small-max 16384 --frames 3 --out "$out/frames.md"
