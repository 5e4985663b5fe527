#!/usr/bin/env python3
# Draws the curve tables of bench/RESULTS.md as PNGs in bench/plots/: the tables themselves are the
# data (each is found by the heading above it and its header row), so a plot can never disagree
# with the numbers beside it. Re-run after editing a table. Needs matplotlib (Debian
# python3-matplotlib): /usr/bin/python3 bench/plot_tables.py [--results bench/RESULTS.md] [--out bench/plots]
import argparse
import os
import re
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit("plot_tables.py: needs matplotlib: apt-get install python3-matplotlib, then run it with /usr/bin/python3")

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def fail(message):
    sys.exit("plot_tables.py: " + message)


def table_after(lines, heading, header_start):
    """The rows (lists of cell strings) of the first table after `heading` whose header row starts with `header_start`."""
    try:
        start = next(i for i, l in enumerate(lines) if l.strip() == heading)
    except StopIteration:
        fail("no heading '%s' in the results file" % heading)
    for i in range(start + 1, len(lines)):
        if lines[i].startswith("|") and lines[i].strip("| \n").startswith(header_start):
            header = [c.strip() for c in lines[i].strip().strip("|").split("|")]
            rows = []
            for l in lines[i + 2:]:
                if not l.startswith("|"):
                    break
                rows.append([c.strip() for c in l.strip().strip("|").split("|")])
            return header, rows
    fail("no table starting '%s' after '%s'" % (header_start, heading))


def number(cell):
    """The first number in a cell ('177.4', '**9.8**', '22.4, 19.0' -> 22.4, '–' -> None)."""
    m = re.search(r"[-+]?\d+(?:\.\d+)?", cell.replace("**", ""))
    return float(m.group(0)) if m else None


def article_sweep(lines, out):
    header, rows = table_after(lines, "### The article's sweep on the H200, beside the article's GTX 680", "lights")
    lights = [number(r[0]) for r in rows]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for k, (title, first) in enumerate([("forward, large lights", 1), ("deferred, small lights", 4), ("Forward+, small lights", 7)]):
        ax = axes[k]
        for j, label, style in [(first, "GTX 680 (the article)", "o-"), (first + 1, "NVIDIA H200 (GLSL ports)", "s-"),
                                (first + 2, "tessera, 16 CPU threads", "^-")]:
            points = [(x, number(r[j])) for x, r in zip(lights, rows) if number(r[j]) is not None]
            ax.plot([p[0] for p in points], [p[1] for p in points], style, label=label)
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xlabel("lights")
        ax.set_ylabel("frame ms (1280x720)")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("The 3dgep experiment: frame time against light count")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "article-sweep.png"), dpi=90)
    plt.close(fig)


def scaling(lines, out):
    heading = "## SIMD blocks, the fast light loop's FMA/rsqrt, and 16-core scaling (device machine)"
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    for ax, (first, name_cols, title) in zip(axes, [("workload", 1, "raster_bench (ms per frame)"),
                                                    ("technique", 2, "Sponza frames, 1280x720")]):
        header, rows = table_after(lines, heading, first)
        threads = [number(h) for h in header[name_cols:] if number(h) is not None and h.strip().isdigit()]
        for r in rows:
            ms = [number(c) for c in r[name_cols:name_cols + len(threads)]]
            label = " ".join(r[:name_cols])
            ax.plot(threads, [ms[0] / m for m in ms], "o-", label=label)
        ax.plot(threads, threads, "k--", alpha=0.4, label="ideal")
        ax.set_xlabel("threads")
        ax.set_ylabel("speed-up over 1 thread")
        ax.set_title(title)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Strong scaling on the 16-core device host")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "scaling.png"), dpi=90)
    plt.close(fig)


def culling(lines, out):
    header, rows = table_after(lines, "## Thread scaling of the culling to 16 cores (device machine)", "threads")
    threads = [number(r[0]) for r in rows]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for j in range(1, len(header)):
        ax.plot(threads, [number(r[j]) for r in rows], "o-", label=header[j].replace(" (run 1, run 2)", ""))
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xlabel("threads")
    ax.set_ylabel("culling ms (first run)")
    ax.set_title("Light culling, 16384 small lights, by tile size and culler")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "culling-scaling.png"), dpi=90)
    plt.close(fig)


def culling_vs_lights(lines, out):
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.5))
    for scenario, marker in [("large", "o"), ("small", "s")]:
        heading = "**forward-plus light culling, %s lights, 16 px tiles** (ms; culling pass only)" % scenario
        header, rows = table_after(lines, heading, "lights")
        lights = [number(r[0]) for r in rows]
        axes[0].plot(lights, [number(r[2]) for r in rows], marker + "-", label="tessera, 2 threads, %s lights" % scenario)
        gtx = [(x, number(r[6])) for x, r in zip(lights, rows) if number(r[6]) is not None]
        axes[0].plot([g[0] for g in gtx], [g[1] for g in gtx], marker + "--", label="GTX 680 (the article), %s lights" % scenario)
        axes[1].plot(lights, [number(r[5]) for r in rows], marker + "-", label="%s lights" % scenario)
    for ax in axes:
        ax.set_xscale("log", base=2)
        ax.set_xlabel("lights")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_yscale("log")
    axes[0].set_ylabel("culling ms (1280x720, 16 px tiles)")
    axes[0].set_title("Forward+ light culling time")
    axes[1].set_ylabel("false positives, % of listed entries")
    axes[1].set_title("Lights listed in a tile that reach none of its pixels")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "culling-vs-lights.png"), dpi=90)
    plt.close(fig)


def culling_by_tile(lines, out):
    header, rows = table_after(lines, "**Tile size** (forward-plus, culling ms at 1 / 2 threads, opaque lights per tile mean / max, "
                                      "false positives)", "scenario")
    sizes = [number(h) for h in header[2:]]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for r in rows:
        # "29.63 / 15.87 ms; ...": the second number is the 2-thread time
        ms = [float(re.findall(r"\d+(?:\.\d+)?", c)[1]) for c in r[2:]]
        ax.plot(sizes, ms, "o-", label="%s lights, %s" % (r[1], r[0]))
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xticks(sizes)
    ax.set_xticklabels(["%d px" % s for s in sizes])
    ax.set_xlabel("tile edge")
    ax.set_ylabel("culling ms, 2 threads")
    ax.set_title("Forward+ culling time by tile size (Sponza 1280x720)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "culling-by-tile.png"), dpi=90)
    plt.close(fig)


def pass_times(cell):
    """'clear 1.34, gbuffer 377.02, lights 665.57' -> [('clear', 1.34), ('gbuffer', 377.02), ...]"""
    out = []
    for part in cell.split(","):
        m = re.match(r"\s*(.+?)\s+([-+]?\d+(?:\.\d+)?)\s*$", part)
        if m:
            out.append((m.group(1), float(m.group(2))))
    return out


def deferred_family(lines, out):
    """Stacked per-pass bars of the G-buffer techniques (issue 14's two tables), one panel per scenario."""
    _, cookbook = table_after(lines, "## deferred-cookbook beside deferred and forward (issue 14)", "technique")
    _, classic = table_after(lines, "### deferred-classic and light-prepass (PR&C D3D11 ch. 11), same machine, commit after "
                                    "`deferred-classic`", "technique")
    bars = {"large": [], "small": []}
    for r in cookbook:  # technique | scenario | lights | passes | frame
        bars[r[1]].append(("%s, %s lights" % (r[0], r[2]), pass_times(r[3])))
    for r in classic:  # technique | scenario | lights | geometry | passes | frame
        bars[r[1]].append(("%s (%s), %s lights" % (r[0], r[3], r[2]), pass_times(r[4])))
    names = []
    for rows in bars.values():
        for _, passes in rows:
            for n, _ in passes:
                if n not in names:
                    names.append(n)
    colours = dict(zip(names, plt.rcParams["axes.prop_cycle"].by_key()["color"] * 3))
    fig, axes = plt.subplots(1, 2, figsize=(16, 7))
    for ax, scenario in zip(axes, ["large", "small"]):
        rows = bars[scenario]
        for i, (label, passes) in enumerate(rows):
            left = 0.0
            for n, ms in passes:
                ax.barh(i, ms, left=left, color=colours[n], label=n if i == 0 or n not in [p for p, _ in rows[0][1]] else None)
                left += ms
        # Linear, so that the stacks read as shares; frames past 5 s are cut and labelled.
        limit = 5000.0
        for i, (label, passes) in enumerate(rows):
            total = sum(ms for _, ms in passes)
            if total > limit:
                ax.text(limit * 0.98, i, "%.0f ms" % total, va="center", ha="right", fontsize=7, color="white")
        ax.set_xlim(0, min(limit, max(sum(ms for _, ms in p) for _, p in rows) * 1.05))
        ax.set_yticks(range(len(rows)))
        ax.set_yticklabels([label for label, _ in rows], fontsize=7)
        ax.invert_yaxis()
        ax.set_xlabel("frame ms, 2 threads, stacked by pass")
        ax.set_title("%s lights, Sponza 1280x720" % scenario)
        ax.grid(True, axis="x", alpha=0.3)
        handles, labels = ax.get_legend_handles_labels()
        seen = {}
        for h, l in zip(handles, labels):
            seen.setdefault(l, h)
        ax.legend(seen.values(), seen.keys(), fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "deferred-family-passes.png"), dpi=80)
    plt.close(fig)


def msaa(lines, out):
    """1x against 4x frame time per technique (the MSAA table), with the per-sample share."""
    _, rows = table_after(lines, "## MSAA: what per-sample shading costs (issue 14)", "technique")
    techniques = []
    for r in rows:
        if r[0] not in techniques:
            techniques.append(r[0])
    fig, ax = plt.subplots(figsize=(9, 4.5))
    for k, samples in enumerate(["1", "4"]):
        ms = [next((number(r[3]) for r in rows if r[0] == t and r[1] == samples), 0.0) for t in techniques]
        ax.bar([i + 0.4 * k for i in range(len(techniques))], ms, width=0.4, label="%sx" % samples)
    ax.set_xticks([i + 0.2 for i in range(len(techniques))])
    ax.set_xticklabels(techniques, fontsize=8, rotation=15)
    ax.set_ylabel("frame ms, 2 threads")
    ax.set_title("MSAA 1x and 4x, Sponza 1280x720, 64 small lights")
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "msaa.png"), dpi=90)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--results", default=os.path.join(REPO, "bench", "RESULTS.md"))
    ap.add_argument("--out", default=os.path.join(REPO, "bench", "plots"))
    args = ap.parse_args()
    with open(args.results, encoding="utf-8") as f:
        lines = f.read().splitlines()
    os.makedirs(args.out, exist_ok=True)
    article_sweep(lines, args.out)
    scaling(lines, args.out)
    culling(lines, args.out)
    culling_vs_lights(lines, args.out)
    culling_by_tile(lines, args.out)
    deferred_family(lines, args.out)
    msaa(lines, args.out)
    print("plot_tables.py: wrote article-sweep.png, scaling.png, culling-scaling.png, culling-vs-lights.png, "
          "culling-by-tile.png, deferred-family-passes.png, msaa.png to " + args.out)


if __name__ == "__main__":
    main()
