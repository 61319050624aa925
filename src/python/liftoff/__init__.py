"""liftoff from Python: beams and arches on a tensionless elastic foundation.

    import liftoff
    r = liftoff.solve("verification/scenes/seed_arch_pinned.toml")   # or TOML text, or a dict
    r.contact_regions, r.design, r.support_reactions, r.certificate    # the keys of `liftoff solve --json`
    r.positions, r.w, r.M, r.V, r.reaction                            # numpy views of the sampled fields
    liftoff.plot(r, "arch.png")

solve, trace and sweep run the C++ library's entry points, the ones the CLI runs, so the answers
are the CLI's; the GIL is released while they work. Bad input raises InputError (MechanismError for
a mechanism), an answer that is not solved SolverFailure (UnstableEquilibrium), a file that cannot be
written OutputError: all liftoff.Error, each with the CLI's one-line message and `exit_code`.
"""
from ._liftoff import (Error, InputError, MechanismError, OutputError, SolverFailure, SolveResult, SweepResult,
                       TraceResult, UnstableEquilibrium, __version__, solve, sweep, trace)
from .plot import plot

__all__ = ["solve", "trace", "sweep", "plot", "SolveResult", "TraceResult", "SweepResult", "Error", "InputError",
           "MechanismError", "SolverFailure", "UnstableEquilibrium", "OutputError", "__version__"]
