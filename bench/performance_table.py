#!/usr/bin/python3
"""docs/performance.md's one table, measured in one run at one commit: `froth mesh` end to end
(reading to writing) on a box, on every valid test model at about 1e5 cells uniform and graded,
on the multi-region heater, on the box cut along a through crack, a lens and a penny, with --convex and with each writer, each against a box of about the
same cells in the same run; and the whole box at 7.5e5 cells against voro++ computing the cells
alone for the same number of seeds (froth_bench, 1 thread for voro++).

    bench/performance_table.py BUILD_DIR MODELS_DIR [--quick]

Prints the commit, the date and a Markdown table. `--quick`: three models, no voro++ row."""
import argparse
import json
import os
import re
import subprocess
import tempfile
import time

import numpy as np

ap = argparse.ArgumentParser()
ap.add_argument("build")
ap.add_argument("models")
ap.add_argument("--quick", action="store_true")
a = ap.parse_args()
FROTH = os.path.join(a.build, "froth")
tmp = tempfile.mkdtemp()
MODELS = ["7_8ths_cube.stl", "hollow_sphere.off", "torus.STL", "plate_holes.STL", "shape_ibeam.stl", "round.stl",
          "two_objects_mixed_case_names.stl", "step.off", "1002_tray_bottom.STL", "ADIS16480.STL", "hinge.stl"]
if a.quick:
    MODELS = ["hinge.stl", "ADIS16480.STL", "round.stl"]
HEATER = [os.path.join(a.models, "multi_region_heater", f + ".stl")
          for f in ("bottomAir", "heater", "leftSolid", "rightSolid", "topAir")]


def mesh(inputs, *flags, output="m.vtu"):
    """froth mesh with a report: cells, total seconds (reading and writing included), peak MiB,
    stage seconds; and the wall time the user waits."""
    rep = os.path.join(tmp, "m.json")
    t0 = time.time()
    subprocess.run([FROTH, "mesh", *inputs, *flags, "-q", "-o", os.path.join(tmp, output), "--report", rep],
                   check=True)
    wall = time.time() - t0
    j = json.load(open(rep))
    return {"cells": j["mesh"]["cells"], "s": j["seconds_total"], "wall": wall,
            "MiB": j["peak_memory_bytes"] / 2**20, "stages": j["seconds"]}


rows = []


def row(case, command, m, box, note=""):
    us = 1e6 * m["s"] / m["cells"]
    rows.append((case, command, f"{m['cells']:,}", f"{m['s']:.2f}", f"{us:.1f}",
                 f"{us / (1e6 * box['s'] / box['cells']):.2f}" if box else "1", f"{m['MiB']:.0f}", note))


box = mesh(["box:0,0,0,1,1,1"], "--cells", "1e5", "--seed", "1")
row("box", "--cells 1e5", box, None, f"choosing r {box['stages'].get('choosing r', 0):.2f} s")
for name in MODELS:
    path = os.path.join(a.models, name)
    uniform = mesh([path], "--cells", "1e5", "--seed", "1")
    row(name, "--cells 1e5", uniform, box)
    graded = mesh([path], "--cells", "1e5", "--seed", "1", "--grade")
    row(name, "--cells 1e5 --grade", graded, box,
        f"choosing r {graded['stages'].get('choosing r', 0):.2f} s, feature size "
        f"{graded['stages'].get('feature size', 0):.2f} s, sizing {graded['stages'].get('sizing', 0):.2f} s, "
        f"sampling {graded['stages'].get('sampling', 0):.2f} s")
row("heater, 5 regions", "--cells 1e5", mesh(HEATER, "--cells", "1e5", "--seed", "1"), box)
CRACKS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data", "cracks")
for sheet in ("box_through.obj", "lens.obj", "penny.obj"):
    row(f"box cut along {sheet}", f"--cells 1e5 --crack {sheet}",
        mesh(["box:0,0,0,1,1,1"], "--cells", "1e5", "--seed", "1", "--crack", os.path.join(CRACKS, sheet)), box)
convex = mesh([os.path.join(a.models, "hinge.stl")], "-r", "0.6", "--seed", "1", "--convex")
row("hinge.stl --convex", "-r 0.6 --convex", convex, box, f"convex stage {convex['stages'].get('convex', 0):.2f} s")


def write_stl(path, tris):
    rec = np.zeros(len(tris), dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
    rec["v"] = tris
    with open(path, "wb") as f:
        f.write(b"\0" * 80 + np.uint32(len(tris)).tobytes() + rec.tobytes())


def fine_surfaces():
    """Two surfaces of 400,000 to 480,000 triangles: a thin torus (radii 1 and 0.03, 800 x 250
    quads) and ADIS16480.STL with each triangle cut into 64 (three midpoint splits: fine facets
    on flat CAD faces, the feature-size search's hard case)."""
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 800, endpoint=False), np.linspace(0, 2 * np.pi, 250, endpoint=False),
                       indexing="ij")
    P = np.stack([(1 + 0.03 * np.cos(v)) * np.cos(u), (1 + 0.03 * np.cos(v)) * np.sin(u), 0.03 * np.sin(v)], -1)
    a, b = P, np.roll(P, -1, axis=0)
    c, d = np.roll(b, -1, axis=1), np.roll(P, -1, axis=1)
    torus = os.path.join(tmp, "torus_400k.stl")
    write_stl(torus, np.concatenate([np.stack([a, b, c], -2).reshape(-1, 3, 3), np.stack([a, c, d], -2).reshape(-1, 3, 3)]))
    t = np.array([[float(x) for x in line.split()[1:4]] for line in open(os.path.join(a_models, "ADIS16480.STL"))
                  if line.strip().startswith("vertex")]).reshape(-1, 3, 3)
    for _ in range(3):
        p, q, r = t[:, 0], t[:, 1], t[:, 2]
        pq, qr, rp = (p + q) / 2, (q + r) / 2, (r + p) / 2
        t = np.concatenate([np.stack(x, 1) for x in ([p, pq, rp], [pq, q, qr], [rp, qr, r], [pq, qr, rp])])
    adis = os.path.join(tmp, "ADIS16480_x64.stl")
    write_stl(adis, t)
    return [("torus, 400,000 triangles", torus, "-r", "0.04"), (f"ADIS16480 x64, {len(t):,} triangles", adis,
                                                                   "--cells", "1e5")]


a_models = a.models
for case, path, *size in fine_surfaces():
    m = mesh([path], *size, "--seed", "1", "--grade")
    row(case, " ".join(size) + " --grade", m, box,
        f"reading {m['stages']['reading']:.2f} s, feature size {m['stages'].get('feature size', 0):.2f} s, sizing "
        f"{m['stages'].get('sizing', 0):.2f} s")
vtu_write = box["stages"]["writing"]
for fmt, out in (("Exodus II", "m.exo"), ("OpenFOAM", "case/constant/polyMesh"), ("facet graph", "m.npz"),
                 ("peridynamic nodes", "m.nodes")):
    m = mesh(["box:0,0,0,1,1,1"], "--cells", "1e5", "--seed", "1", output=out)
    row(f"box to {fmt}", f"-o {out}", m, box, f"writing {m['stages']['writing']:.2f} s (VTU {vtu_write:.2f} s)")

voro = ""
if not a.quick:
    big = mesh(["box:0,0,0,1,1,1"], "-r", "0.01", "--seed", "2", "--threads", "2")
    bench = subprocess.run([os.path.join(a.build, "bench", "froth_bench"), "--repeat", "1", str(big["cells"])],
                           check=True, capture_output=True, text=True).stdout
    line = [l for l in bench.splitlines() if re.match(r"\s*\d+\s+0\.\d+\s+\d+\s*\|", l)][0]
    voro_s = float(line.split("|")[-1].split()[0])
    row("box, 2 threads", "-r 0.01 --seed 2", big, box,
        f"wall {big['wall']:.2f} s against voro++'s cells alone {voro_s:.2f} s (1 thread): ratio "
        f"{big['wall'] / voro_s:.2f}")

commit = subprocess.run(["git", "-C", os.path.dirname(os.path.abspath(__file__)), "log", "-1", "--format=%h (%cs)"],
                        capture_output=True, text=True).stdout.strip()
print(f"Measured {time.strftime('%Y-%m-%d')} at commit {commit}, {os.cpu_count()} cores.\n")
print("| case | options | cells | total s | us per cell | per cell / box | peak MiB | note |")
print("|---|---|---|---|---|---|---|---|")
for r in rows:
    print("| " + " | ".join(r) + " |")
