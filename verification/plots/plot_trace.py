#!/usr/bin/python3
"""Figures of a `liftoff trace` HDF5 file: the load history F = F_dead + lambda F_live.

    /usr/bin/python3 verification/plots/plot_trace.py TRACE.h5 [--out PREFIX]

The same as `liftoff plot TRACE.h5` (verification/plots/plot.py, which draws them): writes
PREFIX_load_displacement.png (lambda against the monitored deflection w, every path of the file
overlaid: fe, ritz, fe_refined; events marked and labelled without overprinting) and
PREFIX_lift_off_map.png (one panel per path: the position along the member across, lambda up,
contact regions shaded, lift-off zones blank, stretches with no foundation hatched, every event
marked and labelled). A file of an interrupted trace is drawn as far as it goes (if the file was
damaged by the kill, its backup TRACE.h5.backup is read instead). Refuses another kind of file.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot  # noqa: E402

if __name__ == "__main__":
    plot.main(kind="trace")
