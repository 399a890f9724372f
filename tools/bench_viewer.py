#!/usr/bin/env python3
"""The browser viewer on the scenes of docs/results.md: how long `trephine
view` takes, what it packs, and in headless Chromium (software WebGL) how
long the viewer takes to draw its first frame and how many of the run's 30
frames a second it draws while playing.

usage: tools/bench_viewer.py [--rounds N] [--out DIR] [--triangles N,...]
       tools/bench_viewer.py --views [--out DIR]

Cases: scenes/integrated.xml (the 1 mm skull drilled, the deforming brain,
the tool) and scenes/bench/craniotomy_view.xml (the 0.5 mm skull drilled),
each run once, then written with each skull budget (--triangles, default
8000, the default of trephine view) and opened N times (default 3,
interleaved) by tests/plugins/viewer/browser/viewerBrowserTest.mjs. Writes
DIR/viewer.csv (default runs/bench-viewer) and prints a table of medians.
Needs Chromium (/usr/bin/chromium) and the viewer's packages (tools/setup).

--views: what each way of looking costs, on the default scene at 14.5 s (the
probe pressing the brain): the opening time and the time to draw one still
frame (median and 90th percentile of 30,
tests/plugins/viewer/browser/viewerFrameTimes.mjs) with the brain in its
tissue colour, coloured by displacement, by stress with the skull by
density, with the CT volume, and two runs side by side (the second with a
brain twice as stiff). Writes DIR/views.csv.
"""
import argparse
import json
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

from bench_common import PROGRAM, ROOT, write_rows

CASES = [
    ("integrated (1 mm skull, brain)", ROOT / "scenes/integrated.xml", "4,14", "skull,brain,tool"),
    ("craniotomy (0.5 mm skull)", ROOT / "scenes/bench/craniotomy_view.xml", "2,8", "skull,tool"),
]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--out", type=Path, default=ROOT / "runs/bench-viewer")
    parser.add_argument("--triangles", default="8000")
    parser.add_argument("--views", action="store_true")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    if args.views:
        return views(args.out)
    rows = []
    for name, scene, times, parts in CASES:
        run = args.out / scene.stem
        subprocess.run([str(PROGRAM), "run", str(scene), "--quiet", "--out", str(run)], check=True)
        for budget in args.triangles.split(","):
            start = time.perf_counter()
            view = subprocess.run([str(PROGRAM), "view", str(run), "--triangles", budget], check=True,
                                  capture_output=True, text=True).stdout
            seconds = time.perf_counter() - start
            size = sum(f.stat().st_size for f in (run / "view/data").iterdir())
            moving = re.search(r"drawn as (\d+)", view)
            still = re.search(r"(\d+) when still", view)
            full = re.search(r"skull: (\d+) triangles", view)
            results = []
            for r in range(args.rounds):
                out = args.out / f"{scene.stem}-{budget}-{r}"
                subprocess.run(["node", str(ROOT / "tests/plugins/viewer/browser/viewerBrowserTest.mjs"), "--web",
                                str(ROOT / "plugins/viewer/web"), "--view", str(run / "view"), "--out", str(out),
                                "--times", times, "--parts", parts, "--min-fps", "1", "--open-limit", "100"],
                               check=False, capture_output=True)
                results.append(json.loads((out / "results.json").read_text()))
            rows.append({
                "case": name, "budget": budget, "skull_triangles": full.group(1) if full else "",
                "moving_triangles": moving.group(1) if moving else "", "still_triangles": still.group(1) if still else "",
                "view_s": f"{seconds:.2f}", "data_mb": f"{size / 1e6:.1f}",
                "open_s": f"{statistics.median(r['openSeconds'] for r in results):.2f}",
                "open_max_s": f"{max(r['openSeconds'] for r in results):.2f}",
                "play_fps": f"{statistics.median(r['playFps'] for r in results):.1f}",
                "play_fps_min": f"{min(r['playFps'] for r in results):.1f}",
                "run_fps": f"{statistics.median(r['runFramesPerSecond'] for r in results):.1f}",
                "failures": sum(len(r["failures"]) for r in results),
                "renderer": results[0]["renderer"],
            })
            print(rows[-1], flush=True)
    write_rows(args.out / "viewer.csv", rows)
    print("\n| case | skull budget | skull triangles: files / moving / still | trephine view (s) | data (MB) "
          "| opens in (s), median (max) | frames drawn a second playing, median (min) of the run's |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['case']} | {r['budget']} | {r['skull_triangles']} / {r['moving_triangles']} / "
              f"{r['still_triangles']} | {r['view_s']} | {r['data_mb']} | {r['open_s']} ({r['open_max_s']}) | "
              f"{r['play_fps']} ({r['play_fps_min']}) of {r['run_fps']} |")
    print(f"\nrenderer: {rows[0]['renderer']}")
    return 0


VIEWS = [
    ("brain in its tissue colour", "t=14.5&brain=tissue"),
    ("brain by displacement (the default)", "t=14.5"),
    ("brain by stress, skull by density", "t=14.5&brain=stress&skull=density"),
    ("CT volume (skull surface hidden)", "t=14.5&ct=1&hide=skull"),
]


def views(out):
    scene = ROOT / "scenes/integrated.xml"
    runs = [out / "views-a", out / "views-b"]
    subprocess.run([str(PROGRAM), "run", str(scene), "--quiet", "--out", str(runs[0])], check=True)
    subprocess.run([str(PROGRAM), "run", str(scene), "--quiet", "--out", str(runs[1]),
                    "--set", "/patient/fem.youngModulus=60"], check=True)
    subprocess.run([str(PROGRAM), "view", str(runs[0])], check=True, capture_output=True)
    subprocess.run([str(PROGRAM), "view", str(runs[0]), str(runs[1]), "--out", str(out / "views-both")], check=True,
                   capture_output=True)
    script = ROOT / "tests/plugins/viewer/browser/viewerFrameTimes.mjs"
    rows = []
    for view, cases in ((runs[0] / "view", VIEWS), (out / "views-both", [("two runs side by side", "t=14.5")])):
        result = out / "views.json"
        subprocess.run(["node", str(script), "--web", str(ROOT / "plugins/viewer/web"), "--view", str(view),
                        "--queries", "|".join(q for _, q in cases), "--out", str(result)], check=True)
        for (name, query), r in zip(cases, json.loads(result.read_text())):
            rows.append({"view": name, "query": query, "open_s": f"{r['openSeconds']:.2f}",
                         "render_median_ms": f"{r['renderMedianMs']:.1f}", "render_p90_ms": f"{r['renderP90Ms']:.1f}"})
    write_rows(out / "views.csv", rows)
    print("\n| view | URL | opens in (s) | one still frame (ms), median (p90) |")
    print("|---|---|---|---|")
    for r in rows:
        print(f"| {r['view']} | `{r['query']}` | {r['open_s']} | {r['render_median_ms']} ({r['render_p90_ms']}) |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
