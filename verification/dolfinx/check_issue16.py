#!/usr/bin/python3
"""Issue 16's von Karman reference (von_karman_reference.py) against closed forms derived here.

    /usr/bin/python3 verification/dolfinx/check_issue16.py

Pinned beam, length L, ends axially restrained (u = 0), Winkler k, load lambda q0 sin(pi x/L),
initial shape w0 = a0 sin(pi x/L) + e sin(2 pi x/L) (a0 = -a: the arch rises away from the
foundation). With w = sum A_n sin(n pi x/L), b_n = n pi/L, the restrained ends give a constant
(tensile) N = EA/L int (w0' w' + w'^2/2) dx = EA [b1^2 (a0 A1/2 + A1^2/4) + b2^2 (e A2/2 + A2^2/4)]
and the equilibrium EI w'''' - N (w0 + w)'' + k w = lambda q is exactly two-mode (the other modes
are unloaded, and N couples them only through N itself):

    mode 1:  (EI b1^4 + k) A1 + N b1^2 (A1 + a0) = lambda q0
    mode 2:  (EI b2^4 + k) A2 + N b2^2 (A2 + e)  = 0.

(a) straight (a0 = e = 0): A2 = 0, N = EA A^2 pi^2/(4 L^2), A from the cubic
    (EI b1^4 + k + N b1^2) A = q0. The P2-CIP crown deflection at 16..128 elements: error, order 2.
(b) perfect arch, symmetric path (A2 = 0, a symmetric mesh keeps it): lambda(A1) = [(EI b1^4 + k) A1
    + EA b1^4 A1 (A1 + 2 a0)(A1 + a0)/4] / q0, whose maximum is at 3 (A1 + a0)^2 = a0^2 - s^2,
    s^2 = 4 (EI b1^4 + k)/(EA b1^4) (first root): the limit load. a/r = 4.5 (r^2 = EI/EA): the limit
    point comes before the bifurcation. The reference's path maximum at 16, 32, 64 elements, and at
    32 by arc-length control (the same discrete problem: the same maximum to 1e-9).
(c) a/r = 8 with e = a/100: mode 2 can only grow when N -> -P2, P2 = EI b2^2 + k/b2^2 (the second
    mode's critical load with the foundation); the perfect arch bifurcates where the symmetric
    path's N reaches -P2, before its limit point. The imperfect path is exact too: at each crown
    deflection A1 (sin(2 pi x/L) vanishes at the crown), A2 is a root of the cubic of mode 2 and
    lambda follows from mode 1. Checked along the reference's path (32 and 64 elements): lambda and
    A2 at every step, the path's maximum, and N / (-P2 A2/(A2 + e)).
(d) (c) on a tensionless foundation: identical to the bilateral path while w >= 0; the first contact
    event is the lift-off at an end, where w'(end) = 0, i.e. |A2| = A1/2 on the exact path of (c).
Pass criteria: observed orders within [1.7, 2.3] (P2 interior penalty: h^2), and the finest mesh's
error within 5 % of the Richardson estimate or, for single-mesh figures, below the error that the
next coarser mesh's order-2 estimate allows. Exit 1 on any failure.
"""
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import von_karman_reference as vk  # noqa: E402

ORDER = (1.7, 2.3)
L, EI, EA = 1.0, 1.0, 1.0e4
R_GYR = math.sqrt(EI / EA)
B1, B2 = math.pi / L, 2 * math.pi / L
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print(f"  FAIL: {what}")


def orders(errors):
    return [math.log2(abs(e0 / e1)) for e0, e1 in zip(errors, errors[1:])]


# ---- closed forms ----

def straight_amplitude(k, q0):
    """The real root of (EA b^4/4) A^3 + (EI b^4 + k) A - q0 = 0 (one: the cubic is increasing)."""
    roots = np.roots([EA * B1 ** 4 / 4, 0.0, EI * B1 ** 4 + k, -q0])
    return float(roots[np.argmin(np.abs(roots.imag))].real)


def thrust(a0, e, A1, A2):
    return EA * (B1 ** 2 * (a0 * A1 / 2 + A1 ** 2 / 4) + B2 ** 2 * (e * A2 / 2 + A2 ** 2 / 4))


def lam_of(k, q0, a0, e, A1, A2):
    return ((EI * B1 ** 4 + k) * A1 + thrust(a0, e, A1, A2) * B1 ** 2 * (A1 + a0)) / q0


def mode2_roots(k, a0, e, A1):
    """Real roots A2 of (EI b2^4 + k) A2 + N(A1, A2) b2^2 (A2 + e) = 0 (a cubic in A2)."""
    c = EA * B1 ** 2 * (a0 * A1 / 2 + A1 ** 2 / 4)
    d = EA * B2 ** 2
    N = np.polynomial.Polynomial([c, d * e / 2, d / 4])
    g = np.polynomial.Polynomial([0.0, EI * B2 ** 4 + k]) + B2 ** 2 * np.polynomial.Polynomial([e, 1.0]) * N
    r = g.roots()
    return np.sort(r[np.abs(r.imag) <= 1e-9 * max(1.0, np.abs(r).max())].real)


def exact_imperfect_path(k, q0, a0, e, A1s):
    """A2 and lambda along the imperfect path, the root followed continuously from A2 = 0."""
    A2, out = 0.0, []
    for A1 in A1s:
        roots = mode2_roots(k, a0, e, A1)
        A2 = float(roots[np.argmin(np.abs(roots - A2))])
        out.append((A2, lam_of(k, q0, a0, e, A1, A2)))
    return out


def trace(p, n, crown_max, steps, stability=True):
    m = vk.Model(p, n)
    return m, vk.trace(m, crown_max, steps, stability=stability)


# ---- (a) ----

def part_a():
    print("(a) straight beam, restrained pinned ends, bilateral k = 100, q0 sin(pi x/L)")
    k, A_target = 100.0, 0.05      # A = 5 r: N b^2 is 3.7 times EI b^4 + k
    q0 = (EI * B1 ** 4 + k + EA * A_target ** 2 * B1 ** 2 / 4 * B1 ** 2) * A_target
    A = straight_amplitude(k, q0)
    N = EA * A ** 2 * math.pi ** 2 / (4 * L ** 2)
    print(f"  exact: A = {A:.15g}, N = {N:.15g} (q0 = {q0:.10g})")
    meshes, errs, nerrs = [16, 32, 64, 128], [], []
    for n in meshes:
        m = vk.Model(vk.Problem(L=L, EI=EI, EA=EA, k=k, load_sines=[(1, q0)]), n)
        x, _, it, res = m.solve(np.zeros(m.ndofs), 1.0)
        errs.append(m.crown_deflection(x) - A)
        nerrs.append(m.thrust(x) - N)
        print(f"  {n:4d} elements: crown {m.crown_deflection(x):.15g} error {errs[-1]:.3e}, "
              f"N error {nerrs[-1]:.3e} (Newton {it}, residual {res:.1e})")
    oa, on = orders(errs), orders(nerrs)
    print(f"  observed orders: crown {', '.join(f'{o:.3f}' for o in oa)}; N {', '.join(f'{o:.3f}' for o in on)}")
    check(all(ORDER[0] <= o <= ORDER[1] for o in oa + on), "(a) observed order outside [1.7, 2.3]")
    # one end axially free: N = 0, the linear answer q0/(EI b^4 + k), at order 2
    lin = q0 / (EI * B1 ** 4 + k)
    ferrs, fN = [], []
    for n in (32, 64):
        m = vk.Model(vk.Problem(L=L, EI=EI, EA=EA, k=k, load_sines=[(1, q0)], axial_right="free"), n)
        x, _, _, _ = m.solve(np.zeros(m.ndofs), 1.0)
        ferrs.append(m.crown_deflection(x) - lin)
        fN.append(m.thrust(x))
    of = orders(ferrs)[0]
    print(f"  axial = \"free\" at the right end: max |N| = {max(map(abs, fN)):.1e}; crown error against the linear "
          f"q0/(EI b^4 + k) = {lin:.10g}: {ferrs[0]:.3e} (32), {ferrs[1]:.3e} (64), order {of:.3f}")
    check(max(map(abs, fN)) <= 1e-10 * N and ORDER[0] <= of <= ORDER[1], "(a) the axially free beam is not the linear one")


# ---- (b) ----

def part_b():
    k, a, q0 = 20.0, 4.5 * R_GYR, 1.0
    a0 = -a
    s2 = 4 * (EI * B1 ** 4 + k) / (EA * B1 ** 4)
    A_lim = -a0 - math.sqrt((a0 ** 2 - s2) / 3)
    lam_lim = lam_of(k, q0, a0, 0.0, A_lim, 0.0)
    P2 = EI * B2 ** 2 + k / B2 ** 2
    A_bif = -a0 - math.sqrt(a0 ** 2 - 4 * P2 / (EA * B1 ** 2))
    print(f"(b) shallow arch a = 4.5 r = {a:g} (amplitude {a0:g}), restrained ends, bilateral k = {k:g}, "
          f"q0 sin: one-mode limit point A1 = {A_lim:.12g}, lambda = {lam_lim:.12g} (bifurcation later, at A1 = {A_bif:.6g})")
    meshes, errs, perrs = [16, 32, 64], [], []
    for n in meshes:
        t0 = time.perf_counter()
        p = vk.Problem(L=L, EI=EI, EA=EA, k=k, sines=[(1, a0)], load_sines=[(1, q0)])
        m, (path, limits, _, stab) = trace(p, n, 2.2 * a, 44)
        lp = limits[0]
        errs.append(lp["lambda"] - lam_lim)
        perr = max(abs(pt["lambda"] - lam_of(k, q0, a0, 0.0, pt["crown"], 0.0)) for pt in path)
        perrs.append(perr)
        a2 = max(abs(pt["A2"]) for pt in path)
        print(f"  {n:4d} elements: limit lambda {lp['lambda']:.12g} at crown {lp['crown']:.10g}, error {errs[-1]:.3e} "
              f"(crown {lp['crown'] - A_lim:.1e}); path max |lambda error| {perr:.3e}; limit points {len(limits)}; "
              f"max |A2| {a2:.1e}; stability events {[ev['kind'] for ev in stab]} ({time.perf_counter() - t0:.1f} s)")
        check(stab and stab[0]["kind"] == "limit_point" and abs(stab[0]["lambda"] - lp["lambda"]) <= 1e-9 * lam_lim,
              "(b) the first stability event is not the limit point")
    # the arc-length control solves the same discrete problem: the same limit point (to the bisection)
    p = vk.Problem(L=L, EI=EI, EA=EA, k=k, sines=[(1, a0)], load_sines=[(1, q0)])
    m = vk.Model(p, 32)
    path_arc, limits_arc, _, _ = vk.trace(m, 2.2 * a, 44, control="arclength", stability=False)
    diff = limits_arc[0]["lambda"] - (lam_lim + errs[1])
    print(f"  arc-length control (32 elements, {len(path_arc) - 1} steps): limit lambda {limits_arc[0]['lambda']:.12g}, "
          f"minus crown control's {diff:.1e}")
    check(abs(diff) <= 1e-9 * lam_lim, "(b) arc-length and crown control disagree on the limit load")
    ob, op = orders(errs), orders(perrs)
    rich = errs[-1] + (errs[-1] - errs[-2]) / 3
    print(f"  observed orders: limit load {', '.join(f'{o:.3f}' for o in ob)}; path {', '.join(f'{o:.3f}' for o in op)}; "
          f"Richardson limit load off by {rich:.2e}")
    check(all(ORDER[0] <= o <= ORDER[1] for o in ob + op), "(b) observed order outside [1.7, 2.3]")
    check(abs(rich) <= 0.05 * abs(errs[-1]), "(b) Richardson misses the one-mode limit load by > 5% of the finest error")


# ---- (c) perfect arch: the bifurcation point ----

def part_c_perfect():
    k, a, q0 = 20.0, 8.0 * R_GYR, 1.0
    a0 = -a
    P2 = EI * B2 ** 2 + k / B2 ** 2
    A_bif = -a0 - math.sqrt(a0 ** 2 - 4 * P2 / (EA * B1 ** 2))
    lam_bif = lam_of(k, q0, a0, 0.0, A_bif, 0.0)
    print(f"(c) perfect arch a = 8 r, bilateral k = {k:g}: the symmetric path's N reaches -P2 = {-P2:.10g} at "
          f"A1 = {A_bif:.10g}, lambda = {lam_bif:.10g} (before the limit point): the first stability event")
    errs = []
    for n in (32, 64):
        p = vk.Problem(L=L, EI=EI, EA=EA, k=k, sines=[(1, a0)], load_sines=[(1, q0)])
        m, (path, limits, _, stab) = trace(p, n, 1.25 * a, 50)
        ev = stab[0]
        errs.append((ev["crown"] - A_bif, ev["lambda"] - lam_bif, ev["N"] + P2))
        print(f"  {n:4d} elements: {ev['kind']} at crown {ev['crown']:.10g} (error {errs[-1][0]:.2e}), lambda "
              f"{ev['lambda']:.10g} (error {errs[-1][1]:.2e}), N {ev['N']:.10g} (N + P2 = {errs[-1][2]:.2e}); "
              f"negative eigenvalues {ev['negative_eigenvalues_from']} -> {ev['negative_eigenvalues_to']}")
        check(ev["kind"] == "bifurcation", "(c) the first stability event of the perfect arch is not a bifurcation")
    for idx, label in enumerate(("crown", "lambda", "N")):
        o = math.log2(abs(errs[0][idx] / errs[1][idx]))
        print(f"  observed order ({label}): {o:.3f}")
        check(ORDER[0] <= o <= ORDER[1], f"(c) perfect: observed order of {label} outside [1.7, 2.3]")


# ---- (c), (d) ----

def part_c(tensionless):
    k, a, q0 = 20.0, 8.0 * R_GYR, 1.0
    a0, e = -a, a / 100
    P2 = EI * B2 ** 2 + k / B2 ** 2
    A_bif = -a0 - math.sqrt(a0 ** 2 - 4 * P2 / (EA * B1 ** 2))
    lam_bif = lam_of(k, q0, a0, 0.0, A_bif, 0.0)
    # the exact imperfect path's maximum and its lift-off event, on a fine A1 grid then refined
    A1s = np.linspace(0.0, 2.5 * a, 25001)
    ex = exact_imperfect_path(k, q0, a0, e, A1s)
    lam_ex = np.array([t[1] for t in ex])
    A2_ex = np.array([t[0] for t in ex])
    i = int(np.argmax(lam_ex[: np.searchsorted(A1s, 1.5 * a)]))
    c2 = np.polyfit(A1s[i - 2:i + 3] - A1s[i], lam_ex[i - 2:i + 3], 4)
    r = np.roots(np.polyder(c2))
    r = r[np.isreal(r)].real
    t = r[np.argmin(np.abs(r))]
    lam_max_ex = float(np.polyval(c2, t))
    j = int(np.argmax(np.abs(A2_ex) > A1s / 2 + 0.0 * A1s)) if np.any(np.abs(A2_ex[1:]) > A1s[1:] / 2) else None
    name = "(d) tensionless" if tensionless else "(c) bilateral"
    print(f"{name}: arch a = 8 r = {a:g}, imperfection e = {e:g} sin(2 pi x/L), k = {k:g}: P2 = EI b2^2 + k/b2^2 = {P2:.10g}; "
          f"perfect bifurcation at A1 = {A_bif:.8g}, lambda = {lam_bif:.10g}; imperfect path max lambda = {lam_max_ex:.10g}")
    lift = None
    if j:
        # |A2| - A1/2 changes sign between j-1 and j: the root of the linear interpolant, then lambda
        f0, f1 = abs(A2_ex[j - 1]) - A1s[j - 1] / 2, abs(A2_ex[j]) - A1s[j] / 2
        A1e = A1s[j - 1] + (A1s[j] - A1s[j - 1]) * f0 / (f0 - f1)
        A2e = exact_imperfect_path(k, q0, a0, e, [A1s[j - 1], A1e])[-1][0]
        lift = (A1e, lam_of(k, q0, a0, e, A1e, A2e))
        print(f"  exact first lift-off (|A2| = A1/2): crown {lift[0]:.10g}, lambda {lift[1]:.10g}")
    results = []
    for n in (32, 64):
        t0 = time.perf_counter()
        p = vk.Problem(L=L, EI=EI, EA=EA, k=k, tensionless=tensionless, sines=[(1, a0), (2, e)],
                       load_sines=[(1, q0)])
        m, (path, limits, events, _) = trace(p, n, 1.25 * a, 100, stability=False)
        if tensionless:
            ev = events[0] if events else None
            print(f"  {n:4d} elements: first contact event {ev and ev['from']} -> {ev and ev['to']} at crown "
                  f"{ev['crown']:.10g} (error {ev['crown'] - lift[0]:.2e}), lambda {ev['lambda']:.10g} "
                  f"(error {ev['lambda'] - lift[1]:.2e}); contact after {ev['contact_after']} "
                  f"({time.perf_counter() - t0:.1f} s)")
            results.append((ev["crown"] - lift[0], ev["lambda"] - lift[1]))
            continue
        # pointwise against the exact path (root followed from the reference's A2)
        lerr, aerr, nrel = 0.0, 0.0, None
        for pt in path[1:]:
            roots = mode2_roots(k, a0, e, pt["crown"])
            A2 = float(roots[np.argmin(np.abs(roots - pt["A2"]))])
            lerr = max(lerr, abs(pt["lambda"] - lam_of(k, q0, a0, e, pt["crown"], A2)))
            aerr = max(aerr, abs(pt["A2"] - A2))
        big = max(path, key=lambda pt: abs(pt["A2"]))
        nrel = big["N"] / (-P2 * big["A2"] / (big["A2"] + e)) - 1
        lmax = limits[0]["lambda"]
        print(f"  {n:4d} elements: path max lambda {lmax:.10g} (error {lmax - lam_max_ex:.3e}); max |lambda error| "
              f"{lerr:.3e}, max |A2 error| {aerr:.3e}; at max |A2| = {big['A2']:.5g}: N = {big['N']:.8g}, "
              f"N/(-P2 A2/(A2+e)) - 1 = {nrel:.2e}, N/(-P2) = {big['N'] / -P2:.6f} ({time.perf_counter() - t0:.1f} s)")
        results.append((lmax - lam_max_ex, lerr, aerr, nrel))
    for idx, label in enumerate(("crown", "lambda") if tensionless else ("max lambda", "path lambda", "path A2", "N")):
        o = math.log2(abs(results[0][idx] / results[1][idx]))
        print(f"  observed order ({label}): {o:.3f}")
        check(ORDER[0] <= o <= ORDER[1], f"{name}: observed order of {label} outside [1.7, 2.3]")


def main():
    t0 = time.perf_counter()
    part_a()
    part_b()
    part_c_perfect()
    part_c(False)
    part_c(True)
    print(f"{len(failures)} failed ({time.perf_counter() - t0:.0f} s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
