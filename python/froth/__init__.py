"""froth: uniform random Voronoi meshes of 3D solids, from Python.

    import froth
    mesh = froth.mesh("part.stl", r=1.2, seed=1)      # or cells=50000; or froth.box(...); or (vertices, triangles)
    mesh.points, mesh.face_vertices, mesh.face_offsets, mesh.cell_offsets, mesh.cell_data["volume"]
    mesh.write("part.vtu")                            # .vtu, .exo/.e, a folder named polyMesh, .npz, .nodes
    mesh.report["cells"]
    again = froth.read("part.vtu")
    for member in froth.ensemble("part.stl", r=1.2, members=20, seed=7): ...

The arrays are read-only numpy views of the C++ mesh (no copy), valid while the Mesh lives.
Errors raise froth.Error subclasses carrying the command line's message and exit code:
UsageError (2), InvalidInputError (3), IoError (4), InternalError (5).
"""
import json
import numbers
import os

from ._froth import (Domain, Error, InternalError, InvalidInputError, IoError, Mesh, UsageError, from_surface, load,
                     load_cracks, load_regions, member_seed, read, version)
from . import _froth

__all__ = ["Domain", "Mesh", "Error", "UsageError", "InvalidInputError", "IoError", "InternalError", "box", "load",
           "load_regions", "load_cracks", "from_surface", "mesh", "ensemble", "read", "member_seed", "version"]
__version__ = version


def box(lo, hi):
    """The box [lo, hi] (two 3-sequences) as a Domain, as the command line's box:X0,Y0,Z0,X1,Y1,Z1."""
    return load("box:" + ",".join(repr(float(v)) for v in (*lo, *hi)))


def _domain(surface, feature_angle, repair, cracks=None):
    if cracks:
        if isinstance(cracks, (str, os.PathLike)):
            cracks = [cracks]
        return load_cracks(_domain(surface, feature_angle, repair), [os.fspath(c) for c in cracks])
    if isinstance(surface, Domain):
        return surface
    if isinstance(surface, (str, os.PathLike)):
        return load(os.fspath(surface), feature_angle=feature_angle, repair=repair)
    if isinstance(surface, tuple) and len(surface) == 2:
        return from_surface(surface[0], surface[1], feature_angle=feature_angle, repair=repair)
    if isinstance(surface, list) and all(isinstance(s, (str, os.PathLike)) for s in surface):
        # Several solids, one region each (a multi-region mesh, as `froth mesh a.stl b.stl`).
        return load_regions([os.fspath(s) for s in surface], feature_angle=feature_angle, repair=repair)
    raise UsageError("froth.mesh takes a path, a list of paths (one region each), a box spec "
                     "'box:X0,Y0,Z0,X1,Y1,Z1', a froth.Domain or a tuple (vertices (n, 3), triangles (m, 3)); got " +
                     type(surface).__name__)


def mesh(surface, r=None, *, cells=None, seed=0, weld=None, quality=True, threads=0, grade=False, min_r=None,
         max_grading=0.2, max_memory=None, feature_angle=30.0, repair=False, convex=False, cracks=None):
    """Mesh a solid: `froth mesh` with the same options gives the same mesh, byte for byte.

    surface: a surface file (STL, OBJ, OFF, PLY), 'box:X0,Y0,Z0,X1,Y1,Z1', a Domain, or a tuple
        (vertices, triangles) of arrays shaped (n, 3) and (m, 3).
    r: the sampling radius; or cells: about this many cells (the r chosen is mesh.r).
    seed: the random seed (0 to 2**64 - 1). weld: the weld tolerance (None: 1e-4 min(r, the
        domain's diagonal); 0: off). quality: measure every cell. threads: 0 for all cores.
    grade, min_r, max_grading: a radius graded to thin walls and gaps (experimental).
    max_memory: refuse a run estimated above this many GB (None: the memory available).
    feature_angle, repair: how a surface file is read (as --feature-angle and --repair).
    convex: split every non-convex cell into convex pieces (cell data "parent"; no welding).
    cracks: sheet files (or one) the solid is cut open along, as --crack (through, edge and penny
        cracks, closed sheets, crossing sheets; in a multi-region solid, inside a region or across
        interfaces); their faces are on patches crack_NAME_a and crack_NAME_b.
    """
    if (r is None) == (cells is None):
        raise UsageError("give r= (the sampling radius) or cells= (about this many cells), not both" if r is not None
                         else "give r= (the sampling radius) or cells= (about this many cells)")
    if cells is not None and not (isinstance(cells, numbers.Real) and cells > 0):
        raise UsageError(f"cells must be a positive number, got {cells!r}")
    domain = _domain(surface, feature_angle, repair, cracks)
    return _froth.mesh(domain, r=0.0 if r is None else float(r), cells=0.0 if cells is None else float(cells),
                       seed=seed, weld=weld, quality=quality, threads=threads, grade=grade, min_r=min_r,
                       max_grading=max_grading, max_memory=max_memory, convex=convex)


def ensemble(surface, r, members, *, seed=0, feature_angle=30.0, repair=False, cracks=None, **options):
    """Yield `members` independent meshes of one solid, member k made with seed member_seed(seed, k):
    the same meshes `froth ensemble` writes. Each has `index` and `member_seed` set. The surface
    (and the cracks) are read once."""
    domain = _domain(surface, feature_angle, repair, cracks)
    for k in range(members):
        s = member_seed(seed, k)
        m = mesh(domain, r, seed=s, **options)
        m.index, m.member_seed = k, s
        yield m


def _report(self):
    """The run report (the JSON --report writes) as a dict."""
    return json.loads(self.report_json())


def _cell(self, c):
    """Cell c's faces, each an array of vertex ids, counter-clockwise seen from outside the cell."""
    lo, hi = self.cell_offsets[c], self.cell_offsets[c + 1]
    fo, fv = self.face_offsets, self.face_vertices
    return [fv[fo[f]:fo[f + 1]] for f in range(lo, hi)]


def _repr(self):
    return f"<froth.Mesh: {self.cell_count} cells, {self.face_count} faces, {len(self.points)} points, r = {self.r:.6g}>"


Mesh.report = property(_report)
Mesh.cell = _cell
Mesh.__repr__ = _repr
