#!/usr/bin/python3
"""Reads a froth VTU back with VTK and checks the local guarantees its cell data states.

  /usr/bin/python3 scripts/check_mesh.py MESH.vtu

- Empty disks: every two seeds are at least min(radius_i, radius_j) apart, that divided by
  sqrt(2) between two protection seeds (kinds 2 to 5), by 2 where one is an interface curve's
  (kind 5, sampled at r/2); a seed's extra pieces share its seed, and so do the convex pieces of a
  cell (--convex, cell data `parent`).
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
    """Every face as (its cell, its point ids), flattened: (face_cell, face_start, ids) with face
    f's ids at ids[face_start[f]:face_start[f + 1]], faces in cell order (VTK's face stream).
    The stream is walked one face of every cell at a time, in numpy."""
    stream = vtk_to_numpy(grid.GetFaces()).astype(np.int64)
    where = vtk_to_numpy(grid.GetFaceLocations()).astype(np.int64)
    n_faces = stream[where]
    at = where + 1  # each cell's next face
    cells = np.arange(len(where))
    starts, lengths, owners, order = [], [], [], []
    for t in range(int(n_faces.max()) if len(where) else 0):
        live = t < n_faces
        m = stream[at[live]]
        starts.append(at[live] + 1)
        lengths.append(m)
        owners.append(cells[live])
        order.append(cells[live] * (1 << 20) + t)  # faces in cell order, then their order in it
        at[live] += 1 + m
    if not starts:
        return np.zeros(0, np.int64), np.zeros(1, np.int64), np.zeros(0, np.int64)
    perm = np.argsort(np.concatenate(order), kind="stable")
    starts, lengths = np.concatenate(starts)[perm], np.concatenate(lengths)[perm]
    face_start = np.concatenate([[0], np.cumsum(lengths)])
    ids = stream[np.repeat(starts - face_start[:-1], lengths) + np.arange(face_start[-1])]
    return np.concatenate(owners)[perm], face_start, ids


def check(path):
    """The violations found in the mesh at `path` (one line per kind), and its cell count."""
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    r = float(vtk_to_numpy(grid.GetFieldData().GetArray("r"))[0])
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    seed, kind, radius = cell_array(grid, "seed"), cell_array(grid, "kind"), cell_array(grid, "radius")
    center, piece, kernel = cell_array(grid, "center"), cell_array(grid, "piece"), cell_array(grid, "kernel")
    problems = []

    # Empty disks, over the distinct seeds: a seed's first piece, and of that the first convex piece.
    first = piece == 0 if piece is not None else np.ones(len(seed), bool)
    parent = cell_array(grid, "parent")
    if parent is not None:
        first_of_parent = np.zeros(len(seed), bool)
        first_of_parent[np.unique(parent, return_index=True)[1]] = True
        first &= first_of_parent
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
    face_cell, face_start, ids = faces_of(grid)
    lengths = np.diff(face_start)
    # Relative to each face's cell center (far from the origin, products of coordinates cancel).
    x = center[face_cell]
    p = points[ids] - np.repeat(np.nan_to_num(x), lengths, axis=0)
    nxt = np.arange(len(ids)) + 1
    nxt[face_start[1:] - 1] = face_start[:-1]  # each face's last vertex to its first
    n = np.add.reduceat(np.cross(p, p[nxt]), face_start[:-1]) / 2  # Newell: area times the normal
    centroid = np.add.reduceat(p, face_start[:-1]) / lengths[:, None]
    area = np.linalg.norm(n, axis=1)
    x = np.where(np.isnan(x), np.nan, 0.0)  # the center, in these coordinates
    # Faces wound inward, cell by cell: the signed volume from the center.
    cell_first = np.searchsorted(face_cell, np.arange(len(seed)))
    volume = np.add.reduceat(np.einsum("ij,ij->i", centroid - x, n), cell_first) / 3
    sign = np.where(volume[face_cell] < 0, -1.0, 1.0)
    beyond = sign * np.einsum("ij,ij->i", n, x - centroid) / np.where(area > 0, area, 1)
    beyond[(area < 1e-12 * r * r) | given_nan[face_cell]] = -np.inf  # a sliver's plane is round-off
    worst_of = np.maximum.reduceat(beyond, cell_first)
    bad_cells = worst_of > 1e-9 * r
    if bad_cells.any():
        problems.append("star shape: %d cells are not star-shaped from their center (it lies %.3g r beyond a face's "
                        "plane)" % (bad_cells.sum(), worst_of.max() / r))
    return problems, len(seed)


def main():
    problems, cells = check(sys.argv[1])
    for p in problems:
        print(p)
    print("%s: %d cells, %s" % (sys.argv[1], cells, "all local guarantees hold" if not problems else
                                "%d kinds of violation" % len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
