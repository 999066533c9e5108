#!/usr/bin/python3
"""Two builds of froth side by side: the same `froth mesh` runs, alternating between the builds,
each case `--repeat` times; prints the median wall time per case and build, their ratio, and each
case's time per cell over the box's (the first case) for each build. Wall time, not the report's
total: it is what the user waits for, whatever each build's report counts.

    bench/compare_builds.py BEFORE_BUILD AFTER_BUILD MODELS_DIR [--repeat 3]

Alternating runs put both builds under the same load: this machine's times drift by 10-25%
over minutes, more than most changes measured here."""
import argparse
import json
import os
import statistics
import subprocess
import tempfile
import time

ap = argparse.ArgumentParser()
ap.add_argument("before")
ap.add_argument("after")
ap.add_argument("models")
ap.add_argument("--repeat", type=int, default=3)
a = ap.parse_args()
tmp = tempfile.mkdtemp()
M = a.models
CASES = [
    ("box --cells 1e5", ["box:0,0,0,1,1,1", "--cells", "1e5", "--seed", "1"]),
    ("ADIS16480.STL --cells 1e5 --grade", [os.path.join(M, "ADIS16480.STL"), "--cells", "1e5", "--grade", "--seed", "1"]),
    ("step.off --cells 1e5 --grade", [os.path.join(M, "step.off"), "--cells", "1e5", "--grade", "--seed", "1"]),
    ("1002_tray_bottom.STL --cells 1e5 --grade",
     [os.path.join(M, "1002_tray_bottom.STL"), "--cells", "1e5", "--grade", "--seed", "1"]),
    ("round.stl --cells 1e5", [os.path.join(M, "round.stl"), "--cells", "1e5", "--seed", "1"]),
    ("hollow_sphere.off --cells 1e5", [os.path.join(M, "hollow_sphere.off"), "--cells", "1e5", "--seed", "1"]),
    ("box -r 0.01 --seed 2", ["box:0,0,0,1,1,1", "-r", "0.01", "--seed", "2"]),
]


def run(build, args):
    rep = os.path.join(tmp, "m.json")
    t0 = time.time()
    subprocess.run([os.path.join(build, "froth"), "mesh", *args, "-q", "-o", os.path.join(tmp, "m.vtu"), "--report", rep],
                   check=True)
    wall = time.time() - t0
    return wall, json.load(open(rep))["mesh"]["cells"]


walls = {(c, b): [] for c, _ in CASES for b in ("before", "after")}
cells = {}
for _ in range(a.repeat):
    for case, args in CASES:
        for build, path in (("before", a.before), ("after", a.after)):
            w, n = run(path, args)
            walls[(case, build)].append(w)
            cells[(case, build)] = n

print("| case | cells | wall s before | after | after / before | per cell / box before | after |")
print("|---|---|---|---|---|---|---|")
box = {b: statistics.median(walls[(CASES[0][0], b)]) / cells[(CASES[0][0], b)] for b in ("before", "after")}
for case, _ in CASES:
    m = {b: statistics.median(walls[(case, b)]) for b in ("before", "after")}
    per = {b: m[b] / cells[(case, b)] / box[b] for b in ("before", "after")}
    print(f"| {case} | {cells[(case, 'after')]:,} | {m['before']:.2f} | {m['after']:.2f} | "
          f"{m['after'] / m['before']:.2f} | {per['before']:.2f} | {per['after']:.2f} |")
