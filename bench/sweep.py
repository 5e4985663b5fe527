#!/usr/bin/env python3
# The speed/accuracy sweep: scenes x techniques x options ("knobs") x light counts x precision modes,
# one `tessera render` process per cell writing <out>/cells/<cell>/result.json; then each image's
# error against the reference and exact renders of the same scene, technique, knobs and lights
# (`tessera diff --json`) and <out>/summary.json and summary.csv. Python 3 standard library only.
#
# Resuming: a cell whose result.json exists is skipped, so an interrupted sweep picks up where it
# stopped (delete a cell's folder to redo it). Errors are cached in each cell's errors.json.
#
# Splitting across machines (each host needs this tree and a built tessera at the same path,
# or pass --tessera; --out should be on a shared filesystem, else copy the disjoint cell folders
# back with `rsync -a host:OUT/cells/ OUT/cells/` before summarizing):
#   python3 bench/sweep.py --out /shared/sweep [flags] --list-cells       # one command per line
#   python3 bench/sweep.py --out /shared/sweep [flags] --list-cells | parallel -j1 -S hostA,hostB
#   n=$(python3 bench/sweep.py --out /shared/sweep [flags] --count-cells)
#   sbatch --array=0-$((n-1)) --cpus-per-task=2 \
#          --wrap "python3 $PWD/bench/sweep.py --out /shared/sweep [flags] --cell \$SLURM_ARRAY_TASK_ID"
#   python3 bench/sweep.py --out /shared/sweep --summarize                  # afterwards, anywhere
# The same [flags] give the same cell list in the same order on every host.
#
# Usage: sweep.py [--tessera PATH] [--out DIR] [--scenes LIST] [--techniques LIST]
#                 [--precisions LIST] [--lights LIST] [--width W --height H] [--repeat N]
#                 [--warmup K] [--threads N] [--full] [--jobs J] [--timeout S] [--registry FILE]
#                 [--list-cells | --count-cells | --print-cells | --cell N[,M,...] | --summarize]
import argparse
import csv
import hashlib
import json
import os
import re
import shlex
import shutil
import socket
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES_DIR = os.path.join(REPO, "scenes")

# Techniques and their options ("knobs") come from the technique registry (`tessera options --json`),
# so a technique added to the library is swept without an edit here. Each ready technique that is
# not an inspection view: its defaults (faithful to the source) and, when any of its options corrects
# an erratum, one set with every correction on; --full adds one set per listed value of each
# word, boolean or integer option that differs from its default (one option changed at a time).
def registry(binary, path=None):
    """The technique registry as `tessera options --json` prints it (or as saved in `path`)."""
    if path:
        try:
            with open(path) as f:
                return json.load(f)
        except (OSError, ValueError) as e:
            fail(f"sweep.py: --registry: cannot read the technique registry from '{path}': {e}")
    try:
        out = subprocess.run([binary, "options", "--json"], check=True, capture_output=True, text=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        fail(f"sweep.py: --tessera: cannot read the technique registry from '{binary} options --json': {e}")
    return json.loads(out)


def option_json(option, text):
    """A catalogue value (text) as the JSON value a scene file's "options" takes."""
    if option["kind"] == "bool":
        return text == "true"
    if option["kind"] == "integer" or (option["kind"] == "integer-or-word" and text.isdigit()):
        return int(text)
    return text


def knob_sets(technique, full):
    """The option sets swept for one registry entry, defaults first."""
    sets = [{}]
    corrections = {o["key"]: option_json(o, o["corrected"]) for o in technique["options"] if o["corrected"] and o["erratum"]}
    if corrections:
        sets.append(corrections)
    if full:
        for o in technique["options"]:
            if o["kind"] not in ("word", "bool", "integer"):
                continue
            default = o["faithful"].split(" ")[0]
            for v in o["values"]:
                if v != default and {o["key"]: option_json(o, v)} not in sets:
                    sets.append({o["key"]: option_json(o, v)})
    return sets


def knobs_from_registry(binary, full, path=None):
    return {t["id"]: knob_sets(t, full) for t in registry(binary, path) if t["ready"] and not t["inspectionView"]}


MSAA_SMALL, MSAA_FULL = [1, 4], [1, 2, 4, 8]  # builtin scene only
LIGHTS_FULL = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024]
PRECISIONS = ["reference", "exact", "fast"]


def fail(message):
    """Bad input: the message (naming the flag, file or value) on stderr, exit code 2."""
    print(message, file=sys.stderr)
    sys.exit(2)


def parse_list(text, convert=str):
    return [convert(x) for x in text.split(",") if x.strip()]


def knob_label(knobs):
    return ",".join(f"{k}={json.dumps(v) if not isinstance(v, str) else v}" for k, v in sorted(knobs.items())) or "defaults"


def scene_file(scene):
    """A bundled scene's name or a path -> the scene file (None for builtin)."""
    if scene == "builtin":
        return None
    if os.path.exists(scene):
        return os.path.abspath(scene)
    path = os.path.join(SCENES_DIR, scene if scene.endswith(".json") else scene + ".json")
    if not os.path.exists(path):
        fail(f"sweep.py: --scenes: '{scene}' is neither a file nor a bundled scene in {SCENES_DIR}")
    return path


def load_scene(path):
    with open(path) as f:
        return json.load(f)


def build_cells(args):
    """Every cell of the sweep, in a fixed order (the same flags give the same list everywhere)."""
    knobs = knobs_from_registry(args.tessera, args.full, args.registry)
    lights = parse_list(args.lights, int) if args.lights else (LIGHTS_FULL if args.full else [8, 32, 128])
    cells = []
    for scene in parse_list(args.scenes):
        path = scene_file(scene)
        if path is None:  # builtin: its own fixed drawing, MSAA as the knob, no technique or lights
            combos = [("builtin", {"msaa": m}, None) for m in (MSAA_FULL if args.full else MSAA_SMALL)]
        else:
            has_generators = bool(load_scene(path).get("generate"))
            combos = []
            for technique in (parse_list(args.techniques) if args.techniques else list(knobs)):
                if technique not in knobs:
                    fail(f"sweep.py: --techniques: '{technique}' has no knob list here (known: {', '.join(knobs)})")
                for k in knobs[technique]:
                    for n in (lights if has_generators else [None]):
                        combos.append((technique, k, n))
        for technique, k, n in combos:
            for precision in parse_list(args.precisions):
                if precision not in PRECISIONS:
                    fail(f"sweep.py: --precisions: '{precision}' is not one of {', '.join(PRECISIONS)}")
                cells.append({"scene": scene, "scene_file": path, "technique": technique, "knobs": k,
                              "lights": n, "precision": precision, "width": args.width, "height": args.height,
                              "threads": args.threads, "repeat": args.repeat, "warmup": args.warmup})
    for c in cells:
        c["group"] = group_id(c)
        c["id"] = f"{c['group']}.{c['precision']}"
    return cells


def group_id(c):
    """The cell's name without its precision: the cells of one group draw the same image."""
    knobs = re.sub(r"[^A-Za-z0-9=.,_-]", "", knob_label(c["knobs"])).replace(",", "+")
    lights = f"L{c['lights']}" if c["lights"] is not None else "Lscene"
    scene = re.sub(r"[^A-Za-z0-9_-]", "_", os.path.splitext(os.path.basename(c["scene"]))[0])
    return f"{scene}.{c['technique']}.{knobs}.{lights}.{c['width']}x{c['height']}.t{c['threads']}"


def write_scene_copy(cell, folder):
    """The scene file with the cell's options merged in, written into the cell's folder; model
    paths made absolute, since a scene file's model paths are relative to the file."""
    scene = load_scene(cell["scene_file"])
    base = os.path.dirname(cell["scene_file"])
    for m in scene.get("models", []):
        if "path" in m and not os.path.isabs(m["path"]):
            m["path"] = os.path.normpath(os.path.join(base, m["path"]))
    scene.pop("$schema", None)
    options = dict(scene.get("options", {}))
    options.update(cell["knobs"])
    if options:
        scene["options"] = options
    path = os.path.join(folder, "scene.json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path


STATS = {
    "scene": re.compile(r"^scene .*: (\d+) triangles, (\d+) draws, (\d+) lights,"),
    "load": re.compile(r"^load\s+([\d.]+) ms"),
    "textures": re.compile(r"^textures\s+([\d.]+) ms"),
    "pass": re.compile(r"^pass (\S+)\s+([\d.]+) ms"),
    "frame": re.compile(r"^frame\s+([\d.]+) ms"),
    "peak": re.compile(r"^peak memory\s+([\d.]+) MiB"),
}


def parse_stats(text):
    r = {"passes_ms": {}}
    for line in text.splitlines():
        if m := STATS["scene"].match(line):
            r["triangles"], r["draws"], r["scene_lights"] = map(int, m.groups())
        elif m := STATS["load"].match(line):
            r["load_ms"] = float(m.group(1))
        elif m := STATS["textures"].match(line):
            r["textures_ms"] = float(m.group(1))
        elif m := STATS["pass"].match(line):
            r["passes_ms"][m.group(1)] = float(m.group(2))
        elif m := STATS["frame"].match(line):
            r["frame_ms"] = float(m.group(1))
        elif m := STATS["peak"].match(line):
            r["peak_mib"] = float(m.group(1))
    if "frame_ms" not in r and r["passes_ms"]:  # builtin with --repeat 1 prints passes only
        r["frame_ms"] = round(sum(r["passes_ms"].values()), 3)
    return r


_COMMIT = None


def commit():
    global _COMMIT
    if _COMMIT is None:
        try:
            head = subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
            dirty = subprocess.run(["git", "-C", REPO, "diff", "--quiet", "HEAD"]).returncode != 0
            _COMMIT = head + ("-dirty" if dirty else "")
        except OSError:
            _COMMIT = "unknown"
    return _COMMIT


_BINARY = {}


def binary_id(path):
    """The first 12 hex digits of the tessera binary's SHA-256: which build rendered a cell, since
    the commit alone does not say (uncommitted work, rebuilds during a sweep)."""
    if path not in _BINARY:
        with open(path, "rb") as f:
            _BINARY[path] = hashlib.sha256(f.read()).hexdigest()[:12]
    return _BINARY[path]


def cell_dir(out, cell):
    return os.path.join(out, "cells", cell["id"])


def write_json(path, data):
    tmp = f"{path}.partial-{os.getpid()}"
    with open(tmp, "w") as f:
        json.dump(data, f, indent=1)
    os.replace(tmp, path)  # atomic: a result.json is complete or absent


def render_command(args, cell, folder):
    cmd = [args.tessera, "render"]
    if cell["scene_file"] is None:
        cmd += ["builtin", "--msaa", str(cell["knobs"]["msaa"])]
    else:
        cmd += [write_scene_copy(cell, folder), "--technique", cell["technique"]]
    if cell["lights"] is not None:
        cmd += ["--lights", str(cell["lights"])]
    cmd += ["--precision", cell["precision"], "--width", str(cell["width"]), "--height", str(cell["height"]),
            "--threads", str(cell["threads"]), "--repeat", str(cell["repeat"]), "--warmup", str(cell["warmup"]),
            "--stats", "--quiet", "--out", os.path.join(folder, "image.png")]
    if cell["precision"] == "reference":  # the float copy of the back buffer comes with --dump
        cmd += ["--dump", os.path.join(folder, "dump")]
    return cmd


def run_cell(args, cell):
    """Renders one cell unless its result.json exists; returns (result, skipped)."""
    folder = cell_dir(args.out, cell)
    result_path = os.path.join(folder, "result.json")
    if os.path.exists(result_path):
        with open(result_path) as f:
            return json.load(f), True
    os.makedirs(folder, exist_ok=True)
    cmd = render_command(args, cell, folder)
    start = time.time()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
        rc, stdout, stderr = proc.returncode, proc.stdout, proc.stderr
    except subprocess.TimeoutExpired as e:
        rc, stdout, stderr = None, e.stdout or "", f"timed out after {args.timeout} s"
        stdout = stdout.decode() if isinstance(stdout, bytes) else stdout
    result = {k: v for k, v in cell.items() if k != "scene_file"}
    result.update({"knob_label": knob_label(cell["knobs"]), "default_knobs": cell["knobs"] in ({}, {"msaa": 1}),
                   "command": shlex.join(cmd), "rc": rc, "wall_s": round(time.time() - start, 3),
                   "host": socket.gethostname(), "commit": commit(), "binary_sha256": binary_id(args.tessera), "time": time.strftime("%Y-%m-%dT%H:%M:%S%z")})
    if rc == 0:
        result.update(parse_stats(stdout))
        result["status"] = "ok"
        result["image"] = "image.png"
        ref = os.path.join(folder, "dump", "backbuffer.reference.exr")
        if os.path.exists(ref):  # keep the float back buffer, drop the other dumped buffers
            os.replace(ref, os.path.join(folder, "reference.exr"))
            result["reference_image"] = "reference.exr"
        shutil.rmtree(os.path.join(folder, "dump"), ignore_errors=True)
    elif rc == 2 and "--precision" in stderr:
        # tessera refuses this precision for these options before loading (e.g. precision
        # reference with AMD's or Intel's own shading): recorded, so a resumed sweep skips it.
        result["status"] = "unsupported"
        result["message"] = stderr.strip().splitlines()[0] if stderr.strip() else ""
    else:  # failed: no result.json, so the next run tries again
        with open(os.path.join(folder, "failed.log"), "w") as f:
            f.write(f"{shlex.join(cmd)}\nrc {rc}\n{stdout}\n{stderr}")
        result["status"] = "failed"
        result["message"] = (stderr.strip().splitlines() or ["(no message)"])[-1]
        return result, False
    write_json(result_path, result)
    return result, False


class Progress:
    """A one-line progress bar on stderr when it is a terminal; silent in pipes."""

    def __init__(self, total):
        self.total, self.done, self.start = total, 0, time.time()
        self.tty = sys.stderr.isatty()

    def update(self, label):
        self.done += 1
        if not self.tty:
            return
        width = 30
        filled = int(width * self.done / max(self.total, 1))
        elapsed = time.time() - self.start
        eta = elapsed / self.done * (self.total - self.done) if self.done else 0
        line = f"[{'#' * filled}{' ' * (width - filled)}] {self.done}/{self.total} eta {eta:4.0f} s  {label}"
        cols = shutil.get_terminal_size((100, 20)).columns
        sys.stderr.write("\r" + line[:cols - 1].ljust(cols - 1))
        sys.stderr.flush()

    def finish(self):
        if self.tty:
            sys.stderr.write("\r" + " " * (shutil.get_terminal_size((100, 20)).columns - 1) + "\r")
            sys.stderr.flush()


def run_cells(args, cells):
    """Runs the cells (--jobs at once); returns how many failed."""
    progress = Progress(len(cells))
    failed = 0

    def report(cell, result):
        nonlocal failed
        if result["status"] == "failed":
            failed += 1
            progress.finish()
            print(f"sweep.py: cell {cell['id']} failed: {result.get('message', '')}", file=sys.stderr)
        progress.update(cell["id"])

    if args.jobs <= 1:
        for cell in cells:
            report(cell, run_cell(args, cell)[0])
    else:
        from concurrent.futures import ThreadPoolExecutor
        with ThreadPoolExecutor(args.jobs) as pool:
            for cell, (result, _) in zip(cells, pool.map(lambda c: run_cell(args, c), cells)):
                report(cell, result)
    progress.finish()
    return failed


def diff(args, a, b):
    proc = subprocess.run([args.tessera, "diff", "--json", "--ignore-alpha", a, b], capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"tessera diff {a} {b}: {proc.stderr.strip()}")
    return json.loads(proc.stdout)


def cell_errors(args, folder, result, reference, exact):
    """Error against the group's reference (max abs, RMSE, PSNR of the image against the reference
    render's float back buffer) and differing pixels against the exact render; cached in errors.json
    while the images are unchanged."""
    image = os.path.join(folder, result["image"])
    inputs = {"image": image}
    if reference:
        inputs["reference"] = os.path.join(args.out, "cells", reference["id"], reference["reference_image"])
    if exact:
        inputs["exact"] = os.path.join(args.out, "cells", exact["id"], exact["image"])
    stamp = {k: [os.path.relpath(p, args.out), os.path.getmtime(p)] for k, p in inputs.items()}
    cache = os.path.join(folder, "errors.json")
    if os.path.exists(cache):
        with open(cache) as f:
            cached = json.load(f)
        if cached.get("inputs") == stamp:
            return cached["errors"]
    errors = {}
    if "reference" in inputs:
        d = diff(args, image, inputs["reference"])
        errors.update({"ref_max_abs": d["max_abs"], "ref_rmse": d["rmse"], "ref_psnr_db": d["psnr_db"],
                       "ref_differing_pixels": d["differing_pixels"]})
    if "exact" in inputs:
        d = diff(args, image, inputs["exact"])
        errors.update({"exact_differing_pixels": d["differing_pixels"], "exact_max_abs": d["max_abs"], "pixels": d["pixels"]})
    write_json(cache, {"inputs": stamp, "errors": errors})
    return errors


CSV_COLUMNS = ["id", "scene", "technique", "knob_label", "lights", "scene_lights", "precision", "width", "height", "threads",
               "repeat", "warmup", "status", "frame_ms", "passes_ms", "peak_mib", "load_ms", "textures_ms", "ref_max_abs",
               "ref_rmse", "ref_psnr_db", "ref_differing_pixels", "exact_differing_pixels", "exact_max_abs", "pixels",
               "host", "commit", "binary_sha256"]


def summarize(args):
    """Reads every cell's result.json under --out, adds the errors and writes summary.json/.csv."""
    cells_root = os.path.join(args.out, "cells")
    results = []
    for name in sorted(os.listdir(cells_root)) if os.path.isdir(cells_root) else []:
        path = os.path.join(cells_root, name, "result.json")
        if os.path.exists(path):
            with open(path) as f:
                results.append(json.load(f))
    by_group = {}
    for r in results:
        by_group.setdefault(r["group"], {})[r["precision"]] = r
    progress = Progress(len(results))
    for r in results:
        progress.update(f"errors {r['id']}")
        if r["status"] != "ok":
            continue
        group = by_group[r["group"]]
        reference = group.get("reference")
        reference = reference if reference and reference.get("reference_image") else None
        exact = group.get("exact")
        exact = exact if exact and exact["status"] == "ok" else None
        r.update(cell_errors(args, os.path.join(cells_root, r["id"]), r, reference, exact))
    progress.finish()
    write_json(os.path.join(args.out, "summary.json"), results)
    with open(os.path.join(args.out, "summary.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(CSV_COLUMNS)
        for r in results:
            row = []
            for c in CSV_COLUMNS:
                v = r.get(c, "")
                if c == "passes_ms":
                    v = ";".join(f"{k}={ms}" for k, ms in v.items()) if v else ""
                row.append("" if v is None else v)
            w.writerow(row)
    ok = sum(r["status"] == "ok" for r in results)
    print(f"sweep.py: {len(results)} cells ({ok} ok, {len(results) - ok} unsupported) -> "
          f"{os.path.join(args.out, 'summary.json')}, summary.csv")


def sweep_flags(args):
    """The flags that define the sweep, with absolute paths, for --list-cells' commands."""
    flags = ["--tessera", os.path.abspath(args.tessera), "--out", os.path.abspath(args.out), "--scenes", args.scenes,
             "--techniques", args.techniques, "--precisions", args.precisions, "--width", str(args.width),
             "--height", str(args.height), "--repeat", str(args.repeat), "--warmup", str(args.warmup),
             "--threads", str(args.threads), "--timeout", str(args.timeout)]
    if args.lights:
        flags += ["--lights", args.lights]
    if args.full:
        flags.append("--full")
    if args.registry:
        flags += ["--registry", os.path.abspath(args.registry)]
    return flags


def main():
    ap = argparse.ArgumentParser(description="Speed/accuracy sweep of tessera render (see the header of this file).")
    ap.add_argument("--tessera", default=os.environ.get("TESSERA", os.path.join(REPO, "build-sweep", "tessera")),
                    help="the tessera binary (default: $TESSERA, else build-sweep/tessera)")
    ap.add_argument("--out", default=os.path.join(REPO, "out", "sweep"), help="output folder (default out/sweep, git-ignored)")
    ap.add_argument("--scenes", default="sponza-large-lights,builtin",
                    help="bundled scene names or scene files, and/or builtin (default: %(default)s)")
    ap.add_argument("--techniques", default="",
                    help="techniques for the scene files (builtin has its own; default: every ready technique of the "
                         "registry but inspection views)")
    ap.add_argument("--precisions", default="reference,exact,fast")
    ap.add_argument("--lights", default="", help="light counts for scenes with light generators "
                    "(default 8,32,128; with --full 1,2,4,...,1024)")
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=180)
    ap.add_argument("--repeat", type=int, default=3, help="timed frames per cell; medians are reported (default 3)")
    ap.add_argument("--warmup", type=int, default=1, help="untimed frames before them (default 1)")
    ap.add_argument("--threads", type=int, default=0, help="tessera --threads (0: all cores)")
    ap.add_argument("--full", action="store_true", help="every knob set and light counts 1..1024")
    ap.add_argument("--jobs", type=int, default=1, help="cells at once on this machine (default 1: timings stay clean)")
    ap.add_argument("--timeout", type=int, default=1800, help="seconds per cell before it counts as failed")
    ap.add_argument("--registry", default="", help="read the technique registry from this file (the JSON of "
                    "`tessera options --json`, or of a program that registered its own techniques) instead of --tessera")
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--list-cells", action="store_true", help="print one command per cell (for GNU parallel) and exit")
    mode.add_argument("--count-cells", action="store_true", help="print the number of cells (for a Slurm job array) and exit")
    mode.add_argument("--print-cells", action="store_true", help="print each cell's id (scene.technique.knobs.lights."
                      "size.threads.precision), one per line, and exit")
    mode.add_argument("--cell", help="run only these cells (indices into the list, comma-separated); no summary")
    mode.add_argument("--summarize", action="store_true", help="only compute errors and write the summaries")
    args = ap.parse_args()
    for flag in ("width", "height", "repeat"):
        if getattr(args, flag) < 1:
            fail(f"sweep.py: --{flag}: {getattr(args, flag)} must be >= 1")
    if args.warmup < 0 or args.threads < 0 or args.jobs < 1:
        fail("sweep.py: --warmup and --threads must be >= 0, --jobs >= 1")

    if args.summarize:
        summarize(args)
        return 0
    cells = build_cells(args)
    if args.count_cells:
        print(len(cells))
        return 0
    if args.print_cells:
        for c in cells:
            print(c["id"])
        return 0
    if args.list_cells:
        base = ["python3", os.path.abspath(__file__)] + sweep_flags(args)
        try:
            for i in range(len(cells)):
                print(shlex.join(base + ["--cell", str(i)]))
        except BrokenPipeError:  # e.g. piped into head
            sys.stderr.close()
        return 0
    if not os.access(args.tessera, os.X_OK):
        fail(f"sweep.py: --tessera: {args.tessera} is not an executable (build it: ninja -C build-sweep tessera_cli)")
    os.makedirs(args.out, exist_ok=True)
    if args.cell is not None:
        try:
            chosen = [cells[int(i)] for i in args.cell.split(",")]
        except (ValueError, IndexError):
            fail(f"sweep.py: --cell: '{args.cell}' is not a list of indices in 0..{len(cells) - 1}")
        return 1 if run_cells(args, chosen) else 0
    failed = run_cells(args, cells)
    summarize(args)
    if failed:
        print(f"sweep.py: {failed} cells failed (see cells/*/failed.log); run again to retry them", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
