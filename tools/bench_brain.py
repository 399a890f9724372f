#!/usr/bin/env python3
"""Deformable collision experiments (thesis section 4.4) on the tetrahedral brain.

usage: tools/bench_brain.py [--quick] [--out DIR] [--only split|scene|paths|margin] [--reuse-split]

1. The step split into refresh, search and the rest (Fig. 4.8 to 4.14):
   build/bin/tet_collision_benchmark on Cube1..Cube7 (Table 4.1) and
   Brain1..Brain5 (Table 4.2) for the grid search and the thesis's scans, on a
   rigid mesh, a mesh whose every node moves every frame (wave) and a local
   bump -> DIR/tet_split.csv, DIR/tet_split_{cube,brain}.png, DIR/tet_moving.png.
2. The whole haptic step per frame in a scene: scenes/bench/tet_circle.xml on
   every mesh (and the real atlas brain, when present) for each search, and
   scenes/bench/tet_wave_circle.xml (every
   node moves) for the grid and the thesis refreshing every box, with
   `build/bin/trephine run` in virtual time -> DIR/tet_scene.csv and
   DIR/tet_frames_{cube,brain}.png (time per frame along the path).
3. Paths 1 to 3 of Table 4.3 (scenes/brain.xml: circle, random-walk, pokes)
   on Brain2, Brain3, Brain4 (and the real atlas mesh when ../shared/data has
   it) -> DIR/tet_paths.csv (force change per frame p99
   and max, NaN frames, ...), DIR/tet_path{1,2,3}.png (normal, penetration,
   force and change of force per frame on Brain3, Fig. 4.15 to 4.17, 4.20,
   4.21) and DIR/tet_paths_penetration.png (Brain2 to 4, Fig. 4.18).
4. Deformations larger than the displacement margin: the wave of
   scenes/bench/tet_wave_circle.xml at amplitudes of 0.25 to 4 mm on Brain3
   and Cube7, with the automatic margin (a quarter of the average edge) and
   margins of 1, 2 and 4 mm: the haptic step's time, the grid's memory and
   the force -> DIR/tet_margin.csv, DIR/tet_margin.png.
--quick keeps Cube1 and Brain1, path 1 and two amplitudes (a smoke test).
"""
import argparse
import json
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

from bench_common import ROOT, ensure_matplotlib, force_steps, percentile, run_scene, write_rows

SPLIT_BENCHMARK = ROOT / "build/bin/tet_collision_benchmark"
CIRCLE = ROOT / "scenes/bench/tet_circle.xml"
WAVE = ROOT / "scenes/bench/tet_wave_circle.xml"
BRAIN_SCENE = ROOT / "scenes/brain.xml"

CUBES = [("Cube1", "phantom:cube?cells=7"), ("Cube2", "phantom:cube?cells=13"), ("Cube3", "phantom:cube?cells=22"),
         ("Cube4", "phantom:cube?cells=30"), ("Cube5", "phantom:cube?cells=40"), ("Cube6", "phantom:cube?cells=50"),
         ("Cube7", "phantom:cube?cells=60")]
BRAINS = [("Brain1", "phantom:brain?tets=3500"), ("Brain2", "phantom:brain?tets=12500"),
          ("Brain3", "phantom:brain?tets=22000"), ("Brain4", "phantom:brain?tets=40500"),
          ("Brain5", "phantom:brain?tets=50000")]
ATLAS = ROOT.parent / "shared/data/brain_tetmesh_mmc_head_atlas/brain_gm_wm.node"
# The real mesh, aimed at the left hemisphere beside the fissure (as scenes/brain_atlas.xml).
ATLAS_SETTINGS = ["/tool/device.center=111 96 180", "/patient/wave.center=111 96 190"]
SEARCHES = ["grid", "first-tetrahedron", "previous-contact"]
PATHS = [("path1", "circle"), ("path2", "random-walk"), ("path3", "pokes")]


def split_experiment(out, quick, plt, rerun):
    json_path = out / "tet_collision.json"
    command = [str(SPLIT_BENCHMARK), "--benchmark_format=console", f"--benchmark_out={json_path}",
               "--benchmark_out_format=json"]
    if quick:
        command.append("--benchmark_filter=BM_TetCollisionStep/(0|7)/")
    if rerun or not json_path.exists():
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    data = json.loads(json_path.read_text())
    rows = []
    for b in data["benchmarks"]:
        if b.get("error_occurred"):
            continue
        mesh, method, motion = b["label"].split("/")
        row = {"mesh": mesh, "tetrahedra": int(b["tetrahedra"]), "method": method, "motion": motion,
               "contact_frames": int(b["contact_frames"]), "frames": int(b["frames"]),
               "colliding_points": int(b.get("colliding_points", 0))}
        for part in ("refresh", "search", "rest", "total"):
            for stat in ("p50", "p99", "max"):
                row[f"{part}_{stat}_us"] = round(b[f"{part}_{stat}_us"], 3)
        rows.append(row)
    write_rows(out / "tet_split.csv", rows)
    context = data.get("context", {})
    print(f"split: {len(rows)} cases on {context.get('num_cpus')} x {context.get('mhz_per_cpu')} MHz -> {out / 'tet_split.csv'}")

    for family in ("Cube", "Brain"):
        chosen = [r for r in rows if r["mesh"].startswith(family) and r["motion"] == "rigid"]
        if not chosen:
            continue
        meshes = sorted({r["mesh"] for r in chosen}, key=lambda m: int(m[len(family):]))
        methods = ["grid", "first-tetrahedron", "previous-contact"]
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
        width = 0.8 / len(methods)
        for k, method in enumerate(methods):
            by_mesh = {r["mesh"]: r for r in chosen if r["method"] == method}
            xs = [i + (k - 1) * width for i in range(len(meshes))]
            search = [by_mesh[m]["search_p50_us"] if m in by_mesh else 0 for m in meshes]
            rest = [by_mesh[m]["rest_p50_us"] if m in by_mesh else 0 for m in meshes]
            axes[0].bar(xs, search, width, label=f"{method}: search", color=f"C{k}")
            axes[0].bar(xs, rest, width, bottom=search, color=f"C{k}", alpha=0.45,
                        label=f"{method}: rest")
            axes[1].bar(xs, [by_mesh[m]["total_p99_us"] if m in by_mesh else 0 for m in meshes], width,
                        label=method, color=f"C{k}")
        for a, title in zip(axes, ("median frame: search + rest", "p99 frame")):
            a.set_xticks(range(len(meshes)))
            a.set_xticklabels([f"{m}\n{next(r['tetrahedra'] for r in chosen if r['mesh'] == m):,}" for m in meshes],
                              fontsize=7)
            a.set_yscale("log")
            a.set_ylabel("us per frame")
            a.set_title(title, fontsize=9)
            a.axhline(1000, color="red", lw=0.6, ls="--")
        axes[0].legend(fontsize=6)
        fig.suptitle(f"{family} meshes, rigid: collision step per frame (211-point tool, 2,500 frames)", fontsize=10)
        fig.tight_layout()
        fig.savefig(out / f"tet_split_{family.lower()}.png", dpi=110)
        plt.close(fig)

    moving = [r for r in rows if r["motion"] != "rigid"]
    if moving:
        meshes = [m for m, _ in CUBES + BRAINS if any(r["mesh"] == m for r in moving)]
        variants = [("grid", "wave"), ("previous-contact", "wave"), ("previous-contact", "bump"),
                    ("previous-contact+moved", "bump")]
        fig, a = plt.subplots(figsize=(11, 4.2))
        width = 0.8 / len(variants)
        for k, (method, motion) in enumerate(variants):
            by_mesh = {r["mesh"]: r for r in moving if r["method"] == method and r["motion"] == motion}
            xs = [i + (k - 1.5) * width for i in range(len(meshes))]
            a.bar(xs, [by_mesh[m]["total_p99_us"] if m in by_mesh else 0 for m in meshes], width,
                  label=f"{method}, {motion} (p99)", color=f"C{k}")
            a.plot(xs, [by_mesh[m]["total_p50_us"] if m in by_mesh else 0 for m in meshes], "k_", ms=6)
        a.set_xticks(range(len(meshes)))
        a.set_xticklabels(meshes, fontsize=7)
        a.set_yscale("log")
        a.set_ylabel("us per frame (bar p99, dash p50)")
        a.axhline(50, color="green", lw=0.6, ls="--")
        a.axhline(100, color="orange", lw=0.6, ls="--")
        a.legend(fontsize=7)
        a.set_title("moving meshes: refresh + search + rest per frame (wave: every node moves every frame)",
                    fontsize=10)
        fig.tight_layout()
        fig.savefig(out / "tet_moving.png", dpi=110)
        plt.close(fig)


def scene_experiment(out, quick, plt):
    meshes = [CUBES[0], BRAINS[0]] if quick else CUBES + BRAINS
    if not quick:
        if ATLAS.exists():
            meshes.append(("Atlas", str(ATLAS)))
        else:
            print(f"bench_brain.py: {ATLAS} not found, the real brain mesh is skipped", file=sys.stderr)
    rows, series = [], defaultdict(dict)
    cases = [(CIRCLE, "rigid", s, []) for s in SEARCHES]
    cases += [(WAVE, "wave", "grid", []), (WAVE, "wave", "previous-contact", ["/patient/brain.boxRefresh=all"])]
    for (name, spec) in meshes:
        for scene, motion, search, extra in cases:
            run_dir = out / f"scene_{name}_{search}_{motion}"
            place = [x for x in ATLAS_SETTINGS if scene == WAVE or "/tool/" in x] if name == "Atlas" else []
            r = run_scene(scene, run_dir, [f"/patient/brain.file={spec}", f"/patient/brain.search={search}"] + extra + place)
            h = r["summary"]["haptics"]
            brain = r["summary"]["components"]["/patient/brain"]["counters"]
            row = {"mesh": name, "tetrahedra": int(brain["tetrahedra"]), "search": search, "motion": motion,
                   "proxy_p50_us": percentile(r["proxy_us"], 0.5), "proxy_p99_us": percentile(r["proxy_us"], 0.99),
                   "proxy_max_us": max(r["proxy_us"]), "step_p50_us": percentile(r["step_us"], 0.5),
                   "step_p99_us": percentile(r["step_us"], 0.99), "step_max_us": max(r["step_us"]),
                   "frames_over_1ms": sum(1 for s in r["step_us"] if s > 1000.0),
                   # The wave's own tick (it publishes every node): the deformation's cost, not the collision's.
                   "deformation_p50_us": percentile(list(r["per_call"].get("/patient/wave", {}).values()), 0.5)
                   if "/patient/wave" in r["per_call"] else 0.0,
                   "contact_frames": h["contact_frames"], "force_step_max_N": h["force_step_N"]["max"],
                   "nan_frames": h["nan_frames"], "proxy_inside_frames": h["proxy_inside_frames"]}
            rows.append(row)
            series[(motion, search)][name] = r["proxy_us"]
            print(f"{name:7s} {motion:5s} {search:17s} step p50 {row['step_p50_us']:8.2f} us  p99 "
                  f"{row['step_p99_us']:8.2f}  max {row['step_max_us']:9.1f}  over 1 ms {row['frames_over_1ms']}")
    write_rows(out / "tet_scene.csv", rows)
    for family in ("Cube", "Brain"):  # (the atlas is drawn with the brains)
        keys = [k for k in series if any(m.startswith(family) for m in series[k])]
        if not keys:
            continue
        fig, axes = plt.subplots(len(keys), 1, figsize=(9, 2.2 * len(keys)), sharex=True)
        for a, key in zip(axes, keys):
            for name, values in series[key].items():
                if name.startswith(family) or (family == "Brain" and name == "Atlas"):
                    a.plot(values, lw=0.5, label=name)
            a.set_yscale("log")
            a.set_ylabel("us")
            a.set_title(f"{key[1]}, {key[0]} mesh: collision (proxy) step per frame", fontsize=8)
            a.axhline(1000, color="red", lw=0.6, ls="--")
        axes[0].legend(fontsize=6, ncol=4)
        axes[-1].set_xlabel("frame")
        fig.tight_layout()
        fig.savefig(out / f"tet_frames_{family.lower()}.png", dpi=110)
        plt.close(fig)


def paths_experiment(out, quick, plt):
    meshes = [BRAINS[0]] if quick else BRAINS[1:4]
    if not quick and ATLAS.exists():
        meshes.append(("Atlas", str(ATLAS)))
    paths = PATHS[:1] if quick else PATHS
    rows, traces = [], {}
    for (name, spec) in meshes:
        for label, path in paths:
            run_dir = out / f"path_{name}_{label}"
            place = ATLAS_SETTINGS[:1] if name == "Atlas" else []
            r = run_scene(BRAIN_SCENE, run_dir, [f"/patient/brain.file={spec}", f"/tool/device.path={path}"] + place)
            h = r["summary"]["haptics"]
            steps = force_steps(r["trace"])
            contact = [float(t["penetration"]) for t in r["trace"] if int(t["contacts"]) > 0]
            rows.append({"mesh": name, "path": f"{label} ({path})", "frames": h["frames"],
                         "contact_frames": h["contact_frames"], "force_max_N": round(h["force_N"]["max"], 4),
                         "force_step_p99_N": round(percentile(steps, 0.99), 4),
                         "force_step_max_N": round(max(steps), 4),
                         "penetration_max_mm": round(max(contact) if contact else 0.0, 4),
                         "nan_frames": h["nan_frames"], "proxy_inside_frames": h["proxy_inside_frames"],
                         "step_p99_us": round(percentile(r["step_us"], 0.99), 2)})
            traces[(name, label)] = r["trace"]
            print(f"{name:7s} {label} dF p99 {rows[-1]['force_step_p99_N']:.4f} N  max {rows[-1]['force_step_max_N']:.4f}"
                  f"  |F| max {rows[-1]['force_max_N']:.3f}  NaN {rows[-1]['nan_frames']}")
    write_rows(out / "tet_paths.csv", rows)
    shown = "Brain3" if not quick else meshes[0][0]
    for label, path in paths:
        trace = traces[(shown, label)]
        t = [float(x["t"]) for x in trace]
        fig, axes = plt.subplots(4, 1, figsize=(9, 9), sharex=True)
        for k in ("normal_x", "normal_y", "normal_z"):
            axes[0].plot(t, [float(x[k]) for x in trace], lw=0.6, label=k)
        axes[0].set_ylabel("contact normal")
        axes[0].legend(fontsize=7)
        axes[1].plot(t, [float(x["penetration_raw"]) for x in trace], lw=0.6, label="raw (detection)")
        axes[1].plot(t, [float(x["penetration"]) for x in trace], lw=0.6, label="rendered")
        axes[1].set_ylabel("penetration (mm)")
        axes[1].legend(fontsize=7)
        for k in ("force_x", "force_y", "force_z"):
            axes[2].plot(t, [float(x[k]) for x in trace], lw=0.6, label=k)
        axes[2].set_ylabel("force (N)")
        axes[2].legend(fontsize=7)
        for k in ("force_x", "force_y", "force_z"):
            v = [float(x[k]) for x in trace]
            axes[3].plot(t, [0.0] + [v[i] - v[i - 1] for i in range(1, len(v))], lw=0.6, label=f"d{k}")
        axes[3].set_ylabel("change per frame (N)")
        axes[3].legend(fontsize=7)
        axes[3].set_xlabel("t (s)")
        axes[0].set_title(f"{shown}, {label} ({path}), k = 0.3 N/mm", fontsize=10)
        fig.tight_layout()
        fig.savefig(out / f"tet_{label}.png", dpi=110)
        plt.close(fig)
    fig, axes = plt.subplots(len(paths), 1, figsize=(9, 2.6 * len(paths)), squeeze=False)
    for a, (label, path) in zip(axes[:, 0], paths):
        for (name, _) in meshes:
            trace = traces[(name, label)]
            a.plot([float(x["t"]) for x in trace], [float(x["penetration"]) for x in trace], lw=0.6, label=name)
        a.set_ylabel("penetration (mm)")
        a.set_title(f"{label} ({path})", fontsize=9)
        a.legend(fontsize=7)
    axes[-1, 0].set_xlabel("t (s)")
    fig.tight_layout()
    fig.savefig(out / "tet_paths_penetration.png", dpi=110)
    plt.close(fig)


def margin_experiment(out, quick, plt):
    """The wave's amplitude bounds every node's displacement; queries widen
    by whatever exceeds the grid's margin. Time against amplitude for each margin."""
    meshes = [BRAINS[0]] if quick else [BRAINS[2], CUBES[6]]
    amplitudes = [0.5, 2.0] if quick else [0.25, 0.5, 1.0, 2.0, 4.0]
    margins = [0.0] if quick else [0.0, 1.0, 2.0, 4.0]  # mm; 0: automatic (a quarter of the average edge)
    rows = []
    for name, spec in meshes:
        for margin in margins:
            for amplitude in amplitudes:
                run_dir = out / f"margin_{name}_{margin:g}_{amplitude:g}"
                r = run_scene(WAVE, run_dir, [f"/patient/brain.file={spec}", f"/patient/wave.amplitude={amplitude}",
                                             f"/patient/brain.displacementMargin={margin}"])
                h = r["summary"]["haptics"]
                brain = r["summary"]["components"]["/patient/brain"]["counters"]
                row = {"mesh": name, "tetrahedra": int(brain["tetrahedra"]),
                       "margin_mm": brain["displacement_margin_mm"], "margin_setting": "auto" if margin == 0 else margin,
                       "amplitude_mm": amplitude, "frames_beyond_margin": int(brain["frames_beyond_margin"]),
                       "grid_entries": int(brain["grid_entries"]),
                       "step_p50_us": percentile(r["step_us"], 0.5), "step_p99_us": percentile(r["step_us"], 0.99),
                       "step_max_us": max(r["step_us"]), "contact_frames": h["contact_frames"],
                       "force_step_max_N": h["force_step_N"]["max"], "nan_frames": h["nan_frames"],
                       "proxy_inside_frames": h["proxy_inside_frames"]}
                rows.append(row)
                print(f"{name:7s} margin {row['margin_mm']:5.2f} mm amplitude {amplitude:4.2f} mm: step p50 "
                      f"{row['step_p50_us']:8.2f} us  p99 {row['step_p99_us']:8.2f}  max {row['step_max_us']:9.1f}  "
                      f"grid entries {row['grid_entries']}  beyond {row['frames_beyond_margin']}")
    write_rows(out / "tet_margin.csv", rows)
    fig, axes = plt.subplots(1, len(meshes), figsize=(5 * len(meshes), 3.4), squeeze=False)
    for a, (name, _) in zip(axes[0], meshes):
        for margin in margins:
            mine = [r for r in rows if r["mesh"] == name and r["margin_setting"] == ("auto" if margin == 0 else margin)]
            label = f"margin auto ({mine[0]['margin_mm']:.2f} mm)" if margin == 0 else f"margin {margin:g} mm"
            a.plot([r["amplitude_mm"] for r in mine], [r["step_p99_us"] for r in mine], marker="o", label=label)
        a.set_xscale("log", base=2)
        a.set_yscale("log")
        a.axhline(1000, color="red", lw=0.6, ls="--")
        a.set_xlabel("wave amplitude = displacement bound (mm)")
        a.set_ylabel("haptic step p99 (us)")
        a.set_title(f"{name}: every node moving, grid search", fontsize=9)
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "tet_margin.png", dpi=110)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", default=str(ROOT / "runs/bench_brain"))
    parser.add_argument("--reuse-split", action="store_true",
                        help="draw the split from DIR/tet_collision.json of an earlier run instead of running it")
    parser.add_argument("--only", choices=["split", "scene", "paths", "margin"], help="run one experiment")
    args = parser.parse_args()
    plt = ensure_matplotlib("bench_brain.py")

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.only in (None, "split"):
        split_experiment(out, args.quick, plt, rerun=not args.reuse_split)
    if args.only in (None, "scene"):
        scene_experiment(out, args.quick, plt)
    if args.only in (None, "paths"):
        paths_experiment(out, args.quick, plt)
    if args.only in (None, "margin"):
        margin_experiment(out, args.quick, plt)
    print(f"wrote CSV files and figures in {out}")


if __name__ == "__main__":
    main()
