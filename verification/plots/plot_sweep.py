#!/usr/bin/python3
"""Figures of a `liftoff sweep` HDF5 file, in the style of the seed paper's Figures 4 to 7.

    /usr/bin/python3 verification/plots/plot_sweep.py SWEEP.h5 [--out PREFIX]

writes PREFIX_deflection.png (deflection along the member for every case, overlaid, one panel
per method: primal, dual and Ritz side by side for `--method all`) and PREFIX_reaction.png (the
foundation reaction likewise). With --dolfinx, each case's scene (stored in the file) is also
solved by the independent dolfinx reference (verification/dolfinx/penalty_reference.py) and drawn
in a panel of its own. w > 0 is into the foundation and is drawn downward, as the member moves.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

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
            scene = next((group[m]["scene"][()] for m in group.keys() if "scene" in group[m]), None)
            cases.append((values[i], methods, scene.decode() if isinstance(scene, bytes) else scene))
    return keys, cases


def add_dolfinx(cases, elements):
    """Solves every case's scene with the dolfinx reference and adds it as a method."""
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "dolfinx", "penalty_reference.py")
    with tempfile.TemporaryDirectory() as tmp:
        for values, methods, scene in cases:
            if scene is None:
                continue
            path, out = os.path.join(tmp, "case.toml"), os.path.join(tmp, "case.json")
            with open(path, "w") as f:
                f.write(scene)
            p = subprocess.run(["/usr/bin/python3", script, path, "--elements", str(elements), "--json", out],
                               capture_output=True, text=True)
            if p.returncode != 0:
                continue
            with open(out) as f:
                d = json.load(f)
            methods["dolfinx"] = {"x": d["fields"]["coordinate"], "w": d["fields"]["w"],
                                  "reaction": d["fields"]["reaction"], "regions": d["contact_regions"],
                                  "coordinate": d["coordinate"]}


def label(keys, values):
    return ", ".join(f"{k} = {v:.4g}" for k, v in zip(keys, values))


def figure(keys, cases, field, ylabel, path):
    methods = [m for m in ("primal", "dual", "ritz", "dolfinx") if any(m in c[1] for c in cases)]
    if not methods:
        sys.exit("plot_sweep: no solved case in the file")
    fig, axes = plt.subplots(1, len(methods), figsize=(4.5 * len(methods), 4), sharey=True, squeeze=False)
    for ax, method in zip(axes[0], methods):
        for values, results, _ in cases:
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
    parser.add_argument("--dolfinx", action="store_true", help="add the dolfinx reference as a panel")
    parser.add_argument("--dolfinx-elements", type=int, default=400)
    args = parser.parse_args()
    prefix = args.out or args.sweep.rsplit(".", 1)[0]
    keys, cases = read(args.sweep)
    if args.dolfinx:
        add_dolfinx(cases, args.dolfinx_elements)
    figure(keys, cases, "w", "deflection w (> 0 into the foundation)", prefix + "_deflection.png")
    figure(keys, cases, "reaction", "foundation reaction (force per length)", prefix + "_reaction.png")


if __name__ == "__main__":
    main()
