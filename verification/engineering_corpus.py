#!/usr/bin/python3
"""The engineering corpus: every method on every scene of verification/scenes/engineering/.

    /usr/bin/python3 verification/engineering_corpus.py --liftoff build/src/liftoff \\
        --closed-form build/verification/closed_form_reference [--elements N] [--only NAME ...]

Each scene (real members in real units, the hand calculation in its comments) is solved with
dual, primal, fast, auto and ritz (`liftoff solve --json`), on the scene's own mesh n unless
--elements says otherwise. The footing is also solved at the seven column moments of issue 10's
sweep (`loads[1].value=lin:-600e3:0:7`). For every scene and method:

  - exit 0: the answer carries a certificate that passed (CERTIFICATE.md);
  - exit 3: exactly one JSON object on stdout with the termination and a message; allowed only
    where a refusal is expected: the dual form on a member that only the foundation holds (its
    stiffness matrix is singular), and primal when dense Lemke's pivoting lost accuracy and its
    re-solved contact set proved it wrong (termination numerical_failure). fast and auto must
    answer everywhere.
  - exit 2 from ritz on a foundation of several [[foundation.segments]] (the Ritz model takes
    one piece), with a message naming the key.
  - Anything else fails.

The answers must agree within their error estimates:
  - FE (dual, primal, fast, auto on mesh n): the contact limits converge at about h^2 but
    oscillate with where a limit falls in its element, so the error of the mesh-n answer is
    taken as its whole change from mesh n/2 (fast; Richardson would take a third of it); the
    same for w_max, w_min and max_reaction;
  - Ritz: its own estimate, estimated_limit_error (the last change of the limits with N). It
    estimates the limits only: Ritz deflections are printed, not compared;
  - the exact closed form (verification/closed_form, Hetenyi's beam solved segment by segment,
    no shared code) for beams it covers (closed_form_applies: whole or partial foundations,
    pieces with voids, gaps, tension_modulus, distributed loads): 1e-10 of the length.
Two values agree when |a - b| <= 3 (e_a + e_b) + 1e-12 * scale (compare.py's rule: the factor 3
covers estimates that are themselves only estimates).

Hand calculations, where they are exact enough to test:
  - the footing (every moment): the rigid-footing pressure distribution plus its first-order
    flexibility correction, computed here from the scene's data. The hand model's own error is
    the series' remainder, taken as no larger than the first-order correction itself (asserted
    to be a small fraction of the answer, so the series converges fast): heel limit within
    |da1| + 3 e, peak pressure within |dp1| + 3 e of rigid + first order;
  - the pipeline: the load factor of the first lift-off, lambda = 2 q / (F beta) (Hetenyi's
    infinite beam: exact while the pipe is in full contact, the clamped ends beta L / 2 = 50 away
    change it by e^-50), against the FE trace on meshes n and n/2, within 3 times their change.
Exit code 1 if anything fails; every case and method is printed.
"""
import argparse
import glob
import json
import math
import os
import subprocess
import sys
import tempfile
import tomllib

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
METHODS = ["dual", "primal", "fast", "auto", "ritz"]
MUST_ANSWER = {"fast", "auto"}
FOOTING = "footing_eccentric_column"
FOOTING_MOMENTS = [-600e3 + 100e3 * i for i in range(7)]  # lin:-600e3:0:7, issue 10
PIPELINE = "pipeline_500m_uplift"
SLEEPER = "sleeper_b70_ballast"
DESIGN_KEYS = ("moment_max", "moment_min", "shear_max_abs")


class Failures:
    def __init__(self):
        self.items = []

    def check(self, ok, where, message):
        if not ok:
            self.items.append(f"{where}: {message}")
            print(f"    FAIL {message}")
        return ok


# ---------------------------------------------------------------------------------------------
# Running liftoff

def run(command):
    p = subprocess.run(command, capture_output=True, text=True)
    try:
        obj = json.loads(p.stdout) if p.stdout.strip() else None
    except json.JSONDecodeError:
        obj = None
    return p.returncode, obj, p.stderr.strip()


def solve(liftoff, scene, method, elements):
    return run([liftoff, "solve", scene, "--method", method, "--elements", str(elements), "--json"])


def limits(result):
    return [x for region in result["contact_regions"] for x in region]


def is_fe(result):
    return "elements" in result and "modes" not in result


# ---------------------------------------------------------------------------------------------
# Scenes

def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {v!r} as TOML")


def toml_text(doc):
    """The scene's tables back as TOML (scenes hold tables, arrays of tables and plain values)."""
    out = []
    for name, value in doc.items():
        blocks = [(f"[[{name}]]", t) for t in value] if isinstance(value, list) else [(f"[{name}]", value)]
        for header, table in blocks:
            out.append(header)
            out += [f"{k} = {toml_value(v)}" for k, v in table.items()]
            out.append("")
    return "\n".join(out)


def held_by_foundation_alone(doc):
    """True when the supports leave a rigid motion free (the stiffness matrix is singular)."""
    supports = doc["supports"]
    ends = [supports["left"], supports["right"]]
    if doc["structure"]["kind"] == "arch":
        return all(e == "free" for e in ends) or sorted(ends) in (["free", "roller"], ["free", "pinned"])
    if "clamped" in ends:
        return False
    return ends.count("pinned") + len(supports.get("interior", [])) < 2


def scale_of(doc):
    s = doc["structure"]
    return 2 * s["half_angle_deg"] if s["kind"] == "arch" else s["length"]


def has_curvature(doc):
    """An imposed curvature: the Ritz model refuses it (exit 2) and the closed form has none."""
    return any(load.get("kind") == "curvature" for load in doc.get("loads", []))


def closed_form_applies(doc):
    """What verification/closed_form solves exactly: a beam with string end supports (pinned,
    clamped, free; no springs, no settlements), no interior supports, the foundation whole or
    partial or in pieces with a constant modulus each (voids between them), a gap (table or
    file), tension_modulus, and force, moment, uniform and distributed loads. Not: a modulus
    varying within a piece, tension_nondimensional_k, curvature loads (closed_form_reference does not read
    those two keys, so it must not be asked)."""
    f = doc["foundation"]
    supports = doc["supports"]
    pieces = f.get("segments", [])
    return (doc["structure"]["kind"] == "beam"
            and all(isinstance(supports.get(end), str) and supports[end] in ("pinned", "clamped", "free")
                    for end in ("left", "right"))
            and not supports.get("interior")
            and not any(isinstance(p.get("modulus", p.get("nondimensional_k", p.get("k"))), list) for p in pieces)
            and "tension_k" not in f and "tension_nondimensional_k" not in f
            and all(load.get("kind") in ("force", "moment", "uniform", "distributed") for load in doc.get("loads", []))
            and not has_curvature(doc))


# ---------------------------------------------------------------------------------------------
# Hand calculation: the rigid footing and its first-order flexibility correction

def rigid_footing(doc):
    """Pressure of a rigid free-free footing under its point forces and moments (no uniform
    loads): the resultant's eccentricity gives a trapezoid (e <= B/6) or a triangle. Returns
    (contact begin, contact end, pressure at begin, pressure at end)."""
    B = doc["structure"]["length"]
    N = sum(l["value"] for l in doc["loads"] if l["kind"] == "force")
    # Moment about x = 0 of the downward forces, clockwise positive; a moment value is ccw.
    m0 = sum(l["value"] * l["at"] for l in doc["loads"] if l["kind"] == "force") \
        - sum(l["value"] for l in doc["loads"] if l["kind"] == "moment")
    xr = m0 / N
    e = xr - B / 2
    if abs(e) <= B / 6:
        return 0.0, B, N / B * (1 - 6 * e / B), N / B * (1 + 6 * e / B)
    c = 3 * (B - xr) if e > 0 else 3 * xr
    return (B - c, B, 0.0, 2 * N / c) if e > 0 else (0.0, c, 2 * N / c, 0.0)


def footing_first_order(doc, samples=60001):
    """First-order flexibility correction of the rigid footing: the footing's bending under the
    column and the rigid pressure (a free-free beam under a self-equilibrated load) plus the
    rigid motion that keeps the pressure's change in equilibrium; the change of the contact
    limit (if inside) and of the pressure at its peak. Returns (rigid, d_limit, d_peak, ratio):
    ratio = the bending deflection against the rigid settlement range (must be small)."""
    B, K = doc["structure"]["length"], doc["foundation"]["modulus"]
    (a, b, pa, pb), x, inside, p, d = footing_flexibility(doc, samples)
    w_rigid = p / K
    ratio = (d[inside].max() - d[inside].min()) / max(w_rigid.max(), 1e-300)
    d_limit = 0.0
    if 0 < a:  # heel limit inside: w_rigid + d = 0 moves it by -d(a) / w_rigid'(a)
        d_limit = -np.interp(a, x, d) / ((pb - pa) / (b - a) / K)
    elif b < B:
        d_limit = -np.interp(b, x, d) / ((pb - pa) / (b - a) / K)
    peak_at = a if pa > pb else b
    d_peak = K * np.interp(peak_at, x, d)
    return (a, b, pa, pb), d_limit, d_peak, ratio


def footing_flexibility(doc, samples):
    """The rigid footing (rigid_footing) sampled at `samples` points x over its length, and the
    first-order change d of w (footing_first_order): the footing's bending under the loads and
    the rigid pressure p, plus the rigid motion that keeps K d self-equilibrated over the rigid
    contact `inside`. Returns ((a, b, pa, pb), x, inside, p, d)."""
    B, EI = doc["structure"]["length"], doc["structure"]["EI"]
    a, b, pa, pb = rigid_footing(doc)
    x = np.linspace(0.0, B, samples)
    inside = (x >= a) & (x <= b)
    p = np.where(inside, pa + (pb - pa) * (x - a) / (b - a), 0.0)

    def integral(f):  # cumulative trapezoid from 0
        return np.concatenate([[0.0], np.cumsum((f[1:] + f[:-1]) / 2 * np.diff(x))])

    # Sagging bending moment: the pressure pushes up (-w), forces push down, a ccw moment M at
    # x0 makes the bending moment jump by -M.
    shear = integral(p)
    bending = integral(shear)
    for l in doc["loads"]:
        if l["kind"] == "force":
            bending -= l["value"] * np.maximum(x - l["at"], 0.0)
        elif l["kind"] == "moment":
            bending -= l["value"] * (x >= l["at"])
    w_bend = integral(integral(-bending / EI))  # w'' = -M/EI, up to a rigid motion
    basis = np.vstack([np.ones_like(x), x])
    gram = np.array([[np.trapz(inside * u * v, x) for v in basis] for u in basis])
    rhs = -np.array([np.trapz(inside * w_bend * u, x) for u in basis])
    r0, r1 = np.linalg.solve(gram, rhs)
    d = w_bend + r0 + r1 * x  # the change of w, with K d self-equilibrated over the contact
    return (a, b, pa, pb), x, inside, p, d


def footing_design(doc, samples=60001):
    """The footing's largest sagging moment and |V| from the rigid pressure, and from it plus the
    first-order flexibility change K d over the rigid contact (footing_first_order's d). Returns
    (rigid, corrected), each {"moment_max", "shear_max_abs"}."""
    K = doc["foundation"]["modulus"]
    _, x, inside, p, d = footing_flexibility(doc, samples)

    def statics(pressure):
        dx = np.diff(x)
        shear = np.concatenate([[0.0], np.cumsum((pressure[1:] + pressure[:-1]) / 2 * dx)])
        for l in doc["loads"]:
            if l["kind"] == "force":
                shear = shear - l["value"] * (x > l["at"])
        bending = np.concatenate([[0.0], np.cumsum((shear[1:] + shear[:-1]) / 2 * dx)])
        for l in doc["loads"]:
            if l["kind"] == "moment":
                bending = bending - l["value"] * (x >= l["at"])
        return {"moment_max": bending.max(), "shear_max_abs": np.abs(shear).max()}

    return statics(p), statics(p + K * d * inside)


# ---------------------------------------------------------------------------------------------
# One case

def member_length(doc):
    s = doc["structure"]
    return s["length"] if s["kind"] != "arch" else 2 * math.radians(s["half_angle_deg"]) * s["radius"]


def statics_round_off(result, key, n, length):
    """Round-off of V or M integrated over n elements (recursive summation: n eps of the terms).
    Beside the mesh estimate it matters only where the exact value is 0 (a free-free member in full
    contact under a uniform load: M = V = 0), which round-off cannot reach relative to itself."""
    c = result.get("certificate", {})
    forces = abs(c.get("applied_force", 0.0)) + abs(c.get("foundation_resultant", 0.0)) + \
        sum(abs(r["force"]) for r in result.get("support_reactions", []))
    terms = forces * length if key.startswith("moment") else forces
    return n * np.finfo(float).eps * terms


def agree(a, ea, b, eb, scale):
    return abs(a - b) <= 3 * (ea + eb) + 1e-12 * scale


def ritz_cannot_take(doc):
    """What the Ritz model refuses by key (exit 2): a ground gap, elastic or settled supports, the
    foundation outside an arch, arch loads other than radial ones (issue 12). None when it can take
    the scene."""
    foundation = doc.get("foundation", {})
    for key in ("gap", "gap_file"):
        if key in foundation:
            return f"foundation.{key}"
    for end in ("left", "right"):
        if isinstance(doc.get("supports", {}).get(end), dict):
            return "supports"  # springs and settlements
    if doc.get("structure", {}).get("kind") != "arch":
        return None
    if foundation.get("side", "inside") == "outside":
        return 'foundation.side = "outside"'
    for load in doc.get("loads", []):
        if load.get("kind") != "moment" and load.get("direction", "radial") != "radial":
            return f'direction = "{load["direction"]}"'
    return None


def run_case(args, name, path, doc, fails):
    n = args.elements or doc.get("solve", {}).get("elements", 200)
    print(f"\n== {name} ({n} elements)")
    scale = scale_of(doc)
    expected_refusal = {"dual"} if held_by_foundation_alone(doc) else set()
    answers = {}
    for method in METHODS:
        rc, obj, err = solve(args.liftoff, path, method, n)
        where = f"{name} {method}"
        if method == "ritz" and ritz_cannot_take(doc):
            print(f"  {method:7} -> exit {rc} (expected: the Ritz model does not take {ritz_cannot_take(doc)}): {err}")
            fails.check(rc == 2, where, f"exit {rc}, expected the keyed refusal (exit 2)")
            continue
        if rc == 0 and obj is not None:
            cert = obj.get("certificate")
            status = "passed" if cert and cert.get("passed") else ("FAILED" if cert else "missing")
            print(f"  {method:7} -> {obj.get('method', '?'):6} {obj['termination']:10} certificate {status:7}"
                  f" limits {[round(v, 6) for v in limits(obj)]} w_max {obj['w_max']:.6e}"
                  f" ({obj['time_s']:.2f} s)")
            fails.check(cert is not None, where, "no certificate in the JSON (CERTIFICATE.md)")
            if cert is not None:
                fails.check(cert.get("passed") is True, where,
                            f"certificate failed: {cert.get('message')}")
            fails.check(obj.get("method_requested") == method, where,
                        f"method_requested is {obj.get('method_requested')!r}, not {method!r}")
            answers[method] = obj
            check_statics(where, obj, fails)
        elif rc == 3:
            message = (obj or {}).get("message") or err
            # Dense Lemke on the primal LCP (K inside, condition ~N^4) may lose its pivots to
            # round-off; it then re-solves its contact set, finds the answer wrong and refuses
            # (issue 10, point 2: right or an honest refusal). Any other refusal is a failure.
            lemke_lost = (method == "primal" and obj is not None
                          and obj.get("termination") == "numerical_failure" and "Lemke" in (message or ""))
            # Dense Lemke refuses a primal LCP above its size limit, before any pivoting.
            too_large = method == "primal" and "dense matrix" in (message or "")
            expected = method in expected_refusal or lemke_lost or too_large
            print(f"  {method:7} -> refused ({'expected' if expected else 'UNEXPECTED'}): {message}")
            fails.check(obj is not None and obj.get("termination") and obj.get("message") and obj.get("exit_code") == 3,
                        where, "exit 3 without one JSON object holding termination, message and exit_code on stdout")
            fails.check(method not in MUST_ANSWER, where, f"{method} must answer every scene")
            fails.check(expected, where, "refused where no refusal is expected")
        elif rc == 2 and method == "ritz" and has_curvature(doc):
            print(f"  {method:7} -> refused (expected: an imposed curvature): {err or (obj or {}).get('message')}")
        elif rc == 2 and method == "ritz" and len(doc["foundation"].get("segments", [])) > 1:
            # The Ritz model takes one foundation piece: a keyed refusal (bad input for it).
            print(f"  {method:7} -> refused (expected): {err}")
            fails.check("foundation.segments" in (err or ""), where, "the refusal does not name foundation.segments")
        else:
            print(f"  {method:7} -> exit {rc}: {err or (obj or {}).get('message')}")
            fails.check(False, where, f"exit {rc}")

    # Error estimates: FE from the change between meshes n/2 and n (fast).
    estimates = {}
    rc, coarse, err = solve(args.liftoff, path, "fast", max(n // 2, 1))
    fine = answers.get("fast")
    if fails.check(rc == 0 and fine is not None and len(limits(coarse)) == len(limits(fine)), f"{name} mesh",
                   f"no FE estimate: fast on {n // 2} elements gives {len(limits(coarse)) if coarse else rc}"
                   f" limits, on {n} {len(limits(fine)) if fine else 'nothing'}"):
        fe = {"limits": [abs(f - c) for f, c in zip(limits(fine), limits(coarse))]}
        for key in ("w_max", "w_min", "max_reaction"):
            fe[key] = abs(fine[key] - coarse[key])
        for key in DESIGN_KEYS:
            if "design" in fine and "design" in coarse:
                fe[key] = abs(fine["design"][key]["value"] - coarse["design"][key]["value"])
        fe["support_reactions"] = [(abs(a["force"] - b["force"]), abs(a["moment"] - b["moment"]))
                                   for a, b in zip(fine.get("support_reactions", []),
                                                   coarse.get("support_reactions", []))]
        estimates["fe"] = fe

    entries = []  # (label, result limits, their estimates, values with estimates or None)
    for method, obj in answers.items():
        if is_fe(obj):
            if "fe" in estimates:
                e = estimates["fe"]
                values = {k: (obj[k], e[k]) for k in ("w_max", "w_min", "max_reaction")}
                values.update({k: (obj["design"][k]["value"], e[k] + statics_round_off(obj, k, n, member_length(doc)))
                               for k in DESIGN_KEYS if k in e and "design" in obj})
                entries.append((method, limits(obj), e["limits"], values))
        else:
            e = obj.get("estimated_limit_error")
            if fails.check(e is not None, f"{name} {method}", "Ritz answer without estimated_limit_error"):
                entries.append((method, limits(obj), [e] * len(limits(obj)), None))
    if closed_form_applies(doc):
        rc, cf, err = run([args.closed_form, path])
        if fails.check(rc == 0, f"{name} closed form", f"exit {rc}: {err}"):
            # Its moment extremes are exact (breakpoints and bisection on V); |V|'s largest is
            # at a breakpoint (a point load, a support, a foundation's edge) on every shipped scene.
            entries.append(("closed form", limits(cf), [1e-10 * scale] * len(limits(cf)),
                            {k: (cf[k], 1e-10 * abs(cf[k]))
                             for k in ("w_max", "w_min") + DESIGN_KEYS if k in cf}))

    # Agreement, every pair.
    for i, (la, va, ea, wa) in enumerate(entries):
        for lb, vb, eb, wb in entries[i + 1:]:
            where = f"{name} {la} vs {lb}"
            if not fails.check(len(va) == len(vb), where, f"{len(va) // 2} against {len(vb) // 2} contact regions"):
                continue
            for k, (a, b, xa, xb) in enumerate(zip(va, vb, ea, eb)):
                fails.check(agree(a, xa, b, xb, scale), where,
                            f"limit {k}: {a:.9g} against {b:.9g}, differ by {abs(a - b):.2e},"
                            f" allowed {3 * (xa + xb) + 1e-12 * scale:.2e}")
            for key in set(wa or {}) & set(wb or {}):
                (a, xa), (b, xb) = wa[key], wb[key]
                fails.check(agree(a, xa, b, xb, max(abs(a), abs(b))), where,
                            f"{key}: {a:.9g} against {b:.9g}, differ by {abs(a - b):.2e},"
                            f" allowed {3 * (xa + xb) + 1e-12 * max(abs(a), abs(b)):.2e}")
    if "ritz" in answers and "fast" in answers:
        r, f = answers["ritz"], answers["fast"]
        print(f"  (Ritz w_max {r['w_max']:.6e} against fast {f['w_max']:.6e}: relative"
              f" {abs(r['w_max'] - f['w_max']) / abs(f['w_max']):.1e}, not estimated by Ritz)")

    if name.startswith(FOOTING):
        hand_footing(name, doc, answers, estimates, fails)
        hand_footing_design(name, doc, answers, estimates, fails)
    if name == PIPELINE:
        hand_pipeline(args, name, path, doc, n, fails)
        hand_pipeline_design(name, doc, answers, estimates, fails)
    if name == SLEEPER:
        hand_sleeper_design(name, doc, answers, estimates, fails)


def check_statics(where, obj, fails):
    """Beams: the support forces plus the foundation's resultant equal the applied force, within
    the certificate's own force-balance tolerance of the same terms; the statics of V and M close
    at the far end within the same tolerance (the design block's closure)."""
    if obj.get("structure") != "beam" or "certificate" not in obj:
        return
    c = obj["certificate"]
    tolerance = next((k["tolerance"] for k in c["checks"] if k["name"] == "force_balance"), None)
    supports = obj.get("support_reactions", [])
    total = sum(s["force"] for s in supports) + c["foundation_resultant"] - c["applied_force"]
    terms = sum(abs(s["force"]) for s in supports) + abs(c["foundation_resultant"]) + abs(c["applied_force"])
    fails.check(tolerance is not None and abs(total) <= tolerance * terms, where,
                f"supports + foundation - applied = {total:.3e} (allowed {tolerance} of {terms:.3e})")
    fails.check("design" in obj, where, "no design values in the JSON")
    closure = obj.get("design", {}).get("closure")
    if closure is not None:  # FE: the free body's statics
        fails.check(max(closure["shear"], closure["moment"]) <= tolerance, where,
                    f"the statics do not close: {closure} (allowed {tolerance:.1e})")


def design_check(where, obj, key, hand, allowed, fails):
    got = obj["design"][key]["value"]
    print(f"  hand: {where}: {key} {got:.7g} against {hand:.7g} (differ {abs(got - hand):.3g}, allowed {allowed:.3g})")
    fails.check(abs(got - hand) <= allowed, where, f"{key} {got:.7g} against the hand value {hand:.7g},"
                f" allowed {allowed:.3g}")


def fe_estimate(estimates, key):
    return estimates.get("fe", {}).get(key, 0.0)


def hand_footing_design(name, doc, answers, estimates, fails):
    """The largest moment and shear of the footing from the rigid pressure plus its first-order
    flexibility correction (footing_first_order), within the correction's size plus 3 times the
    FE estimate (the series' remainder taken no larger than its first term, as for the limit)."""
    rigid, corrected = footing_design(doc)
    for method, obj in answers.items():
        if not is_fe(obj) or "design" not in obj:
            continue
        for key in ("moment_max", "shear_max_abs"):
            design_check(f"{name} {method} vs rigid footing", obj, key, corrected[key],
                         abs(corrected[key] - rigid[key]) + 3 * fe_estimate(estimates, key) + 1e-9 * abs(rigid[key]),
                         fails)


def hand_sleeper_design(name, doc, answers, estimates, fails):
    """The sleeper's moments and shear from rigid statics (uniform pressure (2 P + W) / L), with a
    bound of the flexibility's effect: the pressure departs from uniform by at most
    K max|w - w_rigid| (the scene's Hetenyi deflections, 2.98 to 3.40 mm against 3.24 mm), which
    moves a moment at x by at most that times x^2 / 2 and a shear by that times x."""
    L, K = doc["structure"]["length"], doc["foundation"]["modulus"]
    q = sum(l["value"] for l in doc["loads"] if l["kind"] == "uniform")
    forces = [l for l in doc["loads"] if l["kind"] == "force"]
    P, a = forces[0]["value"], forces[0]["at"]
    p = (sum(l["value"] for l in forces) + q * L) / L
    dp = K * max(abs(3.40e-3 - p / K), abs(2.98e-3 - p / K))  # the scene comment's deflections
    c = L / 2
    hand = {"moment_max": (p - q) * a ** 2 / 2, "moment_min": (p - q) * c ** 2 / 2 - P * (c - a),
            "shear_max_abs": abs((p - q) * a - P)}
    allowed = {"moment_max": dp * a ** 2 / 2, "moment_min": dp * c ** 2 / 2, "shear_max_abs": dp * a}
    for method, obj in answers.items():
        if not is_fe(obj) or "design" not in obj:
            continue
        for key in hand:
            design_check(f"{name} {method} vs rigid sleeper", obj, key, hand[key],
                         allowed[key] + 3 * fe_estimate(estimates, key), fails)


def hand_pipeline_design(name, doc, answers, estimates, fails):
    """The pipeline at lambda = 1: the clamped ends (250 m from the lift, e^-50) hold a
    semi-infinite pipe settled q/K at w = 0, w' = 0: force q / beta, moment q / (2 beta^2)
    (Hetenyi, exact); |V| largest F/2 either side of the lift (statics of the symmetric span,
    exact); the hogging moment at the lift from the rigid-seabed span l = 3F/(4q): q l^2 / 6 -
    ... = R0 l - q l^2 / 2 with R0 = q l / 3, good to the seabed's spreading of the touchdown load
    over 1/beta: allowed a fraction 1/(beta l) of it."""
    EI, K, L = doc["structure"]["EI"], doc["foundation"]["modulus"], doc["structure"]["length"]
    q = sum(l["value"] for l in doc["loads"] if l["kind"] == "uniform")
    F = -sum(l["value"] for l in doc["loads"] if l["kind"] == "force")
    beta = (K / (4 * EI)) ** 0.25
    ends = math.exp(-beta * L / 2)
    span = 3 * F / (4 * q)
    hogging = q * span / 3 * span - q * span ** 2 / 2
    for method, obj in answers.items():
        if not is_fe(obj) or "design" not in obj:
            continue
        where = f"{name} {method} vs Hetenyi"
        supports = obj.get("support_reactions", [])
        errors = estimates.get("fe", {}).get("support_reactions", [(0.0, 0.0)] * len(supports))
        if fails.check(len(supports) == 2, where, f"{len(supports)} support reactions, expected 2"):
            for s, (ef, em), sign in zip(supports, errors, (1, -1)):
                for what, got, hand, e in (("force", s["force"], q / beta, ef),
                                           ("moment", s["moment"], sign * q / (2 * beta ** 2), em)):
                    allowed = 3 * e + ends * abs(hand) + 1e-9 * abs(hand)
                    print(f"  hand: {where}: support at {s['at']:g} {what} {got:.7g} against {hand:.7g}"
                          f" (allowed {allowed:.3g})")
                    fails.check(abs(got - hand) <= allowed, where, f"support at {s['at']} {what} {got:.7g}"
                                f" against {hand:.7g}, allowed {allowed:.3g}")
        design_check(where, obj, "shear_max_abs", F / 2,
                     3 * fe_estimate(estimates, "shear_max_abs") + 1e-9 * F, fails)
        design_check(f"{name} {method} vs rigid seabed", obj, "moment_min", hogging,
                     abs(hogging) / (beta * span) + 3 * fe_estimate(estimates, "moment_min"), fails)


def hand_footing(name, doc, answers, estimates, fails):
    (a, b, pa, pb), d_limit, d_peak, ratio = footing_first_order(doc)
    peak = max(pa, pb)
    print(f"  hand: rigid contact [{a:.6g}, {b:.6g}], peak {peak:.6g}; first order: limit {d_limit:+.3e},"
          f" peak {d_peak:+.4g} (bending / rigid settlement {ratio:.2e})")
    # The series in the flexibility converges fast only for a nearly rigid footing.
    fails.check(ratio < 0.1, f"{name} hand", f"the footing is not nearly rigid (ratio {ratio:.2f})")
    B = doc["structure"]["length"]
    for method, obj in answers.items():
        where = f"{name} {method} vs rigid footing"
        e_lim = estimates["fe"]["limits"] if is_fe(obj) and "fe" in estimates else \
            [obj.get("estimated_limit_error", 0.0)] * len(limits(obj))
        got = limits(obj)
        if not fails.check(len(got) == 2, where, f"{len(got) // 2} contact regions, expected one"):
            continue
        hand = [a + (d_limit if a > 0 else 0.0), b + (d_limit if b < B else 0.0)]
        for k in range(2):
            fails.check(abs(got[k] - hand[k]) <= abs(d_limit) + 3 * e_lim[k] + 1e-12 * B, where,
                        f"limit {got[k]:.9g} against rigid + first order {hand[k]:.9g}"
                        f" (allowed {abs(d_limit) + 3 * e_lim[k]:.2e})")
        if is_fe(obj) and "fe" in estimates:
            e_p = estimates["fe"]["max_reaction"]
            fails.check(abs(obj["max_reaction"] - (peak + d_peak)) <= abs(d_peak) + 3 * e_p, where,
                        f"peak pressure {obj['max_reaction']:.7g} against rigid + first order"
                        f" {peak + d_peak:.7g} (allowed {abs(d_peak) + 3 * e_p:.2e})")


def hand_pipeline(args, name, path, doc, n, fails):
    EI, K = doc["structure"]["EI"], doc["foundation"]["modulus"]
    q = sum(l["value"] for l in doc["loads"] if l["kind"] == "uniform" and l.get("case") == "dead")
    F = -sum(l["value"] for l in doc["loads"] if l["kind"] == "force" and l.get("case", "live") == "live")
    beta = (K / (4 * EI)) ** 0.25
    hand = 2 * q / (F * beta)
    first = []
    for elements in (n // 2, n):
        rc, obj, err = run([args.liftoff, "trace", path, "--method", "fast", "--elements", str(elements), "--json"])
        events = (obj or {}).get("events") or [{}]
        if not fails.check(rc == 0 and events[0].get("kind") == "lift_off_opens", f"{name} trace",
                           f"{elements} elements: exit {rc}, first event {events[0].get('kind')}: {err}"):
            return
        first.append(events[0]["lambda"])
    estimate = abs(first[1] - first[0])
    print(f"  hand: first lift-off at lambda = 2 q / (F beta) = {hand:.8f}; FE trace {first[1]:.8f}"
          f" ({n} el.), {first[0]:.8f} ({n // 2} el.)")
    fails.check(abs(first[1] - hand) <= 3 * estimate + math.exp(-beta * doc["structure"]["length"] / 2),
                f"{name} trace vs Hetenyi", f"first lift-off at {first[1]:.8f}, hand {hand:.8f},"
                f" allowed {3 * estimate:.2e}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--liftoff", required=True)
    parser.add_argument("--closed-form", required=True)
    parser.add_argument("--scenes", default=os.path.join(HERE, "scenes", "engineering"))
    parser.add_argument("--elements", type=int, default=None, help="every scene on this mesh (default: its own)")
    parser.add_argument("--only", nargs="*", default=None, help="scene names (file names without .toml)")
    args = parser.parse_args()

    fails = Failures()
    with tempfile.TemporaryDirectory() as tmp:
        for path in sorted(glob.glob(os.path.join(args.scenes, "*.toml"))):
            name = os.path.basename(path)[:-5]
            if args.only is not None and name not in args.only:
                continue
            with open(path, "rb") as f:
                doc = tomllib.load(f)
            run_case(args, name, path, doc, fails)
            if name == FOOTING:
                # The moments of issue 10's sweep, each as a scene of its own.
                moment = next(l for l in doc["loads"] if l["kind"] == "moment")
                own = moment["value"]
                for value in FOOTING_MOMENTS:
                    if value == own:
                        continue
                    moment["value"] = value
                    case = os.path.join(tmp, f"{name}_M{value:+.0f}.toml")
                    with open(case, "w") as f:
                        f.write(toml_text(doc))
                    run_case(args, f"{name}[M = {value:+.0f}]", case, doc, fails)

    print()
    for item in fails.items:
        print("FAILED", item)
    print(f"{len(fails.items)} failures")
    sys.exit(1 if fails.items else 0)


if __name__ == "__main__":
    main()
