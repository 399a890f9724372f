#!/usr/bin/env python3
"""Haptic step times of two builds on the bench scenes, measured in one run.

Runs each case with the OLD and the NEW `trephine` in turn (old, new, old,
new, ...), RUNS times each, and prints per case the medians over the runs of
the haptic rate group's p50 and p99 step time (us, from summary.json) and
the ratios new/old. The machine's drift then falls on both builds alike.

  tools/compare_haptic_timing.py OLD/bin/trephine build/bin/trephine [--runs 8] [CASE ...]

OLD is a build of an earlier commit (a git worktree built with the release
preset). Scene paths are taken from this checkout.
"""
import argparse
import json
import os
import statistics
import subprocess
import tempfile

CASES = [
    ('skull touch (native)', 'scenes/bench/skull_backends.xml', []),
    ('skull drilling under load', 'scenes/bench/drill_press_slide.xml', []),
    ('brain touch native', 'scenes/bench/brain_backends.xml', []),
    ('brain touch embree', 'scenes/bench/brain_backends.xml', ['--set', '/patient/brain.backend=embree']),
    ('brain touch bullet', 'scenes/bench/brain_backends.xml', ['--set', '/patient/brain.backend=bullet']),
    ('FEM press', 'scenes/bench/brain_fem_press.xml', []),
    ('integrated', 'scenes/integrated.xml', []),
]


def step_times(program, scene, extra, out):
    subprocess.run([program, 'run', scene, '--out', out] + extra, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL, check=True)
    groups = json.load(open(os.path.join(out, 'summary.json')))['groups']
    key = '1000' if '1000' in groups else max(groups, key=lambda k: float(k.split(':')[0]))
    return groups[key]['time_us']['p50'], groups[key]['time_us']['p99']


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('old')
    parser.add_argument('new')
    parser.add_argument('--runs', type=int, default=8)
    parser.add_argument('cases', nargs='*', help='case names (default: all)')
    # Intermixed: the case names may follow --runs N (old new --runs 8 'FEM press').
    args = parser.parse_intermixed_args()
    os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..'))
    print('| case | old p50 / p99 (us) | new p50 / p99 (us) | new/old |')
    print('|---|---|---|---|')
    with tempfile.TemporaryDirectory() as scratch:
        for name, scene, extra in CASES:
            if args.cases and name not in args.cases:
                continue
            times = {'old': [], 'new': []}
            for _ in range(args.runs):
                for build in ('old', 'new'):
                    program = args.old if build == 'old' else args.new
                    times[build].append(step_times(program, scene, extra, os.path.join(scratch, build)))
            old = [statistics.median(t[i] for t in times['old']) for i in (0, 1)]
            new = [statistics.median(t[i] for t in times['new']) for i in (0, 1)]
            print(f'| {name} | {old[0]:.2f} / {old[1]:.2f} | {new[0]:.2f} / {new[1]:.2f} | '
                  f'{new[0] / old[0]:.3f} / {new[1] / old[1]:.3f} |', flush=True)


if __name__ == '__main__':
    main()
