#!/usr/bin/env python3
"""Which CT resampling gives the skull the best accuracy per microsecond.

usage: tools/voxel_resolution.py [--quick] [--out DIR]

Runs `trephine study` on scenes/bench/skull_backends.xml (the 466-point burr
pressed 1 mm into the skull phantom and circled, native back-end) with the
voxel size of the phantom's CT swept from 2 to 0.5 mm, on both surfaces
(smooth: the trilinear isosurface; voxels: the thesis's boxes) with both
penetrations (algorithm1: the thesis's tangent planes through the colliding
voxels' centres; deepest-point), once touching and once drilling. The phantom has an exact shape, so every setting's
penetration and normal errors are against the truth at the same 400 poses.
Where the voxel centres fall on the surface (the scan's phase) moves the
isosurface by up to a quarter voxel, so each size is scanned at three phases
(the phantom's shift: 0, 1/3 and 2/3 of a voxel) and its error is the mean
over them of the p99 (the worst phase beside it). Figure of merit: accuracy
per microsecond = 1 / (error x step p99); the best per surface and task is
marked (per surface and penetration). Writes DIR/voxel_resolution.csv and DIR/voxel_resolution.png (error
and step against voxel size) and prints a markdown table.
"""
import argparse
import csv
import math
import subprocess
import sys
from pathlib import Path

from bench_common import PROGRAM, ROOT, ensure_matplotlib

SCENE = ROOT / "scenes/bench/skull_backends.xml"
VOXELS = [2.0, 1.5, 1.25, 1.0, 0.75, 0.6, 0.5]
SURFACES = ["smooth", "voxels"]
PENETRATIONS = ["algorithm1", "deepest-point"]


PHASES = [0.0, 1 / 3, 2 / 3]  # of a voxel
# Reported: the smooth surface with its own penetration (auto's), and the
# voxel surface with each (smooth + algorithm1 runs too, for the poses' sake,
# and is in the study's own table).
VARIANTS = [("smooth", "deepest-point"), ("voxels", "algorithm1"), ("voxels", "deepest-point")]


def run_study(voxels, task, out):
    files = ",".join(f"phantom:skull?voxel={v}&shift={round(p * v, 4)}" for v in voxels for p in PHASES)
    # The poses come from the finest smooth deepest-point setting at phase 0
    # (file, then surface, then penetration: the last varies fastest).
    per_file = len(SURFACES) * len(PENETRATIONS)
    reference = (len(voxels) - 1) * len(PHASES) * per_file + SURFACES.index("smooth") * len(PENETRATIONS) + \
        PENETRATIONS.index("deepest-point") + 1
    command = [str(PROGRAM), "study", str(SCENE), "--jobs", "1", "--vary", f"/patient/skull.file={files}",
               "--vary", f"/patient/skull.surface={','.join(SURFACES)}",
               "--vary", f"/patient/skull.penetration={','.join(PENETRATIONS)}", "--reference", str(reference),
               "--out", str(out / f"study-{task}")]
    if task == "drill":
        command += ["--set", "/patient/skull.drill=true"]
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    with open(out / f"study-{task}" / "study.csv", newline="") as f:
        return list(csv.DictReader(f))


def mean(values):
    values = [v for v in values if math.isfinite(v)]
    return sum(values) / len(values) if values else math.nan


def median(values):
    values = sorted(values)
    n = len(values)
    return values[n // 2] if n % 2 else 0.5 * (values[n // 2 - 1] + values[n // 2])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="runs/voxel_resolution")
    parser.add_argument("--quick", action="store_true", help="two voxel sizes, touching only")
    args = parser.parse_args()
    plt = ensure_matplotlib("voxel_resolution.py")  # before the studies: it may start this script again
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    voxels = [2.0, 1.0] if args.quick else VOXELS
    rows = []
    for task in ["touch"] if args.quick else ["touch", "drill"]:
        settings = run_study(voxels, task, out)
        for surface, penetration in VARIANTS:
            for voxel in voxels:
                group = [r for r in settings if r["/patient/skull.surface"] == surface and
                         r["/patient/skull.penetration"] == penetration and
                         float(r["/patient/skull.file"].split("voxel=")[1].split("&")[0]) == voxel]
                failed = [r for r in group if r["status"] != "ok"]
                if failed:
                    sys.exit(f"setting {failed[0]['label']} failed: {failed[0]['status']}")
                errors = [float(r["pen_err_p99_mm"]) for r in group]
                error, step = mean(errors), median([float(r["step_p99_us"]) for r in group])
                rows.append({"task": task, "surface": surface, "penetration": penetration, "voxel_mm": voxel,
                             "phases": len(group),
                             "pen_err_p50_mm": mean([float(r["pen_err_p50_mm"]) for r in group]),
                             "pen_err_p99_mm": error, "pen_err_p99_worst_mm": max(errors),
                             "normal_err_p99_deg": mean([float(r["normal_err_p99_deg"]) for r in group]),
                             "step_p50_us": median([float(r["step_p50_us"]) for r in group]), "step_p99_us": step,
                             "accuracy_per_us": 1.0 / (error * step) if error > 0 and step > 0 else math.nan})
    for task in {r["task"] for r in rows}:
        for surface, penetration in VARIANTS:
            group = [r for r in rows if r["task"] == task and r["surface"] == surface and
                     r["penetration"] == penetration]
            best = max(group, key=lambda r: r["accuracy_per_us"])
            for r in group:
                r["best"] = int(r is best)
    with open(out / "voxel_resolution.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print("| task | surface, penetration | voxel (mm) | pen. error p50 / p99 (worst phase) (mm) | normal error p99 (°) "
          "| step p50 / p99 (µs) | 1 / (error x step) (1/(mm µs)) |")
    print("|---|---|---:|---|---:|---|---:|")
    for r in rows:
        mark = " **best**" if r["best"] else ""
        print(f"| {r['task']} | {r['surface']}, {r['penetration']} | {r['voxel_mm']:g} | {r['pen_err_p50_mm']:.3f} / "
              f"{r['pen_err_p99_mm']:.3f} ({r['pen_err_p99_worst_mm']:.3f}) | {r['normal_err_p99_deg']:.1f} | "
              f"{r['step_p50_us']:.1f} / {r['step_p99_us']:.1f} | {r['accuracy_per_us']:.2f}{mark} |")
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    for task in ["touch", "drill"]:
        for (surface, penetration), style in zip(VARIANTS, ["o-", "s--", "^:"]):
            group = sorted((r for r in rows if r["task"] == task and r["surface"] == surface and
                            r["penetration"] == penetration), key=lambda r: r["voxel_mm"])
            if not group:
                continue
            v = [r["voxel_mm"] for r in group]
            label = f"{task}, {surface}, {penetration}"
            top.plot(v, [r["pen_err_p99_mm"] for r in group], style, label=label)
            bottom.plot(v, [r["step_p99_us"] for r in group], style, label=label)
    top.set_ylabel("penetration error p99 (mm)")
    top.set_yscale("log")
    top.legend(fontsize=8)
    bottom.set_ylabel("haptic step p99 (µs)")
    bottom.set_yscale("log")
    bottom.set_xlabel("voxel size of the resampled CT (mm)")
    top.set_title("Skull phantom: accuracy against the exact shape, and the time it costs")
    fig.tight_layout()
    fig.savefig(out / "voxel_resolution.png", dpi=120)


if __name__ == "__main__":
    main()
