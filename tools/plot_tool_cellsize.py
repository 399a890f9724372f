#!/usr/bin/env python3
"""Draws tool_cellsize.png from the tool_cellsize.csv and tool_cellsize.json
that `trephine cellsize MESH --tool R --experiment` writes: the time of one
tool query on TetraBrain's grid against the cell size (log scale), the fitted
polynomial, the optimal zone, and the cell sizes of the tool query's cost
model (delta_tool), of today's rule (half the average edge) and of the
edge-length rule; below, the work the back-end counted against the work the
model predicts.

usage: plot_tool_cellsize.py DIR/tool_cellsize.csv
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    path = sys.argv[1]
    directory = os.path.dirname(path) or "."
    with open(path) as f:
        rows = list(csv.DictReader(f))
    with open(os.path.join(directory, "tool_cellsize.json")) as f:
        summary = json.load(f)
    delta = [float(r["cell_size_mm"]) for r in rows]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    top.plot(delta, [float(r["time_ns"]) / 1000 for r in rows], "o", color="tab:blue",
             label="measured (median of rounds)")
    top.plot(delta, [float(r["fitted_ns"]) / 1000 for r in rows], "-", color="tab:blue", alpha=0.6,
             label="polynomial fit in log(delta)")
    low, high = summary["zone"]
    top.axvspan(low, high, color="tab:green", alpha=0.15, label="optimal zone (within 10%)")
    marks = [("delta_opt", "tab:green", "-"), ("delta_tool", "tab:red", "--"),
             ("delta_half_edge", "tab:orange", "-."), ("delta_trad", "tab:gray", ":")]
    for key, colour, style in marks:
        top.axvline(summary[key], color=colour, linestyle=style, label=f"{key} = {summary[key]:.3g} mm")
    top.set_ylabel("tool query (us)")
    kind = "deforming" if summary["deforming"] else "rigid"
    top.set_title(f"{os.path.basename(summary['mesh'])}: {summary['tetrahedra']} tetrahedra, {kind}; "
                  f"tool radius {summary['tool_radius']:g} mm, {summary['shell_points']} points")
    top.legend(fontsize=7)
    for key, colour in [("listed", "tab:purple"), ("point_tests", "tab:brown"), ("cells", "tab:cyan")]:
        bottom.plot(delta, [float(r[key]) for r in rows], "o", color=colour, label=f"{key} (counted)")
        bottom.plot(delta, [float(r["predicted_" + key]) for r in rows], "-", color=colour, alpha=0.6,
                    label=f"{key} (model, all cells inside)")
    bottom.set_xscale("log")
    bottom.set_yscale("log")
    bottom.set_xlabel("cell size (mm)")
    bottom.set_ylabel("per query")
    bottom.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "tool_cellsize.png"), dpi=120)


if __name__ == "__main__":
    main()
