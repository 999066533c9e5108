"""Long tier: every valid shared model (each heater solid alone) meshes at r = diag/10, /20, /40
and /80 with seeds 1-3, and at r = diag/2 and 2 diag (a few cells over the whole part: the weld
tolerance and the clipper's degenerate loops at their extremes) with seed 1, with and without
--grade: exit 0, cell volumes summing to the enclosed
volume and border faces to the surface area (1e-9). froth checks closed cells, matched faces and
positive volumes itself before writing (exit 5 otherwise). Run with Debian's /usr/bin/python3."""
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

FROTH, MODELS = sys.argv[1], sys.argv[2]
VALID = ["1002_tray_bottom.STL", "7_8ths_cube.stl", "ADIS16480.STL", "hinge.stl", "hollow_sphere.off",
         "plate_holes.STL", "round.stl", "shape_ibeam.stl", "torus.STL", "two_objects_mixed_case_names.stl",
         "unit_cube.STL", "unit_sphere.STL", "step.off"] + \
        [os.path.relpath(p, MODELS) for p in sorted(glob.glob(os.path.join(MODELS, "multi_region_heater", "*.stl")))]


def diagonal(path):
    if path.lower().endswith(".stl"):
        r = vtk.vtkSTLReader()
        r.SetFileName(path)
        r.Update()
        p = vtk_to_numpy(r.GetOutput().GetPoints().GetData())
    else:  # OFF
        words = open(path).read().split()
        n = int(words[1])
        p = np.array(words[4:4 + 3 * n], float).reshape(-1, 3)
    return float(np.linalg.norm(p.max(0) - p.min(0)))


tmp = tempfile.mkdtemp()
failures, runs, t0 = [], 0, time.time()
for name in VALID:
    path = os.path.join(MODELS, name)
    d = diagonal(path)
    for fraction, seeds in ((10, (1, 2, 3)), (20, (1, 2, 3)), (40, (1, 2, 3)), (80, (1, 2, 3)), (2, (1,)), (0.5, (1,))):
        for seed in seeds:
            for grade in ([], ["--grade"]):
                rep, out = os.path.join(tmp, "r.json"), os.path.join(tmp, "m.vtu")
                args = [FROTH, "mesh", path, "-r", repr(d / fraction), "--seed", str(seed), "--no-quality", "-o", out,
                        "--report", rep] + grade
                p = subprocess.run(args, capture_output=True, text=True)
                runs += 1
                what = f"{name} r=diag/{fraction} seed {seed} {' '.join(grade)}"
                if p.returncode != 0:
                    failures.append(f"{what}: exit {p.returncode}: {p.stderr.strip()[:300]}")
                    continue
                j = json.load(open(rep))
                if j["volume"]["relative_error"] > 1e-9:
                    failures.append(f"{what}: volume error {j['volume']['relative_error']}")
                area = j["border_area"]
                if abs(area["border_faces"] - area["surface"]) > 1e-9 * area["surface"]:
                    failures.append(f"{what}: border area {area['border_faces']} vs {area['surface']}")
shutil.rmtree(tmp)
print(f"{runs} runs, {len(failures)} failed, {time.time() - t0:.0f} s")
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
