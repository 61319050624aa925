#!/usr/bin/python3
"""Run penalty_reference.py --refine on the seed scenes and compare with liftoff.

    /usr/bin/python3 verification/dolfinx/compare_liftoff.py [--liftoff build/src/liftoff]
        [--out DIR] [--tolerance 1e-6] [SCENE.toml ...]

Prints a Markdown table: the dolfinx contact limits on the finest mesh, the mesh, the observed
order and Richardson error estimate, the Richardson-extrapolated limits, liftoff's FE (LCP)
limits at --elements 640 and its Ritz limits, and the differences. Runs liftoff as a user
would (its --json output); shares no code with it.
"""

import argparse
import glob
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def run_json(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        message = p.stderr.strip()
        try:   # a refusal (exit 3) carries one JSON object with the reason on stdout
            message = json.loads(p.stdout).get("message") or message
        except (json.JSONDecodeError, AttributeError):
            message = message or p.stdout.strip()
        last = (message.splitlines() or [""])[-1]
        return None, f"refused (exit {p.returncode}): {last}"
    return json.loads(p.stdout), None


def limits(regions):
    return [v for r in regions for v in r]


def fmt(regions, digits=9):
    if regions is None:
        return "-"
    return " ".join(f"[{a:.{digits}g}, {b:.{digits}g}]" for a, b in regions) or "none"


def maxdiff(a, b):
    if a is None or b is None or len(a) != len(b):
        return None
    la, lb = limits(a), limits(b)
    return max((abs(x - y) for x, y in zip(la, lb)), default=0.0)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--liftoff", default=os.path.join(ROOT, "build", "src", "liftoff"))
    ap.add_argument("--out", default=None, help="keep the JSON files here")
    ap.add_argument("--tolerance", type=float, default=1e-6)
    ap.add_argument("--max-elements", type=int, default=25600)
    opts = ap.parse_args()
    scenes = opts.scenes or sorted(glob.glob(os.path.join(ROOT, "verification", "scenes", "*.toml")))
    out = opts.out or os.path.join("/tmp", "dolfinx-penalty-compare")
    os.makedirs(out, exist_ok=True)

    rows = []
    t0 = time.perf_counter()
    for scene in scenes:
        name = os.path.splitext(os.path.basename(scene))[0]
        jpath = os.path.join(out, name + ".json")
        cmd = ["/usr/bin/python3", os.path.join(HERE, "penalty_reference.py"), scene, "--refine",
               "--tolerance", str(opts.tolerance), "--max-elements", str(opts.max_elements), "--json", jpath]
        t = time.perf_counter()
        p = subprocess.run(cmd, capture_output=True, text=True)
        wall = time.perf_counter() - t
        if p.returncode != 0:
            rows.append((name, None, None, None, p.stderr.strip().splitlines()[-1:], wall))
            continue
        ref = json.load(open(jpath))
        fe, fe_err = run_json([opts.liftoff, "solve", scene, "--json", "--elements", "640"])
        rz, rz_err = run_json([opts.liftoff, "solve", scene, "--json", "--method", "ritz"])
        notes = [f"liftoff FE: {fe_err}"] * bool(fe_err) + [f"liftoff Ritz: {rz_err}"] * bool(rz_err)
        rows.append((name, ref, fe, rz, notes, wall))
    total = time.perf_counter() - t0

    unit = {"beam": "x", "arch": "theta deg"}
    print("| scene | dolfinx limits (finest) | elements | order | est. error | dolfinx extrapolated "
          "| liftoff FE 640 | liftoff Ritz | max diff extrap-FE640 | max diff extrap-Ritz | solve s (finest) | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, ref, fe, rz, err, wall in rows:
        if ref is None:
            print(f"| {name} | failed: {err} | | | | | | | | | | {wall:.1f} |")
            continue
        ext = ref.get("extrapolated_contact_regions") or ref["contact_regions"]
        order = ref.get("observed_order")
        est = ref.get("estimated_limit_error")
        d_fe = maxdiff(ext, fe["contact_regions"]) if fe else None
        d_rz = maxdiff(ext, rz["contact_regions"]) if rz else None
        print(f"| {name} ({unit[ref['structure']]}) | {fmt(ref['contact_regions'])} | {ref['elements']} | "
              f"{order:.3f} | {est:.2e} | {fmt(ext, 11)} | {fmt(fe['contact_regions'] if fe else None)} | "
              f"{fmt(rz['contact_regions'] if rz else None)} | "
              f"{'-' if d_fe is None else f'{d_fe:.2e}'} | {'-' if d_rz is None else f'{d_rz:.2e}'} | "
              f"{ref['time_s']:.3f} | {wall:.1f} |" if order is not None and est is not None else
              f"| {name} | {fmt(ref['contact_regions'])} | {ref['elements']} | - | - | - | | | | | "
              f"{ref['time_s']:.3f} | {wall:.1f} |")
    for name, ref, fe, rz, notes, wall in rows:
        for note in (notes if ref is not None else []):
            print(f"{name}: {note}")
    print(f"\ntotal wall time {total:.1f} s; JSON files in {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
