#!/usr/bin/python3
"""Speed-up of the distributed sweep (issue 17): 1000 cases, one process with one thread against
`mpirun -np 2` (one thread per rank), the median wall-clock time of a few runs each.

    /usr/bin/python3 verification/bench/mpi_sweep_bench.py --liftoff build/src/liftoff [--runs 3]
        [--ranks 2] [--elements 2000] [--cases 1000]

The scene is the shipped 500 m pipeline (verification/scenes/engineering/pipeline_500m_uplift.toml)
with its uplift force swept over `--cases` values, on `--elements` elements so that the solves
(tens of milliseconds each) dominate MPI's start-up and the gathering of the results. Both runs
write the CSV only (no --output), so the figure is the solves' distribution, not the HDF5 writing
that rank 0 does alone. Not a test: the figures depend on the machine and on its load (run it on a
quiet machine; the load average is printed beside them). The CPU times are printed too, with the
speed-up they bound (serial CPU time over the ranks' CPU time per rank), which the load does not
change.
"""

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "engineering",
                     "pipeline_500m_uplift.toml")


def cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)  # every waited-for descendant: mpirun's ranks too
    return usage.ru_utime + usage.ru_stime


def timed(command, cpu_times):
    start, start_cpu = time.perf_counter(), cpu()
    r = subprocess.run(command, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    cpu_times.append(cpu() - start_cpu)
    if r.returncode != 0:
        sys.exit(f"mpi_sweep_bench: {' '.join(command)} exited {r.returncode}: {r.stderr.strip()[-500:]}")
    return elapsed


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--liftoff", required=True)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--elements", type=int, default=2000)
    parser.add_argument("--cases", type=int, default=1000)
    args = parser.parse_args()
    root = ["--allow-run-as-root"] if os.geteuid() == 0 else []
    with tempfile.TemporaryDirectory() as tmp:
        sweep = ["sweep", SCENE, "--set", f"loads[1].value=lin:-20e3:-80e3:{args.cases}", "--elements",
                 str(args.elements), "--jobs", "1"]
        serial = [args.liftoff, *sweep, "--csv", os.path.join(tmp, "serial.csv")]
        distributed = ["mpirun", *root, "-np", str(args.ranks), args.liftoff, *sweep, "--csv",
                       os.path.join(tmp, "mpi.csv")]
        times, cpu_times = {"serial": [], "mpi": []}, {"serial": [], "mpi": []}
        for _ in range(args.runs):  # interleaved, so that a change of the machine's load hits both
            times["serial"].append(timed(serial, cpu_times["serial"]))
            times["mpi"].append(timed(distributed, cpu_times["mpi"]))
        with open(os.path.join(tmp, "serial.csv")) as a, open(os.path.join(tmp, "mpi.csv")) as b:
            column = a.readline().split(",").index("time_s")
            b.readline()
            same = all(x.split(",")[:column] == y.split(",")[:column] for x, y in zip(a, b))
    load = os.getloadavg()
    s, m = statistics.median(times["serial"]), statistics.median(times["mpi"])
    print(f"{args.cases} cases, {args.elements} elements, {args.runs} runs each; load average "
          f"{load[0]:.2f} {load[1]:.2f} {load[2]:.2f} on {os.cpu_count()} cores")
    print(f"serial (1 process, 1 thread): {' '.join(f'{t:.2f}' for t in times['serial'])} s, median {s:.2f} s")
    print(f"mpirun -np {args.ranks} (1 thread each): {' '.join(f'{t:.2f}' for t in times['mpi'])} s, median {m:.2f} s")
    print(f"speed-up {s / m:.2f}; the CSVs {'agree' if same else 'DIFFER'} (but time_s)")
    # On a loaded machine the wall-clock ratio measures the load as much as the sweep; the CPU
    # times do not: the CPU-bound speed-up is the serial CPU time over the ranks' total divided
    # by their number (mpirun's own CPU and MPI's start-up counted against the ranks).
    cs, cm = statistics.median(cpu_times["serial"]), statistics.median(cpu_times["mpi"])
    print(f"CPU time (user + system): serial median {cs:.2f} s, mpirun -np {args.ranks} median {cm:.2f} s in all; "
          f"CPU-bound speed-up {cs / (cm / args.ranks):.2f}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
