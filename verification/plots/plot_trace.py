#!/usr/bin/python3
"""Figures of a `liftoff trace` HDF5 file: the load history F = F_dead + lambda F_live.

    /usr/bin/python3 verification/plots/plot_trace.py TRACE.h5 [--out PREFIX]

writes PREFIX_load_displacement.png (lambda against the monitored deflection w, every path of
the file overlaid: fe, ritz, fe_refined) and PREFIX_lift_off_map.png (one panel per path: the
position along the member across, lambda up, contact regions shaded, lift-off zones blank, and
every event marked and labelled with its kind). Events are marked on both. w > 0 is into the
foundation. A file of an interrupted trace is drawn as far as it goes (if the file was damaged
by the kill, its backup TRACE.h5.backup is read instead).
"""
import argparse
import os
import sys

import h5py
import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLES = {"fe": ("tab:blue", "-"), "ritz": ("tab:red", "--"), "fe_refined": ("tab:green", ":")}
KIND_MARKERS = {"lift_off_opens": "v", "contact_opens": "^", "region_vanishes": "x", "lift_off_vanishes": "+",
                "limit_at_support": "s", "limit_at_load": "D", "limit_at_end": ">", "limit_point": "*"}


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def read_path(group):
    steps, events = group["steps"], group["events"]
    # The per-step datasets may differ by one row after a kill: keep the steps they all hold.
    n = min(len(steps[name]) for name in ("lambda", "monitor_deflection", "deflection", "reaction"))
    lam = steps["lambda"][:n]
    regions = [[] for _ in range(n)]
    for step, begin, end in steps["contact_regions"][()].reshape(-1, 3):
        if 0 <= step < n:
            regions[int(step)].append((begin, end))
    m = min(len(events[name]) for name in ("lambda", "kind", "at", "step"))
    event_list = [(float(events["lambda"][i]), text(events["kind"][i]), float(events["at"][i]))
                  for i in range(m) if 0 <= events["step"][i] < n]
    return {"lambda": lam, "w": steps["monitor_deflection"][:n], "regions": regions, "events": event_list,
            "monitor": float(group.attrs.get("monitor", np.nan)),
            "termination": text(group.attrs.get("termination", "running"))}


def read(path):
    candidates = [path, path + ".backup"]
    for candidate in candidates:
        if not os.path.exists(candidate):
            continue
        try:
            with h5py.File(candidate, "r") as f:
                names = [p for p in text(f.attrs["paths"]).split(",") if p in f]
                paths = {name: read_path(f[name]) for name in names}
                x = f["sample_points"][()]
                return {"paths": paths, "coordinate": text(f.attrs["coordinate"]), "begin": x.min(),
                        "end": x.max(), "scene": text(f.attrs["scene_name"])}
        except (OSError, KeyError) as e:
            print(f"plot_trace: {candidate}: {e}", file=sys.stderr)
    sys.exit(f"plot_trace: {path}: not a readable liftoff trace")


def load_displacement(trace, out):
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for name, p in trace["paths"].items():
        color, style = STYLES.get(name, ("black", "-"))
        ax.plot(p["w"], p["lambda"], color=color, linestyle=style, label=f"{name} ({p['termination']})")
        for lam, kind, _ in p["events"]:
            # w at the event from the nearest recorded steps (a fold makes lambda non-monotonic)
            i = int(np.argmin(np.abs(p["lambda"] - lam))) if len(p["lambda"]) else None
            if i is None:
                continue
            j = min(i + 1, len(p["lambda"]) - 1) if p["lambda"][i] < lam else max(i - 1, 0)
            l0, l1 = p["lambda"][i], p["lambda"][j]
            w = p["w"][i] if l1 == l0 else p["w"][i] + (lam - l0) / (l1 - l0) * (p["w"][j] - p["w"][i])
            ax.plot(w, lam, KIND_MARKERS.get(kind, "o"), color=color, markersize=7, markerfacecolor="none")
            ax.annotate(kind, (w, lam), textcoords="offset points", xytext=(6, -3), fontsize=7, color=color)
    monitor = next(iter(trace["paths"].values()))["monitor"] if trace["paths"] else np.nan
    where = "theta" if trace["coordinate"] == "theta_deg" else "x"
    ax.set_xlabel(f"w at {where} = {monitor:.4g} (> 0 into the foundation)")
    ax.set_ylabel("load factor lambda")
    ax.axvline(0.0, color="black", linewidth=0.5)
    ax.set_title(f"{os.path.basename(trace['scene'])}: load-displacement", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    print(out)


def lift_off_map(trace, out):
    names = list(trace["paths"]) or ["(no path)"]
    fig, axes = plt.subplots(1, len(names), figsize=(4.8 * len(names), 4.5), sharey=True, squeeze=False)
    for ax, name in zip(axes[0], names):
        p = trace["paths"].get(name)
        ax.set_xlim(trace["begin"], trace["end"])
        ax.set_title(name if p is None else f"{name}: contact shaded, lift-off blank", fontsize=10)
        ax.set_xlabel("theta (degrees)" if trace["coordinate"] == "theta_deg" else "x")
        ax.grid(True, alpha=0.3)
        if p is None or len(p["lambda"]) == 0:
            continue
        color = STYLES.get(name, ("black", "-"))[0]
        lam, regions = p["lambda"], p["regions"]
        # Runs of steps with the same number of contact regions: each region's limits drawn
        # as curves in lambda and the region between them shaded.
        start = 0
        while start < len(lam):
            stop = start
            while stop + 1 < len(lam) and len(regions[stop + 1]) == len(regions[start]):
                stop += 1
            # Between two runs the topology changes somewhere inside one step: each run is
            # continued, unchanged, to the middle of that step, so the map has no gap.
            lo = 0.5 * (lam[start - 1] + lam[start]) if start > 0 else lam[start]
            hi = 0.5 * (lam[stop] + lam[stop + 1]) if stop + 1 < len(lam) else lam[stop]
            run_lambda = np.concatenate(([lo], lam[start:stop + 1], [hi]))
            for k in range(len(regions[start])):
                begin = np.array([r[k][0] for r in regions[start:stop + 1]])
                end = np.array([r[k][1] for r in regions[start:stop + 1]])
                begin = np.concatenate(([begin[0]], begin, [begin[-1]]))
                end = np.concatenate(([end[0]], end, [end[-1]]))
                ax.fill_betweenx(run_lambda, begin, end, color=color, alpha=0.25, linewidth=0)
                ax.plot(begin, run_lambda, color=color, linewidth=0.8)
                ax.plot(end, run_lambda, color=color, linewidth=0.8)
            start = stop + 1
        for event_lambda, kind, at in p["events"]:
            ax.plot(at, event_lambda, KIND_MARKERS.get(kind, "o"), color="black", markersize=7)
            ax.annotate(f"{kind}\nlambda = {event_lambda:.5g}", (at, event_lambda), textcoords="offset points",
                        xytext=(5, 3), fontsize=7)
    axes[0][0].set_ylabel("load factor lambda")
    fig.suptitle(f"{os.path.basename(trace['scene'])}: lift-off map", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    print(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("trace")
    parser.add_argument("--out", default=None, help="prefix of the PNG files (default: the HDF5 name)")
    args = parser.parse_args()
    prefix = args.out or args.trace.rsplit(".", 1)[0]
    trace = read(args.trace)
    load_displacement(trace, prefix + "_load_displacement.png")
    lift_off_map(trace, prefix + "_lift_off_map.png")


if __name__ == "__main__":
    main()
