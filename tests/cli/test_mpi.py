"""MPI (oversubscribed on a 2-core machine):
- `mpirun -np K froth ensemble` for K = 1, 2, 3 writes the same member files, byte for byte, as one
  process; ranks share out the members.
- `mpirun -np K froth mesh --partition` for K = 1, 2, 3 writes a .pvtu whose cells, read back by
  VTK and sorted by seed (region and piece), are the serial mesh's: same seeds, kinds, volumes and
  face vertex coordinates, bit for bit, also for the five multi_region_heater solids (with the
  report's counts per region and interface); too many ranks for the grid is a usage error that leaves no file."""
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

FROTH, MPIRUN, MODELS = sys.argv[1], sys.argv[2], sys.argv[3]
failures = []
tmp = tempfile.mkdtemp()
args = ["ensemble", "box:0,0,0,1,1,1", "-r", "0.08", "-n", "5", "--seed", "21", "--threads", "1"]
ref = os.path.join(tmp, "serial")
p = subprocess.run([FROTH, *args, "-o", ref], capture_output=True, text=True)
if p.returncode != 0:
    failures.append(f"serial ensemble: {p.stderr}")
for k in (1, 2, 3):
    out = os.path.join(tmp, f"np{k}")
    p = subprocess.run([MPIRUN, "--oversubscribe", "-np", str(k), FROTH, *args, "-o", out], capture_output=True,
                       text=True)
    if p.returncode != 0:
        failures.append(f"mpirun -np {k}: exit {p.returncode}: {p.stderr[-2000:]}")
        continue
    if f"on {k} ranks" not in p.stdout and k > 1:
        failures.append(f"mpirun -np {k}: summary does not say it used {k} ranks: {p.stdout}")
    summary = json.load(open(os.path.join(out, "ensemble.json")))
    if summary["this_run"]["built"] != 5:
        failures.append(f"mpirun -np {k}: built {summary['this_run']}")
    for m in range(5):
        name = f"member_{m:05d}.vtu"
        if open(os.path.join(ref, name), "rb").read() != open(os.path.join(out, name), "rb").read():
            failures.append(f"mpirun -np {k}: {name} differs from the serial ensemble's")


def cells_by_seed(path):
    """{seed bytes: (kind, volume bytes, faces as tuples of vertex coordinate bytes)} of a VTU or PVTU."""
    r = vtk.vtkXMLPUnstructuredGridReader() if path.endswith(".pvtu") else vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    pts = vtk_to_numpy(g.GetPoints().GetData())
    cd = g.GetCellData()
    seeds, kinds, vols, radii = (vtk_to_numpy(cd.GetArray(n)) for n in ("seed", "kind", "volume", "radius"))
    # A multi-region solid's seed has a cell per region (and piece) it reaches.
    part = [vtk_to_numpy(cd.GetArray(n)) if cd.GetArray(n) else np.zeros(len(seeds), int) for n in ("region", "piece")]
    out = {}
    ids = vtk.vtkIdList()
    for c in range(g.GetNumberOfCells()):
        g.GetFaceStream(c, ids)
        stream = [ids.GetId(k) for k in range(ids.GetNumberOfIds())]
        faces, at = [], 1
        for _ in range(stream[0]):
            n = stream[at]
            faces.append(tuple(pts[v].tobytes() for v in stream[at + 1:at + 1 + n]))
            at += n + 1
        out[(seeds[c].tobytes(), int(part[0][c]), int(part[1][c]))] = (int(kinds[c]), vols[c].tobytes(), radii[c].tobytes(), tuple(faces))
    return out


common = ["--threads", "1", "--seed", "5"]
HEATER = [os.path.join(MODELS, "multi_region_heater", f + ".stl")
          for f in ("bottomAir", "heater", "leftSolid", "rightSolid", "topAir")]
# The hollow sphere at diag/30 is graded (its shell is thinner than 2r): each rank samples its
# slab with the graded sampler. Each case is at least 36 layers of sampling
# cubes high, for 3 slabs of 12 (froth/partition.hpp's kCellHaloLayers).
# And the graded hollow sphere cut through along the plane x = 0.1 (a crack with --grade).
sheet = os.path.join(tmp, "through_x.obj")
with open(sheet, "w") as f:
    f.write("v 0.1 -0.7 -0.7\nv 0.1 0.7 -0.7\nv 0.1 0.7 0.7\nv 0.1 -0.7 0.7\nf 1 2 3\nf 1 3 4\n")
# And the box cut along two crossing cracks: a through crack at z = 0.73 and a penny upright
# across it (x = 0.61, its front crossing the first).
crossing = [os.path.join(tmp, "through_z.obj"), os.path.join(tmp, "penny_x.obj")]
with open(crossing[0], "w") as f:
    f.write("v -0.1 -0.1 0.73\nv 1.1 -0.1 0.73\nv 1.1 1.1 0.73\nv -0.1 1.1 0.73\nf 1 2 3\nf 1 3 4\n")
with open(crossing[1], "w") as f:
    f.write("v 0.61 0.23 0.41\nv 0.61 0.77 0.41\nv 0.61 0.77 1.09\nv 0.61 0.23 1.09\nf 1 2 3\nf 1 3 4\n")
# And two regions side by side, a penny in the first (its front 0.3 from the interface) and a
# through crack across both (z = 0.41).
penny, across = os.path.join(tmp, "penny_z.obj"), os.path.join(tmp, "across_z.obj")
with open(penny, "w") as f:
    f.write("v 0.2 0.3 0.75\nv 0.7 0.3 0.75\nv 0.7 0.7 0.75\nv 0.2 0.7 0.75\nf 1 2 3\nf 1 3 4\n")
with open(across, "w") as f:
    f.write("v -0.1 -0.1 0.41\nv 2.1 -0.1 0.41\nv 2.1 1.1 0.41\nv -0.1 1.1 0.41\nf 1 2 3\nf 1 3 4\n")
for name, domain, r, extra in (("box", "box:0,0,0,1,1,1.5", "0.05", []),
                               ("two_boxes_cracked", ["box:0,0,0,1,1,1.5", "box:1,0,0,2,1,1.5"], "0.05",
                                ["--crack", penny, "--crack", across]),
                               ("box_crossing_cracks", "box:0,0,0,1,1,1.5", "0.05",
                                ["--crack", crossing[0], "--crack", crossing[1]]),
                               ("7_8ths", os.path.join(MODELS, "7_8ths_cube.stl"), "2", []),
                               ("hollow_sphere_graded", os.path.join(MODELS, "hollow_sphere.off"), "0.0577", ["--grade"]),
                               ("hollow_sphere_graded_cracked", os.path.join(MODELS, "hollow_sphere.off"), "0.0577",
                                ["--grade", "--crack", sheet]),
                               ("heater", HEATER, "0.006", [])):
    domain = domain if isinstance(domain, list) else [domain]
    serial_path = os.path.join(tmp, f"{name}_serial.vtu")
    serial_report = os.path.join(tmp, f"{name}_serial.json")
    p = subprocess.run([FROTH, "mesh", *domain, "-r", r, *common, *extra, "-o", serial_path, "--report", serial_report],
                       capture_output=True, text=True)
    if p.returncode != 0:
        failures.append(f"serial mesh of {name}: {p.stderr}")
        continue
    serial = cells_by_seed(serial_path)
    for k in (1, 2, 3):
        out = os.path.join(tmp, f"{name}_np{k}.pvtu")
        report = os.path.join(tmp, f"{name}_np{k}.json")
        p = subprocess.run([MPIRUN, "--oversubscribe", "-np", str(k), FROTH, "mesh", *domain, "-r", r, *common, *extra,
                            "--partition", "-o", out, "--report", report], capture_output=True, text=True)
        if p.returncode != 0:
            failures.append(f"{name}: mpirun -np {k} --partition: exit {p.returncode}: {p.stderr[-2000:]}")
            continue
        pieces = sorted(os.listdir(os.path.join(tmp, f"{name}_np{k}")))
        if pieces != [f"{name}_np{k}_{i}.vtu" for i in range(k)]:
            failures.append(f"{name}: mpirun -np {k}: pieces {pieces}")
        bounds = [json.load(open(f)).get("quality_before_welding", json.load(open(f)).get("quality"))["bounds"]
                  for f in (serial_report, report)]
        if bounds[0] != bounds[1]:
            failures.append(f"{name}: mpirun -np {k}: quality bounds {bounds[1]}, serial {bounds[0]}")
        part = json.load(open(report))["partition"]
        if part["ranks"] != k or sum(x["seeds"] for x in part["per_rank"]) != len({key[0] for key in serial}):
            failures.append(f"{name}: mpirun -np {k}: report {part}")
        # Per region: the serial cell counts, volumes and interface areas (summed in another order).
        regions = [json.load(open(f)).get("regions", []) for f in (serial_report, report)]
        interfaces = [json.load(open(f)).get("interfaces", []) for f in (serial_report, report)]
        if [x["cells"] for x in regions[0]] != [x["cells"] for x in regions[1]] or any(
                abs(a["volume"] - b["volume"]) > 1e-12 * b["volume"] for a, b in zip(*regions)) or any(
                abs(a[s] - b[s]) > 1e-12 * b["area"] for a, b in zip(*interfaces)
                for s in ("area_from_first", "area_from_second")):
            failures.append(f"{name}: mpirun -np {k}: regions {regions[1]} {interfaces[1]}, serial {regions[0]} {interfaces[0]}")
        got = cells_by_seed(out)
        if got.keys() != serial.keys():
            failures.append(f"{name}: mpirun -np {k}: {len(got)} cells, serial {len(serial)}, seeds differ")
            continue
        bad = [s for s in serial if serial[s] != got[s]]
        if bad:
            failures.append(f"{name}: mpirun -np {k}: {len(bad)} of {len(serial)} cells differ from the serial mesh's")
        print(f"{name}: {k} ranks: {len(got)} cells identical to the serial mesh; "
              f"ghost/owned seeds {part['ghost_over_owned_seeds']:.3f}")

# Slabs thinner than the halo: a usage error on every rank, no file left.
out = os.path.join(tmp, "thin.pvtu")
p = subprocess.run([MPIRUN, "--oversubscribe", "-np", "3", FROTH, "mesh", "box:0,0,0,1,1,1", "-r", "0.2", *common,
                    "--partition", "-o", out], capture_output=True, text=True)
if p.returncode != 2 or "layers of sampling cubes" not in p.stderr or os.path.exists(out):
    failures.append(f"too many ranks: exit {p.returncode}, {p.stderr[-500:]}")

for f in failures:
    print("FAIL:", f)
print(f"{'FAILED' if failures else 'passed'}: MPI ensembles and partitioned meshes on 1, 2 and 3 ranks")
# The outputs are kept only for a failure to be looked at.
if failures:
    print(f"outputs kept in {tmp}")
else:
    shutil.rmtree(tmp)
sys.exit(1 if failures else 0)
