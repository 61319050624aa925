#!/usr/bin/python3
"""`closed_form_reference localized-buckle SCENE.toml` (verification/closed_form/main.cpp): the perfect
member's localized buckle branch as JSON, against the limits of beam_column.hpp (issue 15).

    /usr/bin/python3 tests/verification/localized_buckle_command_test.py --closed-form build/verification/closed_form_reference

- a -> 0: the branch starts at the bilateral critical load 2 sqrt(K EI) (q = EI = K = 1: P(0.1) within
  1e-6 of it, the deficit falling like a^6, beam_column_test.cpp);
- K large at a fixed lifted length L = 2a = 1: Hobbs' vertical mode, P L^2 / EI -> 80.763 and the
  amplitude -> 2.407e-3 q L^4 / EI from below and above at the rate K^(-1/4); Richardson with that rate
  lands within 2 % of the last error (the closed form's own test's figures);
- the table: lifted_length = 2 a, P falling and the amplitude growing along the admissible part,
  --max-amplitude stopping the table, the amplitude measured from the ground (>= 0, the crown's lift);
- refusals: a scene that is not a uniform heavy beam on a uniform tensionless foundation is exit 2
  with one line naming the key.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "support"))
from checks import check, finish  # noqa: E402

SCENE = """[structure]
kind = "beam"
length = {length}
EI = {EI}

[supports]
left = "clamped"
right = "clamped"

[foundation]
modulus = {K}

[[loads]]
kind = "uniform"
value = {q}
case = "dead"

[[loads]]
kind = "axial"
value = 1.0
"""


def run(program, scene_text, *args, tmp):
    path = os.path.join(tmp, "scene.toml")
    with open(path, "w") as f:
        f.write(scene_text)
    r = subprocess.run([program, "localized-buckle", path, *args], capture_output=True, text=True, timeout=300)
    return r, path


def table(program, tmp, *args, **scene):
    values = dict(length=1000.0, EI=1.0, K=1.0, q=1.0)
    values.update(scene)
    r, _ = run(program, SCENE.format(**values), *args, tmp=tmp)
    if r.returncode != 0:
        check(False, f"localized-buckle {values}: exit 0 (got {r.returncode}: {r.stderr.strip()})")
        return None
    return json.loads(r.stdout)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--closed-form", required=True)
    program = parser.parse_args().closed_form
    hobbs_load, hobbs_uplift = 80.763, 2.407e-3
    with tempfile.TemporaryDirectory() as tmp:
        # a -> 0: 2 sqrt(K EI)
        t = table(program, tmp, "--half-lengths", "0.4,0.2,0.1")
        if t:
            top = t["bilateral_critical"]
            check(abs(top - 2.0) <= 1e-15, f"bilateral_critical = 2 sqrt(K EI) = 2 (got {top!r})")
            loads = [p["axial_force"] for p in t["points"]]
            check(len(loads) == 3, f"three points listed (got {len(loads)})")
            check(all(p < top for p in loads) and loads == sorted(loads), f"P(a) rises to 2 sqrt(K EI) as a falls: {loads}")
            check(top - loads[-1] <= 1e-6 * top, f"P(0.1) within 1e-6 of 2 sqrt(K EI) (deficit {top - loads[-1]:.3g})")
            rate = math.log2((top - loads[1]) / (top - loads[2]))
            check(5.5 < rate < 6.5, f"the deficit falls like a^6 (observed rate {rate:.2f})")
            check(all(p["lifted_length"] == 2 * p["half_length"] for p in t["points"]), "lifted_length = 2 a")
        # K large: Hobbs
        loads, amplitudes = [], []
        for K in (1e9, 1e10, 1e11, 1e12):
            t = table(program, tmp, "--half-lengths", "0.5", K=K)
            if not t or len(t["points"]) != 1:
                check(False, f"K = {K:g}: one point at a = 0.5")
                return finish()
            loads.append(t["points"][0]["axial_force"])  # P L^2 / EI with L = 1
            amplitudes.append(t["points"][0]["amplitude"])  # uplift EI / (q L^4)
        check(abs(t["hobbs_load_parameter"] - hobbs_load) < 1e-3, f"hobbs_load_parameter {t['hobbs_load_parameter']:.5f}")
        load_error = [p - hobbs_load for p in loads]
        amplitude_error = [a - hobbs_uplift for a in amplitudes]
        check(all(e < 0 for e in load_error), f"P L^2/EI approaches 80.763 from below: {loads}")
        check(all(e > 0 for e in amplitude_error), f"the amplitude approaches 2.407e-3 q L^4/EI from above: {amplitudes}")
        for i in range(1, len(loads)):
            rates = (math.log10(load_error[i - 1] / load_error[i]), math.log10(amplitude_error[i - 1] / amplitude_error[i]))
            check(all(abs(r - 0.25) <= 0.02 for r in rates), f"K = 1e{9 + i}: rates {rates[0]:.3f}, {rates[1]:.3f} (1/4)")
        r = 10 ** -0.25
        load_limit = loads[-1] + (loads[-1] - loads[-2]) * r / (1 - r)
        amplitude_limit = amplitudes[-1] + (amplitudes[-1] - amplitudes[-2]) * r / (1 - r)
        # Hobbs' constants are quoted to 4-5 digits: the extrapolation's own 2 % of the last error, or
        # the constant's last digit, whichever is larger.
        check(abs(load_limit - hobbs_load) <= max(0.02 * abs(load_error[-1]), 1e-3),
              f"extrapolated P L^2/EI {load_limit:.5f} (Hobbs 80.763)")
        check(abs(amplitude_limit - hobbs_uplift) <= max(0.02 * abs(amplitude_error[-1]), 1e-6),
              f"extrapolated amplitude {amplitude_limit:.6g} (Hobbs 2.407e-3)")
        # The default table of the done-when scene: the descending branch, cut at --max-amplitude.
        scene = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "continuation", "scenes",
                             "pipeline_upheaval.toml")
        r = subprocess.run([program, "localized-buckle", scene, "--max-amplitude", "1.0"], capture_output=True,
                           text=True, timeout=300)
        check(r.returncode == 0, f"pipeline_upheaval.toml: exit 0 ({r.stderr.strip()})")
        if r.returncode == 0:
            t = json.loads(r.stdout)
            found = [p for p in t["points"] if p["status"] == "found"]
            check(abs(t["bilateral_critical"] - 2 * math.sqrt(2.0e5 * 1.8011e8)) <= 1e-9 * t["bilateral_critical"],
                  f"pipeline: 2 sqrt(K EI) = {t['bilateral_critical']:.6g} N (the scene's 12.00 MN)")
            check(len(found) > 50, f"pipeline: {len(found)} admissible points")
            p, a = [q["axial_force"] for q in found], [q["amplitude"] for q in found]
            check(all(x > y for x, y in zip(p, p[1:])) and all(x < y for x, y in zip(a, a[1:])),
                  "pipeline: P falls and the amplitude grows along the branch")
            check(all(q["amplitude"] >= 0 for q in t["points"]), "pipeline: amplitudes measured from the ground (>= 0)")
            last = t["points"][-1]["amplitude"]
            check(t["points"][-2]["amplitude"] <= 1.0 < last, f"pipeline: the table stops past --max-amplitude 1 "
                                                             f"(last {last:.3f})")
        # Refusals: one line naming the key.
        base = SCENE.format(length=100.0, EI=1.0, K=1.0, q=1.0)
        for what, text, key in (
                ("an arch", base.replace('kind = "beam"', 'kind = "arch"'), "structure.kind"),
                ("foundation pieces", base.replace("modulus = 1.0", "modulus = 1.0\nfrom = 10.0"), "foundation.from"),
                ("a gap", base.replace("modulus = 1.0", "modulus = 1.0\ngap = { at = [0.0, 1.0], value = [0.0, 0.1] }"),
                 "foundation.gap"),
                ("a point force", base + '\n[[loads]]\nkind = "force"\nat = 3.0\nvalue = 1.0\n', "loads[2].kind"),
                ("a live weight", base.replace('case = "dead"', 'case = "live"'), "loads[0].case"),
                ("a partial weight", base.replace('case = "dead"', 'case = "dead"\nfrom = 5.0'), "loads[0]"),
                ("no weight", base.replace("value = 1.0\ncase", "value = 0.0\ncase"), "loads"),
                ("a varying EI", base.replace("EI = 1.0", "EI = [1.0, 2.0]"), "structure.EI")):
            r, path = run(program, text, tmp=tmp)
            lines = r.stderr.strip().splitlines()
            check(r.returncode == 2 and len(lines) == 1 and key in lines[0] and path in lines[0] and not r.stdout,
                  f"{what}: exit 2, one line naming {path} and {key} (got {r.returncode}: {lines})")
        r, _ = run(program, base, "--points", "0", tmp=tmp)
        check(r.returncode == 2 and "--points" in r.stderr, f"--points 0: exit 2 naming --points ({r.stderr.strip()})")
    finish()


if __name__ == "__main__":
    main()
