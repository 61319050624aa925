#!/usr/bin/python3
"""Pictures of any liftoff HDF5 file: a solve, a trace, a sweep or an envelope (what `liftoff plot` runs).

    /usr/bin/python3 verification/plots/plot.py FILE.h5 [--out PREFIX] [--normalise]

The file's kind is its root attribute `kind` ("solve", "trace", "sweep", "envelope"; files written before it
existed are recognised by their layout). Writes, and prints the name of, each PNG:

- solve: PREFIX_diagrams.png, the member with its supports, loads and foundation, then the
  deflection w, the foundation pressure (reaction), the bending moment and the shear force (and
  for arches the normal force) stacked against the position (arches: theta in degrees), contact
  regions shaded, stretches with no foundation hatched, the largest and smallest value of each
  diagram labelled with its position; arches also PREFIX_shape.png, the deformed arch in its plane.
- trace: PREFIX_load_displacement.png (the physical load where the file has one, root attributes
  load_*, else lambda, against w at the monitor), PREFIX_lift_off_map.png and, from the steps' nodal
  fields (files written since issue 37), PREFIX_states.png: the bending moment and the deflection along
  the member at every event, every requested step and the last step (plot_trace.py's figures); when the
  steps carry an axial force (beam-columns), also PREFIX_load_amplitude.png: the axial force against
  the buckle amplitude and the lifted length, the perfect member's closed-form branch beside it. A
  folding path's map is drawn against the buckle amplitude (beam-columns) or the monitored deflection
  (von Karman members; the path length in (w, lambda) where w turns back too), limit points and
  bifurcations marked across it, so that the branches between two limit points do not overlap.
- sweep: PREFIX_deflection.png and PREFIX_reaction.png, every case overlaid, one panel per method
  (plot_sweep.py's figures). Failed cases are left out and listed on the figure. --normalise
  divides each case's curve by its own largest magnitude (max |w|, max reaction), to compare shapes.
- envelope (`liftoff envelope SCENE --hdf5 FILE`): PREFIX_envelopes.png, the envelopes (largest
  and smallest over the cases at each point) of w, the foundation pressure, the bending moment and
  the shear stacked along the member, bold; each extreme labelled with its position and the case
  that governs it (the lead position, or the combination). Combinations: each case's own curve
  thin, in its colour, and a row per case on top with its contact regions. A moving load: the band
  between the envelopes, and PREFIX_lift_off_map.png, the contact regions against the lead
  position (contact, lifted off, no foundation and failed positions drawn differently; the group's
  loads dotted). Failed cases are left out of the envelopes and listed in red.

Units are the file's root attributes `units_length` and `units_force` when present (else "length"
and "force"). w > 0 is into the foundation and is drawn downward, as the member moves; bending
moment sagging positive; reaction compression positive. Exit codes as liftoff's: 2 the file is not
a readable liftoff result, 4 a picture could not be written or a Python module is missing (no
half-written PNG is left: each is written under a temporary name and renamed).
"""
import argparse
import math
import os
import re
import sys
import textwrap

PROG = "liftoff plot"
BAD_INPUT, OUTPUT_ERROR = 2, 4


def fail(code, message):
    print(f"{PROG}: {message}", file=sys.stderr)
    sys.exit(code)


try:
    import numpy as np
    import h5py
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.colors
    import matplotlib.ticker
    import matplotlib.transforms
    from matplotlib.patches import FancyArrowPatch, Rectangle
except ImportError as e:  # pragma: no cover - depends on the machine
    module = getattr(e, "name", None) or str(e)
    fail(OUTPUT_ERROR, f"cannot draw: the Python module '{module}' is missing (Debian: apt install "
                       f"python3-matplotlib python3-h5py python3-numpy)")
try:
    import tomllib
except ImportError:  # Python < 3.11: the scene drawing is skipped
    tomllib = None


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def units_of(attrs):
    # Empty labels (a scene without [units]) are no units either.
    length = (text(attrs["units_length"]) if "units_length" in attrs else "") or "length"
    force = (text(attrs["units_force"]) if "units_force" in attrs else "") or "force"
    return length, force


def file_kind(f):
    """The file's kind: its `kind` attribute, else recognised by its layout; None if not liftoff's."""
    if "kind" in f.attrs:
        return text(f.attrs["kind"])
    if "liftoff_version" not in f.attrs:
        return None
    if "keys" in f.attrs and "cases" in f:
        return "sweep"
    if "paths" in f.attrs:
        return "trace"
    if "structure" in f.attrs and "fields" in f:
        return "solve"
    return None


class Output:
    """The PNGs of one run: each saved under a temporary name, all renamed at the end; on a failure
    every temporary is removed and the run exits 4."""

    def __init__(self):
        self.pending = []

    def save(self, fig, path):
        temporary = path + ".tmp"
        try:
            fig.savefig(temporary, dpi=120, format="png")
        except Exception as e:  # noqa: BLE001 - any failure to write is the output's
            self.abandon()
            fail(OUTPUT_ERROR, f"{path}: cannot write the picture ({e})")
        finally:
            plt.close(fig)
        self.pending.append((temporary, path))

    def abandon(self):
        for temporary, _ in self.pending:
            try:
                os.remove(temporary)
            except OSError:
                pass
        self.pending = []

    def finish(self):
        for i, (temporary, path) in enumerate(self.pending):
            try:
                os.replace(temporary, path)
            except OSError as e:
                self.pending = self.pending[i:]
                self.abandon()
                fail(OUTPUT_ERROR, f"{path}: cannot write the picture ({e.strerror})")
            print(path)
        self.pending = []


# ----------------------------------------------------------------------------------------------
# Labels that do not overprint: each label tries a few offsets around its point and takes the
# first whose box (in pixels) overlaps no label placed before; failing all, the farthest.

class LabelPlacer:
    OFFSETS = [(6, 4), (6, -12), (-6, 4), (-6, -12), (8, 16), (8, -24), (-8, 16), (-8, -24), (10, 30),
               (10, -38), (-10, 30), (-10, -38), (12, 46), (-12, 46), (12, -54), (-12, -54)]

    def __init__(self, fig):
        self.fig = fig
        self.boxes = []

    def place(self, ax, label, xy, below=False, **kwargs):
        """below: try the offsets under the point first (a minimum's label, away from the curve)."""
        renderer = self.fig.canvas.get_renderer()
        axes_box = ax.get_window_extent(renderer)
        best = None
        offsets = sorted(self.OFFSETS, key=lambda o: o[1] >= 0) if below else self.OFFSETS
        for dx, dy in offsets:
            ha = "left" if dx >= 0 else "right"
            va = "bottom" if dy >= 0 else "top"
            a = ax.annotate(label, xy, textcoords="offset points", xytext=(dx, dy), ha=ha, va=va,
                            annotation_clip=False, **kwargs)
            box = a.get_window_extent(renderer).expanded(1.05, 1.1)
            inside = (box.x0 >= axes_box.x0 - 2 and box.x1 <= axes_box.x1 + 2 and box.y0 >= axes_box.y0 - 2
                      and box.y1 <= axes_box.y1 + 2)
            if inside and not any(box.overlaps(b) for b in self.boxes):
                self.boxes.append(box)
                return a
            if best is None and inside:
                best = (dx, dy)
            a.remove()
        dx, dy = best or offsets[0]
        a = ax.annotate(label, xy, textcoords="offset points", xytext=(dx, dy), ha="left" if dx >= 0 else "right",
                        va="bottom" if dy >= 0 else "top", annotation_clip=False,
                        arrowprops=dict(arrowstyle="-", color="0.5", linewidth=0.5), **kwargs)
        self.boxes.append(a.get_window_extent(renderer))
        return a


# ----------------------------------------------------------------------------------------------
# The scene (stored in the file as TOML): foundation extents, supports and loads.

def parse_scene(scene_text):
    if tomllib is None or not scene_text:
        return None
    try:
        return tomllib.loads(scene_text)
    except tomllib.TOMLDecodeError:
        return None


def member_range(scene):
    s = scene.get("structure", {})
    if s.get("kind") == "arch":
        gamma = float(s.get("half_angle_deg", 0.0))
        return -gamma, gamma
    return 0.0, float(s.get("length", 1.0))


def foundation_pieces(scene):
    """The foundation's pieces as (from, to) in the user's coordinate; None if unknown."""
    if scene is None or "foundation" not in scene:
        return None
    begin, end = member_range(scene)
    f = scene["foundation"]
    if "segments" in f:
        pieces = [(float(p.get("from", begin)), float(p.get("to", end))) for p in f["segments"]]
    else:
        pieces = [(float(f.get("from", begin)), float(f.get("to", end)))]
    return sorted(pieces)


def voids(pieces, begin, end):
    """The stretches of [begin, end] with no foundation under them."""
    if pieces is None:
        return []
    out, at = [], begin
    for a, b in pieces:
        if a > at:
            out.append((at, a))
        at = max(at, b)
    if at < end:
        out.append((at, end))
    return [(a, b) for a, b in out if b - a > 1e-12 * max(1.0, abs(end - begin))]


def gap_profile(scene):
    """The ground gap g as (positions, values) from [foundation] gap, or None."""
    if scene is None:
        return None
    gap = scene.get("foundation", {}).get("gap")
    if not gap:
        return None
    at, value = [float(a) for a in gap.get("at", [])], [float(v) for v in gap.get("value", [])]
    return (at, value) if at and len(at) == len(value) else None


def shade_regions(ax, regions, pieces, begin, end, legend=False):
    for i, (a, b) in enumerate(regions):
        ax.axvspan(a, b, color="tab:green", alpha=0.12, linewidth=0, label="contact" if legend and i == 0 else None)
    for i, (a, b) in enumerate(voids(pieces, begin, end)):
        ax.axvspan(a, b, facecolor="none", edgecolor="0.75", hatch="//", linewidth=0,
                   label="no foundation" if legend and i == 0 else None)


def fmt(value):
    """Four significant digits, without an exponent between 1e-3 and 1e7 (112500, not 1.125e+05)."""
    value = float(value)
    if value == 0.0 or not math.isfinite(value):
        return f"{value:g}"
    if 1e-3 <= abs(value) < 1e7:
        return np.format_float_positional(value, precision=4, unique=False, fractional=False, trim="-")
    return f"{value:.4g}"


def draw_scene(ax, scene, regions, pieces, begin, end, units, arch):
    """The member (y = 0), its foundation below, supports at their positions, loads above."""
    length, force = units
    span = end - begin
    ax.set_ylim(-1.0, 1.6)
    ax.set_yticks([])
    ax.plot([begin, end], [0, 0], color="black", linewidth=3, solid_capstyle="butt", zorder=3)
    for a, b in pieces or []:
        ax.add_patch(Rectangle((a, -0.62), b - a, 0.42, facecolor="tan", edgecolor="saddlebrown", hatch="...",
                               linewidth=0.6, alpha=0.6, zorder=1))
    for a, b in regions:
        ax.plot([a, b], [-0.2, -0.2], color="tab:green", linewidth=4, zorder=2)
    supports = scene.get("supports", {})

    def support(at, spec):
        kind = spec if isinstance(spec, str) else spec.get("kind", "pinned")
        label = []
        if kind in ("pinned", "roller"):
            ax.plot(at, -0.08, marker="^", markersize=12, color="black", zorder=4, clip_on=False)
            if kind == "roller":
                ax.plot(at, -0.3, marker="o", markersize=5, color="black", zorder=4, clip_on=False)
        elif kind == "clamped":
            ax.plot([at, at], [-0.7, 0.7], color="black", linewidth=5, zorder=4, solid_capstyle="butt")
        elif kind == "spring":
            zig = np.linspace(0, 1, 9)
            ax.plot(at + 0.006 * span * np.where(np.arange(9) % 2 == 0, 0, 1) * np.sign(0.5 - zig + 1e-9)
                    * (1 if at < begin + span / 2 else -1), -0.05 - 0.55 * zig, color="black", linewidth=1, zorder=4)
            if isinstance(spec, dict) and spec.get("stiffness"):
                label.append(f"k = {fmt(spec['stiffness'])}")
            if isinstance(spec, dict) and spec.get("rotational_stiffness"):
                label.append(f"k_r = {fmt(spec['rotational_stiffness'])}")
        if isinstance(spec, dict) and spec.get("settlement"):
            label.append(f"settles {fmt(spec['settlement'])} {length}")
        if kind != "free":
            label.insert(0, kind)
            ax.text(at, -0.95, ", ".join(label), ha="center" if begin < at < end else
                    ("left" if at == begin else "right"), va="bottom", fontsize=7)

    for side, at in (("left", begin), ("right", end)):
        if side in supports:
            support(at, supports[side])
    for entry in supports.get("interior", []):
        if isinstance(entry, dict):
            support(float(entry["at"]), entry)
        else:
            support(float(entry), "pinned")

    # Loads: > 0 toward the foundation, drawn downward (arches: radial, unrolled along theta).
    # Their labels are returned, to be placed once the layout is final (place_scene_labels).
    labels = []

    def label_at(x, message):
        if labels and labels[-1][1] == message and "force" in message and " x " not in message:
            labels[-1] = (labels[-1][0], message, labels[-1][2] + [x])  # equal point forces: one label
        else:
            labels.append((x, message, [x]))

    loads = scene.get("loads", [])
    if loads:
        ax.set_ylim(-1.0, 1.3 + 0.25 * min(len(loads), 4))
    for load in loads:
        kind, value = load.get("kind"), load.get("value")
        dead = " (dead)" if load.get("case") == "dead" else ""
        direction = f" {load['direction']}" if arch and "direction" in load else ""
        if kind == "force":
            at = float(load["at"])
            down = float(value) > 0
            ax.add_patch(FancyArrowPatch((at, 0.95 if down else 0.08), (at, 0.08 if down else 0.95),
                                         arrowstyle="-|>", mutation_scale=12, color="tab:red", linewidth=1.5, zorder=5))
            label_at(at, f"{fmt(float(value))} {force}{direction}{dead}")
        elif kind == "moment":
            at = float(load["at"])
            # counterclockwise positive: an arc over the point, head on the left for > 0
            r = 0.025 * span
            ccw = float(value) > 0
            ax.add_patch(FancyArrowPatch((at + r, 0.25), (at - r, 0.25) if ccw else (at + r, 0.25),
                                         connectionstyle="arc3,rad=0.9", arrowstyle="-|>", mutation_scale=10,
                                         color="tab:purple", linewidth=1.3, zorder=5) if ccw else
                         FancyArrowPatch((at - r, 0.25), (at + r, 0.25), connectionstyle="arc3,rad=-0.9",
                                         arrowstyle="-|>", mutation_scale=10, color="tab:purple", linewidth=1.3,
                                         zorder=5))
            label_at(at, f"M = {fmt(float(value))} {force} {length}{dead}")
        elif kind in ("uniform", "curvature"):
            a, b = float(load.get("from", begin)), float(load.get("to", end))
            if kind == "curvature":
                ax.add_patch(Rectangle((a, 0.1), b - a, 0.25, facecolor="tab:cyan", alpha=0.25, linewidth=0))
                label_at(0.5 * (a + b), f"curvature {fmt(float(value))} 1/{length}{dead}")
                continue
            q = float(value)
            ax.add_patch(Rectangle((a, 0.1), b - a, 0.4, facecolor="tab:orange", alpha=0.25, linewidth=0, zorder=2))
            for x in np.linspace(a, b, max(3, int(12 * (b - a) / span) + 1)):
                ax.annotate("", (x, 0.1 if q > 0 else 0.5), (x, 0.5 if q > 0 else 0.1),
                            arrowprops=dict(arrowstyle="-|>", color="tab:orange", linewidth=0.8), zorder=2)
            label_at(0.5 * (a + b), f"q = {fmt(q)} {force}/{length}{direction}{dead}")
        elif kind == "distributed":
            at = [float(v) for v in load["at"]]
            values = [float(v) for v in load["value"]]
            top = max(abs(v) for v in values) or 1.0
            ax.fill_between(at, 0.1, [0.1 + 0.4 * abs(v) / top for v in values], color="tab:orange", alpha=0.3,
                            linewidth=0)
            label_at(0.5 * (at[0] + at[-1]),
                     f"q = {fmt(min(values))}..{fmt(max(values))} {force}/{length}{direction}{dead}")
    return labels


def place_scene_labels(fig, ax, labels):
    """Each load's label above it, moved up a line while it would overprint one placed before."""
    renderer = fig.canvas.get_renderer()
    boxes = []
    for x, message, xs in labels:
        if len(xs) > 1:
            message = f"{message} (each of {len(xs)})"
            x = 0.5 * (min(xs) + max(xs))
        lo, hi = ax.get_xlim()
        ha = "left" if x < lo + 0.1 * (hi - lo) else "right" if x > hi - 0.1 * (hi - lo) else "center"
        for level in range(12):
            t = ax.text(x, 1.02, message, ha=ha, va="bottom", fontsize=7, clip_on=False,
                        transform=ax.transData)
            t.set_position((x, 1.02))
            t.set_transform(ax.transData + matplotlib.transforms.ScaledTranslation(0, level * 11 / 72,
                                                                                    fig.dpi_scale_trans))
            box = t.get_window_extent(renderer).expanded(1.04, 1.0)
            if not any(box.overlaps(b) for b in boxes) or level == 11:
                boxes.append(box)
                break
            t.remove()

# ----------------------------------------------------------------------------------------------
# Solve files

def read_solve(group):
    def column(name):
        path = "fields/" + name
        return group[path][()] if path in group else None

    regions = group["contact_regions"][()].reshape(-1, 2) if "contact_regions" in group else np.zeros((0, 2))
    scene_text = text(group["scene"][()]) if "scene" in group else ""
    return {"x": column("coordinate"), "w": column("w"), "u": column("u"), "reaction": column("reaction"),
            "moment": column("bending_moment"), "shear": column("shear_force"), "normal": column("normal_force"),
            "regions": [tuple(r) for r in regions], "coordinate": text(group.attrs.get("coordinate", "x")),
            "structure": text(group.attrs.get("structure", "beam")), "scene_text": scene_text,
            "scene_name": text(group.attrs.get("scene_name", "")), "method": text(group.attrs.get("method", "")),
            "termination": text(group.attrs.get("termination", "")), "message": text(group.attrs.get("message", ""))}


def label_extremes(ax, placer, x, y, unit, where, position_unit):
    """Marks the largest and smallest value with its position (one label if they coincide)."""
    if len(y) == 0:
        return
    scale = float(np.max(np.abs(y)))
    picks = [int(np.argmax(y)), int(np.argmin(y))]
    if scale == 0.0:
        picks = picks[:1]
    seen = []
    for i in picks:
        if i in seen:
            continue
        seen.append(i)
        if scale > 0 and abs(y[i]) < 1e-3 * scale:
            continue  # a zero extreme (the reaction where the member lifts, M at a free end) says nothing
        ax.plot(x[i], y[i], "o", color="black", markersize=4, zorder=5)
        placer.place(ax, f"{fmt(y[i])} {unit}\nat {where} = {fmt(x[i])}{position_unit}", (x[i], y[i]), fontsize=7,
                     bbox=dict(boxstyle="round,pad=0.2", facecolor="white", edgecolor="0.7", alpha=0.9))


def value_limits(ax, key, lo, hi, room):
    """The value axis from lo to hi with `room` times the range added above and below (the whole
    value if the range is empty); w (> 0 into the foundation) drawn downward. No x margins."""
    pad = room * (hi - lo) if hi > lo else max(abs(hi), 1e-30)
    if key == "w":
        ax.set_ylim(hi + pad, lo - pad)
    else:
        ax.set_ylim(lo - pad, hi + pad)
    ax.margins(x=0)


def position_axis(ax, arch, length, begin, end):
    """The bottom panel's position axis: theta along an arch, x in the length unit along a beam."""
    ax.set_xlabel("theta (degrees from the crown)" if arch else f"x [{length}]")
    ax.set_xlim(begin, end)


def plot_solve(path, f, prefix, output):
    r = read_solve(f)
    if r["x"] is None or r["w"] is None:
        fail(BAD_INPUT, f"{path}: the solve file has no fields (/fields/coordinate, /fields/w); expected a file "
                        f"written by `liftoff solve --output`")
    units = units_of(f.attrs)
    length, force = units
    arch = r["structure"] == "arch" or r["coordinate"] == "theta_deg"
    scene = parse_scene(r["scene_text"])
    x = r["x"]
    begin, end = (member_range(scene) if scene else (float(x.min()), float(x.max())))
    pieces = foundation_pieces(scene)
    where = "theta" if arch else "x"
    position_unit = " deg" if arch else f" {length}"
    diagrams = [("w", f"deflection w [{length}]\n(> 0 into the foundation)", length),
                ("reaction", f"foundation pressure\n[{force}/{length}]", f"{force}/{length}"),
                ("moment", f"bending moment M\n[{force} {length}] (sagging > 0)", f"{force} {length}"),
                ("shear", f"shear force V [{force}]", force)]
    if arch and r["normal"] is not None:
        diagrams.append(("normal", f"normal force N [{force}]", force))
    diagrams = [d for d in diagrams if r[d[0]] is not None]
    heights = ([1.1] if scene else []) + [1.0] * len(diagrams)
    fig, axes = plt.subplots(len(heights), 1, sharex=True, figsize=(9, 1.9 * len(heights) + 0.8),
                             gridspec_kw={"height_ratios": heights})
    axes = list(np.atleast_1d(axes))
    scene_axis, scene_labels = None, []
    if scene:
        scene_axis = axes[0]
        scene_labels = draw_scene(scene_axis, scene, r["regions"], pieces, begin, end, units, arch)
        scene_axis.set_ylabel("member,\nloads, supports", fontsize=8)
        axes = axes[1:]
    for ax, (key, ylabel, unit) in zip(axes, diagrams):
        y = r[key]
        shade_regions(ax, r["regions"], pieces, begin, end)
        ax.plot(x, y, color="tab:blue", linewidth=1.4)
        if key not in ("w", "normal"):
            ax.fill_between(x, 0, y, color="tab:blue", alpha=0.08, linewidth=0)
        ax.axhline(0.0, color="black", linewidth=0.6)
        ax.set_ylabel(ylabel, fontsize=8)
        ax.grid(True, alpha=0.3)
        ax.tick_params(labelsize=8)
        if key == "w":
            gap = gap_profile(scene)
            if gap:
                at, value = gap
                xs = [begin] + at + [end]
                ys = [value[0]] + value + [value[-1]]
                ax.plot(xs, ys, color="saddlebrown", linestyle="--", linewidth=1, label="ground (gap g)")
            ax.invert_yaxis()  # w > 0 into the foundation: drawn downward
            if gap:  # the shading is explained under the title; only the ground's line needs a key
                ax.legend(handles=[ax.lines[-1]], fontsize=7, loc="best", framealpha=0.9)
        # room for the labels of the extremes: 25 % margin above and below
        value_limits(ax, key, float(np.min(y)), float(np.max(y)), 0.3)
    position_axis(axes[-1], arch, length, begin, end)
    title = os.path.basename(r["scene_name"]) or os.path.basename(path)
    fig.suptitle(f"{title}: {r['method']} ({r['termination']})", fontsize=10, y=0.995)
    fig.text(0.5, 0.972, ("the arch unrolled along theta;  " if arch else "") +
             "loads toward the foundation point down;  green: contact;  blank: lifted off;  hatched: no foundation;  "
             "dotted band: the foundation", ha="center", va="top", fontsize=7, color="0.3")
    fig.align_ylabels(list(axes) + ([scene_axis] if scene else []))
    fig.tight_layout(rect=(0, 0, 1, 0.975))
    fig.subplots_adjust(hspace=0.12)
    fig.canvas.draw()  # labels are placed on the final layout, in pixels
    if scene:
        place_scene_labels(fig, scene_axis, scene_labels)
    placer = LabelPlacer(fig)
    for ax in axes:  # a legend is a label placed before the others
        if ax.get_legend() is not None:
            placer.boxes.append(ax.get_legend().get_window_extent(fig.canvas.get_renderer()))
    for ax, (key, _, unit) in zip(axes, diagrams):
        label_extremes(ax, placer, x, r[key], unit, where, position_unit)
    output.save(fig, prefix + "_diagrams.png")
    if arch and r["w"] is not None:
        plot_arch_shape(r, scene, units, prefix + "_shape.png", output)


def plot_arch_shape(r, scene, units, out, output):
    """The arch in its plane: unloaded (grey) and deformed (blue), displacements magnified."""
    s = (scene or {}).get("structure", {})
    radius = float(s.get("radius", 1.0))
    theta = np.radians(r["x"])
    w = r["w"]
    u = r["u"] if r["u"] is not None else np.zeros_like(w)
    # w > 0 into the foundation: toward the centre for a foundation inside the arch, outward for one outside
    inward = (scene or {}).get("foundation", {}).get("side", "inside") != "outside"
    largest = float(np.max(np.hypot(w, u))) or 1.0
    magnification = 0.12 * radius / largest
    radial = radius + (-w if inward else w) * magnification
    px = radial * np.sin(theta) + u * magnification * np.cos(theta)
    py = radial * np.cos(theta) - u * magnification * np.sin(theta)
    deep = float(np.max(np.abs(r["x"]))) >= 60.0  # the centre is drawn only where it does not flatten the arch
    xs = np.concatenate((radius * np.sin(theta), px, [0.0] if deep else []))
    ys = np.concatenate((radius * np.cos(theta), py, [0.0] if deep else []))
    aspect = (ys.max() - ys.min()) / max(xs.max() - xs.min(), 1e-30)
    fig, ax = plt.subplots(figsize=(7, min(9.0, max(3.0, 6.2 * aspect + 1.4))))
    ax.plot(radius * np.sin(theta), radius * np.cos(theta), color="0.6", linewidth=2, label="unloaded")
    ax.plot(px, py, color="tab:blue", linewidth=1.5, label=f"deformed, displacements x {magnification:.3g}")
    for a, b in r["regions"]:
        t = np.radians(np.linspace(a, b, 50))
        ax.plot(radius * np.sin(t), radius * np.cos(t), color="tab:green", linewidth=5, alpha=0.4)
    ax.plot([], [], color="tab:green", linewidth=5, alpha=0.4, label="contact")
    if deep:
        ax.plot(0, 0, "+", color="black")
    ax.set_aspect("equal")
    ax.set_xlabel(f"[{units[0]}]")
    ax.set_ylabel(f"[{units[0]}]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower center" if deep else "best")
    ax.set_title(f"{os.path.basename(r['scene_name'])}: deformed shape (foundation {'inside' if inward else 'outside'})",
                 fontsize=10)
    fig.tight_layout()
    output.save(fig, out)


# ----------------------------------------------------------------------------------------------
# Trace files

TRACE_STYLES = {"fe": ("tab:blue", "-"), "ritz": ("tab:red", "--"), "fe_refined": ("tab:green", ":")}
KIND_MARKERS = {"lift_off_opens": "v", "contact_opens": "^", "region_vanishes": "x", "lift_off_vanishes": "+",
                "limit_at_support": "s", "limit_at_load": "D", "limit_at_end": ">", "limit_point": "*",
                "bifurcation": "P"}


def read_trace_path(group):
    steps, events = group["steps"], group["events"]
    # The per-step datasets may differ by one row after a kill: keep the steps they all hold.
    n = min(len(steps[name]) for name in ("lambda", "monitor_deflection", "deflection", "reaction"))
    lam = steps["lambda"][:n]
    regions = [[] for _ in range(n)]
    for step, a, b in steps["contact_regions"][()].reshape(-1, 3):
        if 0 <= step < n:
            regions[int(step)].append((a, b))
    m = min(len(events[name]) for name in ("lambda", "kind", "at", "step"))
    event_list = [(float(events["lambda"][i]), text(events["kind"][i]), float(events["at"][i]))
                  for i in range(m) if 0 <= events["step"][i] < n]
    event_steps = [int(events["step"][i]) for i in range(m) if 0 <= events["step"][i] < n]

    # Beam-columns (issue 15): per step the axial force, the buckle amplitude, the lifted length and the
    # stability; files written before them have none (read as 0 and "unknown").
    def column(name, default):
        if name not in steps:
            return np.full(n, default)
        values = steps[name][()]
        values = values[:n] if len(values) >= n else np.concatenate((values, np.full(n - len(values), default)))
        return np.array([text(v) for v in values]) if default == "unknown" else np.asarray(values, dtype=float)

    # The whole state (issue 37): w and M at every node (FE) or grid point (Ritz) per step, rows from the
    # group's first_step on; files written before it have none.
    fields = None
    if "fields" in steps and "coordinate" in steps["fields"]:
        g = steps["fields"]
        fields = {"coordinate": g["coordinate"][()], "first_step": int(g.attrs.get("first_step", 0))}
        for key in ("w", "bending_moment"):
            fields[key] = g[key][()] if key in g else None

    return {"lambda": lam, "w": steps["monitor_deflection"][:n], "regions": regions, "events": event_list,
            "event_steps": event_steps, "axial_force": column("axial_force", 0.0),
            "amplitude": column("amplitude", 0.0), "lifted_length": column("lifted_length", 0.0),
            "stability": column("stability", "unknown"), "monitor": float(group.attrs.get("monitor", np.nan)),
            "termination": text(group.attrs.get("termination", "running")),
            "requested": column("requested", 0.0) != 0.0, "fields": fields}


def read_trace(path):
    """The trace, or its backup if the file was damaged by a kill; exits 2 if neither reads."""
    for candidate in (path, path + ".backup"):
        if not os.path.exists(candidate):
            continue
        try:
            with h5py.File(candidate, "r") as f:
                names = [p for p in text(f.attrs["paths"]).split(",") if p in f]
                paths = {name: read_trace_path(f[name]) for name in names}
                x = f["sample_points"][()]
                scene_text = text(f["scene"][()]) if "scene" in f else ""
                # The live load as a physical quantity (load = lambda x load_reference), where there is one.
                load = None
                if "load_reference" in f.attrs:
                    load = {"symbol": text(f.attrs.get("load_symbol", "")), "unit": text(f.attrs.get("load_unit", "")),
                            "quantity": text(f.attrs.get("load_quantity", "")),
                            "reference": float(f.attrs["load_reference"])}
                return {"paths": paths, "coordinate": text(f.attrs["coordinate"]), "begin": float(x.min()),
                        "end": float(x.max()), "scene": text(f.attrs["scene_name"]), "units": units_of(f.attrs),
                        "scene_toml": parse_scene(scene_text), "scene_text": scene_text, "load": load,
                        "moment_unit": text(f.attrs.get("units_moment", "")) or None}
        except (OSError, KeyError) as e:
            print(f"{PROG}: {candidate}: {e}", file=sys.stderr)
    fail(BAD_INPUT, f"{path}: not a readable liftoff trace (expected the file of `liftoff trace --output`)")


def event_name(kind):
    return kind.replace("lift_off", "lift-off").replace("_", " ")


def interpolate_w(p, lam):
    """w at an event's lambda from the nearest recorded steps (a fold makes lambda non-monotonic)."""
    if len(p["lambda"]) == 0:
        return None
    i = int(np.argmin(np.abs(p["lambda"] - lam)))
    j = min(i + 1, len(p["lambda"]) - 1) if p["lambda"][i] < lam else max(i - 1, 0)
    l0, l1 = p["lambda"][i], p["lambda"][j]
    return p["w"][i] if l1 == l0 else p["w"][i] + (lam - l0) / (l1 - l0) * (p["w"][j] - p["w"][i])


def monotonic(values):
    """Whether the values never turn back (a map's ordinate must not)."""
    d = np.diff(values)
    return bool(np.all(d >= 0) or np.all(d <= 0))


def path_length(p):
    """The length along the load-deflection curve with w and lambda each scaled to its range: grows
    along any path, whatever turns back."""
    w, lam = np.asarray(p["w"], dtype=float), np.asarray(p["lambda"], dtype=float)
    if len(w) == 0:
        return np.zeros(0)
    dw = np.diff(w) / (np.ptp(w) or 1.0)
    dl = np.diff(lam) / (np.ptp(lam) or 1.0)
    return np.concatenate(([0.0], np.cumsum(np.hypot(dw, dl))))


def folds(p):
    """Whether the path's lambda goes up and down (a limit point): then lambda does not locate a step."""
    d = np.diff(p["lambda"])
    return bool(np.any(d > 0) and np.any(d < 0))


def event_value(p, key, lam, step):
    """p[key] at an event of a folding path (where the nearest lambda may lie on the other branch),
    within the event's own step, the last one written before it: the event is that step (a limit
    point) or lies between it and the next (a bifurcation located inside a step)."""
    v = p[key]
    if step + 1 < len(v):
        l0, l1 = p["lambda"][step], p["lambda"][step + 1]
        if l0 != l1 and min(l0, l1) <= lam <= max(l0, l1):
            return v[step] + (lam - l0) / (l1 - l0) * (v[step + 1] - v[step])
    return v[step]


def event_w(p, lam, step):
    """w at an event: interpolated in lambda on a monotonic path, event_value on a folding one."""
    if folds(p) and 0 <= step < len(p["w"]):
        return event_value(p, "w", lam, step)
    return interpolate_w(p, lam)


def unit_scale(unit, largest):
    """(divisor, label) for values in `unit` up to `largest`: a force, or the force in a moment ("N m") or a
    force per length ("N/m"), in a unit that keeps the numbers below 1000 (N -> kN, MN)."""
    match = re.match(r"^([A-Za-z]+)([ /].*)?$", unit or "")
    if not match or match.group(1) not in FORCE_PREFIXES:
        return 1.0, unit
    divisor, label = force_scale(match.group(1), largest)
    return divisor, label + (match.group(2) or "")


def load_axis(trace, paths):
    """The load axis of a trace: (values of a path p, label, scale): the physical load (lambda x reference, in
    its unit) where the trace has one, lambda otherwise."""
    load = trace.get("load")
    if not load:
        return (lambda p: np.asarray(p["lambda"], dtype=float)), "load factor lambda", 1.0
    largest = max([float(np.max(np.abs(p["lambda"]))) for p in paths if len(p["lambda"])] + [0.0])
    divisor, unit = unit_scale(load["unit"], largest * abs(load["reference"]))
    factor = load["reference"] / divisor
    ref_divisor, ref_unit = unit_scale(load["unit"], abs(load["reference"]))
    label = f"{load['quantity']} {load['symbol']}" + (f" [{unit}]" if unit else "") + \
        f" (= lambda x {fmt(load['reference'] / ref_divisor)}{' ' + ref_unit if ref_unit else ''})"
    return (lambda p: factor * np.asarray(p["lambda"], dtype=float)), label, factor


def load_displacement(trace, out, output):
    length = trace["units"][0]
    load_of, load_label, load_factor = load_axis(trace, trace["paths"].values())
    fig, ax = plt.subplots(figsize=(7, 5))
    # Paths that know their stability (von Karman members, beam-columns) draw it: solid stable,
    # dashed unstable, dotted unknown; the others keep their path's style.
    staged = False
    for name, p in trace["paths"].items():
        color, style = TRACE_STYLES.get(name, ("black", "-"))
        y = load_of(p)
        if not is_von_karman(trace) or all(str(k) == "unknown" for k in p["stability"]):
            ax.plot(p["w"], y, color=color, linestyle=style, label=f"{name} ({p['termination']})")
            continue
        staged = True
        ax.plot([], [], color=color, label=f"{name} ({p['termination']})")
        for a, b, kind in stability_runs(p["stability"]):
            ax.plot(p["w"][a:b + 1], y[a:b + 1], color=color, linestyle=STABILITY_STYLES.get(kind, ":"))
    if staged:
        for kind in ("stable", "unstable"):
            ax.plot([], [], color="black", linestyle=STABILITY_STYLES[kind], label=kind)
    ax.axvline(0.0, color="black", linewidth=0.5)
    ax.grid(True, alpha=0.3)
    monitor = next(iter(trace["paths"].values()))["monitor"] if trace["paths"] else np.nan
    where = f"theta = {fmt(monitor)} deg" if trace["coordinate"] == "theta_deg" else f"x = {fmt(monitor)}"
    ax.set_xlabel(f"w at {where} [{length}] (> 0 into the foundation)")
    ax.set_ylabel(load_label, fontsize=9)
    ax.set_title(f"{os.path.basename(trace['scene'])}: load-displacement", fontsize=10)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    fig.canvas.draw()
    placer = LabelPlacer(fig)
    placer.boxes.append(ax.get_legend().get_window_extent(fig.canvas.get_renderer()))
    for name, p in trace["paths"].items():
        color = TRACE_STYLES.get(name, ("black", "-"))[0]
        # Events at the same load factor and of the same kind (both ends of a symmetric member) are
        # one point of this curve: one marker, one label.
        merged, steps = {}, {}
        for (lam, kind, _), step in zip(p["events"], p["event_steps"]):
            key = (round(lam, 9), kind)
            merged[key] = merged.get(key, 0) + 1
            steps.setdefault(key, step)
        for (lam, kind), count in merged.items():
            w = event_w(p, lam, steps[(lam, kind)])
            if w is None:
                continue
            ax.plot(w, lam * load_factor, KIND_MARKERS.get(kind, "o"), color=color, markersize=7,
                    markerfacecolor="none")
            placer.place(ax, event_name(kind) + (f" (x{count})" if count > 1 else ""), (w, lam * load_factor),
                         fontsize=7, color=color)
    output.save(fig, out)


def lift_off_map(trace, out, output):
    length = trace["units"][0]
    names = list(trace["paths"]) or ["(no path)"]
    scene = trace["scene_toml"]
    pieces = foundation_pieces(scene)
    # A path through a limit point: lambda goes up and down, so against lambda the branches between
    # the limit points overlap. A beam-column's map is drawn against the buckle amplitude, which grows
    # along it; a von Karman member's against the monitored deflection (the abscissa of its
    # load-deflection curve, which a snap-through carries on growing through both limit points), or,
    # where that turns back too, against the path length (path_length).
    folding = any(folds(p) for p in trace["paths"].values())
    by_amplitude = is_beam_column(trace) and folding
    by_deflection = is_von_karman(trace) and folding and all(monotonic(p["w"]) for p in trace["paths"].values())
    by_path_length = is_von_karman(trace) and folding and not by_deflection
    for p in trace["paths"].values():
        p["path_length"] = path_length(p)
    y_key = "amplitude" if by_amplitude else "w" if by_deflection else "path_length" if by_path_length else "lambda"
    fig, axes = plt.subplots(1, len(names), figsize=(5.6 * len(names), 5), sharey=True, squeeze=False)
    for ax, name in zip(axes[0], names):
        p = trace["paths"].get(name)
        ax.set_xlim(trace["begin"], trace["end"])
        ax.set_title(name, fontsize=10)
        ax.set_xlabel("theta (degrees from the crown)" if trace["coordinate"] == "theta_deg" else f"x [{length}]")
        ax.grid(True, alpha=0.3)
        if p is None or len(p["lambda"]) == 0:
            continue
        color = TRACE_STYLES.get(name, ("black", "-"))[0]
        lam, regions = p[y_key], p["regions"]
        for i, (a, b) in enumerate(voids(pieces, trace["begin"], trace["end"])):
            ax.add_patch(Rectangle((a, lam.min()), b - a, lam.max() - lam.min(), facecolor="0.85", edgecolor="0.5",
                                   hatch="//", linewidth=0, zorder=0, label="no foundation" if i == 0 else None))
        # Runs of steps with the same number of contact regions: each region's limits drawn
        # as curves in lambda and the region between them shaded.
        start, first = 0, True
        while start < len(lam):
            stop = start
            while stop + 1 < len(lam) and len(regions[stop + 1]) == len(regions[start]):
                stop += 1
            # Between two runs the topology changes somewhere inside one step: each run is
            # continued, unchanged, to the middle of that step, so the map has no gap.
            lo = 0.5 * (lam[start - 1] + lam[start]) if start > 0 else lam[start]
            hi = 0.5 * (lam[stop] + lam[stop + 1]) if stop + 1 < len(lam) else lam[stop]
            run_lambda = np.concatenate(([lo], lam[start:stop + 1], [hi]))
            for k in range(len(regions[start])):
                a = np.array([r[k][0] for r in regions[start:stop + 1]])
                b = np.array([r[k][1] for r in regions[start:stop + 1]])
                a = np.concatenate(([a[0]], a, [a[-1]]))
                b = np.concatenate(([b[0]], b, [b[-1]]))
                ax.fill_betweenx(run_lambda, a, b, color=color, alpha=0.3, linewidth=0,
                                 label="contact" if first else None)
                first = False
                ax.plot(a, run_lambda, color=color, linewidth=0.8)
                ax.plot(b, run_lambda, color=color, linewidth=0.8)
            start = stop + 1
        ax.add_patch(Rectangle((0, 0), 0, 0, facecolor="white", edgecolor="0.3", linewidth=0.6,
                               label="lifted off (foundation, no contact)"))
        ax.set_ylim(lam.min(), lam.max() + 0.02 * (lam.max() - lam.min() or 1.0))
    monitor = next(iter(trace["paths"].values()))["monitor"] if trace["paths"] else np.nan
    where = f"theta = {fmt(monitor)} deg" if trace["coordinate"] == "theta_deg" else f"x = {fmt(monitor)}"
    axes[0][0].set_ylabel(f"buckle amplitude [{length}]" if by_amplitude else
                          f"w at {where} [{length}] (> 0 into the foundation)" if by_deflection else
                          "path length in (w, lambda), each scaled to its range [-]" if by_path_length else
                          "load factor lambda")
    fig.suptitle(f"{os.path.basename(trace['scene'])}: lift-off map" +
                 ("\nagainst the buckle amplitude (lambda passes a limit point)" if by_amplitude else
                  f"\nagainst the deflection at {where} (lambda turns back along the path)" if by_deflection else
                  "\nagainst the path length (lambda and w pass limit points)" if by_path_length else ""),
                 fontsize=10)
    handles, labels = axes[0][0].get_legend_handles_labels()
    if handles:
        fig.legend(handles, labels, loc="lower center", ncol=len(handles), fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    fig.canvas.draw()
    placer = LabelPlacer(fig)
    for ax, name in zip(axes[0], names):
        p = trace["paths"].get(name)
        if p is None:
            continue
        for (event_lambda, kind, at), step in zip(p["events"], p["event_steps"]):
            y = event_value(p, y_key, event_lambda, step) if y_key != "lambda" else event_lambda
            if y_key != "lambda" and kind in ("limit_point", "bifurcation"):
                # Where the path turns in lambda (or branches): across the member, as the level the
                # map's branches meet at.
                ax.axhline(y, color="0.4", linestyle=":" if kind == "limit_point" else "-.", linewidth=0.8)
            ax.plot(at, y, KIND_MARKERS.get(kind, "o"), color="black", markersize=6)
            placer.place(ax, f"{event_name(kind)}, lambda = {event_lambda:.4g}", (at, y), fontsize=7,
                         bbox=dict(boxstyle="round,pad=0.15", facecolor="white", edgecolor="none", alpha=0.8))
    output.save(fig, out)
    return y_key


# ----------------------------------------------------------------------------------------------
# Beam-columns (issue 15): the axial force against the buckle amplitude and the lifted length, and
# the perfect member's localized buckle from verification/closed_form as the reference branch.

STABILITY_STYLES = {"stable": "-", "unstable": "--", "unknown": ":"}
FORCE_PREFIXES = {"N": ["N", "kN", "MN", "GN"], "kN": ["kN", "MN", "GN"], "lbf": ["lbf", "klbf"], "kip": ["kip"]}


def force_scale(force_unit, largest):
    """(divisor, label): the force axis in a unit that keeps its numbers below 1000 (N -> kN, MN)."""
    names = FORCE_PREFIXES.get(force_unit, [force_unit])
    k = 0
    while k + 1 < len(names) and largest >= 1000.0 ** (k + 1):
        k += 1
    if k == 0 and largest >= 1e4 and len(names) == 1:  # a unit without prefixes: say the power
        k = int(math.log10(largest) // 3)
        return 1000.0 ** k, f"1e{3 * k} {force_unit}"
    return 1000.0 ** k, names[k]


def is_von_karman(trace):
    """Whether the trace's scene takes von Karman kinematics (its axial force is the membrane force)."""
    return (trace.get("scene_toml") or {}).get("structure", {}).get("theory") == "von_karman"


def is_beam_column(trace):
    """Steps that carry a given axial force (beam-columns, issue 15). A von Karman member's thrust is
    its response, not a load N(lambda): the axial-force figure would misread it, so it is not drawn."""
    if is_von_karman(trace):
        return False
    return any(np.any(p["axial_force"] != 0.0) for p in trace["paths"].values())


def closed_form_program(explicit=None):
    """verification/closed_form's program: --closed-form, else LIFTOFF_CLOSED_FORM (which `liftoff plot`
    sets to the one built beside it), else closed_form_reference on the PATH; None if none runs."""
    import shutil
    for candidate in (explicit, os.environ.get("LIFTOFF_CLOSED_FORM"), shutil.which("closed_form_reference")):
        if candidate and os.path.isfile(candidate) and os.access(candidate, os.X_OK):
            return candidate
    return None


def perfect_member_branch(scene_text, program, max_amplitude=None):
    """The closed form's localized buckle table for the scene ({"points": [...], ...}), None with the
    reason when the scene is not a uniform heavy beam on a uniform tensionless foundation (or no program)."""
    import json
    import subprocess
    import tempfile
    if program is None:
        return None, "closed_form_reference not found (set LIFTOFF_CLOSED_FORM)"
    if not scene_text:
        return None, "the file has no scene"
    with tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False) as f:
        f.write(scene_text)
        scene_file = f.name
    try:
        command = [program, "localized-buckle", scene_file]
        if max_amplitude:
            command += ["--max-amplitude", repr(float(max_amplitude))]
        r = subprocess.run(command, capture_output=True, text=True, timeout=120)
    except (OSError, subprocess.TimeoutExpired) as e:
        return None, f"closed_form_reference failed ({e})"
    finally:
        os.remove(scene_file)
    if r.returncode != 0:
        reason = r.stderr.strip().splitlines()[-1] if r.stderr.strip() else f"exit {r.returncode}"
        return None, reason.split(": ", 2)[-1]
    try:
        reference = json.loads(r.stdout)
    except ValueError:
        return None, "closed_form_reference printed no JSON"
    # The closed form is the infinite member's: on a finite one it holds while the buckle and the
    # contact tails on either side (half a wavelength, pi / beta, each; beta = (K / 4 EI)^(1/4)) fit.
    tails = 2.0 * math.pi / (reference["K"] / (4.0 * reference["EI"])) ** 0.25
    length = reference.get("length", math.inf)
    reference["points"] = [q for q in reference["points"] if q["lifted_length"] + tails <= length]
    if not reference["points"]:
        return None, (f"the member (L = {length:.4g}) is too short for the infinite member's localized buckle "
                      f"(its contact tails alone take 2 pi / beta = {tails:.4g})")
    return reference, None


def stability_runs(stability):
    """(start, stop, kind) of the runs of equal stability, stop inclusive. The segment between two runs
    (no gap where the stability changes) takes the less assured of the two (unstable over unknown over
    stable): a stretch is never drawn stable beyond its last stable step."""
    rank = {"stable": 0, "unknown": 1, "unstable": 2}
    raw, start = [], 0
    for i in range(1, len(stability) + 1):
        if i == len(stability) or stability[i] != stability[start]:
            raw.append((start, i - 1, str(stability[start])))
            start = i
    runs = []
    for j, (a, b, kind) in enumerate(raw):
        if j > 0 and rank.get(kind, 1) > rank.get(raw[j - 1][2], 1):
            a -= 1
        if j + 1 < len(raw) and rank.get(kind, 1) >= rank.get(raw[j + 1][2], 1):
            b += 1
        runs.append((a, b, kind))
    return runs


def event_state(p, step, lam):
    """(axial force, amplitude, lifted length) at an event: its step's, the axial force from the path's
    own affine N(lambda) = N_dead + lambda N_live when the steps span two load factors."""
    i = min(max(step, 0), len(p["lambda"]) - 1)
    lams, forces = p["lambda"], p["axial_force"]
    force = forces[i]
    if np.ptp(lams) > 0:
        slope, intercept = np.polyfit(lams, forces, 1)
        force = intercept + slope * lam
    return float(force), float(p["amplitude"][i]), float(p["lifted_length"][i])


def load_amplitude(trace, out, output, closed_form=None):
    length, force = trace["units"]
    paths = {name: p for name, p in trace["paths"].items() if len(p["lambda"])}
    largest = max([float(np.max(np.abs(p["axial_force"]))) for p in paths.values()] + [0.0])
    amplitude_top = max([float(np.max(p["amplitude"])) for p in paths.values()] + [0.0])
    reference, why_not = perfect_member_branch(trace.get("scene_text", ""), closed_form_program(closed_form),
                                               1.3 * amplitude_top if amplitude_top > 0 else None)
    if reference:
        largest = max(largest, reference["bilateral_critical"])
    divisor, force_label = force_scale(force, largest)
    fig, (ax, side) = plt.subplots(1, 2, figsize=(11, 5.4), sharey=True, gridspec_kw={"width_ratios": [3, 2]})
    styles_seen = set()
    for name, p in paths.items():
        color = TRACE_STYLES.get(name, ("black", "-"))[0]
        y = p["axial_force"] / divisor
        for k, (a, b, kind) in enumerate(stability_runs(p["stability"])):
            style = STABILITY_STYLES.get(kind, ":")
            styles_seen.add(kind)
            label = f"{name} ({p['termination']})" if k == 0 else None
            ax.plot(p["amplitude"][a:b + 1], y[a:b + 1], color=color, linestyle=style, linewidth=1.6, label=label)
            side.plot(p["lifted_length"][a:b + 1], y[a:b + 1], color=color, linestyle=style, linewidth=1.6)
    if reference:
        pts = reference["points"]
        found = [q for q in pts if q["status"] == "found"]
        secondary = [q for q in pts if q["status"] != "found"]
        for group, style, label in ((found, "-", "perfect member (closed form)"),
                                    (secondary, ":", "perfect member, its contact tail lifting off too")):
            if group:
                amp = [q["amplitude"] for q in group]
                pf = [q["axial_force"] / divisor for q in group]
                ax.plot(amp, pf, color="black", linestyle=style, linewidth=0.9, label=label, zorder=4)
                side.plot([q["lifted_length"] for q in group], pf, color="black", linestyle=style, linewidth=0.9,
                          zorder=4)
        top = reference["bilateral_critical"] / divisor
        for a_ in (ax, side):
            a_.axhline(top, color="0.5", linewidth=0.7, linestyle="-.")
    for name in ("stable", "unstable", "unknown"):
        if name in styles_seen:
            ax.plot([], [], color="0.3", linestyle=STABILITY_STYLES[name], label=name if name != "unknown"
                    else "stability unknown")
    for a_ in (ax, side):
        a_.grid(True, alpha=0.3)
        a_.set_xlim(left=0.0)
        a_.tick_params(labelsize=8)
    if paths:
        lifted_top = max(float(np.max(p["lifted_length"])) for p in paths.values())
        if amplitude_top > 0:
            ax.set_xlim(0.0, 1.08 * amplitude_top)
        if lifted_top > 0:
            side.set_xlim(0.0, 1.08 * lifted_top)
    ax.set_ylim(bottom=0.0, top=1.12 * largest / divisor if largest > 0 else None)
    ax.set_xlabel(f"buckle amplitude [{length}] (largest lift off the foundation surface)")
    ax.set_ylabel(f"axial force P [{force_label}] (compression > 0)")
    side.set_xlabel(f"lifted length [{length}]")
    fig.suptitle(f"{os.path.basename(trace['scene'])}: axial force against the buckle", fontsize=10)
    ax.legend(fontsize=7, loc="upper right")
    notes = []
    if reference:
        notes.append(f"dash-dot: 2 sqrt(K EI) = {fmt(reference['bilateral_critical'] / divisor)} {force_label}, "
                     f"the bilateral critical load")
    elif why_not:
        notes.append(f"no closed-form reference: {why_not}")
    notes.append("solid: stable, dashed: unstable, dotted: stability unknown; small markers: contact events")
    fig.text(0.5, 0.01, "\n".join(textwrap.wrap(";  ".join(notes), 170)), ha="center", va="bottom", fontsize=7,
             color="0.3")
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    fig.canvas.draw()
    placer = LabelPlacer(fig)
    placer.boxes.append(ax.get_legend().get_window_extent(fig.canvas.get_renderer()))
    for name, p in paths.items():
        color = TRACE_STYLES.get(name, ("black", "-"))[0]
        seen = set()
        for (lam, kind, _), step in zip(p["events"], p["event_steps"]):
            key = (round(lam, 9), kind)
            if key in seen:  # both ends of a symmetric buckle: one point of these curves
                continue
            seen.add(key)
            value, amp, lifted = event_state(p, step, lam)
            major = kind in ("limit_point", "bifurcation")
            marker = KIND_MARKERS.get(kind, "o")
            size = 11 if major else 4
            ax.plot(amp, value / divisor, marker, color=color, markersize=size, markerfacecolor="none" if not major
                    else color, markeredgecolor="black" if major else color, zorder=6)
            side.plot(lifted, value / divisor, marker, color=color, markersize=size * 0.8,
                      markerfacecolor="none" if not major else color, zorder=6)
            if major:
                placer.place(ax, f"{event_name(kind)} ({name}): P = {fmt(value / divisor)} {force_label}",
                             (amp, value / divisor), fontsize=7, color=color,
                             bbox=dict(boxstyle="round,pad=0.15", facecolor="white", edgecolor="none", alpha=0.85))
    output.save(fig, out)


def load_label(trace, lam):
    """"lambda 5.845 (N = 5.845 MN)": a load factor and, where the trace has one, its physical load."""
    load = trace.get("load")
    if not load:
        return f"lambda {lam:.4g}"
    value = lam * load["reference"]
    divisor, unit = unit_scale(load["unit"], abs(value))
    return f"lambda {lam:.4g} ({load['symbol']} = {fmt(value / divisor)}{' ' + unit if unit else ''})"


def states_to_draw(p):
    """The steps whose state is drawn along the member: each event's (once per step), each requested one and the
    last (where the path ended), in path order, as (step, names); only steps that have fields."""
    fields = p.get("fields")
    if fields is None or fields["w"] is None:
        return []
    first, rows = fields["first_step"], len(fields["w"])
    chosen = {}
    for (lam, kind, _), step in zip(p["events"], p["event_steps"]):
        chosen.setdefault(step, []).append(event_name(kind))
    for step in np.flatnonzero(p["requested"]):
        chosen.setdefault(int(step), []).append("requested")
    if len(p["lambda"]):
        chosen.setdefault(len(p["lambda"]) - 1, []).append("last step")
    return [(step, names) for step, names in sorted(chosen.items()) if first <= step < first + rows]


def state_along_member(trace, out, output):
    """The bending moment and the deflection along the member at every event, every requested step and the last step
    of the first path that records the whole state: one curve each, labelled with lambda and the physical load."""
    name, p = next((n, q) for n, q in trace["paths"].items() if states_to_draw(q))
    length, force = trace["units"]
    arch = trace["coordinate"] == "theta_deg"
    fig, (ax_m, ax_w) = plt.subplots(2, 1, sharex=True, figsize=(10, 7.2))
    fields = p["fields"]
    x = fields["coordinate"]
    chosen = states_to_draw(p)
    moments = [fields["bending_moment"][step - fields["first_step"]] for step, _ in chosen]
    largest = max(float(np.max(np.abs(m))) for m in moments) if moments else 0.0
    moment_unit = trace.get("moment_unit") or f"{force} {length}"
    divisor, moment_label = unit_scale(moment_unit, largest)
    colors = plt.cm.viridis(np.linspace(0.0, 0.9, len(chosen)))
    for (step, names), color, m in zip(chosen, colors, moments):
        w = fields["w"][step - fields["first_step"]]
        lam = float(p["lambda"][step])
        label = f"{', '.join(dict.fromkeys(names))}: {load_label(trace, lam)}"
        ax_m.plot(x, m / divisor, color=color, linewidth=1.3, label=label)
        ax_w.plot(x, w, color=color, linewidth=1.3)
        i = int(np.argmax(np.abs(m)))
        ax_m.plot(x[i], m[i] / divisor, "o", color=color, markersize=4)
    for ax in (ax_m, ax_w):
        ax.axhline(0.0, color="black", linewidth=0.6)
        ax.grid(True, alpha=0.3)
        ax.tick_params(labelsize=8)
    ax_w.invert_yaxis()  # w > 0 into the foundation: drawn downward
    ax_m.set_ylabel(f"bending moment M [{moment_label}]\n(sagging > 0)", fontsize=9)
    ax_w.set_ylabel(f"deflection w [{length}]\n(> 0 into the foundation)", fontsize=9)
    ax_w.set_xlabel("theta [deg]" if arch else f"x [{length}]", fontsize=9)
    ax_m.legend(fontsize=7, loc="best", framealpha=0.9)
    ax_m.set_title(f"{os.path.basename(trace['scene'])}: along the member at the events, requested loads and last "
                   f"step ({name} path; dots: largest |M|)", fontsize=10)
    fig.tight_layout()
    output.save(fig, out)


def plot_trace(path, prefix, output, closed_form=None):
    trace = read_trace(path)
    load_displacement(trace, prefix + "_load_displacement.png", output)
    lift_off_map(trace, prefix + "_lift_off_map.png", output)
    if is_beam_column(trace):
        load_amplitude(trace, prefix + "_load_amplitude.png", output, closed_form)
    if any(states_to_draw(p) for p in trace["paths"].values()):
        state_along_member(trace, prefix + "_states.png", output)


# ----------------------------------------------------------------------------------------------
# Sweep files

SOLVED = ("solved", "converged")


def usable(group):
    """Whether a report in a sweep holds an answer: certified if it has a certificate, else solved."""
    if "fields/w" not in group or "fields/coordinate" not in group:
        return False
    if "certificate" in group:
        return int(group["certificate"].attrs.get("passed", 0)) == 1
    return text(group.attrs.get("termination", "")) in SOLVED


def read_sweep(f):
    keys = text(f.attrs["keys"]).split(",")
    values = f["values"][()].reshape(-1, len(keys))
    cases, failures, methods_seen = [], [], []
    for i, name in enumerate(sorted(f["cases"].keys())):
        group = f["cases"][name]
        methods = {}
        if "error" in group.attrs:
            failures.append((values[i], "", text(group.attrs["error"])))
        for method in group.keys():
            m = group[method]
            if method not in methods_seen:
                methods_seen.append(method)
            if not usable(m):
                failures.append((values[i], method, f"{text(m.attrs.get('termination', '?'))}: "
                                                    f"{text(m.attrs.get('message', ''))}"))
                continue
            methods[method] = {"x": m["fields/coordinate"][()], "w": m["fields/w"][()],
                               "reaction": m["fields/reaction"][()] if "fields/reaction" in m else None,
                               "regions": m["contact_regions"][()],
                               "coordinate": text(m.attrs.get("coordinate", "x"))}
        scene = next((group[m]["scene"][()] for m in group.keys() if "scene" in group[m]), None)
        cases.append((values[i], methods, text(scene) if scene is not None else None))
    return keys, cases, failures, methods_seen


def add_dolfinx(cases, elements):
    """Solves every case's scene with the dolfinx reference and adds it as a method."""
    import json
    import subprocess
    import tempfile

    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "dolfinx", "penalty_reference.py")
    with tempfile.TemporaryDirectory() as tmp:
        for values, methods, scene in cases:
            if scene is None:
                continue
            path, out = os.path.join(tmp, "case.toml"), os.path.join(tmp, "case.json")
            with open(path, "w") as f:
                f.write(scene)
            p = subprocess.run(["/usr/bin/python3", script, path, "--elements", str(elements), "--json", out],
                               capture_output=True, text=True)
            if p.returncode != 0:
                continue
            with open(out) as f:
                d = json.load(f)
            methods["dolfinx"] = {"x": np.asarray(d["fields"]["coordinate"]), "w": np.asarray(d["fields"]["w"]),
                                  "reaction": np.asarray(d["fields"]["reaction"]), "regions": d["contact_regions"],
                                  "coordinate": d["coordinate"]}


def case_label(keys, values):
    return ", ".join(f"{k} = {fmt(v)}" for k, v in zip(keys, values))


def failure_lines(keys, failures, width):
    """The note of the cases not drawn: one line per method and termination, with a count."""
    groups = {}
    for values, method, message in failures:
        termination = message.split(":", 1)[0] if method else "error"
        groups.setdefault((method, termination), []).append((values, message))
    lines = [f"not drawn: {len(failures)} answer{'s' if len(failures) != 1 else ''} without a solution"]
    for (method, termination), items in groups.items():
        first_values, first_message = items[0]
        if method and ":" in first_message:
            first_message = first_message.split(":", 1)[1].strip()
        cases = case_label(keys, first_values) + (f" and {len(items) - 1} more" if len(items) > 1 else "")
        line = f"  {method or 'case'}: {len(items)} x {termination} ({cases}): {first_message}"
        wrapped = textwrap.wrap(line, width, initial_indent="", subsequent_indent="      ")
        if len(wrapped) > 3:
            wrapped = wrapped[:3]
            wrapped[-1] = wrapped[-1][:width - 9] + " ..."
        lines.extend(wrapped)
    return lines


def sweep_figure(keys, cases, failures, methods, field, ylabel, out, output, normalise, units, title):
    length = units[0]
    methods = [m for m in methods if any(m in c[1] for c in cases)]
    if not methods:
        return False
    width = max(6.0, 4.6 * len(methods))
    fig, axes = plt.subplots(1, len(methods), figsize=(width, 4.6), sharey=True, squeeze=False)
    # One colour per case, the same in every panel; a legend up to 12 cases, else a colour bar of
    # the first swept key.
    drawn = [i for i, c in enumerate(cases) if any(m in c[1] for m in methods)]
    many = len(drawn) > 12
    first = np.array([cases[i][0][0] for i in drawn], dtype=float)
    logscale = many and first.min() > 0 and first.max() > 100 * first.min()
    norm = (matplotlib.colors.LogNorm if logscale else matplotlib.colors.Normalize)(first.min(), first.max())
    colour = {i: (plt.cm.viridis(norm(cases[i][0][0])) if many else plt.cm.tab10(k % 10)) for k, i in enumerate(drawn)}
    coordinate = "x"
    handles = {}
    for ax, method in zip(axes[0], methods):
        for i, (values, results, _) in enumerate(cases):
            if method not in results or results[method][field] is None:
                continue
            r = results[method]
            y = np.asarray(r[field], dtype=float)
            if normalise:
                scale = float(np.max(np.abs(y)))
                y = y / scale if scale > 0 else y
            coordinate = r["coordinate"]
            handles[i], = ax.plot(r["x"], y, color=colour[i], label=case_label(keys, values), linewidth=1.2)
        ax.axhline(0.0, color="black", linewidth=0.5)
        ax.set_xlabel("theta (degrees from the crown)" if coordinate == "theta_deg" else f"x [{length}]")
        ax.set_title(method, fontsize=10)
        ax.grid(True, alpha=0.3)
    axes[0][0].set_ylabel(ylabel, fontsize=9)
    if field == "w":
        axes[0][0].invert_yaxis()  # w > 0 into the foundation: drawn downward
    fig.suptitle(title, fontsize=10)
    inches = fig.get_figheight()
    bottom = 0.0
    if failures:
        lines = failure_lines(keys, failures, int(width * 16))
        fig.text(0.01, 0.01, "\n".join(lines), fontsize=7, color="tab:red", va="bottom", ha="left")
        bottom += (len(lines) * 0.14 + 0.1) / inches
    if many:
        bar = fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap="viridis"), ax=list(axes[0]),
                           orientation="horizontal", fraction=0.05, pad=0.0)
        bar.set_label(keys[0], fontsize=8)
        fig.tight_layout(rect=(0, bottom + 0.12, 1, 0.97))
        bar.ax.set_position([0.3, bottom + 0.04, 0.4, 0.025])
    else:
        ordered = [handles[i] for i in sorted(handles)]
        columns = min(len(ordered), max(1, int(width // 2.6)))
        rows = -(-len(ordered) // columns)
        fig.legend(ordered, [h.get_label() for h in ordered], loc="lower center", ncol=columns, fontsize=7,
                   frameon=False, bbox_to_anchor=(0.5, bottom))
        bottom += (rows * 0.17 + 0.05) / inches
        fig.tight_layout(rect=(0, bottom, 1, 0.97))
    output.save(fig, out)
    return True


def plot_sweep(path, f, prefix, output, normalise, dolfinx=False, dolfinx_elements=400):
    keys, cases, failures, methods = read_sweep(f)
    if dolfinx:
        add_dolfinx(cases, dolfinx_elements)
        methods = methods + ["dolfinx"]
    units = units_of(f.attrs)
    length, force = units
    if normalise:
        labels = ("w / max |w| of the case (> 0 into the foundation)", "reaction / max reaction of the case")
    else:
        labels = (f"deflection w [{length}] (> 0 into the foundation)", f"foundation pressure [{force}/{length}]")
    title = f"{os.path.basename(path)}: {len(cases)} cases" + (", each curve over its own largest value"
                                                                 if normalise else "")
    drawn = sweep_figure(keys, cases, failures, methods, "w", labels[0], prefix + "_deflection.png", output, normalise,
                         units, title)
    if drawn:
        sweep_figure(keys, cases, failures, methods, "reaction", labels[1], prefix + "_reaction.png", output,
                     normalise, units, title)
    else:
        fail(BAD_INPUT, f"{path}: no case of the sweep has an answer to draw ({len(failures)} failed)")


# ----------------------------------------------------------------------------------------------
# Envelope files (`liftoff envelope SCENE --hdf5 FILE`)

def read_envelope(path, f):
    """The envelope file: its envelopes, cases (label, lead position, termination, own fields) and
    lift-off map; exits 2 when it is not one."""
    try:
        e = f["envelope"]
        cases = f["cases"]
        n = len(cases["certified"])
        position = cases["position"][()] if n else np.zeros(0)
        certified = cases["certified"][()] if n else np.zeros(0)
        regions = f["liftoff_map/regions"][()].reshape(-1, 3) if "liftoff_map/regions" in f else np.zeros((0, 3))
        out = {"x": e["coordinate"][()], "coordinate": text(f.attrs.get("coordinate", "x")),
               "scene_name": text(f.attrs.get("scene_name", "")), "units": units_of(f.attrs),
               "scene": parse_scene(text(f["scene"][()])) if "scene" in f else None,
               "complete": int(f.attrs.get("complete", 0)) == 1, "cases": []}
        for key, name in (("w", "w"), ("reaction", "pressure"), ("moment", "moment"), ("shear", "shear")):
            out[key] = (e[name + "_max"][()], e[name + "_min"][()])
        for k in range(n):
            one = {"label": text(cases.attrs.get(f"label_{k:04d}", f"case {k}")),
                   "position": float(position[k]), "certified": int(certified[k]) == 1,
                   "termination": text(cases.attrs.get(f"termination_{k:04d}", "")),
                   "message": text(cases.attrs.get(f"message_{k:04d}", "")), "regions": [], "fields": None}
            group = f"cases/fields/{k:04d}"
            if group in f:
                g = f[group]
                one["fields"] = {"x": g["coordinate"][()], "w": g["w"][()], "reaction": g["reaction"][()],
                                 "moment": g["bending_moment"][()], "shear": g["shear_force"][()]}
            out["cases"].append(one)
        for k, a, b in regions:
            if 0 <= int(k) < n:
                out["cases"][int(k)]["regions"].append((float(a), float(b)))
        out["extremes"] = {}
        if "extremes" in f:
            attrs = f["extremes"].attrs
            for name in ("w_max", "uplift_max", "pressure_max", "moment_max", "moment_min", "shear_max_abs"):
                if name + "_value" in attrs:
                    out["extremes"][name] = (float(attrs[name + "_value"]), float(attrs[name + "_at"]),
                                             text(attrs[name + "_governing"]))
    except KeyError as error:
        fail(BAD_INPUT, f"{path}: an envelope file without {error}; expected the file of "
                        f"`liftoff envelope SCENE --hdf5 FILE`")
    return out


def governing_extremes(env, key):
    """The summary's extremes (/extremes) on one diagram, each as (value, position, governing case):
    the picture labels what the summary prints, no more."""
    names = {"w": (("w_max", 1.0), ("uplift_max", -1.0)), "reaction": (("pressure_max", 1.0),),
             "moment": (("moment_max", 1.0), ("moment_min", 1.0)), "shear": (("shear_max_abs", 1.0),)}[key]
    return [(sign * env["extremes"][n][0], env["extremes"][n][1], env["extremes"][n][2])
            for n, sign in names if n in env["extremes"]]


def combination_of(label):
    """The combination's name in a case label ("ULS, lead at 4.2" -> "ULS"; "lead at 4.2" -> "")."""
    if label.startswith("lead at "):
        return ""
    return label.rsplit(", lead at ", 1)[0]


def envelope_failure_lines(env, width):
    """The note of the cases left out: one line per combination and termination, with a count and
    the first case's message."""
    failed = [c for c in env["cases"] if not c["certified"]]
    if not failed:
        return []
    total = len(env["cases"])
    lines = [f"not in the envelopes: {len(failed)} of {total} case{'s' if total != 1 else ''} failed (the "
             f"envelopes are incomplete)"]
    groups = {}
    for c in failed:
        groups.setdefault((combination_of(c["label"]), c["termination"]), []).append(c)
    for (_, termination), cases in list(groups.items())[:4]:
        first = cases[0]
        which = first["label"] + (f" and {len(cases) - 1} more" if len(cases) > 1 else "")
        wrapped = textwrap.wrap(f"  {len(cases)} x {termination} ({which}): {first['message']}", width,
                                subsequent_indent="      ")
        if len(wrapped) > 2:
            wrapped = wrapped[:2]
            wrapped[-1] = wrapped[-1][:width - 4] + " ..."
        lines.extend(wrapped)
    if len(groups) > 4:
        lines.append("  and more (the summary of `liftoff envelope` lists every case)")
    return lines


def moving_group(scene):
    """The moving group's offsets from the lead position, and its load case; None without [moving]."""
    moving = (scene or {}).get("moving")
    if not moving:
        return None
    return [float(load.get("offset", 0.0)) for load in moving.get("loads", [])], moving.get("case", "live")


def plot_envelope(path, f, prefix, output):
    env = read_envelope(path, f)
    length, force = env["units"]
    arch = env["coordinate"] == "theta_deg"
    scene = env["scene"]
    x = env["x"]
    if len(x) == 0:
        fail(BAD_INPUT, f"{path}: no case of the envelope was certified: nothing to draw "
                        f"({len(env['cases'])} failed; the summary of `liftoff envelope` says why)")
    begin, end = member_range(scene) if scene else (float(x.min()), float(x.max()))
    pieces = foundation_pieces(scene)
    positions = np.array([c["position"] for c in env["cases"]])
    moving = bool(np.any(np.isfinite(positions)))
    where = "theta" if arch else "x"
    position_unit = " deg" if arch else f" {length}"
    certified = [c for c in env["cases"] if c["certified"] and c["fields"] is not None]
    # Per case curves: thin, one colour each, when the cases are few (combinations); a moving load's
    # dozens of positions are the band between the envelopes.
    per_case = not moving and len(certified) <= 12
    diagrams = [("w", f"deflection w [{length}]\n(> 0 into the foundation)", length),
                ("reaction", f"foundation pressure\n[{force}/{length}]", f"{force}/{length}"),
                ("moment", f"bending moment M\n[{force} {length}] (sagging > 0)", f"{force} {length}"),
                ("shear", f"shear force V [{force}]", force)]
    contact_rows = not moving  # combinations: a row per case with its contact regions on top
    heights = ([0.25 + 0.22 * len(env["cases"])] if contact_rows else []) + [1.0] * len(diagrams)
    lines = envelope_failure_lines(env, 120)
    note = (len(lines) * 0.14 + 0.15) if lines else 0.0
    legend_rows = -(-len(certified) // 4) if per_case else 1
    bottom = note + 0.2 * legend_rows + 0.12
    fig, axes = plt.subplots(len(heights), 1, sharex=True, figsize=(9, 2.0 * sum(heights) + 0.9 + bottom),
                             gridspec_kw={"height_ratios": heights})
    axes = list(np.atleast_1d(axes))
    colours = {c["label"]: plt.cm.tab10(i % 10) for i, c in enumerate(certified)}
    if contact_rows:
        ax = axes.pop(0)
        for i, c in enumerate(env["cases"]):
            row = len(env["cases"]) - 1 - i
            for a, b in voids(pieces, begin, end):
                ax.add_patch(Rectangle((a, row - 0.35), b - a, 0.7, facecolor="0.85", edgecolor="0.5", hatch="//",
                                       linewidth=0))
            if not c["certified"]:
                ax.add_patch(Rectangle((begin, row - 0.35), end - begin, 0.7, facecolor="none", edgecolor="tab:red",
                                       hatch="xx", linewidth=0.6))
                ax.text(0.5 * (begin + end), row, "failed: not in the envelopes", ha="center", va="center",
                        fontsize=7, color="tab:red", zorder=5, bbox=dict(facecolor="white", edgecolor="none", pad=2))
                continue
            ax.add_patch(Rectangle((begin, row - 0.35), end - begin, 0.7, facecolor="none", edgecolor="0.3",
                                   linewidth=0.6))
            for a, b in c["regions"]:
                ax.add_patch(Rectangle((a, row - 0.35), b - a, 0.7, facecolor=colours.get(c["label"], "tab:green"),
                                       alpha=0.55, linewidth=0))
        ax.set_ylim(-0.6, len(env["cases"]) - 0.4)
        ax.set_yticks(range(len(env["cases"])))
        ax.set_yticklabels([c["label"] for c in reversed(env["cases"])], fontsize=8)
        ax.tick_params(axis="y", length=0)
        ax.set_ylabel("contact\nby case", fontsize=8)
        contact_axis = ax
    for ax, (key, ylabel, unit) in zip(axes, diagrams):
        high, low = env[key]
        for a, b in voids(pieces, begin, end):
            ax.axvspan(a, b, facecolor="none", edgecolor="0.75", hatch="//", linewidth=0)
        # The envelopes bold and pale under each case's thin curve, which stays visible where it governs.
        ax.plot(x, high, color="0.25", alpha=0.45 if per_case else 1.0, linewidth=3.5 if per_case else 1.8,
                label="envelope (max, min)", zorder=2)
        ax.plot(x, low, color="0.25", alpha=0.45 if per_case else 1.0, linewidth=3.5 if per_case else 1.8, zorder=2)
        if per_case:
            for c in certified:
                ax.plot(c["fields"]["x"], c["fields"][key], color=colours[c["label"]], linewidth=1.1,
                        label=c["label"], zorder=3)
        else:
            ax.fill_between(x, low, high, color="tab:blue", alpha=0.15, linewidth=0,
                            label="between the envelopes (every lead position)")
        ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: fmt(v)))
        ax.axhline(0.0, color="black", linewidth=0.6)
        ax.set_ylabel(ylabel, fontsize=8)
        ax.grid(True, alpha=0.3)
        ax.tick_params(labelsize=8)
        value_limits(ax, key, float(np.min(low)), float(np.max(high)), 0.4)  # room for the labels
    position_axis(axes[-1], arch, length, begin, end)
    title = os.path.basename(env["scene_name"]) or os.path.basename(path)
    count = len(env["cases"])
    names = list(dict.fromkeys(combination_of(c["label"]) for c in env["cases"]))
    if moving and len(names) > 1:
        what = f"{len(names)} combinations x {count // len(names)} lead positions"
    else:
        what = f"{count} lead positions" if moving else f"{count} combination{'s' if count != 1 else ''}"
    fig.suptitle(f"{title}: envelopes over {what}" + ("" if env["complete"] else " (INCOMPLETE)"), fontsize=10,
                 y=0.995)
    notes = ["bold: the envelopes (largest and smallest over the cases at each point)",
             "labels: the extremes and the case that governs each"]
    if contact_rows:
        notes.append("top: each case's contact in its colour, blank lifted off")
    if moving and len(positions) > 1:
        steps = np.diff(np.sort(positions[np.isfinite(positions)]))
        steps = steps[steps > 0]
        if len(steps):
            notes.append(f"lead positions {fmt(np.min(steps))} {'deg' if arch else length} apart (the teeth: "
                         f"peaks under the loads between positions are not sampled)"
                         if np.max(steps) - np.min(steps) < 1e-9 * max(1.0, np.max(steps)) else
                         f"lead positions {fmt(np.min(steps))} to {fmt(np.max(steps))} apart")
    if voids(pieces, begin, end):
        notes.append("hatched: no foundation")
    fig.text(0.5, 0.975, "\n".join(textwrap.wrap(";  ".join(notes), 150)), ha="center", va="top", fontsize=7,
             color="0.3")
    inches = fig.get_figheight()
    if lines:
        fig.text(0.01, 0.005, "\n".join(lines), fontsize=7, color="tab:red", va="bottom", ha="left")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=min(4, len(handles)), fontsize=7, frameon=False,
               bbox_to_anchor=(0.5, note / inches))
    fig.align_ylabels(axes + ([contact_axis] if contact_rows else []))
    fig.tight_layout(rect=(0, bottom / inches, 1, 1 - 0.35 / inches))
    fig.subplots_adjust(hspace=0.12)
    fig.canvas.draw()
    placer = LabelPlacer(fig)
    for ax, (key, _, unit) in zip(axes, diagrams):
        scale = max(float(np.max(np.abs(env[key][0]))), float(np.max(np.abs(env[key][1]))))
        for value, at, governing in governing_extremes(env, key):
            if scale > 0 and abs(value) < 1e-3 * scale:
                continue  # a zero extreme (no pressure where the member lifts) says nothing
            ax.plot(at, value, "o", color="black", markersize=4, zorder=5)
            if moving:  # "lead at 4.2" with its unit
                governing = re.sub(r"lead at (\S+)$", lambda m: f"lead at {m.group(1)}{position_unit}", governing)
            # A label under a point in the lower half of the axes (a minimum; w's maximum, drawn
            # downward), above one in the upper half: off the curves, into the margin kept for it.
            middle = 0.5 * sum(ax.get_window_extent().intervaly)
            below = ax.transData.transform((at, value))[1] < middle
            placer.place(ax, f"{fmt(value)} {unit} at {where} = {fmt(at)}{position_unit}, governed by {governing}",
                         (at, value), below=below, fontsize=7,
                         bbox=dict(boxstyle="round,pad=0.2", facecolor="white", edgecolor="0.7", alpha=0.9))
    output.save(fig, prefix + "_envelopes.png")
    if moving:
        envelope_lift_off_map(env, scene, pieces, begin, end, prefix + "_lift_off_map.png", output)


def envelope_lift_off_map(env, scene, pieces, begin, end, out, output):
    """x along the member, the lead position up: contact green, lifted off white, no foundation
    hatched grey, failed positions crossed red; the group's loads as dotted lines (lead + offset)."""
    length = env["units"][0]
    arch = env["coordinate"] == "theta_deg"
    unit = "deg" if arch else length
    combinations = list(dict.fromkeys(combination_of(c["label"]) for c in env["cases"]))
    fig, axes = plt.subplots(1, len(combinations), figsize=(max(7.0, 4.6 * len(combinations)), 6.4), sharey=True,
                             squeeze=False)
    group = moving_group(scene)
    positions = np.array([c["position"] for c in env["cases"]])
    lo, hi = float(np.nanmin(positions)), float(np.nanmax(positions))
    failed_any = False
    for ax, name in zip(axes[0], combinations):
        cases = [c for c in env["cases"] if combination_of(c["label"]) == name]
        p = np.array([c["position"] for c in cases])
        # Each position's row reaches half-way to its neighbours.
        edges = np.concatenate(([p[0] - 0.5 * (p[1] - p[0]) if len(p) > 1 else p[0] - 0.5],
                                0.5 * (p[1:] + p[:-1]),
                                [p[-1] + 0.5 * (p[-1] - p[-2]) if len(p) > 1 else p[0] + 0.5]))
        for a, b in voids(pieces, begin, end):
            ax.add_patch(Rectangle((a, edges[0]), b - a, edges[-1] - edges[0], facecolor="0.85", edgecolor="0.5",
                                   hatch="//", linewidth=0, zorder=0))
        for i, c in enumerate(cases):
            if not c["certified"]:
                failed_any = True
                ax.add_patch(Rectangle((begin, edges[i]), end - begin, edges[i + 1] - edges[i], facecolor="none",
                                       edgecolor="tab:red", hatch="xx", linewidth=0, zorder=1))
                continue
            for a, b in c["regions"]:
                ax.add_patch(Rectangle((a, edges[i]), b - a, edges[i + 1] - edges[i], facecolor="tab:green",
                                       alpha=0.45, linewidth=0, zorder=1))
        if group:
            offsets, _ = group
            for k, offset in enumerate(offsets):
                ax.plot(p + offset, p, color="tab:red", linestyle=":", linewidth=1.2, zorder=3,
                        label="the group's loads (lead + offset)" if k == 0 else None)
        ax.set_xlim(begin, end)
        ax.set_ylim(edges[0], edges[-1])
        ax.set_xlabel("theta (degrees from the crown)" if arch else f"x [{length}]")
        ax.grid(True, alpha=0.3)
        if name:
            ax.set_title(name, fontsize=10)
    axes[0][0].set_ylabel(f"lead position of the moving group [{unit}]")
    title = os.path.basename(env["scene_name"])
    per = len(env["cases"]) // len(combinations)
    fig.suptitle(f"{title}: lift-off map of the moving load ({per} lead positions, {fmt(lo)} to {fmt(hi)} {unit}"
                 + (f"; {len(combinations)} combinations" if len(combinations) > 1 else "") + ")", fontsize=10)
    handles = [Rectangle((0, 0), 1, 1, facecolor="tab:green", alpha=0.45, label="contact"),
               Rectangle((0, 0), 1, 1, facecolor="white", edgecolor="0.3", linewidth=0.6,
                         label="lifted off (foundation, no contact)")]
    if voids(pieces, begin, end):
        handles.append(Rectangle((0, 0), 1, 1, facecolor="0.85", edgecolor="0.5", hatch="//", linewidth=0,
                                 label="no foundation"))
    if failed_any:
        handles.append(Rectangle((0, 0), 1, 1, facecolor="none", edgecolor="tab:red", hatch="xx", linewidth=0,
                                 label="failed (not in the envelopes)"))
    handles += [h for h in axes[0][0].get_legend_handles_labels()[0]]
    fig.legend(handles=handles, loc="lower center", ncol=min(len(handles), 3), fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.08 if len(handles) <= 3 else 0.11, 1, 1))
    output.save(fig, out)


# ----------------------------------------------------------------------------------------------

def main(argv=None, kind=None):
    parser = argparse.ArgumentParser(prog=PROG, description=__doc__.splitlines()[0])
    parser.add_argument("file",
                        help="HDF5 file written by liftoff solve, trace or sweep (--output) or envelope (--hdf5)")
    parser.add_argument("--out", default=None, help="prefix of the PNG files (default: the file's name without .h5)")
    parser.add_argument("--normalise", action="store_true",
                        help="sweeps: divide each case's curve by its own largest magnitude")
    parser.add_argument("--dolfinx", action="store_true", help="sweeps: add the dolfinx reference as a panel")
    parser.add_argument("--dolfinx-elements", type=int, default=400)
    parser.add_argument("--closed-form", default=None,
                        help="traces with an axial force: verification/closed_form's closed_form_reference, for the "
                             "perfect member's branch (default: $LIFTOFF_CLOSED_FORM, then the PATH)")
    args = parser.parse_args(argv)
    path = args.file
    prefix = args.out or (path[:-3] if path.endswith(".h5") else path)
    if not os.path.isfile(path):
        fail(BAD_INPUT, f"{path}: no such file; expected an HDF5 file written by liftoff")
    output = Output()
    try:
        f = h5py.File(path, "r")
    except OSError:
        if os.path.exists(path + ".backup"):
            f = None  # a trace damaged by a kill: read_trace takes its backup
        else:
            fail(BAD_INPUT, f"{path}: not an HDF5 file; expected a file written by `liftoff solve/trace/sweep "
                            f"--output` or `liftoff envelope --hdf5`")
    found = file_kind(f) if f is not None else "trace"
    if kind is not None and found is not None and found != kind:
        fail(BAD_INPUT, f"{path}: a {found} file; expected a {kind} file")
    if found in ("solve", "trace", "envelope") and args.normalise:
        article = "an" if found[0] in "aeiou" else "a"
        fail(BAD_INPUT, f"--normalise: {path} is {article} {found} file; expected a sweep file (--normalise draws "
                        f"sweeps only)")
    if found is not None and found not in ("solve", "trace", "sweep", "envelope"):
        fail(BAD_INPUT, f"{path}: a liftoff file of kind '{found}', which plot cannot draw; expected a solve, trace, "
                        f"sweep or envelope file")
    if found == "solve":
        plot_solve(path, f, prefix, output)
    elif found == "envelope":
        plot_envelope(path, f, prefix, output)
    elif found == "sweep":
        plot_sweep(path, f, prefix, output, args.normalise, args.dolfinx, args.dolfinx_elements)
    elif found == "trace":
        if f is not None:
            f.close()
        plot_trace(path, prefix, output, args.closed_form)
    else:
        fail(BAD_INPUT, f"{path}: not a liftoff result file (no root attribute 'kind' or 'liftoff_version'); "
                        f"expected a file written by `liftoff solve/trace/sweep --output` or "
                        f"`liftoff envelope --hdf5`")
    output.finish()


if __name__ == "__main__":
    main()
