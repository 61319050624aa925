#!/usr/bin/python3
"""Monte Carlo: the lift-off length of the B70 sleeper over a lognormal ballast modulus (issue 17).

The B70 sleeper of verification/scenes/engineering/sleeper_b70_ballast.toml with one rail seat
loaded (125 kN at 0.55 m; the other rail unloaded, the extreme of a lateral load transfer): its far
end lifts off the ballast. Nobody knows a ballast modulus to better than a factor of two: take K
lognormal with median 3e7 N/m^2 (the scene's) and a factor of two at one standard deviation (sigma
of ln K = ln 2), solve 400 draws in one sweep, and draw the lift-off length (the length not in
contact) against K and its histogram. (With both rail seats loaded the sleeper stays in contact
for every K: the rail seats press both ends down.)

    /usr/bin/python3 verification/examples/sleeper_monte_carlo.py [OUT.png]
"""
import pathlib
import sys
import tomllib

import matplotlib.pyplot as plt
import numpy

import liftoff

scene = tomllib.loads((pathlib.Path(__file__).resolve().parents[1] /
                       "scenes/engineering/sleeper_b70_ballast.toml").read_text())
scene["loads"] = scene["loads"][:2]  # self-weight and the left rail seat's load
modulus = numpy.random.default_rng(17).lognormal(numpy.log(3e7), numpy.log(2.0), 400)
sweep = liftoff.sweep(scene, {"foundation.modulus": modulus.tolist()})  # every case solved and certified
length = 2.6
lift_off = numpy.array([length - sum(e - b for b, e in c["reports"][0].contact_regions) for c in sweep.cases])

print(f"lift-off length: median {numpy.median(lift_off):.3f} m, 5 % {numpy.percentile(lift_off, 5):.3f} m, "
      f"95 % {numpy.percentile(lift_off, 95):.3f} m; P(lift-off > 0) = {numpy.mean(lift_off > 1e-9):.2f}")
fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
a.semilogx(modulus, lift_off, ".", ms=4)
a.set_xlabel("ballast modulus K [N/m$^2$]")
a.set_ylabel("lift-off length [m]")
a.set_title("B70 sleeper, one 125 kN rail-seat load")
b.hist(lift_off, bins=30)
b.set_xlabel("lift-off length [m]")
b.set_ylabel("draws (of 400)")
b.set_title("K lognormal: median 3e7, factor 2 at 1 sigma")
fig.tight_layout()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "sleeper_monte_carlo.png", dpi=110)
