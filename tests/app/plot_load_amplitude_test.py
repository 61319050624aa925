#!/usr/bin/python3
"""`liftoff plot` of a beam-column trace (issue 15): the load-amplitude figure, on synthetic files.

    /usr/bin/python3 tests/app/plot_load_amplitude_test.py --liftoff build/src/liftoff \\
        --closed-form build/verification/closed_form_reference

The file (tests/app/upheaval_fixture.py) has the layout of `liftoff trace --output` with the per-step
axial force, amplitude, lifted length and stability, two paths (fe, ritz) through a limit point, and
the done-when scene (continuation/scenes/pipeline_upheaval.toml). Checks: `liftoff plot` writes the
two trace pictures as before and PREFIX_load_amplitude.png, with ink, each path in its colour
(tab:blue, tab:red); the perfect member's branch is drawn from the closed-form program that liftoff
names (LIFTOFF_CLOSED_FORM; without one the figure still comes, with fewer black pixels and a note);
unstable steps are dashed (fewer pixels of the path's colour than the same path all stable);
plot_trace.py with --closed-form draws the same figure. A trace without axial force, or of the
layout before these datasets, gets the two old pictures only.
"""
import argparse
import json
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
ROOT = os.path.join(HERE, "..", "..")
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "support"))
from checks import check, finish  # noqa: E402
import upheaval_fixture  # noqa: E402

SCENE = os.path.join(ROOT, "continuation", "scenes", "pipeline_upheaval.toml")
FE_BLUE, RITZ_RED = (31, 119, 180), (214, 39, 40)
def pixels(path):
    return np.round(matplotlib.image.imread(path)[:, :, :3] * 255).astype(int)


def count_colour(path, rgb, tolerance=10):
    return int(np.sum(np.all(np.abs(pixels(path) - np.array(rgb)) <= tolerance, axis=2)))


def drew(result, expected, what):
    check(result.returncode == 0, f"{what}: exit 0 (got {result.returncode}: {result.stderr.strip()})")
    check(result.stdout.split() == expected, f"{what}: names {[os.path.basename(e) for e in expected]} "
                                             f"(got {result.stdout.split()})")
    for path in expected:
        if os.path.isfile(path):
            ink = float(np.mean(np.any(pixels(path) < 250, axis=2)))
            check(ink > 0.02, f"{what}: {os.path.basename(path)} has ink on {100 * ink:.1f} % of its pixels")
        else:
            check(False, f"{what}: {os.path.basename(path)} written")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--liftoff", required=True)
    parser.add_argument("--closed-form", required=True)
    parser.add_argument("--keep", help="write the files here (to look at the pictures)")
    args = parser.parse_args()
    table = json.loads(subprocess.run([args.closed_form, "localized-buckle", SCENE, "--max-amplitude", "1.3"],
                                      capture_output=True, text=True, check=True).stdout)["points"]
    scene_text = open(SCENE).read()
    if args.keep:
        os.makedirs(args.keep, exist_ok=True)
    with tempfile.TemporaryDirectory() as scratch:
        tmp = args.keep or scratch

        def picture_names(prefix, beam_column=True):
            names = [prefix + "_load_displacement.png", prefix + "_lift_off_map.png"]
            return names + [prefix + "_load_amplitude.png"] if beam_column else names

        def plot(h5, *extra, env=None):
            return subprocess.run([args.liftoff, "plot", h5, *extra], capture_output=True, text=True, timeout=300,
                                  env=env)

        h5 = os.path.join(tmp, "upheaval.h5")
        upheaval_fixture.write_upheaval_trace(h5, scene_text, table)
        prefix = os.path.join(tmp, "upheaval")
        drew(plot(h5), picture_names(prefix), "plot upheaval trace")
        figure = prefix + "_load_amplitude.png"
        blue, red = count_colour(figure, FE_BLUE), count_colour(figure, RITZ_RED)
        # Each path's curve over two panels (about 700 x 1.6 pixels each) and its markers: a few thousand,
        # fe's partly under ritz's where they nearly coincide (about 1400 left).
        check(blue > 1000 and red > 1500, f"both paths drawn in their colours ({blue} blue, {red} red pixels)")
        black = count_colour(figure, (0, 0, 0), tolerance=40)

        # Without the closed-form program: the figure still comes, without the black reference branch.
        env = dict(os.environ, LIFTOFF_CLOSED_FORM=os.path.join(tmp, "no_such_program"),
                   PATH="/usr/bin:/bin")
        bare = os.path.join(tmp, "bare")
        drew(plot(h5, "--out", bare, env=env), picture_names(bare), "plot without the closed form")
        bare_black = count_colour(bare + "_load_amplitude.png", (0, 0, 0), tolerance=40)
        # The branch: a thin line across both panels, about 900 + 500 pixels long.
        check(black - bare_black > 600, f"the perfect member's branch drawn from the closed form ({black} black "
                                        f"pixels with it, {bare_black} without)")

        # plot_trace.py itself, with --closed-form: the same three pictures.
        direct = os.path.join(tmp, "direct")
        r = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "verification", "plots", "plot_trace.py"), h5,
                            "--out", direct, "--closed-form", args.closed_form], capture_output=True, text=True,
                           timeout=300, env=env)
        drew(r, picture_names(direct), "plot_trace.py --closed-form")
        direct_black = count_colour(direct + "_load_amplitude.png", (0, 0, 0), tolerance=40)
        check(abs(direct_black - black) <= 0.02 * black, f"plot_trace.py draws the branch too ({direct_black} black "
                                                         f"pixels, liftoff plot {black})")

        # Stability: the fe path alone, stable then unstable, against the same path all stable (solid):
        # the dashes leave out a part of the descending branch's pixels.
        counts = {}
        for name, all_stable in (("fe_only", False), ("fe_stable", True)):
            path = os.path.join(tmp, name + ".h5")
            upheaval_fixture.write_upheaval_trace(path, scene_text, table, paths=["fe"])
            if all_stable:
                with h5py.File(path, "a") as f:
                    n = len(f["fe"]["steps"]["stability"])
                    del f["fe"]["steps"]["stability"]
                    f["fe"]["steps"]["stability"] = np.array(["stable"] * n, dtype=object)
            drew(plot(path), picture_names(os.path.join(tmp, name)), f"plot {name} trace")
            counts[name] = count_colour(os.path.join(tmp, name + "_load_amplitude.png"), FE_BLUE)
        check(counts["fe_stable"] > 1.1 * counts["fe_only"], f"unstable steps dashed ({counts['fe_only']} blue "
                                                             f"pixels dashed, {counts['fe_stable']} all solid)")

        # No axial force (an older trace, or a member without axial loads): the two old pictures only.
        for name, change in (("no_axial", "zero"), ("old_layout", "delete")):
            path = os.path.join(tmp, name + ".h5")
            upheaval_fixture.write_upheaval_trace(path, scene_text, table)
            with h5py.File(path, "a") as f:
                for p in ("fe", "ritz"):
                    steps = f[p]["steps"]
                    for key in ("axial_force", "amplitude", "lifted_length", "stability"):
                        if change == "delete":
                            del steps[key]
                        elif key != "stability":
                            steps[key][...] = 0.0
            drew(plot(path), picture_names(os.path.join(tmp, name), beam_column=False), f"plot {name} trace")
            check(not os.path.exists(os.path.join(tmp, name + "_load_amplitude.png")),
                  f"{name}: no load-amplitude figure")
    finish()


if __name__ == "__main__":
    main()
