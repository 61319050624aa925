"""A synthetic trace file of an upheaval buckle (issue 15's layout), for the plot and check tests.

    write_upheaval_trace(path, scene_text, table)

`table` is the closed form's localized buckle (`closed_form_reference localized-buckle SCENE`, its
"points"). Each path ("fe", "ritz") is the perfect member's branch made imperfect by a hump of
size A0 (Southwell's form): P(A) = P_cf(A) A / (A + A0) at the buckle amplitude A, the lifted
length the closed form's at that amplitude. The load rises from 0, passes a limit point (recorded
as a limit_point event, stable before, unstable after) and falls towards the closed form, which
it approaches as A grows past A0: the relative difference at the same lifted length is
-A0 / (A + A0) (P_cf falls with the lifted length, so at equal length it is a little less). The
live axial force is 1e6 (lambda = P / 1e6), the scene's.
"""
import h5py
import numpy as np

LIVE = 1.0e6
IMPERFECTIONS = {"fe": 0.03, "ritz": 0.035}


def path_steps(table, imperfection, top):
    amp = np.array([p["amplitude"] for p in table if p["status"] == "found"])
    force = np.array([p["axial_force"] for p in table if p["status"] == "found"])
    lifted = np.array([p["lifted_length"] for p in table if p["status"] == "found"])
    a = np.concatenate((np.linspace(0.0, 0.02, 9)[:-1], np.geomspace(0.02, top, 60)))
    p_cf = np.interp(a, amp, force)  # below the table's first amplitude: its first (highest) force
    return a, p_cf * a / (a + imperfection), np.interp(a, amp, lifted) * (a > 0)


def write_upheaval_trace(path, scene_text, table, top=1.0, length=200.0, samples=201, paths=None):
    """paths: the names of IMPERFECTIONS to write (default all)."""
    x = np.linspace(0.0, length, samples)
    chosen = {name: a0 for name, a0 in IMPERFECTIONS.items() if paths is None or name in paths}
    with h5py.File(path, "w") as f:
        f.attrs["liftoff_version"] = "synthetic"
        f.attrs["kind"] = "trace"
        f.attrs["scene_name"] = "pipeline_upheaval.toml"
        f.attrs["coordinate"] = "x"
        f.attrs["options"] = "{}"
        f.attrs["paths"] = ",".join(chosen)
        f.attrs["complete"] = 1
        f.attrs["units_length"] = "m"
        f.attrs["units_force"] = "N"
        f["scene"] = scene_text
        f["sample_points"] = x
        for name, imperfection in chosen.items():
            amplitude, force, lifted = path_steps(table, imperfection, top)
            n = len(amplitude)
            lam = force / LIVE
            limit = int(np.argmax(force))
            g = f.create_group(name)
            g.attrs.update({"complete": 1, "termination": "completed", "message": "synthetic", "monitor": 100.0})
            s = g.create_group("steps")
            s["lambda"] = lam
            s["monitor_deflection"] = -amplitude
            s["iterations"] = np.ones(n, dtype=int)
            s["axial_force"] = force
            s["amplitude"] = amplitude
            s["lifted_length"] = lifted
            s["stability"] = np.array(["stable" if i <= limit else "unstable" for i in range(n)], dtype=object)
            zone = np.abs(x[None, :] - 0.5 * length) < 0.5 * lifted[:, None]
            s["deflection"] = np.where(zone, -amplitude[:, None], 0.015)
            s["reaction"] = np.where(zone, 0.0, 3000.0)
            s["state_topology"] = np.array(["fe contact set"] * n, dtype=object)
            rows = []
            for i in range(n):
                if lifted[i] > 0:
                    rows += [[i, 0.0, 0.5 * (length - lifted[i])], [i, 0.5 * (length + lifted[i]), length]]
                else:
                    rows.append([i, 0.0, length])
            s["contact_regions"] = np.array(rows, dtype=float)
            s["state"] = np.zeros((0, 2))
            first = int(np.argmax(lifted > 0))
            e = g.create_group("events")
            e["lambda"] = np.array([lam[first], lam[limit]])
            e["kind"] = np.array(["lift_off_opens", "limit_point"], dtype=object)
            e["at"] = np.array([0.5 * length, 0.5 * length])
            e["step"] = np.array([first, limit])
            e["description"] = np.array(["a lift-off zone opens", "limit point"], dtype=object)
