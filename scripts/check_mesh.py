#!/usr/bin/python3
"""Reads a froth VTU back with VTK and checks the local guarantees its cell data states.

  /usr/bin/python3 scripts/check_mesh.py MESH.vtu

- Empty disks: every two seeds are at least min(radius_i, radius_j) apart, that divided by
  sqrt(2) between two protection seeds (kinds 2 to 5), by 2 where one is an interface curve's
  (kind 5, sampled at r/2); a seed's extra pieces share its seed.
- Star shape: every cell with a `center` is star-shaped from it: `center` lies on the inner side
  of every face's plane (Newell's normal through the face's centroid; to 1e-9 r), so that a fan
  of tetrahedra from it over any triangulation of the faces has positive volumes.
- A cell star-shaped from no point says so: `kernel` 0 and `center` NaN, never a point.
Prints one line per kind of violation with its count and worst case; exit 1 if any.
Needs Debian's python3-vtk9, python3-numpy and python3-scipy.
"""
import sys

import numpy as np
from scipy.spatial import cKDTree
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader


def cell_array(grid, name):
    a = grid.GetCellData().GetArray(name)
    return None if a is None else vtk_to_numpy(a)


def faces_of(grid):
    """Per cell, its faces as arrays of point ids (VTK's legacy face stream)."""
    stream = vtk_to_numpy(grid.GetFaces())
    where = vtk_to_numpy(grid.GetFaceLocations())
    out = []
    for c in range(grid.GetNumberOfCells()):
        at = int(where[c])
        n = int(stream[at])
        at += 1
        faces = []
        for _ in range(n):
            m = int(stream[at])
            faces.append(stream[at + 1:at + 1 + m])
            at += 1 + m
        out.append(faces)
    return out


def main():
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(sys.argv[1])
    reader.Update()
    grid = reader.GetOutput()
    r = float(vtk_to_numpy(grid.GetFieldData().GetArray("r"))[0])
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    seed, kind, radius = cell_array(grid, "seed"), cell_array(grid, "kind"), cell_array(grid, "radius")
    center, piece, kernel = cell_array(grid, "center"), cell_array(grid, "piece"), cell_array(grid, "kernel")
    problems = []

    # Empty disks, over the distinct seeds.
    first = piece == 0 if piece is not None else np.ones(len(seed), bool)
    s, k, h = seed[first], kind[first], radius[first]
    protected = (k >= 2) & (k <= 5)
    pairs = cKDTree(s).query_pairs(float(h.max()), output_type="ndarray")
    if len(pairs):
        i, j = pairs[:, 0], pairs[:, 1]
        d = np.linalg.norm(s[i] - s[j], axis=1)
        curve = (k[i] == 5) | (k[j] == 5)  # interface curves are sampled at r/2
        need = np.minimum(h[i], h[j]) / np.where(protected[i] & protected[j], np.where(curve, 2, np.sqrt(2)), 1)
        close = d < need * (1 - 1e-9)
        if close.any():
            worst = np.argmin(d / need)
            problems.append("empty disk: %d seed pairs closer than their radius (worst %.3g of it, seeds at %s and %s)"
                            % (close.sum(), d[worst] / need[worst], s[i[worst]], s[j[worst]]))

    # Star shape from `center`, and no center without a kernel.
    no_kernel = kernel == 0 if kernel is not None else np.zeros(len(seed), bool)
    given_nan = np.isnan(center).any(axis=1)
    if (no_kernel & ~given_nan).any():
        problems.append("kernel: %d cells without a kernel give a center" % (no_kernel & ~given_nan).sum())
    if (given_nan & ~no_kernel).any():
        problems.append("kernel: %d cells give no center but are not marked kernel 0" % (given_nan & ~no_kernel).sum())
    bad, worst = 0, 0.0
    for c, faces in enumerate(faces_of(grid)):
        if given_nan[c]:
            continue
        x = center[c]
        beyond = []
        for f in faces:
            p = points[f]
            n = np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0) / 2  # Newell: area times the normal
            area = np.linalg.norm(n)
            if area < 1e-12 * r * r:
                continue  # a sliver's plane is round-off
            beyond.append(np.dot(n / area, x - p.mean(axis=0)))
        beyond = np.array(beyond)
        if beyond.size and (beyond > 0).sum() > (beyond < 0).sum():
            beyond = -beyond  # faces wound inward
        if beyond.size and beyond.max() > 1e-9 * r:
            bad += 1
            worst = max(worst, beyond.max() / r)
    if bad:
        problems.append("star shape: %d cells are not star-shaped from their center (it lies %.3g r beyond a face's "
                        "plane)" % (bad, worst))
    for p in problems:
        print(p)
    print("%s: %d cells, %s" % (sys.argv[1], len(seed), "all local guarantees hold" if not problems else
                                "%d kinds of violation" % len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
