#!/usr/bin/python3
"""Figures of a liftoff_bench run: run time against error, and scaling.

Usage: /usr/bin/python3 verification/bench/plot_bench.py BENCH_DIR [--out DIR]

Reads BENCH_DIR/accuracy.csv and BENCH_DIR/scaling.csv (written by liftoff_bench) and writes
accuracy.png (one row per seed beam scene: contact-limit error and maximum-deflection error
against the median wall time, one line per method, the 1e-6 L target dashed) and scaling.png
(whole-process wall time and peak memory against the number of elements, log-log, with each
method's fitted exponent in the legend) into --out (default BENCH_DIR).
"""
import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {"dual": ("tab:blue", "o"), "primal": ("tab:orange", "s"), "fast": ("tab:green", "^"),
         "ritz": ("tab:red", "D"), "dolfinx": ("tab:purple", "v"), "bilateral": ("tab:gray", "x")}


def read_csv(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def finite(x):
    try:
        v = float(x)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) and v > 0 else None


def fitted_exponent(xs, ys):
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x > 0 and y > 0]
    if len(pts) < 2:
        return float("nan")
    n = len(pts)
    sx = sum(p[0] for p in pts)
    sy = sum(p[1] for p in pts)
    sxx = sum(p[0] ** 2 for p in pts)
    sxy = sum(p[0] * p[1] for p in pts)
    return (n * sxy - sx * sy) / (n * sxx - sx * sx)


def plot_accuracy(rows, out):
    scenes = sorted({r["scene"] for r in rows})
    if not scenes:
        return None
    fig, axes = plt.subplots(len(scenes), 2, figsize=(12, 4.5 * len(scenes)), squeeze=False)
    for i, scene in enumerate(scenes):
        for j, (key, label) in enumerate((("limit_error", "contact-limit error / L"),
                                          ("w_max_error", "max deflection, relative error"))):
            ax = axes[i][j]
            for method in STYLE:
                pts = [(finite(r["median_s"]), finite(r[key]), r["size"]) for r in rows
                       if r["scene"] == scene and r["method"] == method]
                pts = [p for p in pts if p[0] and p[1]]
                if not pts:
                    continue
                colour, marker = STYLE[method]
                unit = "modes" if method == "ritz" else "elements"
                ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker=marker, color=colour,
                          label=f"{method} ({pts[0][2]}..{pts[-1][2]} {unit})")
            if key == "limit_error":
                ax.axhline(1e-6, color="k", ls="--", lw=0.8, label="1e-6 L")
            ax.set_xlabel("median wall time of a solve [s]" + (" (dolfinx: solve only)" if j == 0 else ""))
            ax.set_ylabel(label)
            ax.set_title(scene)
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(out, "accuracy.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_scaling(rows, out):
    methods = [m for m in STYLE if any(r["method"] == m for r in rows)]
    if not methods:
        return None
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    for method in methods:
        pts = [(int(r["elements"]), finite(r["wall_s"]), finite(r["peak_rss_mb"]), r["exit_code"])
               for r in rows if r["method"] == method]
        colour, marker = STYLE[method]
        big = pts[len(pts) // 2:] if len(pts) >= 4 else pts  # the larger half, as liftoff_bench fits
        for k, ax, ylabel in ((1, axes[0], "whole-process wall time [s]"), (2, axes[1], "peak resident memory [MiB]")):
            good = [p for p in pts if p[k]]
            if not good:
                continue
            p_fit = fitted_exponent([p[0] for p in big if p[k]], [p[k] for p in big if p[k]])
            ax.loglog([p[0] for p in good], [p[k] for p in good], marker=marker, color=colour,
                      label=f"{method}: ~N^{p_fit:.2f}")
            failed = [p for p in good if p[3] != "0"]
            if failed:
                ax.loglog([p[0] for p in failed], [p[k] for p in failed], ls="none", marker="o", mfc="none",
                          mec="r", ms=11, label=f"{method}: refused (exit != 0)")
            ax.set_xlabel("elements")
            ax.set_ylabel(ylabel)
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=8)
    axes[0].set_title("time (exponent fitted on the larger half of the sizes)")
    axes[1].set_title("peak memory")
    fig.tight_layout()
    path = os.path.join(out, "scaling.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("bench_dir")
    ap.add_argument("--out", help="where to write the PNGs (default: bench_dir)")
    opts = ap.parse_args(argv)
    out = opts.out or opts.bench_dir
    os.makedirs(out, exist_ok=True)
    written = []
    for name, plot in (("accuracy.csv", plot_accuracy), ("scaling.csv", plot_scaling)):
        path = os.path.join(opts.bench_dir, name)
        if not os.path.exists(path):
            print(f"plot_bench: {path} not found (that section was not run); skipped", file=sys.stderr)
            continue
        result = plot(read_csv(path), out)
        if result:
            written.append(result)
    for path in written:
        print(path)
    return 0 if written else 2


if __name__ == "__main__":
    sys.exit(main())
