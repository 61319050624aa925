#!/usr/bin/env python3
"""Answers before and after a change that should not change them.

    answers.py run LIFTOFF OUTDIR [--jobs N]   every shipped scene through every command and method,
                                               one JSON file per run (stdout, exit code) in OUTDIR
    answers.py compare OLD NEW [--rtol R]      every number of every run, OLD against NEW

A refactor (issue 14: seams, options, typed results) must leave the answers alone: `run` the old
build and the new build, then `compare`. Numbers agree when |a - b| <= rtol * max(|a|, |b|, scale),
where scale is the largest magnitude of the same key in the run (so a field's round-off near zero is
measured against the field, not against itself). Timings and other clock readings are skipped; the
text of messages must match exactly (after the same masking of numbers, which are compared as such).
Exit code 0 when every run agrees, 1 otherwise.
"""
import argparse
import concurrent.futures
import json
import math
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENE_DIRS = ["verification/scenes", "continuation/scenes", "verification/dolfinx/scenes"]
# The dense Lemke methods (O(n^3)) on a 100-element mesh: the same code paths, in seconds.
SOLVE_METHODS = [[], ["--method", "fast"], ["--method", "dual", "--elements", "100"],
                 ["--method", "primal", "--elements", "100"], ["--method", "ritz"], ["--tolerance", "1e-8"]]
# Clock readings and counters of work that legitimately vary (none of them is an answer).
SKIP_KEY = re.compile(r"(^|_)(time|times|seconds|time_s|wall|elapsed|duration)($|_)|_s$")


def scenes():
    for d in SCENE_DIRS:
        yield from sorted((ROOT / d).rglob("*.toml"))


def runs():
    for scene in scenes():
        rel = scene.relative_to(ROOT)
        name = str(rel).replace("/", "__")[:-5]
        for m in SOLVE_METHODS:
            yield f"{name}__solve{''.join(m).replace('--', '_')}", ["solve", str(rel), "--json", *m]
        text = scene.read_text()
        if "[trace]" in text:
            yield f"{name}__trace", ["trace", str(rel), "--json"]
        if "[[combinations]]" in text or "[moving]" in text:
            yield f"{name}__envelope", ["envelope", str(rel), "--json", "/dev/stdout"]


def run_one(liftoff, outdir, key, args):
    target = outdir / f"{key}.json"
    if target.exists():  # a run stopped half-way goes on where it was
        return key, json.loads(target.read_text())["rc"]
    try:
        p = subprocess.run([liftoff, *args], capture_output=True, text=True, timeout=300, cwd=ROOT)
        rc, stdout, stderr = p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired:
        rc, stdout, stderr = "timeout", "", "timed out after 300 s"
    try:
        out = json.loads(stdout) if stdout.strip() else None
    except json.JSONDecodeError:
        out = {"unparsed_stdout": stdout}
    target.write_text(json.dumps({"args": args, "rc": rc, "stdout": out, "stderr": stderr.strip()}, indent=1))
    return key, rc


def cmd_run(a):
    outdir = pathlib.Path(a.outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    todo = list(runs())
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        for key, rc in pool.map(lambda r: run_one(a.liftoff, outdir, *r), todo):
            pass
    print(f"{len(todo)} runs written to {outdir}")
    return 0


NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


def scales(obj, key="", acc=None):
    acc = {} if acc is None else acc
    if isinstance(obj, dict):
        for k, v in obj.items():
            scales(v, k, acc)
    elif isinstance(obj, list):
        for v in obj:
            scales(v, key, acc)
    elif isinstance(obj, (int, float)) and not isinstance(obj, bool) and math.isfinite(obj):
        acc[key] = max(acc.get(key, 0.0), abs(obj))
    return acc


def diff(a, b, path, key, scale, rtol, out):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if SKIP_KEY.search(k):
                continue
            if k not in a or k not in b:
                out.append((math.inf, f"{path}.{k}: only in {'new' if k not in a else 'old'}"))
                continue
            diff(a[k], b[k], f"{path}.{k}", k, scale, rtol, out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append((math.inf, f"{path}: length {len(a)} -> {len(b)}"))
            return
        for i, (x, y) in enumerate(zip(a, b)):
            diff(x, y, f"{path}[{i}]", key, scale, rtol, out)
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        if isinstance(a, int) and isinstance(b, int) and not re.search(r"iteration|evaluation|backtrack", key):
            if a != b:
                out.append((math.inf, f"{path}: {a} -> {b}"))
            return
        if not (math.isfinite(a) and math.isfinite(b)):
            if not (a == b or (math.isnan(a) and math.isnan(b))):
                out.append((math.inf, f"{path}: {a} -> {b}"))
            return
        ref = max(abs(a), abs(b), scale.get(key, 0.0))
        rel = abs(a - b) / ref if ref > 0 else 0.0
        if rel > rtol:
            out.append((rel, f"{path}: {a!r} -> {b!r} (relative {rel:.2g})"))
    elif isinstance(a, str) and isinstance(b, str):
        if NUMBER.sub("#", a) != NUMBER.sub("#", b):
            out.append((math.inf, f"{path}: text {a!r} -> {b!r}"))
    elif a != b:
        out.append((math.inf, f"{path}: {a!r} -> {b!r}"))


def cmd_compare(a):
    old, new = pathlib.Path(a.old), pathlib.Path(a.new)
    names = sorted({p.name for p in old.glob("*.json")} | {p.name for p in new.glob("*.json")})
    bad, worst = 0, 0.0
    for n in names:
        if not (old / n).exists() or not (new / n).exists():
            print(f"{n}: only in {'new' if not (old / n).exists() else 'old'}")
            bad += 1
            continue
        ra, rb = json.loads((old / n).read_text()), json.loads((new / n).read_text())
        out = []
        if ra["rc"] != rb["rc"]:
            out.append((math.inf, f"exit code {ra['rc']} -> {rb['rc']}"))
        diff(ra["stdout"], rb["stdout"], "", "", scales(ra["stdout"]), a.rtol, out)
        finite = [r for r, _ in out if math.isfinite(r)]
        if finite:
            worst = max(worst, max(finite))
        if out:
            bad += 1
            print(f"{n}: {len(out)} differences")
            for _, line in sorted(out, key=lambda t: -t[0])[: a.show]:
                print(f"    {line}")
    print(f"{len(names)} runs compared, {len(names) - bad} agree to rtol {a.rtol:g}, {bad} differ")
    return 0 if bad == 0 else 1


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run")
    r.add_argument("liftoff")
    r.add_argument("outdir")
    r.add_argument("--jobs", type=int, default=2)
    c = sub.add_parser("compare")
    c.add_argument("old")
    c.add_argument("new")
    c.add_argument("--rtol", type=float, default=1e-10)
    c.add_argument("--show", type=int, default=8)
    a = p.parse_args()
    return cmd_run(a) if a.command == "run" else cmd_compare(a)


if __name__ == "__main__":
    sys.exit(main())
