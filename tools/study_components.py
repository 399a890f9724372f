#!/usr/bin/env python3
"""One component's time and counters across the settings of a study.

usage: tools/study_components.py STUDY_DIR COMPONENT [COUNTER ...]

`trephine study` reports the whole haptic step; where another component of
the group dominates it (a deformation moving every node, say), the part a
knob acts on is one component's own time. Prints a markdown table: each
setting's label, the component's time p50 / p99 (us) from its run's
summary.json, and the counters named (of any component: "path:counter", or
of the component itself).
"""
import csv
import json
import sys
from pathlib import Path


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    study, component, counters = Path(sys.argv[1]), sys.argv[2], sys.argv[3:]
    with open(study / "study.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    print("| setting | " + component + " p50 / p99 (us) | " + " | ".join(counters) + " |")
    print("|---|---|" + "---|" * len(counters))
    for row in rows:
        summary_file = study / "settings" / f"{int(row['setting']):03d}" / "summary.json"
        if row["status"] != "ok" or not summary_file.exists():
            print(f"| {row['label']} | {row['status']} |" + " |" * len(counters))
            continue
        components = dict(json.load(open(summary_file))["components"])
        if component not in components:
            sys.exit(f"{summary_file}: no component {component}")
        t = components[component]["time_us"]
        values = []
        for name in counters:
            path, _, counter = name.rpartition(":") if ":" in name else (component, "", name)
            value = components.get(path, {}).get("counters", {}).get(counter)
            values.append("-" if value is None else f"{value:.4g}")
        print(f"| {row['label']} | {t['p50']:.1f} / {t['p99']:.1f} | " + " | ".join(values) + " |")


if __name__ == "__main__":
    main()
