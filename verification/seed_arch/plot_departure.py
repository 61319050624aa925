#!/usr/bin/python3
"""The seed's arch beyond linear theory: figure and report section from seed_arch_departure's CSV.

    build/verification/seed_arch/seed_arch_departure --csv departure.csv
    /usr/bin/python3 verification/seed_arch/plot_departure.py departure.csv --out DIR

Writes DIR/seed_arch_departure.png (crown deflection, contact half-angle and crown thrust against the
load factor, linear dashed and von Karman solid, the three end conditions) and prints the Markdown
section of verification/report/report.md (section 5). verification/report.py calls section() too.
"""
import argparse
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ENDS = ["pinned", "clamped", "roller"]
EI, R = 1.4, 100.0  # the seed's arch: N = (N R^2/EI) EI / R^2


def read(path):
    rows, crossings = [], {}
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                ends, elements, deflection, angle = line[1:].strip().split(",")
                crossings[(ends, int(elements))] = (float(deflection.split("=")[1]), float(angle.split("=")[1]))
    with open(path) as f:
        for row in csv.DictReader(line for line in f if not line.startswith("#")):
            rows.append({k: (v if k == "ends" else float(v)) for k, v in row.items()})
    return rows, crossings


def figure(rows, out):
    fine = max(r["elements"] for r in rows)
    fig, axes = plt.subplots(3, 1, figsize=(7.5, 10), sharex=True)
    colours = dict(zip(ENDS, ["C0", "C1", "C2"]))
    for ends in ENDS:
        mine = [r for r in rows if r["ends"] == ends and r["elements"] == fine]
        lam = [0.0] + [r["load_factor"] for r in mine]
        for ax, key, scale in ((axes[0], "w0", R), (axes[1], "half_angle", 1.0), (axes[2], "thrust", EI / R**2)):
            first = [0.0] if key != "half_angle" else [mine[0][key + "_linear"]]
            first_vk = [0.0] if key != "half_angle" else [mine[0][key + "_linear"]]
            ax.plot(lam, [v * scale for v in first + [r[key + "_linear"] for r in mine]], "--", color=colours[ends])
            ax.plot(lam, [v * scale for v in first_vk + [r[key + "_vk"] for r in mine]], "-", color=colours[ends],
                    label=f"{ends}")
    axes[0].set_ylabel("crown deflection w(0) (R = 100)")
    axes[1].set_ylabel("contact half-angle (deg)")
    axes[1].axhline(10.0, color="grey", lw=0.8, ls=":")
    axes[1].text(0.02, 9.6, "the arch's half-angle, 10 deg", fontsize=8, color="grey")
    axes[2].set_ylabel("crown thrust -N(0) (EI = 1.4)")
    axes[2].axhline(0.0, color="grey", lw=0.8)
    axes[2].set_xlabel("load factor (1: the seed's crown load P = 0.1)")
    for ax in axes:
        ax.axvline(1.0, color="grey", lw=0.8, ls=":")
        ax.grid(alpha=0.3)
    axes[0].legend(title="ends; dashed linear, solid von Karman", fontsize=8)
    axes[0].set_title(f"The seed's arch beyond linear theory ({int(fine)} elements)")
    fig.tight_layout()
    name = os.path.join(out, "seed_arch_departure.png")
    fig.savefig(name, dpi=110)
    return name


def crossing(load_factor, top):
    """A 1 % load factor as the report prints it (nan in the CSV: the history, up to `top`, never reached 1 %)."""
    return f"> {top:g}" if math.isnan(load_factor) else f"{load_factor:.4f}"


def section(rows, crossings):
    fine = int(max(r["elements"] for r in rows))
    coarse = int(min(r["elements"] for r in rows))
    top = max(r["load_factor"] for r in rows)

    def at(ends, elements, lam):
        return next(r for r in rows if r["ends"] == ends and r["elements"] == elements
                    and abs(r["load_factor"] - lam) < 1e-9)

    md = ["## 5. The seed's arch beyond linear theory (von Karman)", "",
          "![seed arch departure](seed_arch_departure.png)", "",
          "`build/verification/seed_arch/seed_arch_departure --csv departure.csv` (default: 200 and 100 "
          "elements; the figures below used `--elements 400`, i.e. 400 and 200) solves the seed's arch with each "
          "end condition by linear theory and by von Karman theory (the circular arch's Marguerre/Donnell "
          "element, `contact/von_karman_solve.hpp`) along the load history lambda = 0.05, 0.10, ..., 2 (lambda = 1: "
          "the seed's P = 0.1), each step started from the previous answer. At the seed's load:", "",
          "| ends | w(0)/R linear | w(0)/R von Karman | diff | half-angle linear | half-angle von Karman | diff "
          "| thrust -N(0) linear | thrust -N(0) von Karman |",
          "|---|---|---|---|---|---|---|---|---|"]
    for ends in ENDS:
        r = at(ends, fine, 1.0)
        md.append(f"| {ends} | {r['w0_linear']:.5e} | {r['w0_vk']:.5e} | {r['w0_vk'] / r['w0_linear'] - 1:+.2%} | "
                  f"{r['half_angle_linear']:.4f} | {r['half_angle_vk']:.4f} | "
                  f"{r['half_angle_vk'] / r['half_angle_linear'] - 1:+.1%} | {r['thrust_linear'] * EI / R**2:.4f} | "
                  f"{r['thrust_vk'] * EI / R**2:+.4f} |")
    md += ["", "The load factor at which each difference first reaches 1 % (bisection on the load factor to "
           f"5e-5, on both meshes; > {top:g}: not reached up to lambda = {top:g}):", "",
           f"| ends | crown deflection, {fine} el. | {coarse} el. | contact half-angle, {fine} el. | {coarse} el. |",
           "|---|---|---|---|---|"]
    for ends in ENDS:
        a, b = crossings[(ends, fine)], crossings[(ends, coarse)]
        md.append("| " + " | ".join([ends] + [crossing(v, top) for v in (a[0], b[0], a[1], b[1])]) + " |")
    md += ["", "Along the history (pinned ends, " + str(fine) + " elements; the CSV has every step and end):", "",
           "| lambda | w(0) diff | half-angle linear | half-angle von Karman | thrust -N(0) linear | von Karman |",
           "|---|---|---|---|---|---|"]
    for lam in (0.05, 0.1, 0.25, 0.5, 1.0, 1.4, 1.5, 2.0):
        r = at("pinned", fine, lam)
        md.append(f"| {lam:.2f} | {r['w0_vk'] / r['w0_linear'] - 1:+.2%} | {r['half_angle_linear']:.4f} | "
                  f"{r['half_angle_vk']:.4f} | {r['thrust_linear'] * EI / R**2:.4f} | "
                  f"{r['thrust_vk'] * EI / R**2:+.4f} |")
    worst = max(abs(at(e, fine, lam)[k] / at(e, coarse, lam)[k] - 1) for e in ENDS for lam in (0.5, 1.0, 2.0)
                for k in ("w0_vk", "half_angle_vk"))
    stable = all(r["stable"] == 1 for r in rows)
    slope = max(r["largest_slope_vk"] for r in rows if r["load_factor"] <= 1.0 + 1e-9)
    md += ["", "What moves, and why. With pinned or clamped ends the crown deflection departs from linear theory by "
           "1 % already at lambda = 0.015 (pinned; 0.011 clamped), where it is 5 % of the arch's thickness: the "
           "departure is linear in the load at small loads (`tests/contact/arch_von_karman_solve_test`: relative "
           "departure 0.68 lambda, pinned). The arch is nearly inextensional (EA R^2/EI = 3e6): linear theory's "
           "membrane strain u' - w, which gives the thrust, is tiny (N/EA = 3e-4 at the seed's load), and the "
           "rotation's square beta^2/2 of the von Karman strain matches it at rotations of a few hundredths of a "
           "radian. That term lengthens the dented crown; with the ends held (pinned, clamped) the lengthening is "
           "taken as tension, so the thrust grows slower than linear theory's, peaks near lambda = 0.4 and changes "
           "sign near lambda = 0.92 (pinned; 1.06 clamped): at the seed's load the pinned arch's linear thrust "
           "N(0) = 0.129 (N/(2 sqrt(K EI)) = 0.46) is all but gone (-0.005, slight tension; clamped 0.211 becomes "
           "0.006). The thrust is what carries part of the crown load to the "
           "supports as an arch (its radial component N/R per unit length); without it the load goes into bending "
           "and the foundation, so the crown sinks deeper (+14 % pinned, +28 % clamped) and the contact region "
           "widens (+56 % and +64 %: the pinned arch's 3.758 degrees becomes 5.857, far from the seed's 3.73). "
           "Beyond the seed's load the tension grows (membrane action, like a cable), so the deflection's "
           "departure falls again (pinned: +15 % at lambda = 0.75, +2 % at 2) while the contact keeps spreading "
           "until the whole arch presses on the foundation (lambda = 1.45 for both, to the step of 0.05). Roller "
           "ends take no thrust (N = 0 at the ends, -0.001 at the crown): there is nothing for the nonlinear strain "
           "to couple to, and von Karman stays within 1e-4 of linear theory up to twice the seed's load.", "",
           f"Within the model. The largest rotation up to the seed's load is {slope:.3f} rad (beta^2 = "
           f"{slope * slope:.3f} against 1: moderate rotations hold). The shallow (Marguerre/Donnell) strain and the "
           "foundation and load acting along the undeformed normal differ from the exact curved-beam theory by "
           "relative order theta^2 <= (10 deg)^2 = 0.03; the von Karman beam on the arch's circle segment (an "
           "independent element, the same contact solve) gives the pinned arch's crown deflection within 0.02 % and "
           "its half-angle within 0.2 % (`arch_von_karman_solve_test`), and the linear arch is 12 % off it: the "
           "departure is the geometric nonlinearity, not the element. The seed's own arch is therefore well beyond "
           "linear theory at its load with pinned or clamped ends; its 3.73 degrees is a linear figure.", ""]
    md += ["", f"Mesh: the von Karman crown deflection and half-angle on {coarse} and {fine} elements differ by at "
           f"most {worst:.1e} (relative) at lambda = 0.5, 1, 2; the 1 % load factors agree to 1e-4. Every answer "
           f"of the history is {'stable' if stable else 'NOT stable everywhere'} (the inertia of the tangent on "
           "its contact set): no loss of stability up to twice the seed's load.", ""]
    return md


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv")
    parser.add_argument("--out", default=".")
    args = parser.parse_args()
    if not os.path.isfile(args.csv):
        parser.error(f"{args.csv}: no such file (expected seed_arch_departure's --csv output)")
    if not os.path.isdir(args.out):
        parser.error(f"--out {args.out}: no such directory")
    rows, crossings = read(args.csv)
    print(figure(rows, args.out))
    print("\n".join(section(rows, crossings)))


if __name__ == "__main__":
    main()
