#!/usr/bin/env python3
"""Plots of one run, made from the files `trephine run` writes.

usage: tools/plot_run.py RUN_DIR

Writes RUN_DIR/force.png (device and proxy height, force, penetration and
change of force per frame over time, from trace.csv, with the run's events
from summary.json marked at their times) and RUN_DIR/timings.png (per-call
time of each ticking component, from timings.csv, against each rate's frame
budget).
"""
import csv
import json
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

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figure_file import save_figure  # noqa: E402


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_events(run):
    """The run's events (summary.json), as (t, kind); none when it has no summary."""
    try:
        summary = json.loads((run / "summary.json").read_text())
    except (OSError, ValueError):
        return []
    return [(float(e["t"]), e["kind"]) for e in summary.get("events", [])]


EVENT_COLOURS = ["tab:orange", "tab:brown", "tab:pink", "tab:gray", "tab:cyan", "tab:olive"]


def mark_events(axes, events):
    """A vertical line on every panel at each event, one colour a kind, named once in the top panel's legend.
    A kind logged many times (a streak of rejected samples) is drawn faintly."""
    kinds = sorted({k for _, k in events})
    for i, kind in enumerate(kinds):
        times = [t for t, k in events if k == kind]
        colour = EVENT_COLOURS[i % len(EVENT_COLOURS)]
        alpha = 0.8 if len(times) <= 20 else 0.3
        for ax in axes:
            for j, t in enumerate(times):
                ax.axvline(t, color=colour, linestyle=":", linewidth=1.0, alpha=alpha,
                           label=f"{kind} ({len(times)})" if ax is axes[0] and j == 0 else None)


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
    axes[1].plot(t, force, color="tab:red")
    axes[1].set_ylabel("|F| (N)")
    axes[2].plot(t, [float(r["penetration"]) for r in rows], color="tab:green",
                 label="rendered: the spring's stretch, device to proxy")
    if "penetration_raw" in rows[0]:
        axes[2].plot(t, [float(r["penetration_raw"]) for r in rows], color="tab:olive", linewidth=0.7,
                     label="detected: the collision query's deepest point")
        axes[2].legend(loc="upper right", fontsize="small")
    axes[2].set_ylabel("penetration (mm)")
    axes[3].plot(t, steps, color="tab:purple")
    axes[3].set_ylabel("|ΔF| per frame (N)")
    if contact_panel:
        axes[4].plot(t, [int(r["primitives"]) for r in rows], label="colliding primitives (voxels or tetrahedra)",
                     linewidth=0.7)
        removed, total = [], 0
        for r in rows:
            total += int(r["removed"])
            removed.append(total)
        if total > 0:
            axes[4].plot(t, removed, label="voxels removed so far", linewidth=0.9)
        axes[4].set_ylabel("count")
        axes[4].legend(loc="upper left", fontsize="small")
    events = read_events(run)
    if events:
        mark_events(axes, events)
    axes[0].legend(loc="upper right", fontsize="small")
    axes[-1].set_xlabel("time (s)")
    fig.suptitle(f"{run.name}: haptic trace")
    fig.tight_layout()
    save_figure(fig, run / "force.png", dpi=110)
    plt.close(fig)


def plot_timings(run, rows):
    """One panel per rate: each component's call time, and the frame's budget (the period)."""
    series = defaultdict(lambda: ([], []))
    rates = {}
    for r in rows:
        ts, us = series[r["component"]]
        ts.append(float(r["t"]))
        us.append(float(r["duration_us"]))
        rates[r["component"]] = float(r["rate_hz"])
    by_rate = defaultdict(list)
    for name in series:
        by_rate[rates[name]].append(name)
    ordered = sorted(by_rate, reverse=True)
    fig, axes = plt.subplots(len(ordered), 1, figsize=(11, 2.6 * len(ordered) + 0.8), sharex=True, squeeze=False)
    for ax, rate in zip(axes[:, 0], ordered):
        for name in by_rate[rate]:
            ts, us = series[name]
            ax.plot(ts, us, label=name, linewidth=0.6)
        ax.axhline(1e6 / rate, color="black", linestyle="--", linewidth=1.0, label=f"budget: one period ({1e6 / rate:g} µs)")
        ax.set_yscale("log")
        ax.set_ylabel(f"{rate:g} Hz: call (µs)")
        ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize="small")
    axes[-1, 0].set_xlabel("time (s)")
    fig.suptitle(f"{run.name}: time per call, by rate")
    fig.tight_layout()
    save_figure(fig, run / "timings.png", dpi=110)
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
