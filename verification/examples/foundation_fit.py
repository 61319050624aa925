#!/usr/bin/python3
"""Least squares: the foundation modulus that best fits measured deflections (issue 17).

The "measurements" are made here: the B70 sleeper (verification/scenes/engineering/
sleeper_b70_ballast.toml) solved with K = 4.5e7 N/m^2, its deflection read at nine gauges and
spoilt by 0.05 mm of noise. The fit minimises the squared misfit over ln K (scipy's bounded scalar
minimiser); the figure shows the gauges, the fitted deflection and the misfit against K.

    /usr/bin/python3 verification/examples/foundation_fit.py [OUT.png]
"""
import pathlib
import sys
import tomllib

import matplotlib.pyplot as plt
import numpy
from scipy.optimize import minimize_scalar

import liftoff

scene = tomllib.loads((pathlib.Path(__file__).resolve().parents[1] /
                       "scenes/engineering/sleeper_b70_ballast.toml").read_text())


def deflection(modulus, at):
    scene["foundation"]["modulus"] = modulus
    r = liftoff.solve(scene)
    return numpy.interp(at, r.positions, r.w), r


gauges = numpy.linspace(0.1, 2.5, 9)
measured = deflection(4.5e7, gauges)[0] + numpy.random.default_rng(17).normal(0.0, 5e-5, gauges.size)
misfit = lambda ln_k: numpy.sum((deflection(numpy.exp(ln_k), gauges)[0] - measured) ** 2)  # noqa: E731
best = minimize_scalar(misfit, bounds=(numpy.log(1e6), numpy.log(1e9)), method="bounded",
                       options={"xatol": 1e-6})
fitted = numpy.exp(best.x)
print(f"fitted K = {fitted:.4g} N/m^2 (the measurements' 4.5e7), rms misfit "
      f"{numpy.sqrt(best.fun / gauges.size) * 1e3:.4f} mm after {best.nfev} solves")

_, r = deflection(fitted, gauges)
fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
a.plot(r.positions, 1e3 * r.w, "k-", label=f"fitted, K = {fitted:.3g}")
a.plot(gauges, 1e3 * measured, "o", mfc="none", label="gauges")
a.invert_yaxis()  # w > 0 into the foundation, drawn as the sleeper moves
a.set_xlabel("x [m]")
a.set_ylabel("w [mm]")
a.legend()
ks = numpy.logspace(7, 8.3, 40)
b.loglog(ks, [misfit(numpy.log(k)) for k in ks], "-")
b.axvline(fitted, color="k", lw=0.8)
b.set_xlabel("K [N/m$^2$]")
b.set_ylabel("sum of squared misfits [m$^2$]")
fig.tight_layout()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "foundation_fit.png", dpi=110)
