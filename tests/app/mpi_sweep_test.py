#!/usr/bin/python3
"""`mpirun -np N liftoff sweep` gives the single-process sweep's files (app/distributed_sweep.hpp).

A shipped scene (the B70 sleeper) swept over its uniform load and ballast modulus, where the uplift
of -1e6 N/m has no equilibrium (those cases fail on purpose, exit 3), once with `--method all` (a
refused method and every failure per case) and once with `--method ritz` (the failed case is an
error). The serial sweep (no mpirun) is the reference; the
distributed one on 1, 2 and 3 ranks (and 2 ranks of 2 threads; oversubscribed: more ranks than cores, so the cases really
interleave) must give:
- the same HDF5 content, bitwise: every group, dataset (dtype, shape, values) and attribute, except
  /cases/*/*/solver's time_s (wall-clock time). Bitwise, not to round-off: each case is solved by
  the same code on the same input in one thread either way, so any difference is a bug of the
  distribution (a case in the wrong place, a field lost), not arithmetic;
- the same CSV except its time_s column, the same exit code and the same stderr lines (the failed
  cases' summary line), printed once;
- a bad scene: the usual one-line message once, exit 2 from every rank, no output file.
"""

import argparse
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "support"))
from checks import check, finish  # noqa: E402


def mpirun(ranks):
    # CI runs as root, which Open MPI refuses without --allow-run-as-root.
    root = ["--allow-run-as-root"] if os.geteuid() == 0 else []
    return ["mpirun", *root, "--oversubscribe", "-np", str(ranks)]


def run(command):
    return subprocess.run(command, capture_output=True, text=True, timeout=900)


def walk(f):
    """Every object and attribute of an HDF5 file: {path: value}, wall-clock times left out."""
    items = {}

    def attributes(path, obj):
        for name, value in obj.attrs.items():
            if name != "time_s":
                items[f"{path}@{name}"] = value

    def visit(path, obj):
        attributes(path, obj)
        items[path] = obj[()] if isinstance(obj, h5py.Dataset) else "group"

    attributes("/", f)
    f.visititems(visit)
    return items


def same(a, b):
    if isinstance(a, (bytes, str)) or isinstance(b, (bytes, str)):
        return type(a) is type(b) and a == b
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b, equal_nan=a.dtype.kind == "f")


def csv_without_time(path):
    with open(path) as f:
        rows = [line.rstrip("\n").split(",") for line in f]
    column = rows[0].index("time_s")
    return [row[:column] + row[column + 1:] for row in rows]


def stderr_lines(text):
    return [line for line in text.replace("\r", "\n").splitlines() if line.startswith("liftoff: ")]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--liftoff", required=True)
    parser.add_argument("--scene", required=True)
    args = parser.parse_args()
    sweeps = {
        "auto": ["--set", "loads[0].value=-1e6,1056,5e4", "--set", "foundation.modulus=log:1e7:1e8:3"],
        "all": ["--set", "loads[0].value=-1e6,1056", "--method", "all"],
        # Ritz stops the uplift case with an error (its FE start has no equilibrium): the case's
        # `error` attribute and CSV row.
        "ritz": ["--set", "loads[0].value=-1e6,1056", "--method", "ritz"],
    }
    with tempfile.TemporaryDirectory() as tmp:
        for name, options in sweeps.items():
            def sweep(launcher, tag, extra=()):
                h5, csv = os.path.join(tmp, f"{name}_{tag}.h5"), os.path.join(tmp, f"{name}_{tag}.csv")
                r = run([*launcher, args.liftoff, "sweep", args.scene, *options, *extra, "--output", h5, "--csv", csv])
                return r, h5, csv

            serial, serial_h5, serial_csv = sweep([], "serial")
            check(serial.returncode == 3, f"{name}: serial sweep exits 3 (a case fails on purpose; got "
                                          f"{serial.returncode}: {serial.stderr.strip()[-300:]})")
            if serial.returncode != 3:
                continue
            with h5py.File(serial_h5) as f:
                reference = walk(f)
                check(len(f["cases"]) == len(f["values"]), f"{name}: {len(f['cases'])} cases in the serial file")
                if name == "ritz":
                    check("error" in f["cases"]["0000"].attrs, "ritz: the uplift case carries its error")
            # Two threads per rank once: the ranks' threads share the counter (MPI_THREAD_SERIALIZED).
            runs = [(1, ()), (2, ()), (3, ())] + ([(2, ("--jobs", "2"))] if name == "auto" else [])
            for ranks, extra in runs:
                r, h5, csv = sweep(mpirun(ranks), f"np{ranks}{''.join(extra)}", extra)
                what = f"{name}, -np {ranks} {' '.join(extra)}".rstrip()
                check(r.returncode == 3, f"{what}: exit 3 as the serial sweep (got {r.returncode}: "
                                         f"{r.stderr.strip()[-300:]})")
                check(stderr_lines(r.stderr) == stderr_lines(serial.stderr),
                      f"{what}: the same messages on stderr, once ({stderr_lines(r.stderr)})")
                if not os.path.exists(h5):
                    check(False, f"{what}: wrote {h5}")
                    continue
                with h5py.File(h5) as f:
                    got = walk(f)
                check(sorted(got) == sorted(reference), f"{what}: the same groups, datasets and attributes "
                                                        f"({len(got)} vs {len(reference)})")
                differ = [k for k in reference if k in got and not same(reference[k], got[k])]
                check(not differ, f"{what}: every dataset and attribute bitwise equal (differ: {differ[:5]})")
                check(csv_without_time(csv) == csv_without_time(serial_csv), f"{what}: the same CSV but time_s")

        # A bad scene: one message (from rank 0), exit 2 on every rank, no output.
        bad = os.path.join(tmp, "bad.toml")
        with open(bad, "w") as f:
            f.write("[structure]\nkind = \"beam\"\nlength = -1.0\n")
        h5 = os.path.join(tmp, "bad.h5")
        r = run([*mpirun(2), args.liftoff, "sweep", bad, "--set", "foundation.modulus=1,2", "--output", h5])
        lines = stderr_lines(r.stderr)
        check(r.returncode == 2, f"bad scene, -np 2: exit 2 (got {r.returncode})")
        check(len(lines) == 1 and "bad.toml" in lines[0], f"bad scene, -np 2: one line naming the file ({lines})")
        check(not os.path.exists(h5) and not os.path.exists(h5 + ".tmp"), "bad scene, -np 2: no output file")
    finish()


if __name__ == "__main__":
    main()
