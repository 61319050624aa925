#!/usr/bin/python3
"""The shipped von Karman scenes traced by the CLI and drawn by `liftoff plot` (issue 16, item 7).

    /usr/bin/python3 tests/app/von_karman_trace_test.py --liftoff build/src/liftoff \\
        --closed-form build/verification/closed_form_reference [--keep DIR]

- verification/scenes/von_karman/shallow_arch_snap_through.toml: `liftoff trace --json` (the
  default path, no --method) exits 0 on the FE path and finds, in order, the snap-through (a
  maximum of lambda), the lift-off zone closing at the pinned end and the lower limit point. Their
  loads against the dolfinx reference at 64 elements (von_karman_reference.py: 21.14143, 20.50315,
  13.51771), an independent discretisation whose error is not estimated: a cross-check at 1e-3
  relative, as tests/continuation/models/fe_member_von_karman_test.cpp does (observed 4.6e-4, 8e-5, 1.4e-3
  at the lower limit: that one at 2e-3). The stability: stable before the maximum, unstable between
  the two limit points, stable after.
- verification/scenes/von_karman/steel_strip_membrane.toml: exit 0, no event (full contact), the
  last step at the hand calculation's full series: midspan w = 15.731 mm, N = 154.82 kN tension
  (the scene's comment; the series truncated at 1e-4 relative: 2e-3 covers the 200 elements' error
  of the FE path, whose solve at the same mesh the solve test holds to that).
- verification/scenes/von_karman/shallow_arch_bifurcation.toml, `--method all`: both paths meet the
  bifurcation, the lift-off at an end and its closing on the asymmetric branch, and the second
  bifurcation where the branch rejoins the symmetric path, at the exact two-mode solution's loads
  (closed_form_reference; see bifurcating_arch for the tolerances), every step stable.
- `liftoff plot` of each trace writes the two pictures with ink; the snap-through's lift-off map is
  drawn against the crown deflection (plot.lift_off_map's ordinate "w"), the strip's (no limit
  point) against lambda.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
sys.path.insert(0, os.path.join(ROOT, "verification", "plots"))
import plot  # noqa: E402

sys.path.insert(0, os.path.join(HERE, "..", "support"))
from checks import check, finish  # noqa: E402

SCENES = os.path.join(ROOT, "verification", "scenes", "von_karman")


def trace(liftoff, scene, output, *extra):
    result = subprocess.run([liftoff, "trace", scene, "--json", "--output", output, *extra], capture_output=True,
                            text=True)
    check(result.returncode == 0, f"{os.path.basename(scene)}: trace exit 0 (got {result.returncode}: "
                                  f"{result.stderr.strip()[-300:]})")
    try:
        return json.loads(result.stdout)
    except json.JSONDecodeError:
        check(False, f"{os.path.basename(scene)}: --json prints one JSON object")
        return {"paths": []}


def drawn(liftoff, h5, prefix):
    result = subprocess.run([liftoff, "plot", h5, "--out", prefix], capture_output=True, text=True)
    check(result.returncode == 0, f"plot {os.path.basename(h5)}: exit 0 (got {result.returncode}: "
                                  f"{result.stderr.strip()[-300:]})")
    for suffix in ("_load_displacement.png", "_lift_off_map.png"):
        path = prefix + suffix
        if not os.path.isfile(path):
            check(False, f"{os.path.basename(path)} written")
            continue
        ink = float(np.mean(np.any(np.round(matplotlib.image.imread(path)[:, :, :3] * 255) < 250, axis=2)))
        check(ink > 0.02, f"{os.path.basename(path)} has ink on {100 * ink:.1f} % of its pixels")


class Discard:
    def save(self, fig, path):
        plot.plt.close(fig)


def ordinate(h5):
    return plot.lift_off_map(plot.read_trace(h5), os.devnull, Discard())


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--liftoff", required=True)
    parser.add_argument("--closed-form", required=True, help="verification's closed_form_reference program")
    parser.add_argument("--keep", help="write the files here (to look at the pictures)")
    args = parser.parse_args()
    if args.keep:
        os.makedirs(args.keep, exist_ok=True)
    with tempfile.TemporaryDirectory() as scratch:
        tmp = args.keep or scratch

        h5 = os.path.join(tmp, "snap.h5")
        out = trace(args.liftoff, os.path.join(SCENES, "shallow_arch_snap_through.toml"), h5)
        paths = out.get("paths", [])
        check([p["path"] for p in paths] == ["fe"], f"snap-through: the default is the FE path alone (got "
                                                     f"{[p['path'] for p in paths]})")
        if paths:
            fe = paths[0]
            check(fe["termination"] == "completed", f"snap-through: completed ({fe['message']})")
            kinds = [e["kind"] for e in fe["events"]]
            check(kinds == ["limit_point", "limit_at_support", "limit_point"],
                  f"snap-through: limit point, zone closing at the end, limit point (got {kinds})")
            if len(kinds) == 3:
                top, closing, bottom = (e["lambda"] for e in fe["events"])
                for name, value, reference, bound in (("upper limit", top, 21.14143, 1e-3),
                                                      ("closing", closing, 20.50315, 1e-3),
                                                      ("lower limit", bottom, 13.51771, 2e-3)):
                    check(abs(value - reference) <= bound * reference,
                          f"snap-through: {name} {value:.7g} within {bound:g} of dolfinx {reference}")
                check("maximum" in fe["events"][0]["description"] and "minimum" in fe["events"][2]["description"],
                      "snap-through: a maximum of lambda, then a minimum")
                stability = [(s["lambda"], s["monitor_deflection"], s["stability"]) for s in fe["steps"]]
                w_top = next(w for lam, w, _ in stability if lam == top)
                w_bottom = next(w for lam, w, _ in stability if lam == bottom)
                wrong = [(lam, w, k) for lam, w, k in stability
                         if (w < 0.99 * w_top and k != "stable") or (1.01 * w_top < w < 0.99 * w_bottom and k != "unstable")
                         or (w > 1.01 * w_bottom and k != "stable")]
                check(not wrong, f"snap-through: stable, unstable between the limit points, stable (wrong: {wrong[:3]})")
        drawn(args.liftoff, h5, os.path.join(tmp, "snap"))
        check(ordinate(h5) == "w", "snap-through: the lift-off map is drawn against the crown deflection")

        h5 = os.path.join(tmp, "strip.h5")
        out = trace(args.liftoff, os.path.join(SCENES, "steel_strip_membrane.toml"), h5)
        paths = out.get("paths", [])
        if paths:
            fe = paths[0]
            check(fe["termination"] == "completed" and not fe["events"],
                  f"steel strip: completed with no event ({fe['message']}, {len(fe['events'])} events)")
            last = fe["steps"][-1]
            check(abs(last["monitor_deflection"] - 0.015731) <= 2e-3 * 0.015731,
                  f"steel strip: midspan w {last['monitor_deflection']:.6g} m against 0.015731")
            check(abs(-last["axial_force"] - 154820.0) <= 2e-3 * 154820.0,
                  f"steel strip: N {-last['axial_force']:.6g} N tension against 154820")
        drawn(args.liftoff, h5, os.path.join(tmp, "strip"))
        check(ordinate(h5) == "lambda", "steel strip: the lift-off map is drawn against lambda (no limit point)")

        bifurcating_arch(args, tmp)
    finish()


# The shallow arch's four events in the order a trace meets them, and the closed form's name of each.
ARCH_EVENTS = [("bifurcation", "first_bifurcation"), ("limit_at_support", "first_lift_off"),
               ("limit_at_support", "last_lift_off"), ("bifurcation", "second_bifurcation")]


def bifurcating_arch(args, tmp):
    """verification/scenes/von_karman/shallow_arch_bifurcation.toml by both paths against the exact
    two-mode solution (closed_form_reference shallow-arch, with the scene's own numbers).

    Ritz: its basis holds both modes exactly, so its loads are the closed form's up to the event
    location (1e-10 in lambda) and the states' Newton accuracy: 1e-9. FE: 32 and 64 elements, the
    64 elements' error within twice its Richardson estimate |l32 - l64| / (2^p - 1), p = 4 for the
    bifurcations (the element's order; fe_member_von_karman_test) and 2 for the contact events (the
    end's lift-off found at the node next to it: w(h) = w'(0) h + O(h^3) vanishes at w'(0) = O(h^2)).
    Every step stable (kappa = 8 > 4: a stable asymmetric branch) up to the second bifurcation."""
    scene_path = os.path.join(SCENES, "shallow_arch_bifurcation.toml")
    with open(scene_path, "rb") as f:
        scene = tomllib.load(f)
    structure = scene["structure"]
    reference = subprocess.run(
        [args.closed_form, "shallow-arch", "--rise", repr(-scene["geometry"]["initial_shape"]["amplitude"]),
         "--length", repr(structure["length"]), "--EI", repr(structure["EI"]), "--EA", repr(structure["EA"]),
         "--modulus", repr(scene["foundation"]["modulus"]), "--load", repr(scene["loads"][0]["value"])],
        capture_output=True, text=True)
    check(reference.returncode == 0, f"arch bifurcation: closed_form_reference exit 0 ({reference.stderr.strip()})")
    if reference.returncode != 0:
        return
    exact = json.loads(reference.stdout)
    check(exact["first"] == "stable_bifurcation" and exact["has_contact_event"],
          f"arch bifurcation: the closed form's first event is a stable bifurcation ({exact['reason']})")
    loads = [exact[name]["lambda"] for _, name in ARCH_EVENTS]
    h5 = os.path.join(tmp, "arch_bifurcation.h5")
    out = trace(args.liftoff, scene_path, h5, "--method", "all")
    coarse = trace(args.liftoff, scene_path, os.path.join(tmp, "arch_bifurcation_32.h5"), "--elements", "32")
    paths = {p["path"]: p for p in out.get("paths", [])}
    fe32 = {p["path"]: p for p in coarse.get("paths", [])}.get("fe")
    check(sorted(paths) == ["fe", "ritz"] and fe32 is not None, f"arch bifurcation: the fe and ritz paths traced "
                                                                 f"(got {sorted(paths)})")
    kinds = [kind for kind, _ in ARCH_EVENTS]
    for name, p in paths.items():
        found = [e["kind"] for e in p["events"]]
        check(p["termination"] == "completed" and found == kinds,
              f"arch bifurcation, {name}: completed with {kinds} (got {p['termination']}, {found}: {p['message']})")
        # But the last: the second bifurcation point, where the tangent is singular (its sign round-off).
        unstable = [s["lambda"] for s in p["steps"][:-1] if s["stability"] != "stable"]
        check(not unstable, f"arch bifurcation, {name}: every step stable up to the second bifurcation (not: "
                            f"{unstable[:3]})")
    if [e["kind"] for e in paths.get("ritz", {"events": []})["events"]] == kinds:
        for (kind, name), load, e in zip(ARCH_EVENTS, loads, paths["ritz"]["events"]):
            check(abs(e["lambda"] - load) <= 1e-9, f"arch bifurcation, ritz: {name} {e['lambda']:.12g} against "
                                                   f"the closed form's {load:.12g}")
    if fe32 and [e["kind"] for e in fe32["events"]] == kinds and [e["kind"] for e in paths["fe"]["events"]] == kinds:
        for (kind, name), load, e32, e64 in zip(ARCH_EVENTS, loads, fe32["events"], paths["fe"]["events"]):
            order = 4 if kind == "bifurcation" else 2
            estimate = abs(e32["lambda"] - e64["lambda"]) / (2**order - 1)
            check(abs(e64["lambda"] - load) <= 2 * estimate,
                  f"arch bifurcation, fe: {name} {e64['lambda']:.10g} (32 el. {e32['lambda']:.10g}) within twice its "
                  f"estimate {estimate:.2g} of the closed form's {load:.10g}")
    drawn(args.liftoff, h5, os.path.join(tmp, "arch_bifurcation"))


if __name__ == "__main__":
    main()
