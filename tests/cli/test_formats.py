"""The solver formats, read back by readers that are not froth: VTK for the VTU, OpenFOAM's
checkMesh for the polyMesh, numpy for the facet graph (.npz) and the peridynamic nodes. For a box,
the unit sphere, non-convex parts and a graded part: the same cells, volumes (1e-12), faces and
neighbour pairs in every format; the facet graph's areas close each cell and sum to the surface.
Run with Debian's /usr/bin/python3. Usage: test_formats.py FROTH MODELS_DIR"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

from harness import CHECKMESH, check, checkmesh, face_stream, failures, froth, read_vtk, summary  # noqa: E402

MODELS = sys.argv[2]
def vtu_cells(path):
    """Per cell its volume and faces (tuples of point ids), from VTK's reader."""
    g = read_vtk(path)
    points = vtk_to_numpy(g.GetPoints().GetData())
    volumes = vtk_to_numpy(g.GetCellData().GetArray("volume"))
    return points, volumes, [face_stream(g, c) for c in range(g.GetNumberOfCells())]


def polygon_area(p):
    n = np.zeros(3)
    for k in range(len(p)):
        n += np.cross(p[k], p[(k + 1) % len(p)])
    return np.linalg.norm(n) / 2


def neighbour_pairs(faces):
    """Interior faces as (cell, cell) pairs with multiplicity, from faces sharing their vertices."""
    owner = {}
    pairs = []
    for c, cell in enumerate(faces):
        for f in cell:
            key = frozenset(f)
            if key in owner:
                pairs.append(tuple(sorted((owner.pop(key), c))))
            else:
                owner[key] = c
    return sorted(pairs), len(owner)


def exodus_cells(path):
    """Per froth cell id: its element variables, and its faces as tuples of global node ids."""
    r = vtk.vtkExodusIIReader()
    r.SetFileName(path)
    r.UpdateInformation()
    r.SetAllArrayStatus(vtk.vtkExodusIIReader.ELEM_BLOCK, 1)
    for i in range(r.GetNumberOfElementResultArrays()):
        r.SetElementResultArrayStatus(r.GetElementResultArrayName(i), 1)
    r.GenerateGlobalNodeIdArrayOn()
    r.Update()
    cells, faces = {}, {}
    it = r.GetOutput().NewIterator()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        ds = it.GetCurrentDataObject()
        cd = ds.GetCellData()
        ids = vtk_to_numpy(cd.GetArray("cell_id")).astype(int)
        vol = vtk_to_numpy(cd.GetArray("volume"))
        seed = vtk_to_numpy(cd.GetArray("seed"))
        gid = vtk_to_numpy(ds.GetPointData().GetArray("GlobalNodeId"))
        for k in range(ds.GetNumberOfCells()):
            cells[ids[k]] = {"volume": vol[k], "seed": seed[k]}
            faces[ids[k]] = face_stream(ds, k, lambda v: int(gid[v]))
        it.GoToNextItem()
    return cells, faces


def foam_list(path):
    text = open(path).read()
    body = text[text.index("}", text.index("FoamFile")) + 1:]
    m = re.search(r"(\d+)\s*\(", body)
    n = int(m.group(1))
    return [int(v) for v in body[m.end():].split()[:n]]


tmp = tempfile.mkdtemp(prefix="froth_formats_")
cases = [
    ("box", "box:0,0,0,1,1,1", ["-r", "0.12"], True),
    ("sphere", os.path.join(MODELS, "unit_sphere.STL"), ["-r", "0.25"], False),
    ("fichera", os.path.join(MODELS, "7_8ths_cube.stl"), ["-r", "6"], False),
    ("hollow", os.path.join(MODELS, "hollow_sphere.off"), ["-r", "0.08"], False),
    ("graded tube", os.path.join(MODELS, "round.stl"), ["-r", "3.0585", "--grade"], False),
]
for name, model, radius, convex_box in cases:
    base = os.path.join(tmp, name.replace(" ", "_"))
    os.makedirs(base)
    args = ["mesh", model, *radius, "--seed", "3"]
    vtu, npz, nodes, foam, exo = (os.path.join(base, f) for f in ("m.vtu", "m.npz", "m.nodes", "case/constant/polyMesh",
                                                                  "m.exo"))
    report = os.path.join(base, "m.json")
    ok = True
    for out in (vtu, npz, nodes, foam, exo):
        p = froth(*args, "-o", out, *(["--report", report] if out == vtu else []))
        check(p.returncode == 0, f"{name}: -o {os.path.basename(out)}: {p.returncode} {p.stderr}")
        ok &= p.returncode == 0
    if not ok:
        continue
    import json
    surface_area = json.load(open(report))["surface_area"] if "surface_area" in json.load(open(report)) else None
    points, volumes, faces = vtu_cells(vtu)
    n = len(volumes)
    pairs, border = neighbour_pairs(faces)

    # The facet graph.
    g = np.load(npz)
    check(int(g["format_version"][0]) == 2, f"{name}: facet graph version")
    check(len(g["cell_volume"]) == n and np.allclose(g["cell_volume"], volumes, rtol=1e-12, atol=0),
          f"{name}: facet graph volumes")
    fc = g["face_cells"]
    check(sorted(map(tuple, fc.tolist())) == pairs, f"{name}: facet graph neighbour pairs differ from the VTU's")
    check(len(g["border_cell"]) == border, f"{name}: facet graph border faces {len(g['border_cell'])} vs {border}")
    # Areas: each cell's faces (interior ones from both sides, border ones) sum to its surface.
    area = np.zeros(n)
    np.add.at(area, fc[:, 0], g["face_area"])
    np.add.at(area, fc[:, 1], g["face_area"])
    np.add.at(area, g["border_cell"], g["border_area"])
    vtu_area = np.array([sum(polygon_area(points[list(f)]) for f in cell) for cell in faces])
    check(np.allclose(area, vtu_area, rtol=1e-9), f"{name}: facet graph areas do not close the cells")
    if surface_area:
        check(abs(g["border_area"].sum() - surface_area) <= 1e-9 * surface_area,
              f"{name}: border area {g['border_area'].sum()} vs surface {surface_area}")
    normals = g["face_normal"]
    check(np.allclose(np.linalg.norm(normals, axis=1), 1, atol=1e-9), f"{name}: face normals are not unit")
    # The normal points from the first cell's seed side to the second's.
    d = g["cell_seed"][fc[:, 1]] - g["cell_seed"][fc[:, 0]]
    check(np.all(np.einsum("ij,ij->i", d, normals) >= 0), f"{name}: a face normal points into its first cell")
    # The peridynamic nodes: one per cell, its volume, its centroid the facet graph's.
    nd = np.loadtxt(nodes)
    check(nd.shape == (n, 5) and np.allclose(nd[:, 4], volumes, rtol=1e-12, atol=0) and np.all(nd[:, 3] == 1),
          f"{name}: peridynamic nodes {nd.shape}")
    check(np.allclose(nd[:, :3], g["cell_centroid"], rtol=0, atol=1e-12 * np.abs(points).max()),
          f"{name}: node positions are not the cell centroids")

    # Exodus II through VTK's reader: every cell once (by cell_id), its volume, the seeds, and the
    # VTU's neighbour pairs from the faces the NFACED elements share (global node ids).
    ex_cells, ex_faces = exodus_cells(exo)
    check(sorted(ex_cells) == list(range(1, n + 1)), f"{name}: Exodus cells {len(ex_cells)} vs {n}")
    check(all(np.isclose(ex_cells[c]["volume"], volumes[c - 1], rtol=1e-12, atol=0) for c in ex_cells),
          f"{name}: Exodus volumes differ from the VTU's")
    check(all(np.allclose(ex_cells[c]["seed"], g["cell_seed"][c - 1], rtol=0, atol=0) for c in ex_cells),
          f"{name}: Exodus seeds differ")
    ex_pairs, ex_border = neighbour_pairs([ex_faces[c] for c in sorted(ex_faces)])
    check(ex_pairs == pairs and ex_border == border, f"{name}: Exodus neighbour pairs or border faces differ")

    # OpenFOAM: owner < neighbour, upper-triangular, the VTU's pairs; checkMesh's verdict.
    owner, neighbour = foam_list(os.path.join(foam, "owner")), foam_list(os.path.join(foam, "neighbour"))
    internal = list(zip(owner[:len(neighbour)], neighbour))
    check(all(a < b for a, b in internal), f"{name}: an owner is not below its neighbour")
    check(internal == sorted(internal), f"{name}: interior faces not in upper-triangular order")
    check(sorted(internal) == pairs, f"{name}: OpenFOAM neighbour pairs differ from the VTU's")
    check(len(owner) - len(neighbour) == border, f"{name}: OpenFOAM border faces")
    if os.path.exists(CHECKMESH):
        p = checkmesh(os.path.join(base, "case"))
        out = p.stdout
        cells = re.search(r"cells:\s+(\d+)", out)
        check(cells and int(cells.group(1)) == n, f"{name}: checkMesh counts {cells and cells.group(1)} cells, not {n}")
        for line in ("Boundary definition OK", "Cell to face addressing OK", "Point usage OK",
                     "Upper triangular ordering OK", "Face vertices OK", "Cell volumes OK"):
            check(line in out, f"{name}: checkMesh does not say '{line}'")
        check(re.search(r"Max cell openness = \S+ OK", out) is not None, f"{name}: checkMesh: cells not closed")
        total = re.search(r"Total volume = (\S+)\.\s", out)
        check(total and abs(float(total.group(1)) - volumes.sum()) <= 1e-5 * volumes.sum(),
              f"{name}: checkMesh total volume {total and total.group(1)}")
        failed = re.findall(r"\*\*\*(.*)", out)
        print(f"{name}: {n} cells; checkMesh: {'Mesh OK' if 'Mesh OK' in out else 'failed: ' + '; '.join(failed)}")
        if convex_box:
            check("Mesh OK" in out, f"{name}: checkMesh does not say Mesh OK: {failed}")
        # Only the geometric checks that non-convex and boundary-skewed cells fail may fail.
        allowed = ("face pyramids", "skewness", "concave cells", "non-orthogonal")
        check(all(any(a in f for a in allowed) for f in failed), f"{name}: checkMesh failed a topological check: {failed}")
    else:
        failures.append("checkMesh not found (Debian package openfoam)")

    # froth convert gives the same files from the VTU as froth mesh gave directly.
    converted = os.path.join(base, "c.npz")
    p = froth("convert", vtu, "-o", converted)
    check(p.returncode == 0, f"{name}: froth convert: {p.returncode} {p.stderr}")
    if p.returncode == 0:
        c = np.load(converted)
        check(all(np.array_equal(c[k], g[k], equal_nan=True) for k in g.files if k not in ("border_plane", "border_patch", "patch_names")),
              f"{name}: froth convert's facet graph differs from froth mesh's")

# Boundary patches: ASCII STL solids (the heater's seven, two disjoint cubes) or, where the file
# names none, the smooth regions between feature curves (a box's six sides). Each patch's border
# faces sum to the input patch's area in the facet graph, OpenFOAM's boundary lists the same
# faces per patch, and --boundary's surface VTU gives every border face its patch.
def stl_patch_areas(path):
    """Each ASCII STL solid's name and area, and the length of its edges shared with a coplanar
    triangle of another solid (where two patches meet inside one facet plane)."""
    areas, names, tri, edges = [], [], [], {}
    for line in open(path):
        w = line.split()
        if not w:
            continue
        if w[0] == "solid":
            names.append(" ".join(w[1:]) or f"solid_{len(names)}")
            areas.append(0.0)
        elif w[0] == "vertex":
            tri.append(np.array([float(x) for x in w[1:4]]))
        elif w[0] == "endfacet":
            n = np.cross(tri[1] - tri[0], tri[2] - tri[0])
            areas[-1] += np.linalg.norm(n) / 2
            for k in range(3):
                a, b = tuple(tri[k]), tuple(tri[(k + 1) % 3])
                edges.setdefault((min(a, b), max(a, b)), []).append((len(names) - 1, n / np.linalg.norm(n)))
            tri = []
    shared = [0.0] * len(names)
    for (a, b), uses in edges.items():
        if len(uses) == 2 and uses[0][0] != uses[1][0] and np.dot(uses[0][1], uses[1][1]) > 1 - 1e-9:
            for patch, _ in uses:
                shared[patch] += np.linalg.norm(np.subtract(a, b))
    return names, areas, shared


for name, model, r, expected in [
        ("heater patches", os.path.join(MODELS, "multi_region_heater", "heater.stl"), "0.004", None),
        ("two cubes", os.path.join(MODELS, "two_objects_mixed_case_names.stl"), "0.3", None),
        ("box sides", "box:0,0,0,2,1,1", "0.2", (["surface_%d" % k for k in range(6)], sorted([2, 2, 2, 2, 1, 1])))]:
    base = os.path.join(tmp, name.replace(" ", "_"))
    os.makedirs(base)
    npz, boundary, foam = (os.path.join(base, f) for f in ("p.npz", "b.vtu", "case/constant/polyMesh"))
    p = froth("mesh", model, "-r", r, "--seed", "2", "-o", npz, "--boundary", boundary)
    q = froth("mesh", model, "-r", r, "--seed", "2", "-o", foam)
    check(p.returncode == 0 and q.returncode == 0, f"{name}: {p.stderr} {q.stderr}")
    if p.returncode or q.returncode:
        continue
    g = np.load(npz)
    names = [str(x) for x in g["patch_names"]]
    got = np.bincount(g["border_patch"], weights=g["border_area"], minlength=len(names))
    if expected is None:
        want_names, want, shared = stl_patch_areas(model)
        check(names == want_names, f"{name}: patch names {names} vs {want_names}")
        # Patches on one facet plane (the heater's interfaces below it) meet inside border faces,
        # and such a face goes whole to the patch under its centre: exact where patches meet at
        # edges of the part; where they meet inside a plane, a patch gains or loses parts of the
        # faces across that line, which lie within a face's width (2 r) of it.
        bound = [1e-9 * w + 2 * float(r) * l for w, l in zip(want, shared)]
        check(len(got) == len(want) and np.isclose(sum(got), sum(want), rtol=1e-9) and
              all(abs(g_ - w) <= b for g_, w, b in zip(got, want, bound)), f"{name}: patch areas {got} vs {want}")
    else:
        check(names == expected[0], f"{name}: patch names {names}")
        check(np.allclose(sorted(got), expected[1], rtol=1e-9), f"{name}: patch areas {sorted(got)}")
    counts = np.bincount(g["border_patch"], minlength=len(names))
    text = open(os.path.join(foam, "boundary")).read()
    foam_counts = [int(x) for x in re.findall(r"nFaces\s+(\d+);", text)]
    check(foam_counts == counts.tolist(), f"{name}: OpenFOAM patches {foam_counts} vs {counts.tolist()}")
    r_ = vtk.vtkXMLUnstructuredGridReader()
    r_.SetFileName(boundary)
    r_.Update()
    patch = vtk_to_numpy(r_.GetOutput().GetCellData().GetArray("patch"))
    check(np.bincount(patch, minlength=len(names)).tolist() == counts.tolist(), f"{name}: --boundary patches")

# --compress: VTK's zlib layout, the same cells, points and faces as the raw VTU, a smaller file,
# and froth's own reader takes it back.
raw, packed = os.path.join(tmp, "raw.vtu"), os.path.join(tmp, "packed.vtu")
for out, extra in ((raw, []), (packed, ["--compress"])):
    p = froth("mesh", os.path.join(MODELS, "hinge.stl"), "-r", "2", "--seed", "5", "-o", out, *extra)
    check(p.returncode == 0, f"--compress: {p.returncode} {p.stderr}")
if os.path.exists(raw) and os.path.exists(packed):
    a, b = vtu_cells(raw), vtu_cells(packed)
    check(np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1]) and a[2] == b[2], "--compress: a different mesh")
    check(os.path.getsize(packed) < 0.7 * os.path.getsize(raw),
          f"--compress: {os.path.getsize(packed)} bytes against {os.path.getsize(raw)}")
    p = froth("quality", packed)
    check(p.returncode == 0 and "every cell closed" in p.stdout, f"froth quality on a compressed VTU: {p.stderr}")

# A polyhedral VTU from another program, without froth's volume array (issue 40: froth convert
# crashed there, rc 139, and left its temporary file): the volumes come from the cells.
plain, novolume = os.path.join(tmp, "plain.vtu"), os.path.join(tmp, "novolume.vtu")
p = froth("mesh", "box:0,0,0,1,1,1", "-r", "0.3", "--seed", "3", "-o", plain, "--quiet")
check(p.returncode == 0, f"box for the volume-less VTU: {p.returncode} {p.stderr}")
g_ = read_vtk(plain)
g_.GetCellData().RemoveArray("volume")
w_ = vtk.vtkXMLUnstructuredGridWriter()
w_.SetFileName(novolume)
w_.SetInputData(g_)
w_.Write()
for ext in (".exo", ".nodes"):
    out = os.path.join(tmp, "novolume" + ext)
    p = froth("convert", novolume, "-o", out)
    check(p.returncode == 0 and os.path.exists(out), f"convert of a VTU without volumes to {ext}: {p.returncode} {p.stderr}")
    check(not [f for f in os.listdir(tmp) if ".tmp" in f], f"convert to {ext} left a temporary file")
if os.path.exists(os.path.join(tmp, "novolume.exo")):
    ex_cells, _ = exodus_cells(os.path.join(tmp, "novolume.exo"))
    _, plain_volumes, _ = vtu_cells(plain)
    ex_volumes = np.array([ex_cells[c]["volume"] for c in sorted(ex_cells)])
    check(len(ex_volumes) == len(plain_volumes) and np.allclose(ex_volumes, plain_volumes, rtol=1e-12, atol=0),
          "convert of a VTU without volumes: the Exodus volumes are not the cells' volumes")

p = froth("mesh", "box:0,0,0,1,1,1", "-r", "0.3", "-o", os.path.join(tmp, "x.exo2"))
check(p.returncode == 2 and "polyMesh" in p.stderr, f"unknown format: {p.returncode} {p.stderr}")

code = summary()
if failures:
    print(f"outputs kept in {tmp}")
else:
    shutil.rmtree(tmp)
sys.exit(code)
