#!/usr/bin/env python3
"""Draws cellsize.png from the cellsize.csv and cellsize.json that
`trephine cellsize MESH --experiment` writes: the detection time per frame
against the cells per mm (as the thesis's Fig. 5.3 draws it against voxels per
axis), the fitted polynomial, the optimal zone, and the cell sizes of the
cost model (delta_a) and of the edge-length rule (delta_trad).

usage: plot_cellsize.py DIR/cellsize.csv
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
    with open(os.path.join(directory, "cellsize.json")) as f:
        summary = json.load(f)
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
    fig.savefig(os.path.join(directory, "cellsize.png"), dpi=120)


if __name__ == "__main__":
    main()
