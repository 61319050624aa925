#!/usr/bin/python3
"""A beam-column trace (issue 15) against the perfect member's localized buckle of the closed form.

    /usr/bin/python3 verification/closed_form/check_upheaval_trace.py TRACE.h5 --closed-form closed_form_reference
    /usr/bin/python3 verification/closed_form/check_upheaval_trace.py --liftoff liftoff --scene SCENE.toml \\
        --closed-form closed_form_reference [--output TRACE.h5]

Reads the file's scene (a uniform heavy beam on a uniform tensionless foundation: the closed form's
`localized-buckle` refuses anything else) and, per path of the file (fe, ritz, fe_refined), prints:
- the limit load: the axial force at the path's limit_point event (from the path's own affine
  N(lambda) = N_dead + lambda N_live), against the bilateral critical load 2 sqrt(K EI), its bound;
- at steps on the descending branch (after the limit point) the axial force P against the closed
  form's P_cf at the same lifted length (the perfect member's branch, verification/closed_form/
  beam_column.hpp) and their relative difference (P - P_cf) / P_cf, which shrinks as the buckle
  grows past the imperfection.
With --liftoff and --scene it first runs `liftoff trace SCENE --output FILE` (a temporary file
unless --output). Exit 0 if every path has a limit point below 2 sqrt(K EI) and its relative
difference shrinks from the first to the last descending row; 1 otherwise; 2 for a file or scene
it cannot read or a liftoff run that fails.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

try:
    import h5py
    import numpy as np
except ImportError as e:  # pragma: no cover - depends on the machine
    print(f"check_upheaval_trace: the Python module '{e.name}' is missing (Debian: python3-h5py python3-numpy)",
          file=sys.stderr)
    sys.exit(2)


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def bad(message):
    print(f"check_upheaval_trace: {message}", file=sys.stderr)
    sys.exit(2)


def read(path):
    """(scene text, units, {path: {lambda, axial_force, amplitude, lifted_length, events}})."""
    try:
        with h5py.File(path, "r") as f:
            if "scene" not in f or "paths" not in f.attrs:
                bad(f"{path}: not a liftoff trace file (no /scene or no paths attribute)")
            paths = {}
            for name in [p for p in text(f.attrs["paths"]).split(",") if p in f]:
                steps, events = f[name]["steps"], f[name]["events"]
                if "axial_force" not in steps:
                    bad(f"{path}: /{name}/steps/axial_force: missing; expected a trace written with the beam-column "
                        f"quantities")
                n = min(len(steps[k]) for k in ("lambda", "axial_force", "amplitude", "lifted_length"))
                paths[name] = {k: steps[k][:n].astype(float) for k in ("lambda", "axial_force", "amplitude",
                                                                       "lifted_length")}
                paths[name]["events"] = [(float(events["lambda"][i]), text(events["kind"][i]), int(events["step"][i]))
                                         for i in range(len(events["kind"])) if 0 <= events["step"][i] < n]
            units = (text(f.attrs.get("units_force", "")) or "force", text(f.attrs.get("units_length", "")) or "length")
            return text(f["scene"][()]), units, paths
    except OSError as e:
        bad(f"{path}: cannot read it as HDF5 ({e})")


def closed_form_table(path, program, scene_text, max_amplitude):
    with tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False) as f:
        f.write(scene_text)
        scene = f.name
    try:
        r = subprocess.run([program, "localized-buckle", scene, "--max-amplitude", repr(max_amplitude)],
                           capture_output=True, text=True, timeout=300)
    finally:
        os.remove(scene)
    if r.returncode != 0:
        why = r.stderr.strip().replace(f"closed_form_reference: {scene}: ", "")
        bad(f"{path}: /scene: no closed-form localized buckle for it ({why})")
    return json.loads(r.stdout)


def limit_load(p):
    """(lambda, P) at the path's first limit_point event, or None."""
    for lam, kind, step in p["events"]:
        if kind == "limit_point":
            if np.ptp(p["lambda"]) > 0:
                slope, intercept = np.polyfit(p["lambda"], p["axial_force"], 1)
                return lam, intercept + slope * lam, step
            return lam, float(p["axial_force"][step]), step
    return None


def check(path, program, rows):
    """Prints the comparison; returns (every check passed, {path: {"limit_load", "rows": [(step, amplitude,
    lifted length, P, P_cf, relative difference)]}})."""
    scene_text, (force, length), paths = read(path)
    if not paths:
        bad(f"{path}: no path in the file")
    top = max(float(np.max(p["amplitude"])) for p in paths.values())
    table = closed_form_table(path, program, scene_text, max(1.5 * top, 1e-12))
    points = table["points"]
    cf_lifted = np.array([q["lifted_length"] for q in points])
    cf_force = np.array([q["axial_force"] for q in points])
    critical = table["bilateral_critical"]
    print(f"{os.path.basename(path)}: EI = {table['EI']:.6g}, K = {table['K']:.6g}, q = {table['q']:.6g}; "
          f"2 sqrt(K EI) = {critical:.6g} {force}")
    ok, results = True, {}
    for name, p in paths.items():
        results[name] = {"limit_load": None, "rows": []}
        limit = limit_load(p)
        if limit is None:
            print(f"  {name}: FAIL no limit_point event ({len(p['lambda'])} steps, P up to "
                  f"{np.max(p['axial_force']):.6g} {force})")
            ok = False
            continue
        lam, load, step = limit
        results[name]["limit_load"] = load
        below = load < critical
        ok &= below
        print(f"  {name}: limit load {load:.6g} {force} at lambda = {lam:.6g} (step {step}), "
              f"{load / critical:.4f} of 2 sqrt(K EI){'' if below else ': FAIL, above the bilateral bound'}")
        after = [i for i in range(step + 1, len(p["lambda"]))
                 if p["lifted_length"][i] > 0 and cf_lifted[0] <= p["lifted_length"][i] <= cf_lifted[-1]]
        if not after:
            print(f"  {name}: FAIL no step on the descending branch within the closed form's lifted lengths")
            ok = False
            continue
        chosen = sorted(set(after[int(round(k))] for k in np.linspace(0, len(after) - 1, min(rows, len(after)))))
        print(f"    {'step':>5} {'amplitude':>11} {'lifted':>10} {'P':>13} {'P_cf':>13} {'(P-P_cf)/P_cf':>14}")
        differences = []
        for i in chosen:
            p_cf = float(np.interp(p["lifted_length"][i], cf_lifted, cf_force))
            d = (p["axial_force"][i] - p_cf) / p_cf
            differences.append(d)
            results[name]["rows"].append((i, p["amplitude"][i], p["lifted_length"][i], p["axial_force"][i], p_cf, d))
            print(f"    {i:5d} {p['amplitude'][i]:11.5g} {p['lifted_length'][i]:10.5g} {p['axial_force'][i]:13.6g} "
                  f"{p_cf:13.6g} {d:14.4e}")
        shrinks = abs(differences[-1]) < abs(differences[0])
        ok &= shrinks
        print(f"    relative difference {abs(differences[0]):.3g} -> {abs(differences[-1]):.3g} "
              f"({'shrinks' if shrinks else 'FAIL: does not shrink'} as the buckle grows; amplitudes in {length})")
    return ok, results


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("trace", nargs="?", help="the HDF5 file of `liftoff trace --output`")
    parser.add_argument("--closed-form", required=True, help="verification/closed_form's closed_form_reference")
    parser.add_argument("--liftoff", help="run `liftoff trace --scene` first")
    parser.add_argument("--scene", help="the scene to trace (with --liftoff)")
    parser.add_argument("--output", help="where --liftoff writes the trace (default: a temporary file)")
    parser.add_argument("--rows", type=int, default=12, help="descending-branch rows printed per path")
    args = parser.parse_args()
    if bool(args.liftoff) != bool(args.scene) or bool(args.trace) == bool(args.liftoff):
        bad("expected TRACE.h5, or --liftoff and --scene (one or the other)")
    with tempfile.TemporaryDirectory() as tmp:
        path = args.trace
        if args.liftoff:
            path = args.output or os.path.join(tmp, "trace.h5")
            r = subprocess.run([args.liftoff, "trace", args.scene, "--output", path], capture_output=True, text=True)
            print(r.stdout, end="")
            if r.returncode != 0:
                bad(f"liftoff trace {args.scene}: exit {r.returncode}: {r.stderr.strip()}")
        sys.exit(0 if check(path, args.closed_form, args.rows)[0] else 1)


if __name__ == "__main__":
    main()
