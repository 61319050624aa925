"""Quick pictures of a liftoff result (matplotlib): plot(result, file=None).

A SolveResult: the deflection w (drawn downward: w > 0 is into the foundation), the foundation
reaction, the bending moment and the shear force stacked against the position, the contact regions
shaded. A TraceResult: the monitored deflection against the load factor, one line per path, its
events marked. `liftoff plot` draws the full pictures from the HDF5 files.
"""
import os


def _figure(rows):
    import matplotlib.pyplot as plt  # without a display matplotlib draws with Agg
    return plt.subplots(rows, 1, sharex=True, figsize=(7, 2.0 * rows + 0.6), squeeze=False)


def _solve_figure(r):
    units = r.json.get("units", {})
    length, force = units.get("length", "length"), units.get("force", "force")
    coordinate = "theta [deg]" if r.json["coordinate"] == "theta_deg" else f"x [{length}]"
    if len(r.positions) == 0:
        raise ValueError("plot: the result has no sampled fields (solve it with fields=True)")
    panels = [(r.w, f"w [{length}]", True), (r.reaction, f"reaction [{force}/{length}]", False),
              (r.M, f"M [{force} {length}]", False), (r.V, f"V [{force}]", False)]
    fig, axes = _figure(len(panels))
    for ax, (values, label, downward) in zip(axes[:, 0], panels):
        ax.plot(r.positions, values, color="k", lw=1.2)
        ax.axhline(0.0, color="0.6", lw=0.6)
        for begin, end in r.contact_regions:
            ax.axvspan(begin, end, color="tab:orange", alpha=0.15, lw=0)
        if downward:
            ax.invert_yaxis()  # w > 0 into the foundation: drawn as the member moves
        ax.set_ylabel(label)
    axes[-1, 0].set_xlabel(coordinate)
    axes[0, 0].set_title(f"{os.path.basename(r.json['scene'])}  ({r.json['method']}, {r.json['termination']}; "
                         f"contact regions shaded)", fontsize=9)
    return fig


def _trace_figure(t):
    fig, axes = _figure(1)
    ax = axes[0, 0]
    for path in t.paths:
        steps = t.steps(path["path"])
        ax.plot(steps["monitor_deflection"], steps["lambda"], lw=1.2, label=path["path"])
        events = path.get("events", [])
        if events:
            import numpy
            lam = [e["lambda"] for e in events]
            w = numpy.interp(lam, steps["lambda"], steps["monitor_deflection"])
            ax.plot(w, lam, "o", ms=4, mfc="none", color=ax.lines[-1].get_color())
    ax.set_xlabel(f"w at {t.json['monitor']:.6g} [{t.json['units'].get('length', 'length')}]")
    ax.set_ylabel("load factor lambda")
    ax.legend(fontsize=8)
    ax.set_title(f"{os.path.basename(t.json['scene'])} (events circled)", fontsize=9)
    return fig


def plot(result, file=None):
    """Draw `result` (a SolveResult or TraceResult); save it to `file` if given. Returns the figure."""
    from ._liftoff import SolveResult, TraceResult
    if isinstance(result, SolveResult):
        fig = _solve_figure(result)
    elif isinstance(result, TraceResult):
        fig = _trace_figure(result)
    else:
        raise TypeError(f"plot: expected a SolveResult or TraceResult, got {type(result).__name__}")
    fig.tight_layout()
    if file is not None:
        fig.savefig(file, dpi=120)
    return fig
