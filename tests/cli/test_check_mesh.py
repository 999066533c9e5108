"""The campaign's checker (scripts/check_mesh.py) finds each kind of violation it looks for: a
froth mesh passes, and copies with one stated guarantee made false, written back by VTK, fail.

  test_check_mesh.py FROTH MODELS_DIR
"""
import os
import sys
import tempfile

import numpy as np
import vtk
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

from harness import check, froth, read_vtk, summary

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import check_mesh  # noqa: E402

models = sys.argv[2]
tmp = tempfile.mkdtemp()
mesh = os.path.join(tmp, "m.vtu")
p = froth("mesh", os.path.join(models, "plate_holes.STL"), "--cells", "1500", "--seed", "4", "--weld", "0", "-o", mesh,
          "-q")
check(p.returncode == 0, f"plate_holes: exit {p.returncode}: {p.stderr}")
problems, cells = check_mesh.check(mesh)
check(problems == [] and cells > 1000, f"the mesh as froth wrote it: {problems}")


def tampered(name, change):
    """The mesh with `change(cell data arrays as numpy, r)` applied, written back: its problems."""
    grid = read_vtk(mesh)
    cd = grid.GetCellData()
    arrays = {n: vtk_to_numpy(cd.GetArray(n)).copy() for n in ("seed", "center", "kernel", "radius", "piece")}
    r = float(vtk_to_numpy(grid.GetFieldData().GetArray("r"))[0])
    change(arrays, r)
    for n, a in arrays.items():
        v = numpy_to_vtk(a, deep=True)
        v.SetName(n)
        cd.RemoveArray(n)
        cd.AddArray(v)
    out = os.path.join(tmp, name + ".vtu")
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(out)
    w.SetInputData(grid)
    check(w.Write() == 1, f"{name}: VTK wrote it")
    return check_mesh.check(out)[0]


def with_kernel(a):
    return int(np.flatnonzero(a["kernel"] == 1)[0])


def seeds_closer(a, r):
    i = int(np.flatnonzero(a["piece"] == 0)[1])
    a["seed"][i] = a["seed"][0] + np.array([0.5 * a["radius"][0], 0, 0])


def center_outside(a, r):
    a["center"][with_kernel(a)] += np.array([3 * r, 0, 0])


def center_without_kernel(a, r):
    a["kernel"][with_kernel(a)] = 0


def nan_with_kernel(a, r):
    a["center"][with_kernel(a)] = np.nan


for name, change, says in [("seeds closer than their radius", seeds_closer, "empty disk"),
                           ("a center outside its cell", center_outside, "star shape"),
                           ("a center given without a kernel", center_without_kernel, "without a kernel give a center"),
                           ("no center where there is a kernel", nan_with_kernel, "not marked kernel 0")]:
    found = tampered(name.replace(" ", "_"), change)
    check(any(says in line for line in found), f"{name}: the checker says {found}, not '{says}'")

sys.exit(summary())
