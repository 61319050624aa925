#!/usr/bin/python3
"""Figures of a `liftoff sweep` HDF5 file, in the style of the seed paper's Figures 4 to 7.

    /usr/bin/python3 verification/plots/plot_sweep.py SWEEP.h5 [--out PREFIX] [--normalise] [--dolfinx]

The same as `liftoff plot SWEEP.h5` (verification/plots/plot.py, which draws them): writes
PREFIX_deflection.png (deflection along the member for every case, overlaid, one panel per
method asked for: fast, auto, primal, dual, ritz) and PREFIX_reaction.png (the foundation
reaction likewise); failed cases are left out and listed under the panels. --normalise divides
each curve by its own largest magnitude. With --dolfinx, each case's scene (stored in the file)
is also solved by the independent dolfinx reference (verification/dolfinx/penalty_reference.py)
and drawn in a panel of its own. w > 0 is into the foundation and is drawn downward.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot  # noqa: E402

if __name__ == "__main__":
    plot.main(kind="sweep")
