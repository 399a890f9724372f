#!/usr/bin/env python3
"""What accuracy costs in time for rigid voxel collision: penetration and
normal error against an exact half-space, next to the time per frame.

usage: tools/accuracy_rigid.py [--quick] [--out DIR]

Runs scenes/bench/rigid_halfspace_accuracy.xml (a 2.5 mm burr walking over a
tilted half-space, slight and deeper contacts) with `build/bin/trephine run`
for each voxel size, shell density and collision variant. The exact
penetration of a frame is radius - n.(device centre), the exact normal n
(the plane passes through the origin). Frames where the exact penetration is
at least 0.05 mm are compared. Writes DIR/accuracy.csv (one row per
configuration: penetration error mean/p95/max in mm, normal error mean/p95/max
in degrees, proxy time p50/p99 in us) and DIR/accuracy.png.
"""
import argparse
import itertools
import math
import subprocess
from collections import defaultdict
from pathlib import Path

from bench_common import PROGRAM, ROOT, ensure_matplotlib, percentile, read_rows, write_rows

SCENE = ROOT / "scenes/bench/rigid_halfspace_accuracy.xml"
RADIUS = 2.5  # mm, the burr of the scene
PLANE = (0.3, 0.2, 0.93)
# Collision variants: (name, VoxelSkull surface, VoxelSkull penetration)
VARIANTS = [("thesis: voxels + Algorithm 1", "voxels", "algorithm1"),
            ("voxels + deepest point", "voxels", "deepest-point"),
            ("smooth + deepest point", "smooth", "deepest-point")]


def measure(voxel, points, variant, out):
    name, surface, penetration = variant
    tag = f"v{voxel}_p{points}_{surface}_{penetration}"
    run_dir = out / tag
    spec = f"phantom:halfspace?voxel={voxel}&nx={PLANE[0]}&ny={PLANE[1]}&nz={PLANE[2]}&size=40"
    command = [str(PROGRAM), "run", str(SCENE), "--quiet", "--out", str(run_dir),
               "--set", f"/patient/skull.file={spec}", "--set", f"/patient/skull.surface={surface}",
               "--set", f"/patient/skull.penetration={penetration}", "--set", f"/tool/burr.pointCount={points}"]
    subprocess.run(command, check=True)
    norm = math.sqrt(sum(c * c for c in PLANE))
    n = [c / norm for c in PLANE]
    depth_errors, angle_errors = [], []
    for row in read_rows(run_dir / "trace.csv"):
        centre = [float(row[f"device_{a}"]) for a in "xyz"]
        exact = RADIUS - sum(a * b for a, b in zip(n, centre))
        if exact < 0.05:
            continue
        depth_errors.append(abs(float(row["penetration"]) - exact))
        measured = [float(row[f"normal_{a}"]) for a in "xyz"]
        cosine = max(-1.0, min(1.0, sum(a * b for a, b in zip(n, measured))))
        angle_errors.append(math.degrees(math.acos(cosine)))
    times = defaultdict(list)
    for row in read_rows(run_dir / "timings.csv"):
        times[row["component"]].append(float(row["duration_us"]))
    proxy = times["/tool/proxy"]
    return {"variant": name, "voxel_mm": voxel, "shell_points": points, "frames": len(depth_errors),
            "depth_err_mean_mm": sum(depth_errors) / max(1, len(depth_errors)),
            "depth_err_p95_mm": percentile(depth_errors, 0.95), "depth_err_max_mm": max(depth_errors, default=0),
            "normal_err_mean_deg": sum(angle_errors) / max(1, len(angle_errors)),
            "normal_err_p95_deg": percentile(angle_errors, 0.95), "normal_err_max_deg": max(angle_errors, default=0),
            "proxy_p50_us": percentile(proxy, 0.5), "proxy_p99_us": percentile(proxy, 0.99)}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="one voxel size and shell only (smoke test)")
    parser.add_argument("--out", default=str(ROOT / "runs/accuracy_rigid"))
    args = parser.parse_args()
    plt = ensure_matplotlib("accuracy_rigid.py")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    voxels = [1.0] if args.quick else [1.0, 0.5, 0.25]
    shells = [466] if args.quick else [100, 466, 2000]
    rows = []
    for voxel, points, variant in itertools.product(voxels, shells, VARIANTS):
        row = measure(voxel, points, variant, out)
        rows.append(row)
        print(f"{row['variant']:30s} voxel {voxel:4.2f} mm  {points:5d} points  depth err mean "
              f"{row['depth_err_mean_mm']:.3f} p95 {row['depth_err_p95_mm']:.3f} max {row['depth_err_max_mm']:.3f} mm"
              f"  normal err mean {row['normal_err_mean_deg']:5.2f} p95 {row['normal_err_p95_deg']:5.2f} deg"
              f"  proxy p50 {row['proxy_p50_us']:6.2f} p99 {row['proxy_p99_us']:6.2f} us")
    write_rows(out / "accuracy.csv", rows)
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5))
    for variant, marker in zip(VARIANTS, "osD"):
        chosen = [r for r in rows if r["variant"] == variant[0]]
        a.scatter([r["proxy_p50_us"] for r in chosen], [r["depth_err_mean_mm"] for r in chosen], marker=marker,
                  label=variant[0])
        b.scatter([r["proxy_p50_us"] for r in chosen], [r["normal_err_mean_deg"] for r in chosen], marker=marker,
                  label=variant[0])
        for r in chosen:
            a.annotate(f"{r['voxel_mm']}/{r['shell_points']}", (r["proxy_p50_us"], r["depth_err_mean_mm"]), fontsize=6)
    a.set_xlabel("proxy step p50 (us)")
    a.set_ylabel("mean penetration error (mm)")
    b.set_xlabel("proxy step p50 (us)")
    b.set_ylabel("mean normal error (deg)")
    a.set_yscale("log")
    b.set_yscale("log")
    a.legend(fontsize=7)
    fig.suptitle("rigid collision: accuracy against an exact half-space vs time (labels: voxel mm / shell points)")
    fig.tight_layout()
    fig.savefig(out / "accuracy.png", dpi=110)
    print(f"wrote {out / 'accuracy.csv'} and {out / 'accuracy.png'}")


if __name__ == "__main__":
    main()
