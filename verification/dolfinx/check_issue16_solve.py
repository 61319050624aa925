#!/usr/bin/python3
"""`liftoff solve` of von Karman beams against the dolfinx von Karman reference at the same load.

    /usr/bin/python3 verification/dolfinx/check_issue16_solve.py --liftoff build/src/liftoff

liftoff is run as a user runs it (`solve SCENE --json --csv-fields`); the reference is
von_karman_reference.py (P2 interior-penalty w, P3 u, penalty-free exact tensionless foundation),
solved at the scene's load by load control from zero (Newton from the previous load, the increment
halved on a failure). No code is shared with liftoff. Scenes:
(a) the steel strip verification/scenes/von_karman/steel_strip_membrane.toml: membrane action of a
    beam with restrained ends on a tensionless bedding (full contact, N = 154.8 kN);
(b) the shallow arch verification/dolfinx/scenes/issue16/shallow_arch_tensionless.toml at load
    factors 10 and 20, below its limit point (lambda 21.14): the unloaded half lifts off; at 25,
    past the limit, `liftoff solve` must refuse (exit 5, termination "limit_point");
(c) the steel strip with its right end axially free: N = 0, the linear answer (also checked
    against liftoff's own `theory = "linear"` answer).
Compared: w at liftoff's nodes (max difference), the membrane force, the contact limits, the
support reactions (vertical and horizontal).

Tolerances, from each side's own convergence, none chosen to pass: the reference on 32, 64, 128
elements gives an observed order p (asserted in [1.7, 2.3]: P2 interior penalty is O(h^2); the
contact limits' order is reported, not asserted, where it is not in the asymptotic range) and the
Richardson extrapolate r_x = r_128 + (r_128 - r_64)/(2^p - 1), whose distance to r_128 estimates
the finest reference's error; liftoff's error is bounded by the change from its N-element answer to
the 2N-element one (a bound for any order >= 1). The check: |liftoff_N - r_x| <= |r_128 - r_x| +
|liftoff_2N - liftoff_N| + 1e-12 (scale), i.e. liftoff agrees with the extrapolated reference to
within the finest reference's own error. Exit 1 on any failure, 2 when a program cannot be run.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import von_karman_reference as vk  # noqa: E402

STRIP = os.path.join(ROOT, "verification", "scenes", "von_karman", "steel_strip_membrane.toml")
ARCH = os.path.join(HERE, "scenes", "issue16", "shallow_arch_tensionless.toml")
MESHES = (32, 64, 128)
ORDER = (1.7, 2.3)  # as check_issue16.py: P2 interior penalty, h^2
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print(f"  FAIL: {what}")


# ---- liftoff, as a user runs it ----

def run_liftoff(liftoff, scene, elements, tmp):
    """(exit code, the JSON report, the CSV fields as (x, w) arrays or None)."""
    csv = os.path.join(tmp, f"fields_{elements}.csv")
    if os.path.exists(csv):
        os.remove(csv)
    p = subprocess.run([liftoff, "solve", scene, "--json", "--elements", str(elements), "--csv-fields", csv],
                       capture_output=True, text=True)
    try:
        report = json.loads(p.stdout)
    except json.JSONDecodeError:
        print(f"liftoff printed no JSON for {scene} (exit {p.returncode}): {p.stderr.strip()}", file=sys.stderr)
        sys.exit(2)
    fields = None
    if p.returncode == 0:
        data = np.genfromtxt(csv, delimiter=",", names=True)
        fields = (data["x"], data["w"])
    return p.returncode, report, fields


def liftoff_figures(report, fields, nodes):
    """The compared figures of a liftoff report: w at `nodes` (nodes of its mesh: sampled exactly)."""
    x, w = fields
    at = [int(np.argmin(np.abs(x - xn))) for xn in nodes]
    assert max(abs(x[i] - xn) for i, xn in zip(at, nodes)) <= 1e-9 * nodes[-1], "a node missing from the samples"
    reactions = sorted(report["support_reactions"], key=lambda r: r["at"])
    return {"nodes": nodes, "w": w[at], "N": np.asarray(report.get("membrane_force", {}).get("value", [])),
            "regions": [tuple(r) for r in report["contact_regions"]],
            "vertical": [r["force"] for r in reactions], "horizontal": [r.get("horizontal", 0.0) for r in reactions]}


# ---- the reference at a load ----

def reference_at(p, n, lam_target=1.0, first_step=0.125):
    """The reference model on n elements, solved at lam_target by load control from zero."""
    m = vk.Model(p, n)
    x, lam, step = np.zeros(m.ndofs), 0.0, first_step * lam_target
    while lam < lam_target:
        step = min(step, lam_target - lam)
        try:
            x, lam = m.solve(x, lam + step)[:2]
            step *= 1.5
        except vk.SolveFailure:
            step /= 2
            if step < 1e-6 * lam_target:
                raise
    return m, x


def p2_w(m, x, at):
    """The reference's P2 w at the points `at`."""
    verts = m.cx[:, 0]
    cell = np.clip(np.searchsorted(verts, at, side="right") - 1, 0, len(verts) - 1)
    wl, wm, wr = (x[m.cw[cell, i]] for i in range(3))
    t = (at - m.cx[cell, 0]) / (m.cx[cell, 2] - m.cx[cell, 0])
    return (2 * wl - 4 * wm + 2 * wr) * t * t + (-3 * wl + 4 * wm - wr) * t + wl


def reference_figures(m, x, nodes):
    """The compared figures: reactions from the residual at the held dofs (the support's force on the
    member, R = internal - external there): liftoff's vertical `force` is positive away from the
    foundation, i.e. -R_w; its `horizontal` is the force on the member along x, R_u."""
    R, _ = m.residual(x, 1.0, want_jac=False)
    tol = 1e-9 * m.p.L

    def held(at, is_w):
        d = np.nonzero((np.abs(m.coord - at) < tol) & (m.is_w == is_w))[0]
        return float(R[d[0]]) if d[0] not in m.free else 0.0
    ends = (0.0, m.p.L)
    return {"w": p2_w(m, x, nodes), "N": m.thrust(x), "regions": m.contact(x),
            "vertical": [-held(a, True) for a in ends], "horizontal": [held(a, False) for a in ends]}


def as_vector(fig, key):
    v = fig[key]
    if key == "regions":
        return np.array([lim for r in v for lim in r])
    return np.atleast_1d(np.asarray(v, dtype=float))


def compare(name, lift, lift2, refs, scale, assert_order=True):
    """One figure: liftoff (N and 2N elements) against the reference on MESHES. Vectors compared in
    the max norm."""
    l1, l2 = as_vector(lift, name), as_vector(lift2, name)
    rs = [as_vector(r, name) for r in refs]
    if name == "N":   # liftoff's per-element membrane force against the reference's (constant) mean
        spread = float(np.abs(l1 - l1.mean()).max())
        l1, l2 = np.array([l1.mean()]), np.array([l2.mean()])
    if any(len(v) != len(l1) for v in [l2] + rs):
        check(False, f"{name}: liftoff's {len(l1)} and the reference's {len(rs[-1])} values differ in number")
        return
    d1, d2 = np.abs(rs[0] - rs[1]).max(), np.abs(rs[1] - rs[2]).max()
    floor = 1e-12 * scale
    p = math.log2(d1 / d2) if d2 > floor and d1 > floor else float("nan")
    pe = p if ORDER[0] <= p <= ORDER[1] else 2.0
    extrapolate = rs[2] + (rs[2] - rs[1]) / (2 ** pe - 1)
    ref_error = float(np.abs(rs[2] - extrapolate).max())
    lift_error = float(np.abs(l2 - l1).max())
    diff = float(np.abs(l1 - extrapolate).max())
    diff_fine = float(np.abs(l1 - rs[2]).max())
    tol = ref_error + lift_error + floor
    extra = f", liftoff's spread over the elements {spread:.1e}" if name == "N" else ""
    print(f"  {name:10s} |liftoff - ref_x| {diff:.3e} (vs ref_{MESHES[-1]}: {diff_fine:.3e}) <= {tol:.3e} "
          f"(ref error {ref_error:.2e}, order {p:.2f}; liftoff error {lift_error:.1e}){extra}")
    check(diff <= tol, f"{name}: liftoff differs from the extrapolated reference by {diff:.3e} > {tol:.3e}")
    if assert_order and d2 > floor:
        check(ORDER[0] <= p <= ORDER[1], f"{name}: the reference's observed order {p:.2f} outside {ORDER}")


def read_for_reference(scene, tmp):
    """The scene as the reference reads it: only the tables it reads (vk.TABLES). The others say
    nothing about the solution it is checked against: [units] only names the units of the numbers
    (liftoff converts nothing: src/scene/README.md, "Scale and warnings"), [trace] drives `liftoff trace`. A
    misspelt key inside a kept table is still refused by the reference."""
    with open(scene) as fh:
        lines = fh.read().splitlines(keepends=True)
    out, kept = [], True
    for line in lines:
        if line.startswith("["):
            name = line.strip().strip("[]").split(".")[0].strip()
            kept = name in vk.TABLES
        if kept:
            out.append(line)
    path = os.path.join(tmp, "reference_" + os.path.basename(scene))
    with open(path, "w") as fh:
        fh.write("".join(out))
    return vk.read_scene(path)


def case(title, scene, liftoff, tmp, lam=1.0, order_of=("w", "N", "vertical", "horizontal")):
    p, solve = read_for_reference(scene, tmp)
    elements = int(solve.get("elements", 128))
    t0 = time.perf_counter()
    code, report, fields = run_liftoff(liftoff, scene, elements, tmp)
    code2, report2, fields2 = run_liftoff(liftoff, scene, 2 * elements, tmp)
    t_lift = time.perf_counter() - t0
    print(f"{title}: liftoff exit {code} ({report.get('termination')}), {elements} and {2 * elements} elements, "
          f"{t_lift:.1f} s")
    if code != 0 or code2 != 0:
        check(False, f"{title}: liftoff solve exit {code}/{code2}: {report.get('message')}")
        return None
    nodes = np.linspace(0.0, p.L, elements + 1)
    lift, lift2 = liftoff_figures(report, fields, nodes), liftoff_figures(report2, fields2, nodes)
    t0 = time.perf_counter()
    refs = []
    for n in MESHES:
        m, x = reference_at(p, n, lam)
        refs.append(reference_figures(m, x, lift["nodes"]))
    print(f"  reference on {', '.join(map(str, MESHES))} elements: {time.perf_counter() - t0:.1f} s; liftoff: "
          f"w_max {report['w_max']:.8g}, N {lift['N'].mean():.8g}, contact "
          f"{[f'[{a:.6g}, {b:.6g}]' for a, b in lift['regions']]}, reactions vertical "
          f"{[f'{v:.6g}' for v in lift['vertical']]} horizontal {[f'{v:.6g}' for v in lift['horizontal']]}")
    scale_w = float(np.abs(lift["w"]).max())
    scale_f = max(float(np.abs(as_vector(lift, "vertical")).max()), float(np.abs(lift["N"]).max()))
    compare("w", lift, lift2, refs, scale_w, "w" in order_of)
    compare("N", lift, lift2, refs, scale_f, "N" in order_of)
    compare("regions", lift, lift2, refs, p.L, "regions" in order_of)
    compare("vertical", lift, lift2, refs, scale_f, "vertical" in order_of)
    compare("horizontal", lift, lift2, refs, scale_f, "horizontal" in order_of)
    return lift


def scene_with(base, tmp, name, replace):
    with open(base) as fh:
        text = fh.read()
    for old, new in replace:
        assert old in text, f"{old!r} not in {base}"
        text = text.replace(old, new)
    path = os.path.join(tmp, name)
    with open(path, "w") as fh:
        fh.write(text)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--liftoff", default=os.path.join(ROOT, "build", "src", "liftoff"))
    args = ap.parse_args()
    if not os.access(args.liftoff, os.X_OK):
        print(f"--liftoff {args.liftoff}: not an executable", file=sys.stderr)
        return 2
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        case("(a) steel strip, restrained ends, tensionless bedding", STRIP, args.liftoff, tmp)
        for lam in (10, 20):
            # the scene's load is lambda = 1: liftoff solves the scene with the load scaled
            scene = scene_with(ARCH, tmp, f"arch_{lam}.toml", [("value = 1.0", f"value = {lam}.0")])
            case(f"(b) shallow arch at lambda {lam} (limit point 21.14)", scene, args.liftoff, tmp)
        scene = scene_with(ARCH, tmp, "arch_25.toml", [("value = 1.0", "value = 25.0")])
        code, report, _ = run_liftoff(args.liftoff, scene, 64, tmp)
        print(f"(b) shallow arch at lambda 25, past its limit point: exit {code}, termination "
              f"{report.get('termination')!r}: {report.get('message')}")
        check(code == 5 and report.get("termination") == "limit_point",
              f"lambda 25 past the limit point: expected exit 5 and termination limit_point, got {code}")
        free = scene_with(STRIP, tmp, "strip_free.toml", [('right = { kind = "pinned", axial = "restrained" }',
                                                          'right = { kind = "pinned", axial = "free" }')])
        lift = case("(c) steel strip, right end axially free", free, args.liftoff, tmp,
                    order_of=("w", "vertical"))
        linear = scene_with(free, tmp, "strip_linear.toml", [
            ('theory = "von_karman"', 'theory = "linear"'),
            ('left = { kind = "pinned", axial = "restrained" }', 'left = "pinned"'),
            ('right = { kind = "pinned", axial = "free" }', 'right = "pinned"')])
        if lift is not None:
            code, report, fields = run_liftoff(args.liftoff, linear, len(lift["nodes"]) - 1, tmp)
            if code != 0:
                check(False, f"(c) the linear scene: liftoff exit {code}: {report.get('message')}")
            else:
                w_lin = liftoff_figures(report, fields, lift["nodes"])["w"]
                diff = float(np.abs(lift["w"] - w_lin).max())
                scale = float(np.abs(w_lin).max())
                print(f"  against liftoff's linear answer: max |w_vK - w_linear| {diff:.2e} "
                      f"({diff / scale:.1e} of max w); max |N| {np.abs(lift['N']).max():.2e}")
                # N = 0 exactly (a free end and no axial load): the two answers differ only by the
                # solvers' stopping tolerances (relative 1e-10 or below)
                check(diff <= 1e-8 * scale, f"(c) von Karman and linear answers differ by {diff:.2e}")
    print(f"{len(failures)} failed ({time.perf_counter() - t0:.0f} s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
