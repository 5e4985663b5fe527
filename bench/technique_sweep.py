#!/usr/bin/env python3
# Runs technique_bench over the 3dgep experiment's sweep (3dgep article §5: large lights 1..512, small
# lights 1..2048, forward and deferred, 1 and 2 threads) as one process per cell, several at once,
# each pinned to its own cores (taskset) so that a 16-core host measures many 1- and 2-thread
# cells side by side. Writes the cells' markdown rows to --out, sorted. Used for bench/RESULTS.md.
#
# Usage: technique_sweep.py --bench PATH [--cores 16] [--scenario large|small|both]
#                           [--techniques forward,deferred] [--frames 3] [--large-max 512]
#                           [--small-max 2048] [--options JSON] [--out rows.md]
import argparse
import os
import subprocess
import sys
import time

def doublings(top: int) -> list:
    """1, 2, 4, ... up to top (the article's light counts)."""
    counts = [1]
    while counts[-1] * 2 <= top:
        counts.append(counts[-1] * 2)
    return counts


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--bench", required=True)
    ap.add_argument("--cores", type=int, default=os.cpu_count())
    ap.add_argument("--scenario", default="both", choices=["large", "small", "both"])
    ap.add_argument("--techniques", default="forward,deferred")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--frames", type=int, default=3)
    ap.add_argument("--large-max", type=int, default=512, help="large lights: 1, 2, 4, ... up to this")
    ap.add_argument("--small-max", type=int, default=2048, help="small lights: 1, 2, 4, ... up to this")
    ap.add_argument("--options", default="", help="JSON technique options passed to technique_bench --options")
    ap.add_argument("--out", default="technique_sweep.md")
    args = ap.parse_args()

    scenarios = ["large", "small"] if args.scenario == "both" else [args.scenario]
    LIGHTS = {"large": doublings(args.large_max), "small": doublings(args.small_max)}
    jobs = []  # (cost estimate, scenario, technique, lights, threads)
    for scenario in scenarios:
        for technique in args.techniques.split(","):
            for lights in LIGHTS[scenario]:
                for threads in (int(t) for t in args.threads.split(",")):
                    # Longest first: cost grows with the light count and falls with threads.
                    jobs.append((lights / threads * (4 if technique == "deferred" else 1), scenario, technique, lights, threads))
    jobs.sort(reverse=True)

    free = list(range(args.cores))
    running = []  # (proc, cores, job, start)
    rows = []
    failed = 0
    while jobs or running:
        started = True
        while jobs and started:
            started = False
            for i, job in enumerate(jobs):
                if job[4] <= len(free):
                    cores = [free.pop(0) for _ in range(job[4])]
                    _, scenario, technique, lights, threads = job
                    cmd = ["taskset", "-c", ",".join(map(str, cores)), args.bench, "--techniques", technique,
                           "--scenario", scenario, "--lights", str(lights), "--threads", str(threads),
                           "--frames", str(args.frames), "--warmup", "1"] + (["--options", args.options] if args.options else [])
                    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                    running.append((proc, cores, job, time.time()))
                    del jobs[i]
                    started = True
                    break
        time.sleep(0.2)
        for entry in list(running):
            proc, cores, job, start = entry
            if proc.poll() is None:
                continue
            running.remove(entry)
            free.extend(cores)
            out, err = proc.communicate()
            lines = [l for l in out.splitlines() if l.startswith("| ") and not l.startswith("| technique")]
            if proc.returncode != 0 or not lines:
                failed += 1
                print(f"FAILED {job[1:]}: rc {proc.returncode}\n{err}", file=sys.stderr, flush=True)
                continue
            for line in lines:
                rows.append((job[1], job[2], job[3], job[4], line))
                print(f"{job[1]:5} {line}  ({time.time() - start:.0f} s)", flush=True)
    rows.sort()
    with open(args.out, "w") as f:
        for scenario in scenarios:
            f.write(f"\n{scenario} lights\n\n| technique | lights | threads | passes (median ms) | frame ms |\n|---|---|---|---|---|\n")
            for r in rows:
                if r[0] == scenario:
                    f.write(r[4] + "\n")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
