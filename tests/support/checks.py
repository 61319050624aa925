"""The python test scripts' one checker.

Each check prints `ok` or `FAIL` and the claim; a failed one is remembered, so that a script runs
every check and reports them all, and `finish()` at its end exits 1 naming how many failed (ctest
reads the exit code). An exception still ends the script non-zero on its own.
"""
import sys

failures = []


def check(condition, what):
    print(("ok    " if condition else "FAIL  ") + what)
    if not condition:
        failures.append(what)


def finish():
    if failures:
        print(f"{len(failures)} check(s) failed", file=sys.stderr)
        sys.exit(1)
    print("all checks passed")
