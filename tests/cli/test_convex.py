"""froth mesh --convex (issue 22 item 3), read back by VTK: every piece convex, the pieces of a cell summing to the cell's volume
in the same run without --convex, the mesh still conforming (each face in one cell on the
border or in exactly two with the same vertices), the report's counts matching the file, and
checkMesh finding the pieces' face pyramids correctly oriented where the unsplit mesh has
inverted ones. Multi-region solids too (the heater's five solids, a sphere inclusion in a box):
each piece in its cell's region, each region's pieces summing to its enclosed volume and each
interface's area from either side to the input's (1e-9).

Convex is checked as each piece's convex hull (scipy's qhull over its vertices) holding no more
volume than the piece, within 1e-12 r^3: the unsplit cells miss theirs by up to 0.3 r^3. froth
itself tests every vertex against every face plane within 1e-12 r, with the planes its faces were
cut from (seed bisectors, domain facets); planes refitted to a file's vertices cannot do that,
since the clipper leaves vertices up to 1e-11 r off their planes and a face 1e-6 r wide then
tilts by 1e-5.
Usage: test_convex.py FROTH MODELS_DIR"""
import collections
import json
import os
import re
import sys
import tempfile

import numpy as np
from vtk.util.numpy_support import vtk_to_numpy

from scipy.spatial import ConvexHull

from harness import check, checkmesh, face_stream, froth, read_vtk, summary

MODELS = sys.argv[2]
# (model, r, the largest aspect ratio of a piece where it is known to be small): the 7/8 cube's
# float STL has steps of 1e-7 r between facets of one face, which cuts would turn into slabs.
CASES = [("hollow_sphere.off", 0.08, 1e3), ("hinge.stl", 1.5, None), ("round.stl", 0.3, 1e3),
         ("7_8ths_cube.stl", 4.0, 10), ("1002_tray_bottom.STL", 5.0, None),
         ("multi_region_heater", 0.012, 10), ("sphere in a box", 0.26, None)]
REGION_INPUTS = {
    "multi_region_heater": [os.path.join(MODELS, "multi_region_heater", f + ".stl")
                            for f in ("bottomAir", "heater", "leftSolid", "rightSolid", "topAir")],
    "sphere in a box": ["box:-1.5,-1.5,-1.5,1.5,1.5,1.5", os.path.join(MODELS, "unit_sphere.STL")],
}


def hull_excess(points, faces):
    """The volume of the cell's convex hull beyond the cell's own (0 for a convex cell)."""
    ids = sorted({v for f in faces for v in f})
    return ConvexHull(points[ids]).volume


def area(points, f):
    q = points[list(f)]
    return 0.5 * np.linalg.norm(np.cross(q[1:-1] - q[0], q[2:] - q[0]).sum(axis=0))


def check_regions(name, g, whole, parent, volume, points, faces, j):
    """A multi-region mesh's pieces: in their cell's region, volumes per region and interface
    areas from each side as the input's."""
    region = vtk_to_numpy(g.GetCellData().GetArray("region"))
    whole_region = vtk_to_numpy(whole.GetCellData().GetArray("region"))
    check(np.array_equal(region, whole_region[parent]), f"{name}: a piece is not in its cell's region")
    for k, reg in enumerate(j["regions"]):
        v = float(volume[region == k].sum())
        check(abs(v - reg["enclosed_volume"]) <= 1e-9 * reg["enclosed_volume"],
              f"{name}: region {reg['name']}: pieces {v} against {reg['enclosed_volume']}")
    names = [x["name"] for x in j["regions"]]
    sides = collections.defaultdict(float)
    for c, fs in enumerate(faces):
        for f in fs:
            sides[tuple(sorted(f)), names[region[c]]] = area(points, f)
    by_face = collections.defaultdict(dict)
    for (key, reg), a in sides.items():
        by_face[key][reg] = a
    from_side = collections.defaultdict(float)
    for regs in by_face.values():
        if len(regs) == 2:
            pair = tuple(sorted(regs))
            for reg, a in regs.items():
                from_side[pair, reg] += a
    for i in j["interfaces"]:
        pair = tuple(sorted(i["regions"]))
        for reg in pair:
            check(abs(from_side[pair, reg] - i["area"]) <= 1e-9 * i["area"],
                  f"{name}: interface {pair} from {reg}: {from_side[pair, reg]} against {i['area']}")


def run_case(tmp, name, r, aspect_bound):
    inputs = REGION_INPUTS.get(name, [os.path.join(MODELS, name)])
    stem = os.path.join(tmp, name.split(".")[0].replace(" ", "_"))
    p = froth("mesh", *inputs, "-r", str(r), "--seed", "1", "--convex", "-q", "-o", stem + "_convex.vtu",
              "--report", stem + "_convex.json")
    check(p.returncode == 0, f"{name}: --convex exits {p.returncode}: {p.stderr}")
    if p.returncode != 0:
        return
    p = froth("mesh", *inputs, "-r", str(r), "--seed", "1", "--weld", "0", "-q", "-o", stem + ".vtu")
    check(p.returncode == 0, f"{name}: the unsplit mesh exits {p.returncode}: {p.stderr}")
    full_report = json.load(open(stem + "_convex.json"))
    report = full_report["convex"]
    g, whole = read_vtk(stem + "_convex.vtu"), read_vtk(stem + ".vtu")
    points = vtk_to_numpy(g.GetPoints().GetData())
    n = g.GetNumberOfCells()
    parent = vtk_to_numpy(g.GetCellData().GetArray("parent"))
    volume = vtk_to_numpy(g.GetCellData().GetArray("volume"))
    whole_volume = vtk_to_numpy(whole.GetCellData().GetArray("volume"))
    check(len(whole_volume) == parent.max() + 1 and np.all(np.diff(parent) >= 0),
          f"{name}: parent does not number the unsplit mesh's cells in order")
    summed = np.bincount(parent, weights=volume, minlength=len(whole_volume))
    check(np.allclose(summed, whole_volume, rtol=1e-9, atol=0),
          f"{name}: pieces do not sum to their cell's volume (worst {np.max(np.abs(summed / whole_volume - 1)):.3g})")
    # Convexity: no cell's hull holds more than the cell, but the cells the report leaves.
    faces = [face_stream(g, c) for c in range(n)]
    excess = np.array([hull_excess(points, f) for f in faces]) - volume
    nonconvex = int(np.count_nonzero(excess > 1e-12 * r ** 3))
    pieces = np.bincount(parent)
    split = int(np.count_nonzero(pieces > 1))
    check(split == report["cells_split"] and int(pieces[pieces > 1].sum()) == report["pieces"],
          f"{name}: the report's {report['cells_split']} cells split into {report['pieces']} pieces; the file has "
          f"{split} into {int(pieces[pieces > 1].sum())}")
    check(nonconvex <= report["cells_left_nonconvex"],
          f"{name}: {nonconvex} cells' convex hulls exceed them by over 1e-12 r^3 (worst {excess.max() / r ** 3:.3g} "
          f"r^3); the report leaves {report['cells_left_nonconvex']}")
    if aspect_bound is not None:
        check(report["piece_aspect_max"] <= aspect_bound,
              f"{name}: a piece has aspect ratio {report['piece_aspect_max']:.3g}, above {aspect_bound}: a sliver")
    # Cells are left only at steps of the input's round-off: non-convex by at most
    # 1e-6 (r + the largest coordinate) (src/convex).
    step = 1e-6 * (r + float(np.abs(points).max())) / r
    check(report["left_vertex_beyond_face_plane_over_r"] <= step,
          f"{name}: {report['cells_left_nonconvex']} cells left non-convex by up to "
          f"{report['left_vertex_beyond_face_plane_over_r']:.3g} r, more than the input's round-off {step:.3g} r")
    # Conformity: each cell closed (each directed edge once, its reverse once), and each face in
    # one cell (the border) or in two, there in the other orientation.
    open_cells = 0
    for fs in faces:
        edges = collections.Counter((f[k], f[(k + 1) % len(f)]) for f in fs for k in range(len(f)))
        open_cells += any(c != 1 or edges[(b, a)] != 1 for (a, b), c in edges.items())
    check(open_cells == 0, f"{name}: {open_cells} cells are not closed")
    owners = collections.defaultdict(list)
    for c, fs in enumerate(faces):
        for f in fs:
            owners[tuple(sorted(f))].append((c, f))
    unmatched = 0
    for key, where in owners.items():
        if len(where) == 1:
            continue
        (c1, f1), (c2, f2) = where[0], where[-1]
        k = f2.index(f1[0])
        reversed_ok = len(where) == 2 and c1 != c2 and all(f2[(k - i) % len(f2)] == f1[i] for i in range(len(f1)))
        unmatched += not reversed_ok
    check(unmatched == 0, f"{name}: {unmatched} faces are not shared by exactly two cells in opposite orientations")
    if name in REGION_INPUTS:
        check_regions(name, g, whole, parent, volume, points, faces, full_report)
    print(f"{name} r={r}: {len(whole_volume)} cells -> {n}; {split} split into {report['pieces']} pieces "
          f"(up to {report['most_pieces_of_a_cell']}); largest hull excess {excess.max() / r ** 3:.2e} r^3; "
          f"{report['cells_left_nonconvex']} left non-convex (by up to {report['left_vertex_beyond_face_plane_over_r']:.2g} r); smallest piece {report['smallest_piece_volume_over_r3']:.3g} r^3; "
          f"pieces' aspect mean {report['piece_aspect_mean']:.3g}")


def run_checkmesh(tmp):
    path = os.path.join(MODELS, "hollow_sphere.off")
    for flag in ["", "--convex"]:
        case = os.path.join(tmp, "foam" + flag.strip("-"))
        p = froth("mesh", path, "-r", "0.08", "--seed", "1", *([flag] if flag else []), "-q",
                  "-o", os.path.join(case, "constant", "polyMesh"))
        check(p.returncode == 0, f"polyMesh {flag}: exits {p.returncode}: {p.stderr}")
        out = checkmesh(case).stdout
        inverted = re.search(r"Error in face pyramids: (\d+) faces", out)
        if flag:
            check("Face pyramids OK" in out, f"checkMesh --convex: face pyramids not OK: {inverted and inverted.group(0)}")
        else:
            check(inverted is not None, "checkMesh: the unsplit hollow sphere no longer has inverted face pyramids "
                                        "(the --convex comparison needs a new case)")
        print(f"checkMesh, hollow sphere {flag or 'unsplit'}: "
              f"{'face pyramids OK' if 'Face pyramids OK' in out else inverted and inverted.group(0)}")


def main():
    with tempfile.TemporaryDirectory() as tmp:
        for name, r, aspect_bound in CASES:
            run_case(tmp, name, r, aspect_bound)
        run_checkmesh(tmp)
        p = froth("mesh", "box:0,0,0,1,1,1", "-r", "0.2", "--convex", "--weld", "0.001", "-q", "-o", os.path.join(tmp, "b.vtu"))
        check(p.returncode == 2 and "convex cells cannot be combined with welding" in p.stderr,
              f"--convex with --weld: exit {p.returncode}: {p.stderr}")
        p = froth("mesh", "box:0,0,0,1,1,1", "-r", "0.2", "--convex", "-o", os.path.join(tmp, "b.vtu"))
        check(p.returncode == 0 and "every cell was convex already" in p.stdout, f"--convex on a box: {p.stdout}{p.stderr}")
    return summary()


if __name__ == "__main__":
    sys.exit(main())
