#!/usr/bin/env python3
"""Rigid collision experiments (thesis section 3.4) on scenes/bench/rigid_circle.xml.

usage: tools/bench_rigid.py [--quick] [--out DIR] [--ct PATH] [--surfaces smooth,voxels]

Runs the same 2,500-frame path on Cube100..Cube500 (Table 3.1), Skull1..Skull5
(Table 3.2, phantom) and, when present, the real CT head, each for the touch
and the drill task, and for each bone surface of VoxelSkull (smooth: the
project's trilinear isosurface; voxels: the thesis's voxel boxes), with
`build/bin/trephine run` in virtual time. From each
run's timings.csv, trace.csv and summary.json it writes DIR/rigid.csv (one row
per model and task: haptic group and proxy time p50/p99/max in us, colliding
voxels, force figures) and the figures DIR/rigid_{cube,skull}_{touch,drill}.png
(time per frame and colliding voxels per frame, as the thesis's Fig. 3.11 to
3.15) and DIR/rigid_force_{touch,drill}.png (normal, raw and rectified
penetration, force and change of force per frame, Fig. 3.17 to 3.26).
--quick runs two small models only (a smoke test).
"""
import argparse
import itertools
import sys
from pathlib import Path

from bench_common import ROOT, ensure_matplotlib, force_steps, percentile, run_scene, write_rows

SCENE = ROOT / "scenes/bench/rigid_circle.xml"
DEFAULT_CT = ROOT.parent / "shared/data/ct_head_vtk_headsq/quarter.nhdr"

CUBES = [("Cube100", "phantom:cube?voxels=100"), ("Cube200", "phantom:cube?voxels=200"),
         ("Cube300", "phantom:cube?voxels=300"), ("Cube400", "phantom:cube?voxels=400"),
         ("Cube450", "phantom:cube?voxels=450"), ("Cube500", "phantom:cube?voxels=500")]
SKULLS = [("Skull1", "phantom:skull?voxel=1.5"), ("Skull2", "phantom:skull?voxel=1.25"),
          ("Skull3", "phantom:skull?voxel=1.0"), ("Skull4", "phantom:skull?voxel=0.75"),
          ("Skull5", "phantom:skull?voxel=0.5")]


def run(name, task, surface, settings, out):
    return run_scene(SCENE, out / f"{name}_{task}_{surface}",
                     settings + [f"/patient/skull.drill={'true' if task == 'drill' else 'false'}",
                                 f"/patient/skull.surface={surface}"]
                     # The thesis's experiments drill with the thesis's law (a fixed rate per frame).
                     + (["/patient/skull.removal=thesis"] if task == "drill" else []))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", default=str(ROOT / "runs/bench_rigid"))
    parser.add_argument("--ct", default=str(DEFAULT_CT))
    parser.add_argument("--surfaces", default="smooth,voxels")
    args = parser.parse_args()
    plt = ensure_matplotlib("bench_rigid.py")

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    models = [("cube", n, [f"/patient/skull.file={f}"]) for n, f in CUBES]
    models += [("skull", n, [f"/patient/skull.file={f}"]) for n, f in SKULLS]
    if Path(args.ct).exists():
        # The real CT (raw units, bone above about 1150), resampled to 1 mm and 0.5 mm voxels. Its top is
        # cropped (a vertical approach enters the open skull), so the burr comes from the side.
        for size in ("1.0", "0.5"):
            models.append(("ct", f"CT-head-{size}mm", [f"/patient/skull.file={args.ct}", "/patient/skull.isovalue=1150",
                                                       f"/patient/skull.voxelSize={size}",
                                                       "/tool/device.direction=-1 0 0"]))
    else:
        print(f"bench_rigid.py: {args.ct} not found, the real CT head is skipped", file=sys.stderr)
    if args.quick:
        models = [models[0], models[len(CUBES)]]

    results = {}
    rows = []
    surfaces = args.surfaces.split(",")
    for (family, name, settings), surface, task in itertools.product(models, surfaces, ("touch", "drill")):
        r = run(name, task, surface, settings, out)
        results[(name, task, surface)] = (family, r)
        h = r["summary"]["haptics"]
        voxels = [int(t["primitives"]) for t in r["trace"]]
        rows.append({
            "model": name, "task": task, "surface": surface,
            "step_p50_us": percentile(r["step_us"], 0.5), "step_p99_us": percentile(r["step_us"], 0.99),
            "step_max_us": max(r["step_us"]),
            "proxy_p50_us": percentile(r["proxy_us"], 0.5), "proxy_p99_us": percentile(r["proxy_us"], 0.99),
            "proxy_max_us": max(r["proxy_us"]),
            "frames_over_1ms": sum(1 for s in r["step_us"] if s > 1000.0),
            "max_colliding_voxels": max(voxels), "contact_frames": h["contact_frames"],
            "force_max_N": h["force_N"]["max"], "force_step_max_N": h["force_step_N"]["max"],
            "force_step_p99_N": h["force_step_N"]["p99"], "nan_frames": h["nan_frames"],
            "proxy_inside_frames": h["proxy_inside_frames"],
            "voxels_removed": r["summary"]["drilling"]["voxels_removed"],
        })
        print(f"{name:16s} {surface:6s} {task:5s} step p50 {rows[-1]['step_p50_us']:7.2f} us  p99 {rows[-1]['step_p99_us']:7.2f}"
              f"  max {rows[-1]['step_max_us']:8.1f}  voxels<= {rows[-1]['max_colliding_voxels']:4d}"
              f"  |F|max {rows[-1]['force_max_N']:.2f} N  dF max {rows[-1]['force_step_max_N']:.3f} N"
              f"  inside {rows[-1]['proxy_inside_frames']}")
    write_rows(out / "rigid.csv", rows)

    for family, surface, task in itertools.product(("cube", "skull", "ct"), surfaces, ("touch", "drill")):
        chosen = [(n, r) for (n, t, sf), (fam, r) in results.items() if fam == family and t == task and sf == surface]
        if not chosen:
            continue
        fig, (a, b) = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
        for name, r in chosen:
            a.plot(r["proxy_us"], lw=0.6, label=name)
            b.plot([int(t["primitives"]) for t in r["trace"]], lw=0.6, label=name)
        a.set_ylabel("collision handling (us)")
        a.set_title(f"{family} models, {surface} surface, {task}: proxy step per frame")
        a.legend(fontsize=7)
        b.set_ylabel("colliding voxels")
        b.set_xlabel("frame")
        fig.tight_layout()
        fig.savefig(out / f"rigid_{family}_{surface}_{task}.png", dpi=110)
        plt.close(fig)

    force_model = next((n for n in ("Skull5", "Skull3") if (n, "touch", surfaces[0]) in results), None)
    if force_model is None:
        force_model = next(iter(results))[0]
    for surface, task in itertools.product(surfaces, ("touch", "drill")):
        r = results[(force_model, task, surface)][1]
        t = [float(x["t"]) for x in r["trace"]]
        fig, axes = plt.subplots(4, 1, figsize=(9, 9), sharex=True)
        for k in ("normal_x", "normal_y", "normal_z"):
            axes[0].plot(t, [float(x[k]) for x in r["trace"]], lw=0.6, label=k)
        axes[0].set_ylabel("contact normal")
        axes[0].legend(fontsize=7)
        axes[1].plot(t, [float(x["penetration_raw"]) for x in r["trace"]], lw=0.6, label="raw (detection)")
        axes[1].plot(t, [float(x["penetration"]) for x in r["trace"]], lw=0.6, label="rectified")
        axes[1].set_ylabel("penetration (mm)")
        axes[1].legend(fontsize=7)
        force = [(float(x["force_x"]) ** 2 + float(x["force_y"]) ** 2 + float(x["force_z"]) ** 2) ** 0.5
                 for x in r["trace"]]
        axes[2].plot(t, force, lw=0.6)
        axes[2].set_ylabel("|F| (N)")
        axes[3].plot(t, force_steps(r["trace"]), lw=0.6)
        axes[3].set_ylabel("|F_k - F_k-1| (N)")
        axes[3].set_xlabel("t (s)")
        axes[0].set_title(f"force parameters, {force_model}, {surface} surface, {task}")
        fig.tight_layout()
        fig.savefig(out / f"rigid_force_{surface}_{task}.png", dpi=110)
        plt.close(fig)
    print(f"wrote {out / 'rigid.csv'} and figures in {out}")


if __name__ == "__main__":
    main()
