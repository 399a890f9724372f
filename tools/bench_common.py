"""Helpers shared by the experiment scripts in tools/ (bench_rigid.py,
bench_brain.py, accuracy_rigid.py): the program paths, running a scene,
reading its CSV outputs, percentiles, and matplotlib from Debian's python3."""
import csv
import json
import math
import os
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PROGRAM = ROOT / "build/bin/trephine"


def ensure_matplotlib(script):
    """Re-executes under /usr/bin/python3 (where tools/setup installs
    python3-matplotlib) when this python has no matplotlib; returns pyplot
    with the Agg back-end."""
    try:
        import matplotlib
    except ImportError:
        if sys.executable != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
            os.execv("/usr/bin/python3", ["/usr/bin/python3", *sys.argv])
        sys.exit(f"{script}: matplotlib is missing; install python3-matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def write_rows(path, rows):
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def percentile(values, q):
    """The nearest-rank q-quantile (q in [0, 1]); NaN for no values."""
    ordered = sorted(values)
    if not ordered:
        return float("nan")
    return ordered[min(len(ordered), max(1, math.ceil(q * len(ordered)))) - 1]


def force_steps(trace):
    """|F_k - F_k-1| (N) per frame of a trace.csv, 0 for the first."""
    steps = [0.0]
    for i in range(1, len(trace)):
        d = [float(trace[i][k]) - float(trace[i - 1][k]) for k in ("force_x", "force_y", "force_z")]
        steps.append(math.sqrt(sum(v * v for v in d)))
    return steps


def run_scene(scene, run_dir, settings):
    """`trephine run` of `scene` into `run_dir` with `--set` for each of
    `settings`, in virtual time. Returns summary.json, the trace rows, the
    per-call times (us) by component and call, and per frame the proxy's time
    (the collision handling) and the haptic step's (the tool node's components:
    device + proxy + force)."""
    command = [str(PROGRAM), "run", str(scene), "--quiet", "--out", str(run_dir)]
    for s in settings:
        command += ["--set", s]
    subprocess.run(command, check=True)
    per_call = defaultdict(dict)
    for row in read_rows(run_dir / "timings.csv"):
        per_call[row["component"]][int(row["call"])] = float(row["duration_us"])
    proxy = per_call["/tool/proxy"]
    frames = sorted(proxy)
    # The haptic step: every component of the tool node (device or simulated hand, proxy, force).
    tool = [c for c in per_call if c.startswith("/tool/")]
    step = [sum(per_call[c].get(i, 0.0) for c in tool) for i in frames]
    return {"summary": json.loads((run_dir / "summary.json").read_text()), "trace": read_rows(run_dir / "trace.csv"),
            "per_call": per_call, "proxy_us": [proxy[i] for i in frames], "step_us": step}
