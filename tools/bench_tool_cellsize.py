#!/usr/bin/env python3
"""The tool query's cell size against its measured optimum, mesh by mesh:
`trephine cellsize MESH --tool 2.5 --experiment --json` (the 266-point shell
of scenes/brain.xml) on Brain1 to Brain5, Cube1 to Cube7 and, when
../shared/data is there, the atlas brain; rigid, and with --deforming the grids
of a deforming mesh. Prints a markdown table (delta_opt, the zone, the three
rules' cells and their errors) and writes DIR/tool_cellsize.csv, with each
mesh's sweep in DIR/<mesh>-<mode>/.

usage: tools/bench_tool_cellsize.py [--out DIR] [--quick] [--modes rigid,deforming]
"""
import argparse
import csv
import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
ATLAS = ROOT.parent / "shared/data/brain_tetmesh_mmc_head_atlas/brain_gm_wm.node"
MESHES = [(f"Brain{i + 1}", f"phantom:brain?tets={n}") for i, n in enumerate([3500, 12500, 22000, 40500, 50000])]
MESHES += [(f"Cube{i + 1}", f"phantom:cube?cells={n}") for i, n in enumerate([7, 13, 22, 30, 40, 50, 60])]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="runs/tool_cellsize")
    parser.add_argument("--quick", action="store_true", help="Brain1 and Cube1, one round of 20 poses")
    parser.add_argument("--modes", default="rigid,deforming")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    meshes = MESHES[:1] + MESHES[5:6] if args.quick else list(MESHES)
    if not args.quick:
        if ATLAS.exists():
            meshes.append(("Atlas", str(ATLAS)))
        else:
            print(f"note: {ATLAS} is absent; the atlas brain is skipped", file=sys.stderr)
    program = ROOT / "build/bin/trephine"
    rows = []
    for mode in args.modes.split(","):
        for name, mesh in meshes:
            command = [str(program), "cellsize", mesh, "--tool", "2.5", "--experiment", "--json",
                       "--out", str(out / f"{name}-{mode}")]
            if mode == "deforming":
                command.append("--deforming")
            if args.quick:
                command += ["--rounds", "1", "--poses", "20"]
            result = subprocess.run(command, capture_output=True, text=True)
            if result.returncode != 0:
                sys.exit(f"{' '.join(command)} failed:\n{result.stderr}")
            d = json.loads(result.stdout)
            rows.append({"mesh": name, "mode": mode, "tetrahedra": d["tetrahedra"],
                         "average_edge": d["average_edge"], "delta_opt": d["delta_opt"],
                         "zone_low": d["zone"][0], "zone_high": d["zone"][1], "delta_tool": d["delta_tool"],
                         "delta_half_edge": d["delta_half_edge"], "delta_trad": d["delta_trad"],
                         "epsilon_tool": d["epsilon_tool"], "epsilon_half_edge": d["epsilon_half_edge"],
                         "epsilon_trad": d["epsilon_trad"]})
            print(f"{name} {mode}: done", file=sys.stderr)
    with open(out / "tool_cellsize.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print("| mesh | mode | tetrahedra | average edge | delta_opt | zone | delta_tool (eps) | half edge (eps) | edge (eps) |")
    print("|---|---|---:|---:|---:|---|---|---|---|")
    for r in rows:
        print(f"| {r['mesh']} | {r['mode']} | {r['tetrahedra']:,} | {r['average_edge']:.2f} | {r['delta_opt']:.2f} | "
              f"{r['zone_low']:.2f} to {r['zone_high']:.2f} | {r['delta_tool']:.2f} ({r['epsilon_tool']:.2f}) | "
              f"{r['delta_half_edge']:.2f} ({r['epsilon_half_edge']:.2f}) | {r['delta_trad']:.2f} ({r['epsilon_trad']:.2f}) |")


if __name__ == "__main__":
    main()
