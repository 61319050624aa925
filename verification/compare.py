#!/usr/bin/python3
"""Comparison harness: every scene in verification/scenes/, liftoff's methods against each other
and against independent references, with tolerances from each side's own error estimate.

    /usr/bin/python3 verification/compare.py --liftoff build/src/liftoff \\
        --closed-form build/verification/closed_form_reference [--dolfinx] [--markdown FILE]

For every contact limit each method gives a value and an error estimate:
  - FE dual: on meshes n/2, n and 2n; limits converge at about h^2 but oscillate with where the
    limit falls in its element, so the error of the 2n result is taken as its whole change from n
    (not a third of it, as Richardson would for a monotone sequence);
  - FE primal: on mesh n; the same discrete solution as the dual on that mesh (to round-off), so
    it carries the dual's estimate for mesh n (its change from n/2);
  - Ritz: automatic modes, its own estimate (the last change of the limits with N);
  - closed form (beams): exact up to its Newton tolerance (1e-10 of the length);
  - dolfinx penalty model (with --dolfinx): its refinement study's estimate.
Two methods agree when |a - b| <= 3 (e_a + e_b) + 1e-12 * length. A table is printed (and
written as Markdown with --markdown); the exit code is 1 if any pair disagrees.
"""
import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))


def run_json(command):
    p = subprocess.run(command, capture_output=True, text=True)
    if p.returncode != 0:
        return None, (p.stderr.strip() or p.stdout.strip())
    return json.loads(p.stdout), None


def limits(result):
    return [x for region in result["contact_regions"] for x in region]


def liftoff_results(liftoff, scene, elements):
    out = {}
    coarse, err = run_json([liftoff, "solve", scene, "--method", "dual", "--elements", str(elements // 2), "--json"])
    mid, err2 = run_json([liftoff, "solve", scene, "--method", "dual", "--elements", str(elements), "--json"])
    fine, err3 = run_json([liftoff, "solve", scene, "--method", "dual", "--elements", str(2 * elements), "--json"])
    if mid and fine and coarse and len(limits(mid)) == len(limits(fine)) == len(limits(coarse)):
        out["FE dual"] = (limits(fine), [abs(f - m) for f, m in zip(limits(fine), limits(mid))],
                          f"{2 * elements} el.")
        mesh_estimate = [abs(m - c) for m, c in zip(limits(mid), limits(coarse))]
        primal, err4 = run_json([liftoff, "solve", scene, "--method", "primal", "--elements", str(elements), "--json"])
        if primal:
            out["FE primal"] = (limits(primal), mesh_estimate, f"{elements} el.")
    else:
        out["FE dual"] = (None, err or err2 or err3, "")
    ritz, err = run_json([liftoff, "solve", scene, "--method", "ritz", "--json"])
    if ritz:
        estimate = ritz.get("estimated_limit_error", 0.0)
        out["Ritz"] = (limits(ritz), [estimate] * len(limits(ritz)), f"{ritz['modes']} modes")
    else:
        out["Ritz"] = (None, err, "")
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--liftoff", required=True)
    parser.add_argument("--closed-form", required=True)
    parser.add_argument("--dolfinx", action="store_true", help="also run verification/dolfinx/penalty_reference.py")
    parser.add_argument("--scenes", default=os.path.join(HERE, "scenes"))
    parser.add_argument("--markdown", default=None)
    parser.add_argument("--elements", type=int, default=100, help="the FE mesh n (dual also on n/2 and 2n)")
    args = parser.parse_args()

    rows, failures = [], 0
    for scene in sorted(glob.glob(os.path.join(args.scenes, "*.toml"))):
        name = os.path.basename(scene)[:-5]
        with open(scene, "rb") as f:
            description = tomllib.load(f)
        arch = description["structure"]["kind"] == "arch"
        length = 2 * description["structure"]["half_angle_deg"] if arch else description["structure"]["length"]
        results = liftoff_results(args.liftoff, scene, args.elements)
        reference, err = run_json([args.closed_form, scene])
        if reference:
            results["closed form"] = (limits(reference), [1e-10 * length] * len(limits(reference)), "exact")
        if args.dolfinx:
            with tempfile.TemporaryDirectory() as tmp:
                out = os.path.join(tmp, "d.json")
                p = subprocess.run(["/usr/bin/python3", os.path.join(HERE, "dolfinx", "penalty_reference.py"), scene,
                                    "--refine", "--json", out], capture_output=True, text=True)
                if p.returncode == 0:
                    with open(out) as f:
                        d = json.load(f)
                    results["dolfinx"] = (limits(d), [d.get("estimated_limit_error", 0.0)] * len(limits(d)),
                                          f"{d['elements']} el.")
                else:
                    results["dolfinx"] = (None, p.stderr.strip().splitlines()[-1:] or ["failed"], "")

        methods = [m for m, (values, _, _) in results.items() if values is not None]
        for m, (values, message, _) in results.items():
            if values is None:
                print(f"{name}: {m} failed: {message}")
                failures += 1
        counts = {len(results[m][0]) for m in methods}
        if len(counts) != 1:
            print(f"{name}: methods disagree on the number of contact limits: "
                  + ", ".join(f"{m} {len(results[m][0])}" for m in methods))
            failures += 1
            continue
        for i in range(counts.pop()):
            # The pair that uses most of its allowance decides.
            worst, allowed_at_worst = None, None
            for a in methods:
                for b in methods:
                    va, ea = results[a][0][i], results[a][1][i]
                    vb, eb = results[b][0][i], results[b][1][i]
                    difference, allowed = abs(va - vb), 3 * (ea + eb) + 1e-12 * length
                    if worst is None or difference / allowed > worst / allowed_at_worst:
                        worst, allowed_at_worst = difference, allowed
            ok = worst <= allowed_at_worst
            failures += not ok
            cells = [f"{results[m][0][i]:.9f} ± {results[m][1][i]:.1e}" for m in methods]
            rows.append((name, i + 1, methods, cells, worst, allowed_at_worst, ok))

    header_methods = ["FE dual", "FE primal", "Ritz", "closed form", "dolfinx"]
    lines = ["| scene | limit | " + " | ".join(header_methods) + " | largest difference | allowed | |",
             "|---|---|" + "---|" * len(header_methods) + "---|---|---|"]
    for name, i, methods, cells, worst, allowed, ok in rows:
        by_method = dict(zip(methods, cells))
        lines.append(f"| {name} | {i} | " + " | ".join(by_method.get(m, "-") for m in header_methods)
                     + f" | {worst:.1e} | {allowed:.1e} | {'ok' if ok else 'DISAGREE'} |")
    table = "\n".join(lines)
    print(table)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(table + "\n")
    print(f"{len(rows) - failures} passed, {failures} failed")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
