#!/usr/bin/python3
"""Issue 12's inputs in the dolfinx reference, checked against the closed form.

    /usr/bin/python3 verification/dolfinx/check_issue12.py \\
        --closed-form build/verification/closed_form_reference [--scenes DIR] [--only NAME ...]

Every scene in verification/dolfinx/scenes/issue12/ (one per new input) is solved by
penalty_reference.py --refine. Its first comment lines say what it is checked against:

  - nothing said: the closed form of the scene itself (closed_form_reference SCENE);
  - "# closed-form equivalent: OTHER.toml": the closed form of an equivalent scene written with
    keys the closed form reads (a curvature load over a whole free strip = end moments EI kappa_T;
    settled supports = a gap shifted by the support motion; stiff springs = a clamped end);
  - "# dolfinx equivalent: OTHER.toml": the dolfinx reference on an equivalent scene;
  - "# closed-form: none": no reference; the refinement study alone;
  - "# twin of X": only an input of another scene's check, not run on its own.

Checks: the refinement converges (limits settle to --tolerance of the length), the observed
order of the contact limits is 2 within [1.5, 2.5] (P2 interior penalty: the limits converge at
h^2; three meshes give a noisy estimate of it), and every limit agrees with the reference within
compare.py's rule, |a - b| <= 3 (e_a + e_b) + 1e-12 length, with e the dolfinx Richardson
estimate and 1e-10 length for the closed form (its Newton tolerance). Exit 1 on any failure.
"""
import argparse
import glob
import json
import os
import re
import subprocess
import sys
import tempfile
import time
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
ORDER_WINDOW = (1.5, 2.5)


def markers(path):
    out = {}
    with open(path) as f:
        for line in f:
            if not line.startswith("#"):
                break
            m = re.match(r"#\s*(closed-form equivalent|dolfinx equivalent|closed-form|twin of)\s*:?\s*(\S+)", line)
            if m:
                out[m.group(1)] = m.group(2)
    return out


def limits(regions):
    return [v for r in regions for v in r]


def dolfinx(scene, tmp, tolerance):
    out = os.path.join(tmp, os.path.basename(scene) + ".json")
    t = time.perf_counter()
    p = subprocess.run(["/usr/bin/python3", os.path.join(HERE, "penalty_reference.py"), scene, "--refine",
                        "--tolerance", str(tolerance), "--json", out], capture_output=True, text=True)
    if p.returncode != 0:
        return None, (p.stderr.strip().splitlines() or [f"exit {p.returncode}"])[-1], time.perf_counter() - t
    with open(out) as f:
        return json.load(f), None, time.perf_counter() - t


def closed_form(exe, scene):
    p = subprocess.run([exe, scene], capture_output=True, text=True)
    if p.returncode != 0:
        return None, (p.stderr.strip() or f"exit {p.returncode}")
    return json.loads(p.stdout), None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--closed-form", required=True)
    ap.add_argument("--scenes", default=os.path.join(HERE, "scenes", "issue12"))
    ap.add_argument("--only", nargs="*", default=None)
    ap.add_argument("--tolerance", type=float, default=1e-6)
    args = ap.parse_args()

    failures, rows = [], []

    def check(ok, name, message):
        if not ok:
            failures.append(f"{name}: {message}")
            print(f"  FAIL {name}: {message}")
        return ok

    with tempfile.TemporaryDirectory() as tmp:
        for scene in sorted(glob.glob(os.path.join(args.scenes, "*.toml"))):
            name = os.path.basename(scene)[:-5]
            mk = markers(scene)
            if "twin of" in mk or (args.only is not None and name not in args.only):
                continue
            with open(scene, "rb") as f:
                doc = tomllib.load(f)
            st = doc["structure"]
            length = 2 * st["half_angle_deg"] if st["kind"] == "arch" else st["length"]
            d, err, wall = dolfinx(scene, tmp, args.tolerance)
            if not check(d is not None, name, f"dolfinx failed: {err}"):
                continue
            est = d.get("estimated_limit_error") or 0.0
            order = d.get("observed_order")
            check(d.get("refinement_converged") is True, name,
                  f"limits not settled to {args.tolerance:g} L by {d['elements']} elements")
            moving = any(v is not None for v in (d.get("per_limit_order") or []))
            if moving:      # some limit moves with the mesh: its order must be about 2
                check(order is not None and ORDER_WINDOW[0] <= order <= ORDER_WINDOW[1], name,
                      f"observed order {order} outside {ORDER_WINDOW}")
            ref_name, ref, ref_est = "none", None, 0.0
            if mk.get("closed-form") == "none":
                pass
            elif "dolfinx equivalent" in mk:
                ref_name = "dolfinx " + mk["dolfinx equivalent"]
                ref, err, _ = dolfinx(os.path.join(args.scenes, mk["dolfinx equivalent"]), tmp, args.tolerance)
                if check(ref is not None, name, f"dolfinx on {mk['dolfinx equivalent']} failed: {err}"):
                    ref_est = ref.get("estimated_limit_error") or 0.0
            else:
                target = mk.get("closed-form equivalent", os.path.basename(scene))
                ref_name = "closed form" + ("" if target == os.path.basename(scene) else " " + target)
                ref, err = closed_form(args.closed_form, os.path.join(args.scenes, target))
                ref_est = 1e-10 * length
                check(ref is not None, name, f"closed form of {target}: {err}")
            worst, allowed = None, None
            if ref is not None:
                a, b = limits(d["contact_regions"]), limits(ref["contact_regions"])
                if check(len(a) == len(b), name, f"{len(a) // 2} contact regions against {len(b) // 2} ({ref_name})"):
                    for k, (x, y) in enumerate(zip(a, b)):
                        tol = 3 * (est + ref_est) + 1e-12 * length
                        if worst is None or abs(x - y) / tol > worst / allowed:
                            worst, allowed = abs(x - y), tol
                        check(abs(x - y) <= tol, name,
                              f"limit {k}: dolfinx {x:.10g} against {y:.10g} ({ref_name}), differ by "
                              f"{abs(x - y):.2e}, allowed {tol:.2e}")
            regions = " ".join(f"[{x:.9g}, {y:.9g}]" for x, y in d["contact_regions"]) or "none"
            rows.append((name, regions, d["elements"], order, est, ref_name, worst, allowed, wall))
            print(f"  {name}: {regions} ({d['elements']} el., order {order}, est {est:.1e}) "
                  f"vs {ref_name}: diff {worst if worst is None else f'{worst:.1e}'} ({wall:.1f} s)", flush=True)

    print("\n| scene | dolfinx contact (finest) | elements | order | est. error | reference | difference | allowed |")
    print("|---|---|---|---|---|---|---|---|")
    for name, regions, n, order, est, ref_name, worst, allowed, wall in rows:
        print(f"| {name} | {regions} | {n} | {'-' if order is None else f'{order:.2f}'} | {est:.1e} | {ref_name} | "
              f"{'-' if worst is None else f'{worst:.1e}'} | {'-' if allowed is None else f'{allowed:.1e}'} |")
    for f in failures:
        print("FAILED", f)
    print(f"{len(rows)} scenes, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
