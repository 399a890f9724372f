#!/usr/bin/env python3
"""Plots of one run, made from the files `trephine run` writes.

usage: tools/plot_run.py RUN_DIR

Writes RUN_DIR/force.png (device and proxy height, force, penetration and
change of force per frame over time, from trace.csv) and RUN_DIR/timings.png
(per-call time of each ticking component, from timings.csv).
"""
import csv
import math
import os
import sys
from collections import defaultdict
from pathlib import Path

try:
    import matplotlib
except ImportError:
    # Another python3 earlier on PATH (a pyenv one, say) may lack Debian's
    # matplotlib, which tools/setup installs for /usr/bin/python3.
    if sys.executable != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3", *sys.argv])
    sys.exit("plot_run.py: matplotlib is missing; install python3-matplotlib")

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def plot_trace(run, rows):
    t = [float(r["t"]) for r in rows]
    force = [math.sqrt(sum(float(r[f"force_{a}"]) ** 2 for a in "xyz")) for r in rows]
    steps = [0.0] + [
        math.sqrt(sum((float(b[f"force_{a}"]) - float(a_[f"force_{a}"])) ** 2 for a in "xyz"))
        for a_, b in zip(rows, rows[1:])
    ]
    # Colliding primitives and drilled voxels when the run has them (after the contract's columns).
    contact_panel = "primitives" in rows[0]
    fig, axes = plt.subplots(5 if contact_panel else 4, 1, figsize=(9, 11 if contact_panel else 9), sharex=True)
    axes[0].plot(t, [float(r["device_z"]) for r in rows], label="device z")
    axes[0].plot(t, [float(r["proxy_z"]) for r in rows], label="proxy z", linestyle="--")
    axes[0].set_ylabel("height (mm)")
    axes[0].legend(loc="upper right")
    axes[1].plot(t, force, color="tab:red")
    axes[1].set_ylabel("|F| (N)")
    axes[2].plot(t, [float(r["penetration"]) for r in rows], color="tab:green", label="rendered")
    if "penetration_raw" in rows[0]:
        axes[2].plot(t, [float(r["penetration_raw"]) for r in rows], color="tab:olive", linewidth=0.7,
                     label="raw (detection)")
        axes[2].legend(loc="upper right")
    axes[2].set_ylabel("penetration (mm)")
    axes[3].plot(t, steps, color="tab:purple")
    axes[3].set_ylabel("|ΔF| per frame (N)")
    if contact_panel:
        axes[4].plot(t, [int(r["primitives"]) for r in rows], label="colliding primitives", linewidth=0.7)
        removed, total = [], 0
        for r in rows:
            total += int(r["removed"])
            removed.append(total)
        axes[4].plot(t, removed, label="removed so far", linewidth=0.9)
        axes[4].set_ylabel("voxels")
        axes[4].legend(loc="upper left")
    axes[-1].set_xlabel("time (s)")
    fig.suptitle(f"{run.name}: haptic trace")
    fig.tight_layout()
    fig.savefig(run / "force.png", dpi=110)
    plt.close(fig)


def plot_timings(run, rows):
    series = defaultdict(lambda: ([], []))
    for r in rows:
        ts, us = series[r["component"]]
        ts.append(float(r["t"]))
        us.append(float(r["duration_us"]))
    fig, ax = plt.subplots(figsize=(9, 4))
    for name, (ts, us) in series.items():
        ax.plot(ts, us, label=name, linewidth=0.7)
    ax.set_yscale("log")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("call time (µs)")
    ax.legend(loc="upper right", fontsize="small")
    ax.set_title(f"{run.name}: time per call")
    fig.tight_layout()
    fig.savefig(run / "timings.png", dpi=110)
    plt.close(fig)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    run = Path(sys.argv[1])
    trace = read_csv(run / "trace.csv")
    if trace:
        plot_trace(run, trace)
    timings = read_csv(run / "timings.csv")
    if timings:
        plot_timings(run, timings)
    print(f"plots     {run}/force.png, {run}/timings.png")


if __name__ == "__main__":
    main()
