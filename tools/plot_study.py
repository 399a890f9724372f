#!/usr/bin/env python3
"""What accuracy costs in time, from the study.csv `trephine study` writes.

usage: tools/plot_study.py DIR/study.csv [--budget-us US]

Writes DIR/pareto.png: for every setting that ran, time per haptic frame
(median, with a bar to its p99) against the penetration error at the study's
poses (p99), each point labelled with its setting; the Pareto front (no other
setting as fast and as accurate and better in one) is joined and its points
filled; a reference setting measured against itself is a cross apart; the
haptic frame's budget (US, 1000 by default: a 1 kHz loop) is a dashed line.
"""
import csv
import math
import os
import sys
from pathlib import Path

try:
    import matplotlib
except ImportError:
    if sys.executable != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3", *sys.argv])
    print("plot_study.py: matplotlib is missing; install python3-matplotlib", file=sys.stderr)
    sys.exit(4)  # the program that runs this says so; any other failure is the script's own message

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figure_file import save_figure  # noqa: E402


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def main(argv):
    budget_us = 1000.0
    if len(argv) == 4 and argv[2] == "--budget-us":
        budget_us = number(argv[3])
        argv = argv[:2]
    if len(argv) != 2 or not budget_us > 0:
        sys.exit(__doc__)
    source = Path(argv[1])
    with open(source, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["status"] == "ok"]
    points = []
    for r in rows:
        t50, t99, err = number(r["step_p50_us"]), number(r["step_p99_us"]), number(r["pen_err_p99_mm"])
        # A reference setting measured against itself (no exact reference) has
        # no error by definition and takes no part in the front: drawn apart.
        itself = r.get("reference") == "1" and r.get("exact_reference", "1") != "1"
        if math.isfinite(t50) and math.isfinite(err):
            points.append((t50, t99, err, r["setting"] + ": " + r["label"], r["pareto"] == "1", itself))
    if not points:
        sys.exit(f"plot_study.py: {source}: no setting with both a time and an error")
    fig, ax = plt.subplots(figsize=(8, 7.0))
    # Labels of settings at about the same error and time would overprint:
    # each takes the first of a few heights (points) clear of those placed.
    errors = [p[2] for p in points]
    span = (max(errors) - min(errors)) or max(abs(errors[0]), 1e-9)
    placed = []  # (log10 time, error, height of the label)
    for t50, t99, err, label, on_front, itself in points:
        ax.errorbar([t50], [err], xerr=[[0], [max(0.0, t99 - t50)]], fmt="x" if itself else "o",
                    color="C0" if on_front else "C3" if itself else "C7", mfc="C0" if on_front else "white",
                    capsize=3)
        where = math.log10(max(t50, 1e-12))
        height = next(h for h in (4, -11, 15, -22, 26, -33)
                      if not any(abs(where - w) < 0.8 and abs(err - e) < 0.05 * span and h == d
                                 for w, e, d in placed))
        placed.append((where, err, height))
        ax.annotate(label, (t50, err), textcoords="offset points", xytext=(5, height), fontsize=7)
    front = sorted((p for p in points if p[4]), key=lambda p: p[0])
    if len(front) > 1:
        ax.plot([p[0] for p in front], [p[2] for p in front], "-", color="C0", label="Pareto front")
    # What the markers mean, and the frame's budget.
    ax.plot([], [], "o", color="C0",
            label="on the front: no other setting as fast and as accurate, and better in one")
    ax.plot([], [], "o", color="C7", mfc="white", label="off the front")
    if any(p[5] for p in points):
        ax.plot([], [], "x", color="C3", label="the reference setting, measured against itself: not compared")
    ax.axvline(budget_us, color="black", linestyle="--", linewidth=1.0,
               label=f"haptic frame budget ({budget_us:g} µs)")
    # Below the axes, clear of the settings' labels.
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=1, fontsize="small", frameon=False)
    ax.set_xscale("log")
    ax.set_xlabel("haptic step (µs): median, bar to p99")
    ax.set_ylabel("penetration error p99 (mm)")
    ax.set_title(f"What accuracy costs in time ({len(points)} settings)")
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    out = source.with_name("pareto.png")
    save_figure(fig, out, dpi=120)
    print(out)
    pairs_png = plot_pairs(source.with_name("pairs.csv"), rows, budget_us)
    if pairs_png:
        print(pairs_png)


def front_of(points):
    """The points (time, error) no other is at least as good as in both and better in one."""
    return [p for p in points
            if not any(q[0] <= p[0] and q[1] <= p[1] and (q[0] < p[0] or q[1] < p[1]) for q in points)]


def plot_pairs(pairs_csv, rows, budget_us):
    """pairs.png: a panel per tool and target, when the study has more than one."""
    if not pairs_csv.exists():
        return None
    with open(pairs_csv, newline="") as f:
        pairs = [r for r in csv.DictReader(f) if r["status"] == "ok"]
    names = []
    for r in pairs:
        name = (r["tool"], r["target"])
        if name not in names:
            names.append(name)
    if len(names) < 2:
        return None
    step = {r["setting"]: number(r["step_p50_us"]) for r in rows}
    reference = {r["setting"] for r in rows if r.get("reference") == "1"}
    fig, axes = plt.subplots(1, len(names), figsize=(5.2 * len(names), 4.8), squeeze=False)
    for ax, (tool, target) in zip(axes[0], names):
        points = []
        for r in pairs:
            if (r["tool"], r["target"]) != (tool, target):
                continue
            t, err = step.get(r["setting"], math.nan), number(r["pen_err_p99_mm"])
            itself = r["exact_reference"] != "1" and r["setting"] in reference
            if math.isfinite(t) and math.isfinite(err):
                points.append((t, err, r["setting"], itself))
        competing = [(p[0], p[1]) for p in points if not p[3]]
        front = set(front_of(competing))
        for t, err, setting, itself in points:
            on = (t, err) in front and not itself
            ax.plot([t], [err], "x" if itself else "o", color="C0" if on else "C3" if itself else "C7",
                    mfc="C0" if on else "white")
            ax.annotate(setting, (t, err), textcoords="offset points", xytext=(4, 3), fontsize=7)
        line = sorted(front)
        if len(line) > 1:
            ax.plot([p[0] for p in line], [p[1] for p in line], "-", color="C0")
        ax.axvline(budget_us, color="black", linestyle="--", linewidth=1.0)
        ax.set_xscale("log")
        ax.set_title(f"{tool} on {target}", fontsize=9)
        ax.set_xlabel("haptic step p50 (µs)")
        ax.set_ylabel("penetration error p99 (mm)")
        ax.grid(True, which="both", alpha=0.3)
    fig.suptitle("Every tool on every target it touched (numbers: the settings of study.csv; filled: on the "
                 "front; x: the reference setting measured against itself)", fontsize=9)
    fig.tight_layout()
    out = pairs_csv.with_name("pairs.png")
    save_figure(fig, out, dpi=110)
    return out


if __name__ == "__main__":
    main(sys.argv)
