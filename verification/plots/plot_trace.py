#!/usr/bin/python3
"""Figures of a `liftoff trace` HDF5 file: the load history F = F_dead + lambda F_live.

    /usr/bin/python3 verification/plots/plot_trace.py TRACE.h5 [--out PREFIX] [--closed-form PROGRAM]

The same as `liftoff plot TRACE.h5` (verification/plots/plot.py, which draws them): writes
PREFIX_load_displacement.png (the physical load, lambda x the live load's value where the live case is
of one kind, else lambda, against the monitored deflection w, every path of the file overlaid: fe,
ritz, fe_refined; events marked and labelled without overprinting), PREFIX_states.png (the bending
moment and the deflection along the member at every event, requested step and the last step, from the
steps' nodal fields, one curve each labelled with lambda and the load) and
PREFIX_lift_off_map.png (one panel per path: the position along the member across, lambda up,
contact regions shaded, lift-off zones blank, stretches with no foundation hatched, every event
marked and labelled; when the path passes a limit point, against the buckle amplitude for a
beam-column and against the monitored deflection for a von Karman member, or the path length in
(w, lambda) scaled to their ranges where w turns back too, limit points drawn across) and, when the
steps carry an axial force (beam-columns, issue 15), PREFIX_load_amplitude.png (the axial force
against the buckle amplitude and the lifted length, stable solid, unstable dashed, limit points and
bifurcations labelled, and the perfect member's closed-form branch from `closed_form_reference
localized-buckle`, found with --closed-form, $LIFTOFF_CLOSED_FORM or the PATH). A file of an
interrupted trace is drawn as far as it goes (if the file was damaged by the kill, its backup
TRACE.h5.backup is read instead). Refuses another kind of file.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot  # noqa: E402

if __name__ == "__main__":
    plot.main(kind="trace")
