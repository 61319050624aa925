#!/usr/bin/python3
"""Builds the verification report: Markdown with PNG figures, for every shipped scene.

    /usr/bin/python3 verification/report.py --liftoff build/src/liftoff \\
        --closed-form build/verification/closed_form_reference [--dolfinx] --out report/

Writes OUT/report.md with:
  1. the agreement table of verification/compare.py (every scene, every method, estimates);
  2. convergence plots: contact limit error against elements (FE dual) and against modes (Ritz),
     with observed orders, against the best reference of each scene;
  3. the seed's Figures 4 and 5 redrawn (deflection for several k, primal, dual and Ritz side by
     side, and the reaction) from `liftoff sweep`, and its Figure 6 (the arch, each end condition);
  4. the seed's arch half-angle (3.73 degrees) beside ours, and why they differ;
  5. with --seed-arch-departure build/verification/seed_arch/seed_arch_departure: the seed's arch beyond
     linear theory (von Karman), its figure, tables and discussion (verification/seed_arch/plot_departure.py).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.join(HERE, "scenes")
BEAMS = ["seed_beam_end_moments", "seed_beam_end_moments_central_load"]
ARCHES = ["seed_arch_pinned", "seed_arch_roller", "seed_arch_clamped"]


def solve(liftoff, scene, *options):
    p = subprocess.run([liftoff, "solve", os.path.join(SCENES, scene + ".toml"), "--json", *options],
                       capture_output=True, text=True, check=True)
    return json.loads(p.stdout)


def first_interior_limit(result):
    """The first contact limit that is not an end of the member (the one that moves)."""
    lo, hi = result["_ends"]
    for region in result["contact_regions"]:
        for x in region:
            if abs(x - lo) > 1e-9 and abs(x - hi) > 1e-9:
                return x
    return float("nan")


def with_ends(result, scene):
    import tomllib
    with open(os.path.join(SCENES, scene + ".toml"), "rb") as f:
        s = tomllib.load(f)["structure"]
    result["_ends"] = (-s["half_angle_deg"], s["half_angle_deg"]) if s["kind"] == "arch" else (0.0, s["length"])
    return result


def order(xs, errors):
    import numpy as np
    x, e = np.log(np.array(xs, float)), np.log(np.array(errors, float))
    return float(np.polyfit(x, e, 1)[0])


def convergence(liftoff, closed_form, out):
    """Error of the first moving limit against elements (FE) and modes (Ritz)."""
    lines = ["| scene | reference | FE observed order (error vs 1/elements) | Ritz observed order (error vs 1/N) |",
             "|---|---|---|---|"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for scene in BEAMS + ARCHES:
        reference_value, reference_name = None, None
        p = subprocess.run([closed_form, os.path.join(SCENES, scene + ".toml")], capture_output=True, text=True)
        if p.returncode == 0:
            reference_value = first_interior_limit(with_ends(json.loads(p.stdout), scene))
            reference_name = "closed form"
        else:
            reference_value = first_interior_limit(with_ends(solve(liftoff, scene, "--method", "ritz", "--modes", "256"),
                                                             scene))
            reference_name = "Ritz, 256 modes"
        meshes = [10, 20, 40, 80, 160, 320]
        fe = [abs(first_interior_limit(with_ends(solve(liftoff, scene, "--elements", str(n)), scene)) - reference_value)
              for n in meshes]
        modes = [4, 8, 16, 32, 64] + ([128] if reference_name == "closed form" else [])
        ritz = [abs(first_interior_limit(with_ends(solve(liftoff, scene, "--method", "ritz", "--modes", str(n)), scene))
                    - reference_value) for n in modes]
        fe_pairs = [(1 / n, e) for n, e in zip(meshes, fe) if e > 0]
        ritz_pairs = [(1 / n, e) for n, e in zip(modes, ritz) if e > 0]
        axes[0].loglog([n for n, e in zip(meshes, fe) if e > 0], [e for e in fe if e > 0], "o-", label=scene)
        axes[1].loglog([n for n, e in zip(modes, ritz) if e > 0], [e for e in ritz if e > 0], "o-", label=scene)
        lines.append(f"| {scene} | {reference_name} | {order(*zip(*fe_pairs)):.2f} | {order(*zip(*ritz_pairs)):.2f} |")
    for ax, title, xlabel in ((axes[0], "FE + LCP (dual)", "elements"), (axes[1], "Ritz", "modes N")):
        ax.set_title(title)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("error of the first moving contact limit (x/L or degrees)")
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "convergence.png"), dpi=110)
    return "\n".join(lines)


def sweeps(liftoff, out, dolfinx):
    figures = []
    for scene in BEAMS:
        h5 = os.path.join(out, scene + "_sweep.h5")
        subprocess.run([liftoff, "sweep", os.path.join(SCENES, scene + ".toml"), "--set", "foundation.k=10,100,1e3,1e4",
                        "--method", "all", "--elements", "200", "-o", h5, "--csv", os.path.join(out, scene + "_sweep.csv")],
                       check=True, capture_output=True)
        subprocess.run(["/usr/bin/python3", os.path.join(HERE, "plots", "plot_sweep.py"), h5, "--out",
                        os.path.join(out, scene)] + (["--dolfinx"] if dolfinx else []), check=True, capture_output=True)
        os.remove(h5)
        figures += [scene + "_deflection.png", scene + "_reaction.png"]
    return figures


def dolfinx_half_angle(scene):
    out = os.path.join(tempfile.mkdtemp(), "d.json")
    p = subprocess.run(["/usr/bin/python3", os.path.join(HERE, "dolfinx", "penalty_reference.py"),
                        os.path.join(SCENES, scene + ".toml"), "--refine", "--json", out], capture_output=True, text=True)
    if p.returncode != 0:
        return float("nan"), float("nan")
    with open(out) as f:
        d = json.load(f)
    return d["contact_regions"][0][1], d.get("estimated_limit_error") or float("nan")


def arch_figure(liftoff, out, dolfinx):
    import h5py
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    rows = []
    for scene in ARCHES:
        h5 = os.path.join(out, scene + ".h5")
        subprocess.run([liftoff, "solve", os.path.join(SCENES, scene + ".toml"), "--elements", "400", "-o", h5],
                       check=True, capture_output=True)
        with h5py.File(h5, "r") as f:
            theta, w, r = f["fields/coordinate"][()], f["fields/w"][()], f["fields/reaction"][()]
            half = f["contact_regions"][()][0][1]
        os.remove(h5)
        ends = scene.split("_")[-1]
        axes[0].plot(theta, w / 100.0, label=f"{ends}: contact half-angle {half:.4f} deg")
        axes[1].plot(theta, r * 0.2 ** 3 / 1.4, label=ends)
        ritz = solve(liftoff, scene, "--method", "ritz")
        primal = solve(liftoff, scene, "--method", "primal", "--elements", "100")
        reference = dolfinx_half_angle(scene) if dolfinx else (float("nan"), float("nan"))
        rows.append((ends, half, primal["contact_regions"][0][1], ritz["contact_regions"][0][1],
                     ritz.get("estimated_limit_error", float("nan")), reference))
    axes[0].set_ylabel("w / R (> 0 into the foundation)")
    axes[0].invert_yaxis()
    axes[1].set_ylabel("reaction r h^3 / EI")
    for ax in axes:
        ax.set_xlabel("theta (degrees)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "arch.png"), dpi=110)
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--liftoff", required=True)
    parser.add_argument("--closed-form", required=True)
    parser.add_argument("--dolfinx", action="store_true")
    parser.add_argument("--out", default="verification-report")
    parser.add_argument("--seed-arch-departure", help="the seed_arch_departure executable (section 5)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    table_file = os.path.join(args.out, "agreement.md")
    compare = [sys.executable, os.path.join(HERE, "compare.py"), "--liftoff", args.liftoff, "--closed-form",
               args.closed_form, "--markdown", table_file] + (["--dolfinx"] if args.dolfinx else [])
    agreement = subprocess.run(compare, capture_output=True, text=True)
    with open(table_file) as f:
        table = f.read()
    orders = convergence(args.liftoff, args.closed_form, args.out)
    sweep_figures = sweeps(args.liftoff, args.out, args.dolfinx)
    arch_rows = arch_figure(args.liftoff, args.out, args.dolfinx)

    seed = 3.73
    md = ["# liftoff verification report", "",
          "Generated by `verification/report.py`. Sign convention: w > 0 into the foundation.", "",
          "## 1. Agreement on every contact limit", "",
          "Each cell: value ± the method's own error estimate (see `verification/compare.py`). Two methods agree "
          "when their difference is at most 3 times the sum of their estimates.", "", table,
          f"Harness exit code: {agreement.returncode} ({agreement.stdout.strip().splitlines()[-1]})", "",
          "## 2. Convergence", "", "![convergence](convergence.png)", "", orders, "",
          "FE contact limits converge at about h^2 (the linear reaction interpolation), oscillating with where the "
          "limit falls inside its element; Ritz limits converge algebraically (point loads).", "",
          "## 3. The seed's Figures 4 and 5: stiffness sweeps", ""]
    md += [f"![{f}]({f})" for f in sweep_figures]
    md += ["", "CSV summaries: " + ", ".join(f"`{s}_sweep.csv`" for s in BEAMS), "",
           "## 4. The seed's arch (Figures 6 and 7) and its 3.73 degrees", "", "![arch](arch.png)", "",
           "| ends | FE dual, 400 el. | FE primal, 100 el. | Ritz (± estimate) | dolfinx (± estimate) | Ritz minus the seed's 3.73 |",
           "|---|---|---|---|---|---|"]
    for ends, fe, primal, ritz, ritz_error, (reference, reference_error) in arch_rows:
        md.append(f"| {ends} | {fe:.5f} | {primal:.5f} | {ritz:.5f} ± {ritz_error:.0e} | {reference:.5f} ± "
                  f"{reference_error:.0e} | {ritz - seed:+.3f} deg ({(ritz - seed) / seed:+.1%}) |")
    md += ["", "The seed reports a contact half-angle of 3.73 degrees for all its formulations. The converged "
           "half-angle of the stated model is 3.7581 degrees with pinned ends, 5.6692 with roller ends (the ends "
           "the seed's Ritz functions imply) and 3.6241 with clamped ends. The seed's number is closest to the "
           "pinned arch, 0.75 % below it, and it is what a 10-element FE mesh of the pinned arch gives (3.7321 "
           "degrees, see `tests/contact/seed_arch_test`): we believe the seed's mesh was coarse. Nothing here is "
           "tuned to the seed's number.", ""]
    if args.seed_arch_departure:
        sys.path.insert(0, os.path.join(HERE, "seed_arch"))
        import plot_departure  # noqa: E402

        departure_csv = os.path.join(args.out, "seed_arch_departure.csv")
        subprocess.run([args.seed_arch_departure, "--elements", "400", "--max-factor", "2", "--step", "0.05",
                        "--csv", departure_csv], check=True, capture_output=True)
        rows, crossings = plot_departure.read(departure_csv)
        plot_departure.figure(rows, args.out)
        md += plot_departure.section(rows, crossings)
    with open(os.path.join(args.out, "report.md"), "w") as f:
        f.write("\n".join(md))
    print(os.path.join(args.out, "report.md"))


if __name__ == "__main__":
    main()
