#!/usr/bin/python3
"""Smoke test of verification/bench/trace_bench.py (the trace benchmark of issue 37), a few seconds:

- the scene copies it makes (lambda_max raised, live loads scaled) read back as the scene with only
  those values changed, for every shipped trace scene and the fuzz corpus;
- its Richardson extrapolation recovers the limit and the order of an exact sequence L + C h^p;
- `--dry-run` plans every section without running liftoff;
- `--quick --sections fuzz,ritz` on the given liftoff prints both sections' tables and the targets
  block, and writes their CSVs with the rows it printed.

    /usr/bin/python3 tests/verification/trace_bench_test.py --liftoff build/src/liftoff
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import tempfile
import tomllib

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
BENCH = os.path.join(ROOT, "verification", "bench", "trace_bench.py")
sys.path.insert(0, os.path.dirname(BENCH))
import trace_bench  # noqa: E402

failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print(f"FAILED: {what}")


def scene_copies(tmp):
    scenes = trace_bench.shipped_trace_scenes() + trace_bench.fuzz_corpus_scenes()
    check(len(scenes) >= 10, f"found {len(scenes)} trace scenes, expected the shipped ones (>= 10)")
    for path in scenes:
        original = trace_bench.read_scene(path)
        copy = trace_bench.scene_copy(path, tmp, "copy.toml", lambda_max=70.0, live_factor=2.5)
        with open(copy, "rb") as fh:
            doc = tomllib.load(fh)
        check(doc["trace"]["lambda_max"] == 70.0, f"{path}: lambda_max of the copy")
        for before, after in zip(original.get("loads", []), doc.get("loads", [])):
            live = before.get("case", "live") == "live"
            scale = 2.5 if live else 1.0
            values = before["value"] if isinstance(before["value"], list) else [before["value"]]
            got = after["value"] if isinstance(after["value"], list) else [after["value"]]
            check(got == [v * scale for v in values], f"{path}: load {before} scaled by {scale}, got {after['value']}")
            after["value"] = before["value"]
        doc["trace"]["lambda_max"] = original["trace"]["lambda_max"]
        check(doc == original, f"{path}: the copy differs from the scene in more than lambda_max and the live loads")


def richardson():
    for p in (1.0, 2.0, 3.0, 4.0):
        limit, c = 1.2345, -0.37
        values = [limit + c * h ** p for h in (0.04, 0.02, 0.01)]
        converged, order, estimate = trace_bench.richardson(values)
        check(abs(order - p) < 1e-6, f"richardson order {order} for p = {p}")
        check(abs(converged - limit) < 1e-12, f"richardson limit {converged} for p = {p}, exact {limit}")
        check(abs(estimate - abs(limit - values[-1])) < 1e-12, f"richardson estimate {estimate} for p = {p}")
    converged, order, _ = trace_bench.richardson([1.0, 1.1, 1.0])  # no monotone sequence: no order
    check(converged == 1.0 and math.isnan(order), "richardson without an order: the finest value, order nan")


def matching():
    """A symmetric pair (same load, either side) is matched side to side, one to one; an FE event no
    Ritz event took comes back alone; a coarse mesh's events are matched to the finest one's."""
    ritz = [{"kind": "lift_off_opens", "lambda": 0.40372, "at": 42.47},
            {"kind": "lift_off_opens", "lambda": 0.40372, "at": -42.47}]
    fine = [{"kind": "lift_off_opens", "lambda": 0.40401, "at": -42.49},
            {"kind": "lift_off_opens", "lambda": 0.40401, "at": 42.49}, {"kind": "limit_point", "lambda": 0.9, "at": 0.0}]
    coarse = [{"kind": "lift_off_opens", "lambda": 0.4042, "at": 42.3},
              {"kind": "lift_off_opens", "lambda": 0.4042, "at": -42.3}, {"kind": "limit_point", "lambda": 0.91, "at": 0.0}]
    runs = [trace_bench.Run(doc={"paths": [{"events": coarse}]}), trace_bench.Run(doc={"paths": [{"events": fine}]})]
    pairs = trace_bench.match_events(ritz, runs)
    check(len(pairs) == 3, f"match_events: {len(pairs)} pairs, expected 3")
    for e, chain in pairs[:2]:
        check(chain is not None and all(c["at"] * e["at"] > 0 for c in chain),
              f"match_events: {e} matched across: {chain}")
    check(pairs[2][0] is None and [c["lambda"] for c in pairs[2][1]] == [0.91, 0.9],
          "match_events: the unmatched FE event")


def dry_run(liftoff):
    r = subprocess.run([sys.executable, BENCH, "--dry-run", "--liftoff", liftoff, "--fuzz-cases", "0"],
                       capture_output=True, text=True, timeout=60)
    check(r.returncode == 0, f"--dry-run exit {r.returncode}: {r.stderr[-500:]}")
    commands = [line for line in r.stdout.splitlines() if line.startswith("  liftoff ")]
    check(any("--method ritz" in c for c in commands) and any(" solve " in c for c in commands)
          and any("--elements 1024" in c for c in commands),
          "--dry-run plans traces, Ritz paths, solves, 1024 elements")


def quick(liftoff, out):
    r = subprocess.run([sys.executable, BENCH, "--quick", "--sections", "fuzz,ritz", "--liftoff", liftoff,
                        "--out", out], capture_output=True, text=True, timeout=120)
    check(r.returncode == 0, f"--quick exit {r.returncode}: {r.stderr[-500:]}")
    for title in ("2. fuzzed and shipped trace scenes", "3a. how the Ritz path ends", "3b. Ritz events",
                  "targets (issue 37"):
        check(title in r.stdout, f"--quick prints '{title}'")
    for name, rows in (("fuzz", 2), ("ritz_ends", 1), ("ritz_events", 1)):
        path = os.path.join(out, f"{name}.csv")
        if not os.path.exists(path):
            check(False, f"{path} written")
            continue
        with open(path, newline="") as fh:
            table = list(csv.DictReader(fh))
        check(len(table) >= rows, f"{name}.csv has {len(table)} rows, expected at least {rows}")
    with open(os.path.join(out, "fuzz.csv"), newline="") as fh:
        for row in csv.DictReader(fh):
            check(row["termination_A"] not in ("", "timeout") and float(row["time_s_A"]) > 0,
                  f"fuzz.csv row {row['scene']} {row['path']}: a finished run with a time")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--liftoff", required=True)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        scene_copies(tmp)
        richardson()
        matching()
        dry_run(args.liftoff)
        quick(args.liftoff, os.path.join(tmp, "out"))
    print("trace_bench_test: " + ("passed" if not failures else f"{len(failures)} failure(s)"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
