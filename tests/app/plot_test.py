#!/usr/bin/python3
"""`liftoff plot` (src/app/plot_command.cpp, verification/plots/plot.py) through the real executable.

    /usr/bin/python3 tests/app/plot_test.py --liftoff build/src/liftoff

Writes a solve, a trace and a sweep file with liftoff itself, draws each with `liftoff plot`, and
checks what a user would notice first: the exit code, the PNG files named on stdout (and nothing
else, no .tmp left), that each picture has ink on it, that "no foundation" is drawn (its grey)
only where the scene has a void, that a trace's states along the member are drawn at its events'
steps and its last, and that a sweep with a failed case carries the red note. Envelope
files (`liftoff envelope --hdf5`): a moving load draws its envelopes and its lift-off map against
the lead position (the void grey, contact green, the file's units stored for the axes), load
combinations with a failed case draw their envelopes with every case's own curve and the red note
(and no lift-off map). Then
the errors: a missing file, a file that is not HDF5, an HDF5 file that is not liftoff's, and
--normalise on a solve file are exit 2 with one line on stderr naming the file; an output prefix
in a directory that does not exist is exit 4 with nothing written.
"""
import argparse
import os
import subprocess
import sys
import tempfile

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "support"))
from checks import check, finish  # noqa: E402
sys.path.insert(0, os.path.join(HERE, "..", "..", "verification", "plots"))
import plot as plot_module  # noqa: E402


def run(liftoff, *args):
    return subprocess.run([liftoff, *args], capture_output=True, text=True, timeout=600)


def pixels(path):
    image = matplotlib.image.imread(path)[:, :, :3]
    return np.round(image * 255).astype(int)


def ink(path):
    """Fraction of pixels that are not white."""
    p = pixels(path)
    return float(np.mean(np.any(p < 250, axis=2)))


def count_colour(path, rgb, tolerance=3):
    p = pixels(path)
    return int(np.sum(np.all(np.abs(p - np.array(rgb)) <= tolerance, axis=2)))


# Two soils with a void between them (a trench).
TWO_SOILS = """[[foundation.segments]]
from = 0.0
to = 5.0
modulus = 2.0e7

[[foundation.segments]]
from = 7.0
to = 12.0
modulus = 2.0e7"""

# A beam on TWO_SOILS, a pinned left end, a point force, a moment, a dead uniform load: every kind
# of thing the solve picture draws.
BEAM = """
[structure]
kind = "beam"
length = 12.0
EI = 2.0e7

[supports]
left = "pinned"
right = "free"

""" + TWO_SOILS + """

[[loads]]
kind = "uniform"
value = 5.0e3
case = "dead"

[[loads]]
kind = "force"
at = 9.0
value = 200e3

[[loads]]
kind = "moment"
at = 3.0
value = -50e3

[solve]
elements = 120

[trace]
lambda_max = 1.0
monitor = 9.0
"""

# The same member on one foundation everywhere: its lift-off map has no void.
WHOLE = BEAM.replace(TWO_SOILS, """[foundation]
modulus = 2.0e7""")

# A pair of loads rolled over the trench, and load combinations of which one (the uplift W, -2e6
# away from the foundation, which the single pin cannot hold) has no equilibrium.
MOVING = BEAM.split("[[loads]]")[0] + """
[[loads]]
kind = "uniform"
value = 5.0e3
case = "dead"

[moving]
loads = [{ kind = "force", offset = 0.0, value = 200e3 }, { kind = "force", offset = 1.5, value = 200e3 }]
from = 0.0
to = 10.5
step = 0.5

[solve]
elements = 120

[units]
system = "N-m"
"""
COMBINATIONS = WHOLE.split("[[loads]]")[0] + """
[[loads]]
kind = "uniform"
value = 5.0e3
case = "G"

[[loads]]
kind = "force"
at = 9.0
value = 200e3
case = "Q"

[[loads]]
kind = "force"
at = 9.0
value = -2e6
case = "W"

[[combinations]]
name = "G"
factors = { G = 1.0 }

[[combinations]]
name = "ULS"
factors = { G = 1.35, Q = 1.5 }

[[combinations]]
name = "uplift"
factors = { G = 1.0, W = 1.0 }

[solve]
elements = 120

[units]
system = "kN-m"
"""

VOID_GREY = (217, 217, 217)  # plot.py's "no foundation" face colour, 0.85
NOTE_RED = (214, 39, 40)  # tab:red, the note of the failed cases (three cases drawn: blue, orange, green)
CONTACT_GREEN = (160, 212, 160)  # tab:green (44, 160, 44) at alpha 0.45 on white: the lift-off map's contact
CASE_BLUE, CASE_ORANGE = (31, 119, 180), (255, 127, 14)  # tab:blue, tab:orange: the first two cases' curves


def drew(result, expected, what):
    """`liftoff plot` succeeded and named exactly the expected PNGs, each present with ink on it."""
    check(result.returncode == 0, f"{what}: exit 0 (got {result.returncode}: {result.stderr.strip()})")
    named = result.stdout.split()
    check(named == expected, f"{what}: names {expected} on stdout (got {named})")
    for path in expected:
        exists = os.path.isfile(path)
        check(exists and not os.path.exists(path + ".tmp"), f"{what}: {os.path.basename(path)} written, no .tmp left")
        if exists:
            # A figure of axes, curves and labels inks several per cent of its pixels; an empty
            # figure (a failed plot) inks none. 2 % is far below every picture's own (8 % to 25 %).
            fraction = ink(path)
            check(fraction > 0.02, f"{what}: {os.path.basename(path)} has ink on {100 * fraction:.1f} % of its pixels")


def wrote(liftoff, code, kind, what, h5, *args):
    """`liftoff ARGS` exited with `code` and wrote h5, a liftoff file of root attribute kind = `kind`."""
    r = run(liftoff, *args)
    check(r.returncode == code, f"{what}: exit {code} (got {r.returncode}: {r.stderr.strip()})")
    with h5py.File(h5) as f:
        check(f.attrs.get("kind") == kind, f"{what}: root attribute kind = {kind}")


def write(path, text):
    with open(path, "w") as f:
        f.write(text)
    return path


def error(result, code, name, what):
    lines = result.stderr.strip().splitlines()
    check(result.returncode == code, f"{what}: exit {code} (got {result.returncode})")
    check(len(lines) == 1 and name in lines[0], f"{what}: one line on stderr naming {name} (got {lines})")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--liftoff", required=True)
    parser.add_argument("--keep", help="write the files here (to look at the pictures) instead of a temporary directory")
    args = parser.parse_args()
    liftoff = args.liftoff
    if args.keep:
        os.makedirs(args.keep, exist_ok=True)
    with tempfile.TemporaryDirectory() as scratch:
        tmp = args.keep or scratch
        beam, whole = write(os.path.join(tmp, "beam.toml"), BEAM), write(os.path.join(tmp, "whole.toml"), WHOLE)

        # solve: a beam, and the default scene (an arch: diagrams against theta and its shape)
        h5 = os.path.join(tmp, "beam.h5")
        wrote(liftoff, 0, "solve", "solve beam", h5, "solve", beam, "--output", h5)
        drew(run(liftoff, "plot", h5), [os.path.join(tmp, "beam_diagrams.png")], "plot solve")
        arch = os.path.join(tmp, "arch.h5")
        check(run(liftoff, "solve", "--output", arch).returncode == 0, "solve default arch: exit 0")
        prefix = os.path.join(tmp, "pictures_arch")
        drew(run(liftoff, "plot", arch, "--out", prefix), [prefix + "_diagrams.png", prefix + "_shape.png"],
             "plot arch --out")

        # trace: with a void (hatched grey on the lift-off map) and without (no grey)
        for name, scene, void in (("trace_void", beam, True), ("trace_whole", whole, False)):
            h5 = os.path.join(tmp, name + ".h5")
            wrote(liftoff, 0, "trace", f"{name}: trace", h5, "trace", scene, "--output", h5)
            pictures = [os.path.join(tmp, name + suffix)
                        for suffix in ("_load_displacement.png", "_lift_off_map.png", "_states.png")]
            drew(run(liftoff, "plot", h5), pictures, f"plot {name}")
            # The states along the member: one curve per step of an event (both ends of one event are one
            # step) and the last step, from the file's nodal fields.
            path = plot_module.read_trace(h5)["paths"]["fe"]
            drawn = [step for step, _ in plot_module.states_to_draw(path)]
            expected = sorted(set(path["event_steps"]) | {len(path["lambda"]) - 1})
            check(drawn == expected and path["fields"]["w"].shape == (len(path["lambda"]), 121),
                  f"{name}: states drawn at steps {expected} (got {drawn}), w of 121 nodes per step")
            grey = count_colour(pictures[1], VOID_GREY)
            # The void, 2 of 12 length units over the whole lambda range, fills about 30 000 pixels of
            # the map; lines and text blend through this grey at their edges (about 100 pixels).
            check(grey > 10000 if void else grey < 1000, f"{name}: 'no foundation' grey pixels {grey} "
                                                      f"({'the void drawn' if void else 'no void, none drawn'})")

        # sweep with fast and one failing case: the force of -2e6 (away from the foundation) lifts
        # the pinned-free beam off, which its one pin cannot hold: no equilibrium
        h5 = os.path.join(tmp, "sweep.h5")
        wrote(liftoff, 3, "sweep", "sweep with a failing case", h5, "sweep", whole, "--set",
              "loads[1].value=-2e6,100e3,200e3,300e3", "--method", "fast", "--jobs", "1", "--output", h5, "--csv",
              os.path.join(tmp, "sweep.csv"))
        with h5py.File(h5) as f:
            failed = [c for c in f["cases"] if text(f["cases"][c]["fast"].attrs["termination"]) != "solved"]
            check(len(failed) == 1, f"sweep: exactly one case failed (got {failed})")
        pictures = [os.path.join(tmp, "sweep_deflection.png"), os.path.join(tmp, "sweep_reaction.png")]
        drew(run(liftoff, "plot", h5), pictures, "plot sweep (fast, one failed case)")
        red = count_colour(pictures[0], NOTE_RED, tolerance=10)
        check(red > 100, f"sweep: the failed case's note is on the figure ({red} red pixels)")
        prefix = os.path.join(tmp, "normalised")
        drew(run(liftoff, "plot", h5, "--normalise", "--out", prefix),
             [prefix + "_deflection.png", prefix + "_reaction.png"], "plot sweep --normalise")

        # envelope of a moving load: the envelopes and the lift-off map against the lead position
        h5 = os.path.join(tmp, "moving.h5")
        wrote(liftoff, 0, "envelope", "envelope moving", h5, "envelope",
              write(os.path.join(tmp, "moving.toml"), MOVING), "--hdf5", h5)
        with h5py.File(h5) as f:
            check(text(f.attrs.get("units_length", "")) == "m" and text(f.attrs.get("units_force", "")) == "N",
                  "envelope file: units_length = m, units_force = N (what the axes say)")
            check(len(f["cases/certified"]) == 22 and all(f["cases/certified"][()] == 1),
                  "envelope file: the 22 lead positions certified")
        pictures = [os.path.join(tmp, "moving_envelopes.png"), os.path.join(tmp, "moving_lift_off_map.png")]
        drew(run(liftoff, "plot", h5), pictures, "plot envelope (moving)")
        # The trench, 2 of 12 length units over every lead position, fills about 40 000 pixels of the
        # map; contact (green at alpha 0.45 on white) most of the rest.
        grey = count_colour(pictures[1], VOID_GREY)
        check(grey > 10000, f"envelope lift-off map: the trench drawn as 'no foundation' ({grey} grey pixels)")
        green = count_colour(pictures[1], CONTACT_GREEN, tolerance=4)
        check(green > 50000, f"envelope lift-off map: contact drawn ({green} green pixels)")

        # load combinations, one of which fails: drawn without it, with the red note
        h5 = os.path.join(tmp, "combinations.h5")
        wrote(liftoff, 3, "envelope", "envelope with a failing combination", h5, "envelope",
              write(os.path.join(tmp, "combinations.toml"), COMBINATIONS), "--hdf5", h5)
        with h5py.File(h5) as f:
            check(list(f["cases/certified"][()]) == [1, 1, 0], "envelope file: the uplift combination failed")
            check(sorted(f["cases/fields"]) == ["0000", "0001"], "envelope file: the certified combinations' own "
                  f"fields stored, for their curves (got {sorted(f['cases/fields'])})")
        prefix = os.path.join(tmp, "combinations")
        drew(run(liftoff, "plot", h5, "--out", prefix), [prefix + "_envelopes.png"],
             "plot envelope (combinations, one failed)")
        check(not os.path.exists(prefix + "_lift_off_map.png"), "combinations: no lift-off map against a position")
        red = count_colour(prefix + "_envelopes.png", NOTE_RED, tolerance=10)
        check(red > 100, f"combinations: the failed case's note is on the figure ({red} red pixels)")
        # Each certified case's own curve in its colour (tab:blue, tab:orange) beside the bold envelope.
        for name, rgb in (("G", CASE_BLUE), ("ULS", CASE_ORANGE)):
            n = count_colour(prefix + "_envelopes.png", rgb, tolerance=10)
            check(n > 300, f"combinations: case {name}'s own curves drawn ({n} pixels of its colour)")
        error(run(liftoff, "plot", h5, "--normalise"), 2, "--normalise", "plot --normalise on an envelope file")

        # errors
        missing = os.path.join(tmp, "missing.h5")
        error(run(liftoff, "plot", missing), 2, "missing.h5", "plot a missing file")
        not_hdf5 = write(os.path.join(tmp, "scene.h5"), BEAM)
        error(run(liftoff, "plot", not_hdf5), 2, not_hdf5, "plot a file that is not HDF5")
        foreign = os.path.join(tmp, "foreign.h5")
        with h5py.File(foreign, "w") as f:
            f["data"] = np.arange(10.0)
            f.attrs["creator"] = "someone else"
        error(run(liftoff, "plot", foreign), 2, foreign, "plot an HDF5 file that is not liftoff's")
        check(not any(n.startswith("foreign_") for n in os.listdir(tmp)), "foreign file: no picture written")
        error(run(liftoff, "plot", os.path.join(tmp, "beam.h5"), "--normalise"), 2, "--normalise",
              "plot --normalise on a solve file")
        # A Python without h5py (or matplotlib): the script says which module, exit 4. The module is
        # hidden from the import system (sys.modules[name] = None makes `import name` fail).
        script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "verification", "plots", "plot.py")
        for module in ("h5py", "matplotlib"):
            hide = (f"import sys, runpy; sys.modules[{module!r}] = None; sys.argv = ['plot.py', {h5!r}]; "
                    f"runpy.run_path({script!r}, run_name='__main__')")
            r = subprocess.run(["/usr/bin/python3", "-c", hide], capture_output=True, text=True, timeout=120)
            error(r, 4, f"'{module}'", f"plot.py without {module}")
        nowhere = os.path.join(tmp, "no_such_directory", "p")
        error(run(liftoff, "plot", os.path.join(tmp, "beam.h5"), "--out", nowhere), 4, nowhere,
              "plot into a directory that does not exist")
    finish()


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


if __name__ == "__main__":
    main()
