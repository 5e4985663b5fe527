#!/usr/bin/env python3
# Draws bench/sweep.py's summary.json as PNGs: frame time against light count per technique (laid
# out like the 3dgep article "Forward vs Deferred vs Forward+ Rendering with DirectX 11"), and a
# Pareto chart of frame time against RMSE to the reference render for every mode and option set.
# Needs matplotlib (Debian python3-matplotlib: run it with /usr/bin/python3).
#
# Several --summary files (repeated runs of one sweep on a shared, noisy machine) are merged cell by
# cell, keeping each cell's fastest run: contention only ever adds time, and the errors are
# deterministic (identical in every run).
#
# Usage: plot.py [--summary out/sweep/summary.json ...] [--out bench/plots] [--pareto-lights N]
import argparse
import json
import math
import os
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
except ImportError:
    sys.exit("plot.py: needs matplotlib: apt-get install python3-matplotlib, then run it with /usr/bin/python3")

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def fail(message):
    """Bad input: the message (naming the flag, file or value) on stderr, exit code 2."""
    print(message, file=sys.stderr)
    sys.exit(2)
TECHNIQUE_ORDER = ["forward", "deferred", "deferred-killzone", "forward-plus", "tiled-deferred", "forward-plus-amd",
                   "builtin", "preview"]
COLORS = {t: c for t, c in zip(TECHNIQUE_ORDER, plt.get_cmap("tab10").colors)}
MARKERS = {"reference": "s", "exact": "o", "fast": "^"}
LINES = {"exact": "-", "fast": "--", "reference": ":"}


def load(paths):
    """The finished cells of every summary, one per cell id: the run with the lowest frame time."""
    best = {}
    for path in paths:
        try:
            with open(path) as f:
                cells = json.load(f)
        except OSError as e:
            fail(f"plot.py: --summary: cannot read {path}: {e.strerror} (run bench/sweep.py first)")
        except json.JSONDecodeError as e:
            fail(f"plot.py: --summary: {path} is not JSON: {e}")
        for c in cells:
            if c.get("status") == "ok" and c.get("frame_ms") is not None:
                if c["id"] not in best or c["frame_ms"] < best[c["id"]]["frame_ms"]:
                    best[c["id"]] = c
    return list(best.values())


def scene_name(c):
    return os.path.splitext(os.path.basename(c["scene"]))[0]


def plain_log_axis(axis):
    """Log scale with plain numbers (3, 30, 300) rather than powers of ten."""
    axis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(matplotlib.ticker.FuncFormatter(
        lambda v, _: f"{v:g}" if f"{v:.0e}"[0] in "25" else ""))


def save(fig, path):
    fig.savefig(path, dpi=80)
    plt.close(fig)
    print(f"plot.py: wrote {path} ({os.path.getsize(path) // 1024} KiB)")


def time_vs_lights(cells, out, runs):
    """One panel per scene with light generators: frame ms against light count, log-log, one line
    per technique (its default options) and precision (exact solid, fast dashed)."""
    scenes = sorted({scene_name(c) for c in cells if c.get("lights") is not None})
    if not scenes:
        print("plot.py: no cells with a light count (scenes with light generators): no time-vs-lights chart")
        return
    fig, axes = plt.subplots(1, len(scenes), figsize=(6.4 * len(scenes), 4.6), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        series = {}
        for c in cells:
            if scene_name(c) == scene and c.get("lights") is not None and c.get("default_knobs") and c["precision"] != "reference":
                series.setdefault((c["technique"], c["precision"]), []).append((c["lights"], c["frame_ms"]))
        for (technique, precision), points in sorted(series.items(), key=lambda kv: (TECHNIQUE_ORDER.index(kv[0][0])
                                                                                     if kv[0][0] in TECHNIQUE_ORDER else 99, kv[0][1])):
            points.sort()
            ax.plot([p[0] for p in points], [p[1] for p in points], LINES.get(precision, "-"), marker=MARKERS.get(precision, "o"),
                    color=COLORS.get(technique), label=f"{technique} ({precision})", markersize=4)
        ax.set_xscale("log", base=2)
        ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        ax.set_yscale("log")
        plain_log_axis(ax.yaxis)
        ax.set_xlabel("lights")
        ax.set_ylabel("frame time (ms, median)")
        sample = next(c for c in cells if scene_name(c) == scene)
        best = f", fastest of {runs} runs" if runs > 1 else ""
        ax.set_title(f"{scene}, {sample['width']}x{sample['height']}, default options{best}", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    save(fig, os.path.join(out, "time-vs-lights.png"))


def pareto_front(points):
    """The points no other point beats on both error and time (lower is better for both)."""
    front, best = [], math.inf
    for p in sorted(points, key=lambda p: (p[0], p[1])):
        if p[1] < best:
            front.append(p)
            best = p[1]
    return front


def pareto(cells, out, lights):
    """One panel per scene: every cell (technique x options x precision) at one light count as a
    point (RMSE against the reference render, frame ms), with the Pareto front drawn through."""
    panels = []
    for scene in sorted({scene_name(c) for c in cells}):
        group = [c for c in cells if scene_name(c) == scene and c.get("ref_rmse") is not None]
        counts = sorted({c["lights"] for c in group if c.get("lights") is not None})
        if counts:
            n = lights if lights in counts else counts[len(counts) // 2]
            group = [c for c in group if c.get("lights") == n]
            title = f"{scene}, {n} lights"
        else:
            title = scene
        if group:
            panels.append((title, group))
    if not panels:
        print("plot.py: no cells with an error against a reference render: no Pareto chart")
        return
    fig, axes = plt.subplots(1, len(panels), figsize=(6.0 * len(panels), 5.0), squeeze=False)
    for ax, (title, group) in zip(axes[0], panels):
        floor = min((c["ref_rmse"] for c in group if c["ref_rmse"] > 0), default=1e-3) / 2
        points = []
        for c in group:
            x = max(c["ref_rmse"], floor)
            points.append((x, c["frame_ms"], c))
            ax.scatter(x, c["frame_ms"], marker=MARKERS.get(c["precision"], "o"), color=COLORS.get(c["technique"]), s=28,
                       edgecolors="black" if c.get("default_knobs") else "none", linewidths=0.6)
        front = pareto_front(points)
        ax.step([p[0] for p in front], [p[1] for p in front], where="post", color="gray", alpha=0.6, linewidth=1)
        for x, y, c in front:
            label = c["technique"] + ("" if c.get("default_knobs") else f" {c['knob_label']}")
            ax.annotate(f"{label} ({c['precision']})", (x, y), fontsize=6, xytext=(4, 2), textcoords="offset points")
        xs = [p[0] for p in points]
        if max(xs) / min(xs) > 4:
            ax.set_xscale("log")
            plain_log_axis(ax.xaxis)
        else:  # the modes often differ in the 4th digit: a linear axis with plain numbers
            ax.ticklabel_format(axis="x", style="plain", useOffset=False)
            ax.xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%.5f"))
            ax.tick_params(axis="x", labelrotation=20, labelsize=7)
        ax.set_yscale("log")
        plain_log_axis(ax.yaxis)
        ax.set_xlabel("RMSE against the reference render (8-bit code units)")
        ax.set_ylabel("frame time (ms, median)")
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
    # One legend for all panels: colour = technique, marker = precision, black edge = default options.
    techniques = sorted({c["technique"] for _, g in panels for c in g},
                        key=lambda t: TECHNIQUE_ORDER.index(t) if t in TECHNIQUE_ORDER else 99)
    handles = [plt.Line2D([], [], linestyle="", marker="o", color=COLORS.get(t), label=t) for t in techniques]
    handles += [plt.Line2D([], [], linestyle="", marker=m, color="black", fillstyle="none", label=p) for p, m in MARKERS.items()]
    handles.append(plt.Line2D([], [], linestyle="", marker="o", color="white", markeredgecolor="black", label="default options"))
    fig.legend(handles=handles, loc="lower center", ncol=min(len(handles), 6), fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    save(fig, os.path.join(out, "pareto.png"))


def table(cells, lights):
    """A markdown table of the Pareto chart's cells: per scene, technique and options, the frame
    time of each precision, the peak memory, and the error against the reference render's float
    back buffer of each mode's 8-bit image (the reference's own PNG: its 8-bit quantization)."""
    groups = {}
    for c in cells:
        if c.get("lights") in (lights, None):
            groups.setdefault((scene_name(c), c["technique"], c["knob_label"], c.get("lights")), {})[c["precision"]] = c

    def num(v, fmt):
        return "–" if v is None else format(v, fmt)

    def err(c):
        return "–" if not c or c.get("ref_rmse") is None else f"{c['ref_rmse']:.4f} ({c['ref_max_abs']:.2f})"

    print(f"| scene | technique | options | frame ms: reference / exact / fast | peak MiB | RMSE (max): reference's PNG | "
          f"exact | fast | fast ≠ exact (px) |")
    print("|---|---|---|---|---|---|---|---|---|")
    order = lambda k: (k[0], TECHNIQUE_ORDER.index(k[1]) if k[1] in TECHNIQUE_ORDER else 99, k[2] != "defaults", k[2])
    for key in sorted(groups, key=order):
        g = groups[key]
        times = " / ".join(num(g[p]["frame_ms"] if p in g else None, ".0f") for p in ("reference", "exact", "fast"))
        peak = max(c.get("peak_mib", 0) for c in g.values())
        scene = key[0] + (f", {key[3]} lights" if key[3] is not None else "")
        fast = g.get("fast")
        print(f"| {scene} | {key[1]} | {key[2]} | {times} | {peak:.0f} | {err(g.get('reference'))} | {err(g.get('exact'))} | {err(fast)} | "
              f"{num(fast.get('exact_differing_pixels') if fast else None, 'd')} |")


def main():
    ap = argparse.ArgumentParser(description="Charts of a bench/sweep.py run (see the header of this file).")
    ap.add_argument("--summary", nargs="+", default=[os.path.join(REPO, "out", "sweep", "summary.json")],
                    help="summary.json of one or more runs of the sweep (default out/sweep/summary.json)")
    ap.add_argument("--out", default=os.path.join(REPO, "bench", "plots"))
    ap.add_argument("--pareto-lights", type=int, default=32, help="light count of the Pareto chart's generated-light scenes "
                    "(default 32; else the middle count present)")
    ap.add_argument("--table", action="store_true", help="also print a markdown table of the Pareto chart's cells")
    args = ap.parse_args()
    cells = load(args.summary)
    if not cells:
        fail(f"plot.py: {', '.join(args.summary)} hold no finished cells")
    os.makedirs(args.out, exist_ok=True)
    time_vs_lights(cells, args.out, len(args.summary))
    pareto(cells, args.out, args.pareto_lights)
    if args.table:
        table(cells, args.pareto_lights)
    return 0


if __name__ == "__main__":
    sys.exit(main())
