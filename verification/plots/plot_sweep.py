#!/usr/bin/python3
"""Figures of a `liftoff sweep` HDF5 file, in the style of the seed paper's Figures 4 to 7.

    /usr/bin/python3 verification/plots/plot_sweep.py SWEEP.h5 [--out PREFIX]

writes PREFIX_deflection.png (deflection along the member for every case, overlaid, one panel
per method: primal, dual and Ritz side by side for `--method all`) and PREFIX_reaction.png (the
foundation reaction likewise). w > 0 is into the foundation and is drawn downward, as the
member moves.
"""
import argparse
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with h5py.File(path, "r") as f:
        keys = f.attrs["keys"].split(",")
        values = f["values"][()].reshape(-1, len(keys))
        cases = []
        for i, name in enumerate(sorted(f["cases"].keys())):
            group = f["cases"][name]
            methods = {}
            for method in group.keys():
                m = group[method]
                if "fields" not in m:
                    continue
                methods[method] = {
                    "x": m["fields/coordinate"][()],
                    "w": m["fields/w"][()],
                    "reaction": m["fields/reaction"][()],
                    "regions": m["contact_regions"][()],
                    "coordinate": m.attrs["coordinate"],
                }
            cases.append((values[i], methods))
    return keys, cases


def label(keys, values):
    return ", ".join(f"{k} = {v:.4g}" for k, v in zip(keys, values))


def figure(keys, cases, field, ylabel, path):
    methods = [m for m in ("primal", "dual", "ritz") if any(m in c[1] for c in cases)]
    if not methods:
        sys.exit("plot_sweep: no solved case in the file")
    fig, axes = plt.subplots(1, len(methods), figsize=(5 * len(methods), 4), sharey=True, squeeze=False)
    for ax, method in zip(axes[0], methods):
        for values, results in cases:
            if method not in results:
                continue
            r = results[method]
            ax.plot(r["x"], r[field], label=label(keys, values))
        ax.axhline(0.0, color="black", linewidth=0.5)
        coordinate = cases[0][1][method]["coordinate"] if method in cases[0][1] else "x"
        ax.set_xlabel("theta (degrees)" if coordinate == "theta_deg" else "x")
        ax.set_title(method)
        ax.grid(True, alpha=0.3)
    axes[0][0].set_ylabel(ylabel)
    if field == "w":
        axes[0][0].invert_yaxis()  # w > 0 into the foundation: drawn downward
    axes[0][-1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sweep")
    parser.add_argument("--out", default=None, help="prefix of the PNG files (default: the HDF5 name)")
    args = parser.parse_args()
    prefix = args.out or args.sweep.rsplit(".", 1)[0]
    keys, cases = read(args.sweep)
    figure(keys, cases, "w", "deflection w (> 0 into the foundation)", prefix + "_deflection.png")
    figure(keys, cases, "reaction", "foundation reaction (force per length)", prefix + "_reaction.png")


if __name__ == "__main__":
    main()
