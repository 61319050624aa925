#!/usr/bin/python3
"""The load path's speed and the Ritz path's accuracy, measured through the command line (issue 37).

    /usr/bin/python3 verification/bench/trace_bench.py [--liftoff BIN] [--vs BIN2]
        [--sections scaling,fuzz,ritz] [--elements 64,128,256,512,1024] [--repeats N]
        [--timeout 300] [--quick] [--dry-run] [--scenes TEXT] [--out DIR]

Every figure is a whole `liftoff trace ... --json` or `liftoff solve ... --json` process, so that the
same command measures today's binary and a rewritten path engine, and can put two binaries side by
side (`--vs`: runs A, B, A, B, ... one after the other, medians side by side, B/A per row; on a
shared machine only ratios from one interleaved run mean anything). Sections:

  scaling  steps and time per step of the FE path against elements (64 to 1024) for the shallow
           arch (traced to lambda = 70; also at 200 elements, the issue's target row), the
           upheaval buckle and the footing; one `liftoff solve` of the same scene at the load
           where the trace ended (live loads scaled in a copy of the scene: `solve` applies every
           load once), and the ratio trace / solve; the Ritz path once per scene.
  fuzz     every trace scene of tests/fuzz/corpus/ and every shipped one, FE (`--method auto`) and
           Ritz paths, at most 64 elements: time, steps, termination; the largest time against
           the issue's "a few seconds".
  ritz     the shipped scenes where both paths run: each Ritz event against the FE path's event
           of the same kind and nearest load on three meshes, Richardson-extrapolated at the
           observed order; whether the Ritz path ended `completed` at lambda_max.

Then a "targets" block: each speed and accuracy target of issue 37 with the measured figure and
met / not met. verification/bench/README.md says how to read the tables. Not a test: the times
depend on the machine and its load (the load average is printed); steps, events and ratios of an
interleaved run are the figures to compare.
"""

import argparse
import collections
import csv
import glob
import json
import math
import os
import re
import resource
import shlex
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import tomllib
from dataclasses import dataclass, field

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

# The three scenes for steps against elements. The arch is traced to lambda = 70, the
# figure the issue quotes ("301 s to trace to lambda = 70" at 200 elements).
SCALING_SCENES = [
    ("shallow arch", "verification/scenes/von_karman/shallow_arch_snap_through.toml", 70.0),
    ("upheaval buckle", "continuation/scenes/pipeline_upheaval.toml", None),
    ("footing", "continuation/scenes/footing_trace.toml", None),
]
ARCH_TARGET_ELEMENTS = 200  # "the shallow arch at 200 elements at least 20x faster than today"
ARCH_TARGET_SPEEDUP = 20.0
EVENT_TOLERANCE = 1e-5  # "locates events within 1e-5 of the FE path's converged value" (relative)
FUZZ_MAX_ELEMENTS = 64  # "no fuzzed scene of 64 elements or fewer needs more than a few seconds"
FAST_RUN = 10.0  # s: a run shorter than this is repeated (median of three) when --repeats is not given
# The two 500 m pipelines have beta L = 100: 128 elements give beta h = 0.78, before the FE event
# loads converge at their order, so their Richardson meshes start at 256.
RITZ_FE_MESHES = {"pipeline_500m_uplift.toml": (256, 512, 1024), "pipeline_uplift.toml": (256, 512, 1024)}


# ---------------------------------------------------------------------------------------------
# Scenes: read with tomllib, written back (a temporary copy) by a small TOML emitter.

def read_scene(path):
    with open(path, "rb") as fh:
        return tomllib.load(fh)


def toml_key(key):
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else json.dumps(key)


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)  # the shortest text that reads back to the same double ('1e-05' is TOML)
    if isinstance(v, str):
        return json.dumps(v)  # JSON's escapes are those of a TOML basic string
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{toml_key(k)} = {toml_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(f"no TOML text for {type(v).__name__}")


def toml_text(doc):
    """The scene as TOML: top-level tables and arrays of tables, anything deeper inline."""
    lines = [f"{toml_key(k)} = {toml_value(v)}" for k, v in doc.items()
             if not isinstance(v, dict) and not is_table_array(v)]
    for key, value in doc.items():
        blocks = [value] if isinstance(value, dict) else value if is_table_array(value) else []
        header = f"[{toml_key(key)}]" if isinstance(value, dict) else f"[[{toml_key(key)}]]"
        for block in blocks:
            lines += ["", header] + [f"{toml_key(k)} = {toml_value(v)}" for k, v in block.items()]
    return "\n".join(lines) + "\n"


def is_table_array(v):
    return isinstance(v, list) and len(v) > 0 and all(isinstance(x, dict) for x in v)


def absolute_files(node, directory):
    """Keys naming a file (`gap_file`) made absolute: the copy lives elsewhere."""
    if isinstance(node, dict):
        for key, value in node.items():
            if key.endswith("_file") and isinstance(value, str):
                node[key] = os.path.normpath(os.path.join(directory, value))
            else:
                absolute_files(value, directory)
    elif isinstance(node, list):
        for item in node:
            absolute_files(item, directory)


def scene_copy(path, directory, name, lambda_max=None, live_factor=None):
    """A copy of the scene with [trace] lambda_max replaced and/or every live load times a factor
    (`solve` applies each load once whatever its case: F_dead + f F_live is the state at lambda = f)."""
    doc = read_scene(path)
    absolute_files(doc, os.path.dirname(os.path.abspath(path)))
    if lambda_max is not None:
        doc.setdefault("trace", {})["lambda_max"] = float(lambda_max)
    if live_factor is not None:
        for load in doc.get("loads", []):
            if load.get("case", "live") == "live":
                v = load["value"]
                load["value"] = [x * live_factor for x in v] if isinstance(v, list) else v * live_factor
    text = toml_text(doc)
    if tomllib.loads(text) != doc:  # the emitter's own check: the copy reads back as the scene
        raise RuntimeError(f"trace_bench: the copy of {path} does not read back as the scene")
    out = os.path.join(directory, name)
    with open(out, "w") as fh:
        fh.write(text)
    return out


def scene_elements(path):
    """The elements a shipped or corpus scene asks for: the corpus' `# args: ... --elements N`, else
    [solve] elements, else liftoff's default 200."""
    with open(path) as fh:
        for line in fh:
            m = re.match(r"#\s*args:.*--elements\s+(\d+)", line)
            if m:
                return int(m.group(1))
    return int(read_scene(path).get("solve", {}).get("elements", 200))


def reached(final_lambda, lambda_max):
    """The path ended at lambda_max to a path's own accuracy (the issue's Ritz path failed 1e-8 short)."""
    return final_lambda is not None and lambda_max is not None and \
        abs(final_lambda - lambda_max) <= 1e-6 * max(1.0, abs(lambda_max))


def trace_scenes(patterns):
    found = []
    for pattern in patterns:
        for path in sorted(glob.glob(os.path.join(ROOT, pattern), recursive=True)):
            if "trace" in read_scene(path) and path not in found:
                found.append(path)
    return found


def shipped_trace_scenes():
    return trace_scenes(["continuation/scenes/*.toml", "verification/scenes/**/*.toml"])


def fuzz_corpus_scenes():
    return trace_scenes(["tests/fuzz/corpus/*.toml"])


def rel(path):
    return os.path.relpath(path, ROOT)


# ---------------------------------------------------------------------------------------------
# Runs: one liftoff process, its wall and CPU time and its JSON.

@dataclass
class Run:
    wall: float = math.nan
    cpu: float = math.nan
    exit_code: int = -1
    timed_out: bool = False
    skipped: bool = False  # not run: a smaller mesh of the same scene already timed out
    doc: dict = None
    error: str = ""

    def path(self, kind=None):
        """The path object of the JSON (the first, or the one named `kind`)."""
        for p in (self.doc or {}).get("paths", []):
            if kind is None or p.get("path") == kind:
                return p
        return None

    @property
    def steps(self):
        p = self.path()
        return len(p["steps"]) if p and isinstance(p.get("steps"), list) else None

    @property
    def rejected(self):
        p = self.path()
        return p.get("rejected_steps") if p else None

    @property
    def events(self):
        p = self.path()
        return p.get("events", []) if p else (self.doc or {}).get("events", [])

    @property
    def termination(self):
        if self.skipped or self.timed_out:
            return "timeout"
        if self.doc is None:
            return f"exit {self.exit_code}"
        return self.doc.get("termination", "?")

    @property
    def final_lambda(self):
        return (self.doc or {}).get("final_lambda")

    @property
    def message(self):
        return (self.doc or {}).get("message", self.error)


def run_liftoff(binary, args, timeout):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    run = Run()
    try:
        r = subprocess.run([binary, *args], capture_output=True, text=True, timeout=timeout, cwd=ROOT)
        run.exit_code = r.returncode
        try:
            run.doc = json.loads(r.stdout) if r.stdout.strip() else None
        except json.JSONDecodeError:
            run.error = "no JSON on stdout"
        if run.doc is None:
            run.error = (r.stderr.strip().splitlines() or [run.error or "no output"])[-1][:300]
    except subprocess.TimeoutExpired:
        run.timed_out = True
    run.wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)  # subprocess.run waits for the killed child too
    run.cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    return run


@dataclass
class Measured:
    """One row's runs of one binary: the first run's JSON, the median times."""
    runs: list = field(default_factory=list)

    @property
    def first(self):
        return self.runs[0] if self.runs else Run(skipped=True)

    @property
    def complete(self):
        return bool(self.runs) and not any(r.timed_out or r.skipped for r in self.runs)

    @property
    def wall(self):
        return statistics.median(r.wall for r in self.runs) if self.complete else math.nan

    @property
    def cpu(self):
        return statistics.median(r.cpu for r in self.runs) if self.complete else math.nan

    @property
    def ms_per_step(self):
        steps = self.first.steps
        return 1e3 * self.wall / steps if steps else math.nan


class Bench:
    """Runs each command on every binary, interleaved (A, B, A, B, ...), skips a mesh once a
    smaller one of the same series timed out, and echoes progress on stderr."""

    def __init__(self, binaries, timeout, repeats, dry_run=False):
        self.binaries, self.timeout, self.repeats, self.dry_run = binaries, timeout, repeats, dry_run
        self.timed_out_series = set()  # (binary index, series name)
        self.commands = []  # for --dry-run

    def measure(self, args, series=None, repeats=None):
        """[Measured per binary]; `series` names a sequence of growing meshes (skip after a timeout)."""
        self.commands.append(args)
        out = [Measured() for _ in self.binaries]
        if self.dry_run:
            return out
        wanted = repeats if repeats is not None else self.repeats
        rounds = wanted or 1
        r = 0
        while r < rounds:
            for i, binary in enumerate(self.binaries):
                if out[i].runs and not out[i].complete:
                    continue  # timed out (or skipped) already: not again
                if series is not None and (i, series) in self.timed_out_series:
                    out[i].runs = [Run(skipped=True)]
                    continue
                print(f"  [{'AB'[i]}] liftoff {' '.join(args)}", file=sys.stderr, flush=True)
                run = run_liftoff(binary, args, self.timeout)
                out[i].runs.append(run)
                if run.timed_out and series is not None:
                    self.timed_out_series.add((i, series))
            if r == 0 and wanted is None and all(m.complete and m.wall < FAST_RUN for m in out):
                rounds = 3  # fast: the median of three
            r += 1
        return out


# ---------------------------------------------------------------------------------------------
# Tables: rows of raw values, printed aligned with units and written as CSV.

def fmt_time(m, timeout):
    if m.first.skipped:
        return f"> {timeout:g} s"
    if not m.complete:
        return f"> {timeout:g} s"
    return f"{m.wall:.3g}" if m.wall < 100 else f"{m.wall:.0f}"


def fmt(x, spec=".3g"):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    if spec == ".3g" and isinstance(x, float) and 1e3 <= abs(x) < 1e7:
        return f"{x:.0f}"  # 1080, not 1.08e+03
    return format(x, spec) if isinstance(x, (int, float)) else str(x)


def ratio(b, a):
    return b / a if a and b and math.isfinite(a) and math.isfinite(b) and a > 0 else math.nan


class Table:
    def __init__(self, name, title, columns):
        self.name, self.title, self.columns, self.rows, self.raw = name, title, columns, [], []

    def add(self, text_row, raw_row):
        self.rows.append([str(x) for x in text_row])
        self.raw.append(raw_row)

    def print(self):
        print(f"\n{self.title}")
        widths = [max([len(c)] + [len(r[i]) for r in self.rows]) for i, c in enumerate(self.columns)]
        print("  " + "  ".join(c.rjust(w) if i else c.ljust(w) for i, (c, w) in enumerate(zip(self.columns, widths))))
        for row in self.rows:
            print("  " + "  ".join(x.rjust(w) if i else x.ljust(w) for i, (x, w) in enumerate(zip(row, widths))))

    def write_csv(self, directory):
        if not directory or not self.raw:
            return
        os.makedirs(directory, exist_ok=True)
        keys = list(dict.fromkeys(k for row in self.raw for k in row))
        with open(os.path.join(directory, f"{self.name}.csv"), "w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=keys)
            writer.writeheader()
            writer.writerows(self.raw)


def merged(values):
    """One text for every binary's value: the value where they agree, else 'a / b'."""
    return values[0] if len(set(values)) == 1 else " / ".join(values)


def per_binary(labels, *names):
    """Column headers, one per binary for each name: 'time (s)' -> 'time A (s)', 'time B (s)'."""
    cols = []
    for name in names:
        unit = re.search(r"\s*\(.*\)$", name)
        base, suffix = (name[:unit.start()], unit.group(0)) if unit else (name, "")
        cols += [f"{base} {label}{suffix}" if len(labels) > 1 else name for label in labels]
    return cols


# ---------------------------------------------------------------------------------------------
# Section 1: steps and time per step against elements, trace against solve.

def scaling_section(bench, opts, tmp, results):
    labels = bench_labels(bench)
    vs = len(labels) > 1
    cols = ["scene", "elements", "path"] + per_binary(labels, "trace (s)") + (["B/A"] if vs else []) \
        + per_binary(labels, "cpu (s)") + (["B/A cpu"] if vs else []) \
        + ["steps", "rejected", "events"] + per_binary(labels, "ms/step") + ["termination", "solve (s)"] \
        + per_binary(labels, "trace/solve") + ["solve at lambda"]
    table = Table("scaling", "1. steps and time per step against elements (FE path; Ritz path once per scene)", cols)
    scenes = SCALING_SCENES[:1] if opts.quick else SCALING_SCENES
    for label, path, lambda_max in filter_scenes(scenes, opts.scenes):
        scene = os.path.join(ROOT, path)
        if lambda_max is not None:
            scene = scene_copy(scene, tmp, f"scaling_{os.path.basename(path)}", lambda_max=lambda_max)
        meshes = sorted(set(opts.elements + ([ARCH_TARGET_ELEMENTS] if path == SCALING_SCENES[0][1]
                                              and not opts.quick else [])))
        for n in meshes:
            trace = bench.measure(["trace", scene, "--elements", str(n), "--json"], series=label)
            solve, solve_lambda = solve_at_end(bench, scene, n, trace, tmp, label)
            add_scaling_row(table, label, n, "fe", trace, solve, opts, vs, solve_lambda)
            results.setdefault("scaling", []).append((label, n, "fe", trace, solve))
        ritz = bench.measure(["trace", scene, "--method", "ritz", "--json"])
        add_scaling_row(table, label, "-", "ritz", ritz, None, opts, vs)
        results.setdefault("scaling", []).append((label, None, "ritz", ritz, None))
    return table


def solve_at_end(bench, scene, n, trace, tmp, label):
    """One `liftoff solve` of the scene where the trace ended (A's end, else B's), the live loads of a
    copy times that lambda. Where that solve is refused (beyond a snap-through a solve from zero
    stops at the limit point, exit 5), at half the first limit point's lambda instead: a state of
    the first branch, away from the fold where a solve's own load steps shorten (the arch at 0.95
    of its snap-through load: 13 solves on 256 elements, 4 s). (solve, lambda) or (None, None)."""
    if bench.dry_run:
        return bench.measure(["solve", "<the scene, live loads x the trace's final lambda>", "--elements", str(n),
                              "--json"]), None
    firsts = [m.first for m in trace if m.first.final_lambda is not None]
    if not firsts:
        return None, None
    lam = firsts[0].final_lambda
    solve = solve_at(bench, scene, n, lam, tmp, label)
    folds = [e["lambda"] for e in firsts[0].events if e["kind"] == "limit_point"]
    if solve[0].first.exit_code != 0 and folds:
        lam = 0.5 * folds[0]
        solve = solve_at(bench, scene, n, lam, tmp, label)
    return solve, lam


def solve_at(bench, scene, n, lam, tmp, label):
    copy = scene_copy(scene, tmp, f"solve_{n}_{lam:.6g}_{os.path.basename(scene)}", live_factor=lam)
    return bench.measure(["solve", copy, "--elements", str(n), "--json"], series=f"{label} solve")


def add_scaling_row(table, label, n, path, trace, solve, opts, vs, solve_lambda=None):
    t, c = [m.wall for m in trace], [m.cpu for m in trace]
    solve = solve or [None] * len(trace)
    solve_t = [s.wall if s else math.nan for s in solve]
    text = [label, n, path] + [fmt_time(m, opts.timeout) for m in trace] + ([fmt(ratio(t[1], t[0]))] if vs else []) \
        + [fmt(x) for x in c] + ([fmt(ratio(c[1], c[0]))] if vs else []) \
        + [merged([fmt(m.first.steps, "d") for m in trace]), merged([fmt(m.first.rejected, "d") for m in trace]),
           merged([fmt(len(m.first.events) if m.first.doc else None, "d") for m in trace])] \
        + [fmt(m.ms_per_step) for m in trace] + [merged([m.first.termination for m in trace]),
                                                 merged([solve_text(s) for s in solve])] \
        + [fmt(ratio(a, b)) for a, b in zip(t, solve_t)] + [fmt(solve_lambda, ".6g")]
    raw = {"scene": label, "elements": n, "path": path, "solve_lambda": solve_lambda}
    for i, (m, s) in enumerate(zip(trace, solve)):
        raw.update({f"trace_s_{'AB'[i]}": m.wall, f"cpu_s_{'AB'[i]}": m.cpu, f"steps_{'AB'[i]}": m.first.steps,
                    f"rejected_{'AB'[i]}": m.first.rejected, f"events_{'AB'[i]}": len(m.first.events),
                    f"ms_per_step_{'AB'[i]}": m.ms_per_step, f"termination_{'AB'[i]}": m.first.termination,
                    f"final_lambda_{'AB'[i]}": m.first.final_lambda, f"message_{'AB'[i]}": m.first.message,
                    f"solve_s_{'AB'[i]}": s.wall if s else None,
                    f"solve_termination_{'AB'[i]}": s.first.termination if s else None})
    table.add(text, raw)


def solve_text(m):
    if m is None:
        return "-"
    if not m.complete:
        return "timeout"
    t = fmt(m.wall)
    return t if m.first.exit_code == 0 else f"{t} (exit {m.first.exit_code})"


# ---------------------------------------------------------------------------------------------
# Section 2: the fuzz corpus' and the shipped trace scenes, both paths, at most 64 elements.

def fuzz_section(bench, opts, tmp, results):
    labels = bench_labels(bench)
    vs = len(labels) > 1
    cols = ["scene", "path", "elements"] + per_binary(labels, "time (s)") + (["B/A"] if vs else []) \
        + ["steps", "rejected", "termination", "final lambda"]
    table = Table("fuzz", f"2. fuzzed and shipped trace scenes, every path, at most {FUZZ_MAX_ELEMENTS} elements",
                  cols)
    scenes = [(rel(s), s, [], scene_elements(s)) for s in fuzz_corpus_scenes()[:1 if opts.quick else None]]
    if not opts.quick:
        scenes += generated_fuzz_scenes(opts, tmp)
        scenes += [(rel(s), s, [], scene_elements(s)) for s in shipped_trace_scenes()]
    for name, scene, extra, elements in [s for s in scenes if not opts.scenes or opts.scenes in s[0]]:
        n = min(elements, FUZZ_MAX_ELEMENTS)
        for method, path in (("auto", "fe"), ("ritz", "ritz")):
            runs = bench.measure(["trace", scene, "--method", method, "--elements", str(n), *extra, "--json"])
            t = [m.wall for m in runs]
            text = [name, path, n] + [fmt_time(m, opts.timeout) for m in runs]
            if vs:
                text.append(fmt(ratio(t[1], t[0])))
            text += [merged([fmt(m.first.steps, "d") for m in runs]),
                     merged([fmt(m.first.rejected, "d") for m in runs]), merged([m.first.termination for m in runs]),
                     merged([fmt(m.first.final_lambda, ".10g") for m in runs])]
            raw = {"scene": name, "path": path, "elements": n, "options": " ".join(extra)}
            for i, m in enumerate(runs):
                raw.update({f"time_s_{'AB'[i]}": m.wall, f"steps_{'AB'[i]}": m.first.steps,
                            f"rejected_{'AB'[i]}": m.first.rejected, f"termination_{'AB'[i]}": m.first.termination,
                            f"final_lambda_{'AB'[i]}": m.first.final_lambda, f"message_{'AB'[i]}": m.first.message})
            table.add(text, raw)
            results.setdefault("fuzz", []).append((name, path, n, runs, read_scene(scene)["trace"].get("lambda_max")))
    return table


def generated_fuzz_scenes(opts, tmp):
    """The scene fuzzer's trace campaign ("fuzz: valid scenes, trace" of tests/fuzz/scene_fuzz_test.cpp,
    seed --fuzz-seed): its scenes, written by the test binary under LIFTOFF_FUZZ_WRITE without running
    them, each with the campaign's --modes and --elements (else the scene's). [(name, scene, extra
    args, elements)]; none, with a note, where that binary is missing or predates LIFTOFF_FUZZ_WRITE."""
    if opts.fuzz_cases <= 0:
        return []
    binary = opts.fuzz_test
    with open(binary, "rb") if os.path.isfile(binary) else open(os.devnull, "rb") as fh:
        if b"LIFTOFF_FUZZ_WRITE" not in fh.read():
            print(f"trace_bench: no generated fuzz scenes: {binary} is missing or cannot write its cases "
                  "(build the target scene_fuzz_test of this tree, or give --fuzz-test)", file=sys.stderr)
            opts.notes.append(f"generated fuzz scenes not run: no {binary} with LIFTOFF_FUZZ_WRITE")
            return []
    where = os.path.join(opts.out, "fuzz_scenes") if opts.out else os.path.join(tmp, "fuzz_scenes")
    env = dict(os.environ, LIFTOFF_FUZZ_WRITE=where, LIFTOFF_FUZZ_SCALE=repr(opts.fuzz_cases / 40.0),
               LIFTOFF_FUZZ_SEED=str(opts.fuzz_seed))
    subprocess.run([binary, "fuzz: valid scenes\\, trace"], env=env, capture_output=True, check=True, timeout=120)
    found = []
    for case in sorted(glob.glob(os.path.join(where, "trace-*")), key=lambda d: int(d.rsplit("-", 1)[1])):
        with open(os.path.join(case, "command.txt")) as fh:
            args = shlex.split(fh.readline())
        option = {a: args[i + 1] for i, a in enumerate(args[:-1]) if a in ("--modes", "--elements")}
        scene = os.path.join(case, "scene.toml")
        found.append((f"fuzz {os.path.basename(case)}", scene, ["--modes", option["--modes"]] if "--modes" in option
                      else [], int(option["--elements"]) if "--elements" in option else scene_elements(scene)))
    return found


# ---------------------------------------------------------------------------------------------
# Section 3: Ritz events against the FE path's converged ones.

def richardson(values, ratio_h=2.0):
    """(converged, order, error estimate) from an event's loads on meshes refined by ratio_h, the
    finest last. Three: extrapolated at the observed order; without a monotone sequence (no order)
    the finest, with the larger change as its estimate. Two (a finer mesh timed out): the finest,
    with the change as its estimate (an order of at least one keeps the finest's error below it on
    a ratio of 2). One: no estimate."""
    if len(values) < 3:
        return values[-1], math.nan, abs(values[-1] - values[0]) if len(values) == 2 else math.nan
    a, b, c = values[-3:]
    d1, d2 = b - a, c - b
    if d2 == 0.0:
        return c, math.inf, 0.0
    q = d1 / d2
    if q <= 1.0:
        return c, math.nan, max(abs(d1), abs(d2))
    p = math.log(q) / math.log(ratio_h)
    extrapolated = c + d2 / (ratio_h ** p - 1.0)
    return extrapolated, p, abs(extrapolated - c)


def closest(events, kind, lam, at, taken=()):
    """The index of the event of `kind` nearest in lambda, among as near ones (a symmetric pair:
    within 1e-9) the nearest in position; one not `taken` while another is left; None if none."""
    same = [j for j, f in enumerate(events) if f["kind"] == kind]
    free = [j for j in same if j not in taken] or same
    if not free:
        return None
    best = min(abs(events[j]["lambda"] - lam) for j in free)
    near = [j for j in free if abs(events[j]["lambda"] - lam) <= best + 1e-9 * max(1.0, abs(lam))]
    return min(near, key=lambda j: abs(events[j]["at"] - at))


def match_events(ritz_events, fe_runs):
    """[(Ritz event, [FE event per mesh])]: each Ritz event with the FE event of its kind nearest in
    lambda (then in position) on the finest mesh, one to one, and on each coarser mesh the event
    nearest to that one; the finest mesh's events that no Ritz event took, with Ritz None."""
    finest = fe_runs[-1].events
    pairs, taken = [], set()
    for e in ritz_events:
        j = closest(finest, e["kind"], e["lambda"], e["at"], taken)
        if j is None:
            pairs.append((e, None))
            continue
        taken.add(j)
        pairs.append((e, fe_chain(fe_runs, finest[j])))
    pairs += [(None, fe_chain(fe_runs, f)) for j, f in enumerate(finest) if j not in taken]
    return pairs


def fe_chain(fe_runs, event):
    chain = []
    for run in fe_runs:
        k = closest(run.events, event["kind"], event["lambda"], event["at"])
        chain.append(None if k is None else run.events[k])
    return chain


def ritz_section(bench, opts, results):
    labels = bench_labels(bench)
    ends = Table("ritz_ends", "3a. how the Ritz path ends (completed at lambda_max, or why not)",
                 ["scene", "binary", "termination", "final lambda", "lambda_max", "steps", "rejected", "time (s)",
                  "completed at lambda_max", "message"])
    events = Table("ritz_events", f"3b. Ritz events against the FE path's converged ones (relative difference "
                   f"against {EVENT_TOLERANCE:g})",
                   ["scene", "binary", "event", "at", "lambda ritz", "FE meshes", "lambda FE (finest)",
                    "order", "FE converged", "FE est (rel)", "|ritz - FE| (rel)", "within 1e-5"])
    scenes = shipped_trace_scenes()
    if opts.quick:
        scenes = [os.path.join(ROOT, "continuation/scenes/footing_trace.toml")]
    for scene in [s for s in scenes if not opts.scenes or opts.scenes in rel(s)]:
        meshes = opts.ritz_meshes or (RITZ_FE_MESHES.get(os.path.basename(scene), (128, 256, 512))
                                      if not opts.quick else (32, 64, 128))
        ritz = bench.measure(["trace", scene, "--method", "ritz", "--json"])
        fe = [bench.measure(["trace", scene, "--method", "auto", "--elements", str(n), "--json"],
                            series=f"ritz-fe {scene}") for n in meshes]
        for i, label in enumerate(labels):
            add_ritz_end(ends, scene, label, ritz[i], opts, results)
            done = [(n, m[i].first) for n, m in zip(meshes, fe) if m[i].first.doc is not None]
            if ritz[i].first.doc is None or not done:
                continue
            names = "x".join(str(n) for n, _ in done) + "".join(
                f" ({n}: {m[i].first.termination})" for n, m in zip(meshes, fe) if m[i].first.doc is None)
            for e, chain in match_events(ritz[i].first.events, [run for _, run in done]):
                add_event_row(events, scene, label, e, chain, [n for n, _ in done], names, results)
    return [ends, events]


def add_ritz_end(table, scene, label, m, opts, results):
    lambda_max = read_scene(scene)["trace"].get("lambda_max")
    run = m.first
    at_max = reached(run.final_lambda, lambda_max)
    verdict = "yes" if at_max and run.termination == "completed" else \
        "NO: reached, not completed" if at_max else "no (stopped earlier)"
    if run.termination == "completed" and not at_max:
        verdict = "completed earlier (max_amplitude)" if "amplitude" in (run.message or "") else "completed earlier"
    short = (run.message or "").replace("\n", " ")
    table.add([rel(scene), label, run.termination, fmt(run.final_lambda, ".10g"), fmt(lambda_max, "g"),
               fmt(run.steps, "d"), fmt(run.rejected, "d"), fmt_time(m, opts.timeout), verdict,
               short[:70] + ("..." if len(short) > 70 else "")],
              {"scene": rel(scene), "binary": label, "termination": run.termination, "final_lambda": run.final_lambda,
               "lambda_max": lambda_max, "steps": run.steps, "rejected": run.rejected, "time_s": m.wall,
               "verdict": verdict, "message": run.message})
    results.setdefault("ritz_ends", []).append((rel(scene), label, run, at_max, m))


def add_event_row(table, scene, label, e, chain, meshes, names, results):
    """One event: the Ritz load against the FE loads of the finest meshes that have the event
    (a coarse mesh may miss it), extrapolated."""
    while chain and any(c is None for c in chain):  # the finest meshes that have it
        chain, meshes = chain[1:], meshes[1:]
    if not chain:
        table.add([rel(scene), label, e["kind"], fmt(e["at"], ".6g"), fmt(e["lambda"], ".10g"), names,
                   "no FE event of this kind", "-", "-", "-", "-", "no match"],
                  {"scene": rel(scene), "binary": label, "kind": e["kind"], "at": e["at"], "lambda_ritz": e["lambda"],
                   "verdict": "no match"})
        results.setdefault("ritz_events", []).append((rel(scene), label, e, None))
        return
    values = [c["lambda"] for c in chain]
    converged, order, estimate = richardson(values, meshes[1] / meshes[0] if len(meshes) > 1 else 2.0)
    scale = max(abs(converged), 1e-300)
    est = estimate / scale
    kind, at = (e or chain[-1])["kind"], (e or chain[-1])["at"]
    if e is None:
        diff, verdict = math.nan, "Ritz has none"
    else:
        diff = abs(e["lambda"] - converged) / scale
        verdict = "met" if diff + est <= EVENT_TOLERANCE else \
            "not met" if diff - est > EVENT_TOLERANCE else "undecided (FE est)"
    used = "x".join(map(str, meshes))
    table.add([rel(scene), label, kind, fmt(at, ".6g"), fmt(e["lambda"] if e else None, ".10g"),
               names if used in names else f"{used} of {names}", fmt(values[-1], ".10g"), fmt(order, ".2f"),
               fmt(converged, ".10g"), fmt(est, ".2e"), fmt(diff, ".2e"), verdict],
              {"scene": rel(scene), "binary": label, "kind": kind, "at": at, "lambda_ritz": e["lambda"] if e else None,
               "meshes": used, **{f"lambda_fe_{n}": v for n, v in zip(meshes, values)}, "order": order,
               "lambda_fe_converged": converged, "fe_estimate_rel": est, "difference_rel": diff, "verdict": verdict})
    results.setdefault("ritz_events", []).append((rel(scene), label, e, (diff, est, verdict)))


# ---------------------------------------------------------------------------------------------
# Targets.

def targets_block(bench, opts, results):
    labels = bench_labels(bench)
    print("\ntargets (issue 37, item 4)")
    lines = []
    arch = [r for r in results.get("scaling", []) if r[0] == SCALING_SCENES[0][0] and r[1] == ARCH_TARGET_ELEMENTS]
    if not arch:
        lines.append((f"shallow arch at {ARCH_TARGET_ELEMENTS} elements >= {ARCH_TARGET_SPEEDUP:g}x faster than today",
                      "not measured (section scaling with the arch, without --quick)", "-"))
    else:
        trace = arch[0][3]
        times = ", ".join(f"{label} {fmt_time(m, opts.timeout)} s (cpu {fmt(m.cpu)} s), {fmt(m.first.steps, 'd')} steps"
                          for label, m in zip(labels, trace))
        if len(trace) > 1:
            wall, cpu = ratio(trace[1].wall, trace[0].wall), ratio(trace[1].cpu, trace[0].cpu)
            verdict = {(True, True): "met", (True, False): "met (wall only)", (False, True): "met (cpu only)",
                       (False, False): "not met"}[(wall >= ARCH_TARGET_SPEEDUP, cpu >= ARCH_TARGET_SPEEDUP)]
            lines.append((f"shallow arch (lambda 70) at {ARCH_TARGET_ELEMENTS} elements >= {ARCH_TARGET_SPEEDUP:g}x "
                          "faster than today (B = today)", f"{times}; B/A = {fmt(wall)} (cpu {fmt(cpu)})", verdict))
        else:
            lines.append((f"shallow arch (lambda 70) at {ARCH_TARGET_ELEMENTS} elements >= {ARCH_TARGET_SPEEDUP:g}x "
                          "faster than today", f"{times} (give --vs TODAY for the ratio)", "-"))
    fuzz = results.get("fuzz", [])
    for i, label in enumerate(labels):
        for kind, rows in (("fuzzed", [r for r in fuzz if is_fuzzed(r[0])]),
                           ("shipped", [r for r in fuzz if not is_fuzzed(r[0])])):
            if not rows:
                continue
            worst = max(rows, key=lambda r: r[3][i].wall if r[3][i].complete else math.inf)
            m = worst[3][i]
            t = m.wall if m.complete else math.inf
            name = (f"no fuzzed scene (<= {FUZZ_MAX_ELEMENTS} elements) over {opts.few_seconds:g} s, any path"
                    if kind == "fuzzed" else f"[info] shipped scenes at <= {FUZZ_MAX_ELEMENTS} elements, any path")
            verdict = ("met" if t <= opts.few_seconds else "not met") if kind == "fuzzed" else "-"
            lines.append((f"{name} [{label}]", f"{len(rows)} runs, largest {fmt_time(m, opts.timeout)} s: "
                          f"{worst[0]} {worst[1]}", verdict))
    if not any(is_fuzzed(r[0]) for r in fuzz):
        lines.append((f"no fuzzed scene (<= {FUZZ_MAX_ELEMENTS} elements) over a few seconds, any path",
                      "not measured (section fuzz)", "-"))
    ends = results.get("ritz_ends", []) + ritz_ends_of_fuzz(results, labels)
    for label in labels:
        mine = [r for r in ends if r[1] == label]
        if not mine:
            continue
        bad = [r for r in mine if r[3] and r[2].termination != "completed"]
        short = collections.Counter(r[2].termination for r in mine if not r[3] and r[2].termination != "completed")
        refused = short.pop("bad_input", 0)
        lines.append((f"Ritz path ends `completed` when it reaches lambda_max [{label}]",
                      f"{len(mine)} Ritz runs: {len(bad)} reached lambda_max without `completed`"
                      + (f" ({', '.join(r[0] for r in bad)})" if bad else "")
                      + f"; {sum(short.values())} stopped short"
                      + "".join(f", {n} {t}" for t, n in sorted(short.items())) + f"; {refused} refused the scene",
                      "met" if not bad else "not met"))
    events = results.get("ritz_events", [])
    for label in labels:
        mine = [r for r in events if r[1] == label and r[2] is not None and r[3] is not None]
        if not mine:
            continue
        worst = max(mine, key=lambda r: r[3][0] if math.isfinite(r[3][0]) else -1)
        counts = {v: sum(1 for r in mine if r[3][2] == v) for v in ("met", "not met", "undecided (FE est)")}
        unmatched = sum(1 for r in events if r[1] == label and (r[3] is None or r[2] is None))
        lines.append((f"Ritz events within {EVENT_TOLERANCE:g} (relative) of the FE converged value [{label}]",
                      f"{len(mine)} events: {counts['met']} met, {counts['not met']} not, "
                      f"{counts['undecided (FE est)']} undecided; largest {fmt(worst[3][0], '.2e')} "
                      f"({worst[0]} {worst[2]['kind']}); {unmatched} unmatched",
                      "met" if counts["not met"] == 0 and counts["undecided (FE est)"] == 0 and not unmatched
                      else "not met" if counts["not met"] else "undecided"))
    informational_lines(lines, results, labels)
    width = max(len(a) for a, _, _ in lines)
    for a, b, c in lines:
        print(f"  {a.ljust(width)}  {c:9}  {b}")
    for note in opts.notes:
        print(f"  note: {note}")


def is_fuzzed(name):
    return name.startswith("tests/fuzz/") or name.startswith("fuzz ")


def ritz_ends_of_fuzz(results, labels):
    """Section 2's Ritz runs in section 3's form: (scene, label, run, reached lambda_max, measured)."""
    return [(scene, label, m.first, reached(m.first.final_lambda, lambda_max), m)
            for scene, path, _, runs, lambda_max in results.get("fuzz", []) if path == "ritz"
            for label, m in zip(labels, runs)]


def informational_lines(lines, results, labels):
    """Not targets with a number in the issue, but what it asks to see: trace / solve, steps
    against the mesh."""
    rows = [r for r in results.get("scaling", []) if r[2] == "fe" and r[4]]
    for label_i, label in enumerate(labels):
        for scene in dict.fromkeys(r[0] for r in rows):
            mine = [r for r in rows if r[0] == scene and r[3][label_i].complete]
            if len(mine) < 2:
                continue
            lo, hi = mine[0], mine[-1]
            s = [r[3][label_i].first.steps for r in (lo, hi)]
            solve_ratio = ", ".join(f"{r[1]}: {fmt(ratio(r[3][label_i].wall, r[4][label_i].wall), '.3g')}"
                                    for r in mine)
            lines.append((f"[info] {scene}: steps {lo[1]} -> {hi[1]} elements [{label}]",
                          f"{s[0]} -> {s[1]} steps; trace / solve {solve_ratio}", "-"))


# ---------------------------------------------------------------------------------------------

def bench_labels(bench):
    return ["A", "B"][:len(bench.binaries)]


def filter_scenes(scenes, text):
    return [s for s in scenes if not text or text in s[1] or text in s[0]]


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=__doc__.split("\n\n", 1)[1])
    p.add_argument("--liftoff", default=os.path.join(ROOT, "build", "src", "liftoff"),
                   help="binary A (default build/src/liftoff)")
    p.add_argument("--vs", help="binary B, run interleaved with A (e.g. today's main); B/A per row")
    p.add_argument("--sections", default="scaling,fuzz,ritz", help="any of scaling,fuzz,ritz")
    p.add_argument("--elements", default="64,128,256,512,1024", help="section scaling's meshes")
    p.add_argument("--ritz-elements", help="section ritz's three FE meshes, e.g. 128,256,512 (default per scene)")
    p.add_argument("--repeats", type=int, help="runs per row (default: 3 when a run takes under 10 s, else 1)")
    p.add_argument("--timeout", type=float, default=300.0, help="seconds per run (default 300)")
    p.add_argument("--few-seconds", type=float, default=5.0, help="the fuzz target's 'a few seconds' (default 5)")
    p.add_argument("--fuzz-cases", type=int, default=40,
                   help="scenes of the fuzzer's trace campaign in section fuzz (default 40, its own count; 0: none)")
    p.add_argument("--fuzz-seed", type=int, default=20240610, help="the fuzzer's seed (default its own, 20240610)")
    p.add_argument("--fuzz-test",
                   help="the scene_fuzz_test binary that writes them (default build/tests/scene_fuzz_test)")
    p.add_argument("--scenes", help="only scenes whose path (or label) contains this text")
    p.add_argument("--quick", action="store_true", help="64 and 128 elements, one scene per section (about a minute)")
    p.add_argument("--dry-run", action="store_true", help="read the scenes and print the commands, run nothing")
    p.add_argument("--out", help="write each table as DIR/<table>.csv")
    opts = p.parse_args(argv)
    opts.sections = [s.strip() for s in opts.sections.split(",") if s.strip()]
    unknown = set(opts.sections) - {"scaling", "fuzz", "ritz"}
    if unknown:
        p.error(f"--sections: unknown {', '.join(sorted(unknown))} (expected scaling, fuzz, ritz)")
    opts.elements = [64, 128] if opts.quick else [int(x) for x in opts.elements.split(",")]
    opts.ritz_meshes = tuple(int(x) for x in opts.ritz_elements.split(",")) if opts.ritz_elements else None
    if opts.ritz_meshes and (len(opts.ritz_meshes) != 3 or opts.ritz_meshes[1] * opts.ritz_meshes[1]
                             != opts.ritz_meshes[0] * opts.ritz_meshes[2]):
        p.error("--ritz-elements: three meshes refined by one ratio (e.g. 128,256,512)")
    opts.fuzz_test = opts.fuzz_test or os.path.join(ROOT, "build", "tests", "scene_fuzz_test")
    opts.notes = []
    if opts.quick and opts.repeats is None:
        opts.repeats = 1
    for b in [opts.liftoff] + ([opts.vs] if opts.vs else []):
        if not opts.dry_run and not (os.path.isfile(b) and os.access(b, os.X_OK)):
            p.error(f"no executable {b}")
    return opts


def header(opts, binaries):
    print("trace_bench: liftoff trace / solve through the command line (issue 37)")
    for label, b in zip("AB", binaries):
        print(f"  {label} = {os.path.abspath(b)}")
    load = os.getloadavg()
    print(f"  load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f} on {os.cpu_count()} cores; "
          f"timeout {opts.timeout:g} s per run; repeats {opts.repeats or 'auto (3 under 10 s, else 1)'}; "
          "times are wall-clock medians (s)")
    if len(binaries) > 1:
        print("  runs interleaved A, B, A, B ...; B/A > 1: A is faster")


def main(argv=None):
    opts = parse_args(argv if argv is not None else sys.argv[1:])
    binaries = [opts.liftoff] + ([opts.vs] if opts.vs else [])
    bench = Bench(binaries, opts.timeout, opts.repeats, dry_run=opts.dry_run)
    header(opts, binaries)
    results, tables = {}, []
    tmp = tempfile.mkdtemp(prefix="trace_bench_")
    try:
        if "scaling" in opts.sections:
            tables.append(scaling_section(bench, opts, tmp, results))
        if "fuzz" in opts.sections:
            tables.append(fuzz_section(bench, opts, tmp, results))
        if "ritz" in opts.sections:
            tables += ritz_section(bench, opts, results)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if opts.dry_run:
        print(f"\nplan: {len(bench.commands)} commands per binary")
        for args in bench.commands:
            print("  liftoff " + " ".join(rel(a) if os.path.isabs(a) and a.startswith(ROOT) else a for a in args))
        return 0
    for table in tables:
        table.print()
        table.write_csv(opts.out)
    targets_block(bench, opts, results)
    if opts.out:
        print(f"\ntables written to {opts.out}/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
