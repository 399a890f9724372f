#!/usr/bin/env python3
"""OpenIGTLink in a running scene: scenes/devices/igtl_plane.xml in real time,
driven by a tracker on Debian's libopenigtlink (build/bin/igtl_tracker_client)
sending TRANSFORMs at each rate asked, against the same scene's haptic step
with a scripted device (scenes/examples/plane_touch.xml), in one run of this
script. Writes igtlink.csv and igtlink.md into --out.

  tools/bench_igtlink.py --duration 60 --rates 100,500,1000 --out build/bench_igtlink"""
import argparse
import json
import os
import platform
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_common import PROGRAM, ROOT, write_rows  # noqa: E402

CLIENT = ROOT / "build/bin/igtl_tracker_client"


def haptic_group(summary):
    return summary["groups"]["1000"]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--duration", type=float, default=60.0)
    parser.add_argument("--rates", default="100,500,1000", help="tracker rates (Hz), comma-separated")
    parser.add_argument("--quick", action="store_true", help="3 s runs")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    if not CLIENT.exists():
        sys.exit(f"bench_igtlink: {CLIENT} is not built (libopenigtlink-dev missing?)")
    duration = 3.0 if args.quick else args.duration
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    # The same scene's step with a scripted device: the baseline.
    base = args.out / "scripted"
    subprocess.run([str(PROGRAM), "run", str(ROOT / "scenes/examples/plane_touch.xml"), "--realtime", "--quiet",
                    "--duration", str(duration), "--out", str(base)], check=True)
    g = haptic_group(json.loads((base / "summary.json").read_text()))
    rows.append({"case": "scripted device", "tracker_hz": "", "step_p50_us": g["time_us"]["p50"],
                 "step_p99_us": g["time_us"]["p99"], "deadline_misses": g["deadline_misses"]})
    port = 19000 + os.getpid() % 1000
    for hz in [float(r) for r in args.rates.split(",")]:
        run = args.out / f"tracker_{hz:g}hz"
        sim = subprocess.Popen([str(PROGRAM), "run", str(ROOT / "scenes/devices/igtl_plane.xml"), "--realtime",
                                "--quiet", "--duration", str(duration), "--out", str(run),
                                "--set", f"/tool/device.port={port}"])
        client = subprocess.run([str(CLIENT), str(port), str(hz), str(duration + 1.0), "0", "0", "1.5"],
                                capture_output=True, text=True)
        if sim.wait() != 0 or client.returncode != 0:
            sys.exit(f"bench_igtlink: {hz:g} Hz failed: {client.stderr}")
        seen = json.loads(client.stdout)
        summary = json.loads((run / "summary.json").read_text())
        g = haptic_group(summary)
        d = summary["components"]["/tool/device"]["counters"]
        rows.append({"case": "IGTLinkDevice", "tracker_hz": round(seen["transform_hz"], 1),
                     "step_p50_us": g["time_us"]["p50"], "step_p99_us": g["time_us"]["p99"],
                     "deadline_misses": g["deadline_misses"], "transforms_received": d["transforms_received"],
                     "sensors_sent": d["sensors_sent"], "sensors_received": seen["sensors_received"],
                     "bad_sensors": seen["bad_sensors"], "last_force_z_N": seen["last_force_z_N"]})
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    rows = [{k: r.get(k, "") for k in keys} for r in rows]
    write_rows(args.out / "igtlink.csv", rows)
    with open(args.out / "igtlink.md", "w") as f:
        f.write(f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; "
                f"{duration:g} s per case.\n\n| " + " | ".join(keys) + " |\n|" + "---|" * len(keys) + "\n")
        for r in rows:
            f.write("| " + " | ".join(str(r[k]) for k in keys) + " |\n")
    print((args.out / "igtlink.md").read_text())


if __name__ == "__main__":
    main()
