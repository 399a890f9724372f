#!/usr/bin/env python3
"""The device bridge across the process boundary: `trephine run` of a bridged
scene and of the device emulator beside it, both in real time, and what each
side saw (summary.json). Writes bridge.csv and bridge.md into --out.

  tools/bench_bridge.py --duration 60 --out build/bench_bridge

Cases (--cases, comma-separated; all by default):
  plane-shm, plane-udp      the plane scene (the round trip is nearly all transport), 1 kHz
  plane-shm-4k              the same at 4 kHz (every component of both haptic groups)
  drill-shm, drill-udp      the drilling scene, the hand pressing at the force limit, 1 kHz
  drill-inprocess           the same hand in the simulation's own process (HandDevice), for comparison
--quick runs each for 3 s."""
import argparse
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_common import PROGRAM, ROOT, percentile, read_rows, write_rows  # noqa: E402

DEVICES = ROOT / "scenes/devices"

CASES = {
    "plane-shm": ("bridge_plane.xml", "hand_emulator_plane.xml", "shm", 1000),
    "plane-udp": ("bridge_plane.xml", "hand_emulator_plane.xml", "udp", 1000),
    "plane-shm-4k": ("bridge_plane.xml", "hand_emulator_plane.xml", "shm", 4000),
    "drill-shm": ("bridge_drill.xml", "hand_emulator_drill.xml", "shm", 1000),
    "drill-udp": ("bridge_drill.xml", "hand_emulator_drill.xml", "udp", 1000),
    "drill-inprocess": None,
}

SIM_HAPTIC = {"bridge_plane.xml": ["/tool/device", "/tool/force"],
              "bridge_drill.xml": ["/tool/device", "/tool/proxy", "/tool/force"]}
EMU_HAPTIC = ["/tool/intent", "/tool/hand", "/tool/device"]


def settings(components, transport, rate, side, port):
    out = []
    for c in components:
        out += ["--set", f"{c}.rate={rate}"]
    if transport == "udp":
        out += ["--set", "/tool/device.transport=udp"]
        key = "address" if side == "sim" else "peer"
        out += ["--set", f"/tool/device.{key}=127.0.0.1:{port}"]
    else:
        out += ["--set", f"/tool/device.channel=/trephine-bench-{os.getpid()}"]
    return out


def run_pair(name, sim_scene, emu_scene, transport, rate, duration, out):
    port = 27400 + os.getpid() % 500
    sim_dir, emu_dir = out / name / "sim", out / name / "emulator"
    sim = subprocess.Popen([str(PROGRAM), "run", str(DEVICES / sim_scene), "--realtime", "--quiet",
                            "--duration", str(duration), "--out", str(sim_dir)]
                           + settings(SIM_HAPTIC[sim_scene], transport, rate, "sim", port))
    emu = subprocess.Popen([str(PROGRAM), "run", str(DEVICES / emu_scene), "--realtime", "--quiet",
                            "--duration", str(duration + 1.0), "--out", str(emu_dir)]
                           + settings(EMU_HAPTIC, transport, rate, "emu", port))
    if sim.wait() != 0 or emu.wait() != 0:
        sys.exit(f"bench_bridge: {name}: a run failed ({sim.returncode}, {emu.returncode})")
    return json.loads((sim_dir / "summary.json").read_text()), json.loads((emu_dir / "summary.json").read_text()), \
        sim_dir


def unexplained(summary):
    h = summary["haptics"]
    # SpringForce renders no proxy: its steps are not split into explained and not.
    nothing = {"max": float("nan"), "p99": float("nan")}
    return h.get("force_step_unexplained_N", nothing), h["passivity"], h["force_N"], h


def row_for(name, transport, rate, sim, emu):
    d = sim["components"]["/tool/device"]["counters"]
    e = emu["components"]["/tool/device"]["counters"]
    group = next(iter(sim["groups"].values()))
    steps, passivity, force, h = unexplained(sim)
    return {
        "case": name, "transport": transport, "rate_hz": rate, "frames": h["frames"],
        "round_trip_p50_us": round(d["round_trip_p50_us"], 1), "round_trip_p99_us": round(d["round_trip_p99_us"], 1),
        "round_trip_max_us": round(d["round_trip_max_us"], 1), "round_trips": int(d["round_trips_measured"]),
        "late_answers": int(e["late_answers"]), "poses_lost": int(d["poses_lost"]),
        "poses_stale": int(d["poses_stale"]), "watchdog_trips": int(d["watchdog_trips"]),
        "device_watchdog_trips": int(e["watchdog_trips"]),
        "paced_frames": group.get("paced_frames", 0), "unpaced_frames": group.get("unpaced_frames", 0),
        "step_p99_us": round(group["time_us"]["p99"], 1),
        "force_max_N": round(force["max"], 3), "unexplained_p99_N": round(steps["p99"], 4),
        "unexplained_max_N": round(steps["max"], 4), "min_energy_mJ": round(passivity["min_energy_in_mJ"], 4),
        "nan_frames": h["nan_frames"], "proxy_inside_frames": h.get("proxy_inside_frames", 0),
    }


def run_inprocess(duration, out):
    """The drilling case's hand in the simulation's own process, in real time."""
    run_dir = out / "drill-inprocess"
    subprocess.run([str(PROGRAM), "run", str(ROOT / "scenes/bench/hand_drill.xml"), "--realtime", "--quiet",
                    "--duration", str(duration), "--out", str(run_dir), "--set", "/tool/intent.depth=25"],
                   check=True)
    sim = json.loads((run_dir / "summary.json").read_text())
    steps, passivity, force, h = unexplained(sim)
    group = next(iter(sim["groups"].values()))
    return {"case": "drill-inprocess", "transport": "-", "rate_hz": 1000, "frames": h["frames"],
            "step_p99_us": round(group["time_us"]["p99"], 1), "force_max_N": round(force["max"], 3),
            "unexplained_p99_N": round(steps["p99"], 4), "unexplained_max_N": round(steps["max"], 4),
            "min_energy_mJ": round(passivity["min_energy_in_mJ"], 4), "nan_frames": h["nan_frames"],
            "proxy_inside_frames": h.get("proxy_inside_frames", 0)}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--duration", type=float, default=60.0, help="s of each run (default 60)")
    parser.add_argument("--cases", default=",".join(CASES), help="comma-separated (default: all)")
    parser.add_argument("--quick", action="store_true", help="3 s runs (a smoke test)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    duration = 3.0 if args.quick else args.duration
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for name in args.cases.split(","):
        if name not in CASES:
            sys.exit(f"bench_bridge: no case '{name}' (cases: {', '.join(CASES)})")
        started = time.time()
        if CASES[name] is None:
            rows.append(run_inprocess(duration, args.out))
        else:
            sim_scene, emu_scene, transport, rate = CASES[name]
            sim, emu, _ = run_pair(name, sim_scene, emu_scene, transport, rate, duration, args.out)
            rows.append(row_for(name, transport, rate, sim, emu))
        print(f"{name}: {time.time() - started:.0f} s", file=sys.stderr)
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    rows = [{k: r.get(k, "") for k in keys} for r in rows]
    write_rows(args.out / "bridge.csv", rows)
    with open(args.out / "bridge.md", "w") as f:
        f.write(f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; "
                f"{duration:g} s per case.\n\n")
        f.write("| " + " | ".join(keys) + " |\n|" + "---|" * len(keys) + "\n")
        for r in rows:
            f.write("| " + " | ".join(str(r[k]) for k in keys) + " |\n")
    print((args.out / "bridge.md").read_text())


if __name__ == "__main__":
    main()
