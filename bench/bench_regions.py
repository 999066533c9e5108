#!/usr/bin/python3
"""Multi-region solids against one solid (issue 24's speed target: at most 1.5 times a box's time
per cell): the five multi_region_heater solids and a three-layer laminate at about 1e5 cells, each
against a box of the same shape and r in the same run, froth's defaults otherwise (welding on),
`--no-quality`. Each pair runs `--repeat` times, alternated; the table gives the last run of each.

    bench/bench_regions.py build/froth tests/data/models [--repeat 2] [--grade]

`--grade` meshes the regions with --grade too (their layers are thicker than 2r here: the field
stays uniform unless r is raised; the column says)."""
import argparse
import json
import os
import subprocess
import tempfile

ap = argparse.ArgumentParser()
ap.add_argument("froth")
ap.add_argument("models")
ap.add_argument("--repeat", type=int, default=2)
ap.add_argument("--grade", action="store_true")
a = ap.parse_args()

heater = [os.path.join(a.models, "multi_region_heater", f + ".stl")
          for f in ("bottomAir", "heater", "leftSolid", "rightSolid", "topAir")]
laminate = ["box:0,0,0,1,1,0.3", "box:0,0,0.3,1,1,0.6", "box:0,0,0.6,1,1,1"]
# (name, inputs, r, the box of the same shape)
cases = [("heater set (5 solids)", heater, 0.00234, "box:0,0,0,0.2,0.08,0.1"),
         ("laminate (3 boxes)", laminate, 0.0199, "box:0,0,0,1,1,1")]
tmp = tempfile.mkdtemp()


def run(inputs, r, extra):
    out, rep = os.path.join(tmp, "m.vtu"), os.path.join(tmp, "m.json")
    subprocess.run([a.froth, "mesh", *inputs, "-r", repr(r), "--no-quality", "-q", "-o", out, "--report", rep, *extra],
                   check=True)
    j = json.load(open(rep))
    return {"cells": j["mesh"]["cells"], "s": j["seconds_total"], "sampling": j["seconds"].get("sampling", 0),
            "MB": j["peak_memory_bytes"] / 2**20, "graded": bool(j.get("sizing", {}).get("graded"))}


print(f"froth mesh INPUTS -r R --no-quality{' --grade' if a.grade else ''} against a box of the same shape and r, "
      f"last of {a.repeat} runs")
print(f"{'input, r':>30} {'cells':>8} {'s':>6} {'us/cell':>7} {'box cells':>9} {'box s':>6} {'box us/cell':>11} "
      f"{'ratio':>5} {'sampling s (box)':>16} {'peak MB (box)':>13}")
for name, inputs, r, box in cases:
    for _ in range(a.repeat):
        m = run(inputs, r, ["--grade"] if a.grade else [])
        b = run([box], r, [])
    us, bus = 1e6 * m["s"] / m["cells"], 1e6 * b["s"] / b["cells"]
    label = f"{name}, {r}" + (" graded" if m["graded"] else "")
    print(f"{label:>30} {m['cells']:>8} {m['s']:>6.2f} {us:>7.1f} {b['cells']:>9} {b['s']:>6.2f} {bus:>11.1f} "
          f"{us / bus:>5.2f} {m['sampling']:>7.2f} ({b['sampling']:.2f}) {m['MB']:>6.0f} ({b['MB']:.0f})")
