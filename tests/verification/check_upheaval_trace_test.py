#!/usr/bin/python3
"""verification/closed_form/check_upheaval_trace.py on synthetic traces (tests/app/upheaval_fixture.py).

    /usr/bin/python3 tests/verification/check_upheaval_trace_test.py --closed-form build/verification/closed_form_reference

The fixture's paths are the closed form's branch made imperfect, P = P_cf(A) A / (A + A0): the script
must find each path's limit load (the largest P, where the limit_point event is) and, at the same
lifted length, the relative difference -A0 / (A + A0) (to the closed-form table's interpolation,
1e-3), shrinking down the branch; exit 0. A path without a limit point is exit 1; a file of the
layout before the beam-column quantities, or a scene without a closed form, is exit 2 with one line.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
sys.path.insert(0, os.path.join(HERE, "..", "app"))
sys.path.insert(0, os.path.join(HERE, "..", "support"))
from checks import check, finish  # noqa: E402
sys.path.insert(0, os.path.join(ROOT, "verification", "closed_form"))
import check_upheaval_trace  # noqa: E402
import upheaval_fixture  # noqa: E402

SCRIPT = os.path.join(ROOT, "verification", "closed_form", "check_upheaval_trace.py")
SCENE = os.path.join(ROOT, "continuation", "scenes", "pipeline_upheaval.toml")
def run(*args):
    return subprocess.run(["/usr/bin/python3", SCRIPT, *args], capture_output=True, text=True, timeout=300)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--closed-form", required=True)
    program = parser.parse_args().closed_form
    table = json.loads(subprocess.run([program, "localized-buckle", SCENE, "--max-amplitude", "1.3"],
                                      capture_output=True, text=True, check=True).stdout)["points"]
    scene_text = open(SCENE).read()
    with tempfile.TemporaryDirectory() as tmp:
        trace = os.path.join(tmp, "upheaval.h5")
        upheaval_fixture.write_upheaval_trace(trace, scene_text, table)
        r = run(trace, "--closed-form", program)
        check(r.returncode == 0, f"synthetic upheaval: exit 0 (got {r.returncode}: {r.stderr.strip()})")
        ok, results = check_upheaval_trace.check(trace, program, 12)
        check(ok and sorted(results) == ["fe", "ritz"], f"both paths checked and passing ({sorted(results)})")
        with h5py.File(trace) as f:
            for name, imperfection in upheaval_fixture.IMPERFECTIONS.items():
                largest = float(np.max(f[name]["steps"]["axial_force"][()]))
                load = results[name]["limit_load"]
                check(abs(load - largest) <= 1e-9 * largest, f"{name}: limit load {load:.6g} = the largest P {largest:.6g}")
                rows = results[name]["rows"]
                check(len(rows) == 12, f"{name}: 12 rows on the descending branch ({len(rows)})")
                worst = max(abs(d - (-imperfection / (a + imperfection))) for _, a, _, _, _, d in rows)
                check(worst < 1e-3, f"{name}: (P - P_cf)/P_cf = -A0/(A + A0) at the same lifted length "
                                    f"(worst difference {worst:.2e})")
                d = [abs(row[-1]) for row in rows]
                check(all(x > y for x, y in zip(d, d[1:])), f"{name}: the difference shrinks down the branch "
                                                            f"({d[0]:.3f} -> {d[-1]:.3f})")
        # No limit point: the ritz path's event removed.
        with h5py.File(trace, "a") as f:
            events = f["ritz"]["events"]
            for key in ("lambda", "at", "step"):
                data = events[key][()][:1]
                del events[key]
                events[key] = data
            for key in ("kind", "description"):
                data = events[key][()][:1]
                del events[key]
                events[key] = np.array(data, dtype=object)
        r = run(trace, "--closed-form", program)
        check(r.returncode == 1 and "ritz: FAIL no limit_point event" in r.stdout,
              f"a path without a limit point: exit 1, said (got {r.returncode})")
        # The layout before the beam-column quantities.
        with h5py.File(trace, "a") as f:
            del f["fe"]["steps"]["axial_force"]
        r = run(trace, "--closed-form", program)
        lines = r.stderr.strip().splitlines()
        check(r.returncode == 2 and len(lines) == 1 and "axial_force" in lines[0] and trace in lines[0],
              f"no axial_force: exit 2, one line naming the file and the dataset ({lines})")
        # A scene with no closed form (a point force on the member).
        other = os.path.join(tmp, "other.h5")
        upheaval_fixture.write_upheaval_trace(other, scene_text + '\n[[loads]]\nkind = "force"\nat = 50.0\nvalue = 1.0\n',
                                              table)
        r = run(other, "--closed-form", program)
        lines = r.stderr.strip().splitlines()
        check(r.returncode == 2 and len(lines) == 1 and "loads[2].kind" in lines[0] and other in lines[0],
              f"a scene with no closed form: exit 2, one line naming the key ({lines})")
    finish()


if __name__ == "__main__":
    main()
