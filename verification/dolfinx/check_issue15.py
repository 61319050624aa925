#!/usr/bin/python3
"""Issue 15's axial term in the dolfinx reference, checked against sine series.

    /usr/bin/python3 verification/dolfinx/check_issue15.py [--elements 100 200 400 800]

Two scenes in verification/dolfinx/scenes/issue15/, each a pinned strut of length L on a bilateral
foundation K under a dead compression P (no reference code is shared: the series are summed here):

  - bilateral_strut.toml: uniform load q; midspan deflection
        w(L/2) = sum_{n odd} 4 q / (n pi (EI k^4 - P k^2 + K)) sin(n pi / 2),  k = n pi / L;
  - imperfect_strut.toml: no load, a piecewise-linear stress-free initial shape w0 (the foundation
    follows it); the deflection from it, v, solves EI v'''' - P v'' ... = -P w0'' (the weak form's
        +P int w0' v'), so v(L/2) = sum_n P k^2 b_n / (EI k^4 - P k^2 + K) sin(n pi / 2),
    b_n = (2/L) int w0 sin(k x) dx, exact per linear piece.

The series are summed to n = 20001 (the terms fall like n^-5 and n^-4: the tail is below 1e-14).
Checks per scene: the error falls at the observed order 2 within [1.8, 2.2] (P2 interior penalty,
a point value) and the Richardson extrapolation of the last two meshes meets the series within
5% of the finest mesh's error. Exit 1 on any failure.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
ORDER_WINDOW = (1.8, 2.2)
TERMS = 20001


def strut(scene):
    with open(scene, "rb") as fh:
        raw = tomllib.load(fh)
    st, fd = raw["structure"], raw["foundation"]
    P = sum(ld["value"] for ld in raw["loads"] if ld["kind"] == "axial")
    q = sum(ld["value"] for ld in raw["loads"] if ld["kind"] == "uniform")
    w0 = raw.get("geometry", {}).get("initial_shape")
    return st["length"], st["EI"], fd["modulus"], P, q, w0


def series_load(L, EI, K, P, q):
    total = 0.0
    for n in range(1, TERMS + 1, 2):
        k = n * math.pi / L
        total += 4 * q / (n * math.pi * (EI * k ** 4 - P * k ** 2 + K)) * math.sin(n * math.pi / 2)
    return total


def sine_coefficient(at, values, L, k):
    """(2/L) int_0^L w0 sin(k x) dx for w0 piecewise linear through (at, values), exact."""
    total = 0.0
    for x0, x1, v0, v1 in zip(at, at[1:], values, values[1:]):
        c1 = (v1 - v0) / (x1 - x0)
        c0 = v0 - c1 * x0
        # int (c0 + c1 x) sin(kx) dx = -(c0 + c1 x) cos(kx)/k + c1 sin(kx)/k^2
        F = lambda x: -(c0 + c1 * x) * math.cos(k * x) / k + c1 * math.sin(k * x) / k ** 2
        total += F(x1) - F(x0)
    return 2.0 / L * total


def series_shape(L, EI, K, P, w0):
    total = 0.0
    for n in range(1, TERMS + 1, 2):
        k = n * math.pi / L
        b = sine_coefficient(w0["at"], w0["value"], L, k)
        total += P * k ** 2 * b / (EI * k ** 4 - P * k ** 2 + K) * math.sin(n * math.pi / 2)
    return total


def midspan(scene, elements):
    out = subprocess.run([sys.executable, os.path.join(HERE, "penalty_reference.py"), scene, "--elements",
                          str(elements), "--json", "-"], capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError(f"{scene}: penalty_reference exit {out.returncode}: {out.stderr.strip()}")
    r = json.loads(out.stdout)
    L = strut(scene)[0]
    # the extreme deflection is at midspan (symmetric struts, n = 1 critical mode)
    for key in ("w_max", "w_min"):
        if abs(r["at_" + key] - L / 2) <= 1e-12 * L and r[key] != 0.0:
            return r[key]
    raise RuntimeError(f"{scene}: the extreme deflection is not at midspan ({r['at_w_max']}, {r['at_w_min']})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--elements", type=int, nargs="+", default=[100, 200, 400, 800])
    opts = ap.parse_args()
    failures = 0
    for name in ("bilateral_strut", "imperfect_strut"):
        scene = os.path.join(HERE, "scenes", "issue15", name + ".toml")
        L, EI, K, P, q, w0 = strut(scene)
        exact = series_shape(L, EI, K, P, w0) if w0 else series_load(L, EI, K, P, q)
        values = [midspan(scene, n) for n in opts.elements]
        errors = [v - exact for v in values]
        orders = [math.log2(abs(e0 / e1)) for e0, e1 in zip(errors, errors[1:])]
        extrapolated = values[-1] + (values[-1] - values[-2]) / 3.0
        print(f"{name}: series {exact:.15g}")
        for n, v, e in zip(opts.elements, values, errors):
            print(f"  {n:6d} elements: {v:.15g}  error {e:.3e}")
        print(f"  observed orders {', '.join(f'{o:.3f}' for o in orders)}; Richardson {extrapolated:.15g} "
              f"(off by {extrapolated - exact:.2e})")
        if not all(ORDER_WINDOW[0] <= o <= ORDER_WINDOW[1] for o in orders[1:]):
            print(f"  FAIL: observed order outside {ORDER_WINDOW}")
            failures += 1
        if not abs(extrapolated - exact) <= 0.05 * abs(errors[-1]):
            print("  FAIL: the extrapolation misses the series by more than 5% of the finest error")
            failures += 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
