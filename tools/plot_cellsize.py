#!/usr/bin/env python3
"""Draws the figure of a cell-size experiment from the CSV and JSON that
`trephine cellsize` writes beside each other.

DIR/cellsize.csv (`trephine cellsize MESH --experiment`, two meshes):
cellsize.png, the detection time per frame against the cells per mm (as the
thesis's Fig. 5.3 draws it against voxels per axis), the fitted polynomial,
the optimal zone, and the cell sizes of the cost model (delta_a) and of the
edge-length rule (delta_trad).

DIR/tool_cellsize.csv (`trephine cellsize MESH --tool R --experiment`):
tool_cellsize.png, the time of one tool query on TetraBrain's grid against
the cell size (log scale), the fit, the zone, and the cells of the tool
query's model (delta_tool), of half an edge and of the edge; below, the work
the back-end counted against the work the model predicts.

usage: plot_cellsize.py DIR/cellsize.csv | DIR/tool_cellsize.csv
"""
import csv
import json
import os
import sys

try:
    import matplotlib
except ImportError:
    print("plot_cellsize.py: matplotlib is missing; install python3-matplotlib", file=sys.stderr)
    sys.exit(4)  # the program that runs this says so; any other failure is the script's own message

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figure_file import save_figure  # noqa: E402


def read(path):
    """The CSV's rows and the summary JSON beside it (same stem)."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    with open(os.path.splitext(path)[0] + ".json") as f:
        return rows, json.load(f)


def draw_pair(rows, summary, directory):
    n = [float(r["cells_per_mm"]) for r in rows]
    t = [float(r["time_us"]) for r in rows]
    fitted = [float(r["fitted_us"]) for r in rows]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(n, t, "o", color="tab:blue", label="measured (median per frame)")
    ax.plot(n, fitted, "-", color="tab:blue", alpha=0.6, label="polynomial fit")
    low, high = summary["zone"]
    ax.axvspan(1 / high, 1 / low, color="tab:green", alpha=0.15, label="optimal zone (within 10%)")
    marks = [("delta_opt", "tab:green", "-"), ("delta_a", "tab:red", "--"), ("delta_trad", "tab:gray", ":")]
    for key, colour, style in marks:
        ax.axvline(1 / summary[key], color=colour, linestyle=style,
                   label=f"{key} = {summary[key]:.3g} mm")
    ax.set_xlabel("cells per mm (1 / cell size)")
    ax.set_ylabel("detection time per frame (us)")
    ax.set_title(f"{os.path.basename(summary['mesh'])}: {summary['tetrahedra']} tetrahedra, two copies")
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, os.path.join(directory, "cellsize.png"), dpi=120)


def draw_tool(rows, summary, directory):
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
    save_figure(fig, os.path.join(directory, "tool_cellsize.png"), dpi=120)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    path = sys.argv[1]
    directory = os.path.dirname(path) or "."
    rows, summary = read(path)
    (draw_tool if os.path.basename(path).startswith("tool_") else draw_pair)(rows, summary, directory)


if __name__ == "__main__":
    main()
