#!/usr/bin/env python3
"""Before/after comparison of `liftoff trace --json` outputs, one file per scene and path.

usage: compare_traces.py BEFORE_DIR AFTER_DIR [--suffix _ritz] [--tolerance 1e-10] [--time]

For every BEFORE_DIR/*<suffix>.json with a counterpart in AFTER_DIR, compares each path's
termination, final lambda, and events (kind, lambda, at) paired in order, and prints one table:
a line per scene ("same" when every figure agrees within the tolerance: lambda to `tolerance`
relative to max(1, |lambda|), positions to 1e-9 of max(1, |at|)), then a line per difference.
With --time, the paths' time_s before and after. Exit 0 always: the table is for a person
(every difference must be explained), not a gate. Files that did not parse (a crash, a refusal
without JSON) are reported with the first line of their .err beside them.
"""
import argparse
import glob
import json
import os
import sys


def load(path):
    try:
        with open(path) as f:
            return json.load(f), None
    except Exception as e:  # noqa: BLE001 - any unreadable output is reported, not raised
        err = path[:-5] + ".err"
        first = open(err).readline().strip() if os.path.exists(err) else ""
        return None, f"unreadable ({e.__class__.__name__}) {first[:120]}"


def close(a, b, tol):
    return abs(a - b) <= tol * max(1.0, abs(a), abs(b))


def compare_path(before, after, tol):
    """Differences between two paths, as lines."""
    lines = []
    if before["termination"] != after["termination"]:
        lines.append(f"termination {before['termination']} -> {after['termination']}")
    if not close(before["final_lambda"], after["final_lambda"], tol):
        lines.append(f"final lambda {before['final_lambda']:.12g} -> {after['final_lambda']:.12g} "
                     f"({after['final_lambda'] - before['final_lambda']:+.3e})")
    eb, ea = before["events"], after["events"]
    for i in range(max(len(eb), len(ea))):
        if i >= len(eb):
            e = ea[i]
            lines.append(f"event {i}: only after: {e['kind']} lambda {e['lambda']:.12g} at {e['at']:.9g}")
            continue
        if i >= len(ea):
            e = eb[i]
            lines.append(f"event {i}: only before: {e['kind']} lambda {e['lambda']:.12g} at {e['at']:.9g}")
            continue
        b, a = eb[i], ea[i]
        what = []
        if b["kind"] != a["kind"]:
            what.append(f"kind {b['kind']} -> {a['kind']}")
        if not close(b["lambda"], a["lambda"], tol):
            what.append(f"lambda {b['lambda']:.12g} -> {a['lambda']:.12g} ({a['lambda'] - b['lambda']:+.3e})")
        if not close(b["at"], a["at"], 1e-9):
            what.append(f"at {b['at']:.9g} -> {a['at']:.9g}")
        if what:
            lines.append(f"event {i} ({b['kind']}): " + "; ".join(what))
    return lines


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--suffix", default="", help="compare only files ending in SUFFIX.json")
    parser.add_argument("--tolerance", type=float, default=1e-10, help="relative, on lambda")
    parser.add_argument("--time", action="store_true", help="print the paths' times")
    args = parser.parse_args()

    files = sorted(glob.glob(os.path.join(args.before, f"*{args.suffix}.json")))
    width = max((len(os.path.basename(f)) - 5 for f in files), default=10)
    same = differ = 0
    for path in files:
        name = os.path.basename(path)[:-5]
        other = os.path.join(args.after, os.path.basename(path))
        if not os.path.exists(other):
            print(f"{name:<{width}}  missing after")
            differ += 1
            continue
        before, why_b = load(path)
        after, why_a = load(other)
        if before is None or after is None:
            print(f"{name:<{width}}  before: {why_b or 'ok'}; after: {why_a or 'ok'}")
            differ += 1
            continue
        lines, times = [], []
        by_name = {p["path"]: p for p in after["paths"]}
        for p in before["paths"]:
            q = by_name.get(p["path"])
            if q is None:
                lines.append(f"path {p['path']} missing after")
                continue
            lines += [f"{p['path']}: {line}" for line in compare_path(p, q, args.tolerance)]
            times.append(f"{p['path']} {p['time_s']:.3f} s -> {q['time_s']:.3f} s "
                         f"({len(p['steps'])} -> {len(q['steps'])} steps, {p['rejected_steps']} -> "
                         f"{q['rejected_steps']} rejected)")
        status = "same" if not lines else f"{len(lines)} difference(s)"
        same += not lines
        differ += bool(lines)
        print(f"{name:<{width}}  {status}" + (f"   [{'; '.join(times)}]" if args.time else ""))
        for line in lines:
            print(f"{'':<{width}}    {line}")
    print(f"{same} same, {differ} with differences")


if __name__ == "__main__":
    sys.exit(main())
