"""End-to-end: the froth program's exit codes and outputs, read back by real readers (VTK 9.1 and
meshio 7). Run with Debian's /usr/bin/python3 (python3-vtk9, python3-meshio)."""
import json
import os
import pty
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

import harness  # noqa: E402
from harness import FROTH, check, failures, froth, read_vtk  # noqa: E402

MODELS = sys.argv[2]
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data")


def vtk_volumes(grid):
    """Each polyhedron's volume from the faces VTK parsed (divergence theorem, each face fanned
    from its centroid as froth does, so welded faces that are slightly non-planar count the same
    in both cells that share them). VTK's own vtkCellSizeFilter triangulates polyhedra
    approximately (0.3% off on faceted fringe cells)."""
    pts = vtk_to_numpy(grid.GetPoints().GetData())
    out = np.empty(grid.GetNumberOfCells())
    for c in range(grid.GetNumberOfCells()):
        cell, v = grid.GetCell(c), 0.0
        for f in range(cell.GetNumberOfFaces()):
            face = cell.GetFace(f)
            p = pts[[face.GetPointId(k) for k in range(face.GetNumberOfPoints())]]
            centroid = p.mean(axis=0)
            v += np.einsum("j,ij->", centroid, np.cross(p, np.roll(p, -1, axis=0)))
        out[c] = v / 6
    return out


tmp = tempfile.mkdtemp()
for name, domain, r, volume in [("box", "box:0,0,0,1,2,1", 0.12, 2.0),
                                ("sphere", os.path.join(MODELS, "unit_sphere.STL"), 0.15, None)]:
    out, rep = os.path.join(tmp, name + ".vtu"), os.path.join(tmp, name + ".json")
    # Welding off: the cell data must then keep the paper's bounds exactly.
    p = froth("mesh", domain, "-r", str(r), "--seed", "7", "-o", out, "--report", rep, "--weld", "0")
    check(p.returncode == 0, f"{name}: exit code {p.returncode}: {p.stderr}")
    check("cells" in p.stdout and "relative error" in p.stdout, f"{name}: summary paragraph missing")
    report = json.load(open(rep))
    cells = report["mesh"]["cells"]
    feats = report["features"]
    expect = {"convex_edges": 12, "reflex_edges": 0, "corners": 8, "curves": 12} if name == "box" else \
        {"convex_edges": 0, "reflex_edges": 0, "corners": 0, "curves": 0, "flat_edges": 1920}
    check(all(feats[k] == v for k, v in expect.items()) and feats["angle_degrees"] == 30,
          f"{name}: features {feats}")
    check(report["volume"]["relative_error"] <= 1e-9, f"{name}: report volume error")
    if volume is not None:
        check(abs(report["volume"]["domain"] - volume) < 1e-12, f"{name}: domain volume")

    g = read_vtk(out)
    check(g.GetNumberOfCells() == cells, f"{name}: VTK reads {g.GetNumberOfCells()} cells, report says {cells}")
    types = {g.GetCellType(i) for i in range(g.GetNumberOfCells())}
    check(types == {vtk.VTK_POLYHEDRON}, f"{name}: cell types {types}")
    cd = g.GetCellData()
    vol = vtk_to_numpy(cd.GetArray("volume"))
    seeds = vtk_to_numpy(cd.GetArray("seed"))
    kind = vtk_to_numpy(cd.GetArray("kind"))
    check(seeds.shape == (cells, 3), f"{name}: seed array shape {seeds.shape}")
    check(set(np.unique(kind)) <= {0, 1}, f"{name}: kinds {np.unique(kind)}")
    check(abs(vol.sum() - report["volume"]["domain"]) <= 1e-9 * report["volume"]["domain"],
          f"{name}: volume array sums to {vol.sum()}")
    # VTK's own volume of each polyhedron, from the faces it read.
    vv = vtk_volumes(g)
    check(np.allclose(vv, vol, rtol=1e-9, atol=0), f"{name}: VTK polyhedron volumes differ, max {np.max(abs(vv - vol))}")
    check(abs(vv.sum() - report["volume"]["domain"]) <= 1e-9 * report["volume"]["domain"],
          f"{name}: VTK total volume {vv.sum()}")
    fd = g.GetFieldData()
    check(abs(fd.GetArray("r").GetValue(0) - r) == 0, f"{name}: field r")
    check(fd.GetArray("random_seed").GetValue(0) == 7, f"{name}: field random_seed")
    check(fd.GetArray("weld") is not None and fd.GetArray("version") is not None, f"{name}: field weld/version")
    # Quality cell data, consistent with the report: the aspect ratio is outradius / inradius,
    # and interior cells keep the paper's bounds (Theorem 1, Lemma 6).
    q = {k: vtk_to_numpy(cd.GetArray(k)) for k in
         ("aspect", "outradius", "inradius", "min_dihedral", "max_dihedral", "min_edge")}
    check(np.allclose(q["aspect"], q["outradius"] / q["inradius"], rtol=1e-12), f"{name}: aspect = Ro/Ri")
    check(np.all(q["outradius"] <= r * (1 + 1e-9)), f"{name}: outradius <= r (Lemma 1)")
    interior = kind == 0
    check(np.all(q["aspect"][interior] <= 2), f"{name}: interior aspect <= 2")
    check(np.all(q["min_dihedral"][interior] >= 60 - 1e-7) and np.all(q["max_dihedral"][interior] <= 150 + 1e-7),
          f"{name}: interior dihedrals in [60, 150]")
    rq = report["quality"]
    check(abs(rq["cells"]["interior"]["aspect"]["max"] - q["aspect"][interior].max()) < 1e-12,
          f"{name}: report and VTU agree on the interior aspect ratio")
    check(rq["bounds"]["theorem1_violations"] == 0, f"{name}: report counts no Theorem 1 violation")
    check(abs(rq["shortest_edge"] - q["min_edge"].min()) < 1e-15, f"{name}: shortest edge")

    # meshio 7.0.0 parses the polyhedra and cell data. (Its Mesh constructor then pairs cell data
    # with blocks in the wrong order when polyhedra differ in vertex count: upstream meshio
    # PR #1463; so the check goes through its VTU parser.)
    from meshio.vtu._vtu import VtuReader
    m = VtuReader(out)
    check(sum(len(b.data) for b in m.cells) == cells, f"{name}: meshio cell count")
    check(all(b.type.startswith("polyhedron") for b in m.cells), f"{name}: meshio cell types")
    check(sum(len(x) for x in m.cell_data["volume"]) == cells, f"{name}: meshio cell data")
    check(len(m.points) == g.GetNumberOfPoints(), f"{name}: meshio point count")
    check(float(m.field_data["r"][0]) == r, f"{name}: meshio field data")

# Welding on (a large tolerance, so that many edges collapse): still a valid conforming mesh that
# VTK reads, with the total volume kept within the stated bound and the report's figures.
out, rep = os.path.join(tmp, "welded.vtu"), os.path.join(tmp, "welded.json")
p = froth("mesh", os.path.join(MODELS, "unit_sphere.STL"), "-r", "0.15", "--seed", "3", "--weld", "0.015", "-o", out,
          "--report", rep)
check(p.returncode == 0, f"welded: {p.stderr}")
report = json.load(open(rep))
wd = report["welding"]
check(wd["edges_collapsed"] > 0, "welded: nothing collapsed")
check(abs(wd["volume_change"]) <= wd["volume_change_bound"] + 1e-12, "welded: volume change beyond the bound")
check(wd["clusters_refused"] > 0 or wd["shortest_edge_after"] >= 0.015, "welded: an edge shorter than w is left")
check("bounds" in report["quality_before_welding"], "welded: no pre-welding bounds")
g = read_vtk(out)
check(g.GetNumberOfCells() == report["mesh"]["cells"], "welded: VTK cell count")
vv = vtk_volumes(g)
check(abs(vv.sum() - report["volume"]["cells_sum"]) <= 1e-9 * vv.sum(),
      f"welded: VTK total volume {vv.sum()} vs {report['volume']['cells_sum']}")
check(np.allclose(vv, vtk_to_numpy(g.GetCellData().GetArray("volume")), rtol=1e-9, atol=0), "welded: cell volumes")
check(np.all(vv > 0), "welded: a cell VTK reads has no positive volume")

# Non-convex domains end to end: the Fichera corner (reflex edges protected: edge and vertex
# cells) and the hollow sphere (a cavity found by nesting); VTK reads the clipped, partly
# non-convex polyhedra and their volumes sum to the enclosed volume; border faces lie on the
# input surface's planes. --repair meshes multibody.stl after reorienting it.
for name, args, kinds_wanted in [("fichera", [os.path.join(MODELS, "7_8ths_cube.stl"), "-r", "3"], {0, 1, 2, 3}),
                                 ("hollow", [os.path.join(MODELS, "hollow_sphere.off"), "-r", "0.06"], {0, 1}),
                                 ("repaired", [os.path.join(MODELS, "multibody.stl"), "-r", "0.05", "--repair"], {1})]:
    out, rep = os.path.join(tmp, name + ".vtu"), os.path.join(tmp, name + ".json")
    p = froth("mesh", *args, "--seed", "3", "-o", out, "--report", rep, "--weld", "0")
    check(p.returncode == 0, f"{name}: exit code {p.returncode}: {p.stderr}")
    report = json.load(open(rep))
    check(not report["input"]["convex"], f"{name}: input not reported non-convex")
    g = read_vtk(out)
    cells = report["mesh"]["cells"]
    check(g.GetNumberOfCells() == cells, f"{name}: VTK reads {g.GetNumberOfCells()} cells of {cells}")
    kind = vtk_to_numpy(g.GetCellData().GetArray("kind"))
    check(kinds_wanted <= set(np.unique(kind)), f"{name}: kinds {np.unique(kind)}, wanted {kinds_wanted}")
    vv = vtk_volumes(g)
    check(abs(vv.sum() - report["volume"]["domain"]) <= 1e-9 * report["volume"]["domain"],
          f"{name}: VTK total volume {vv.sum()} vs {report['volume']['domain']}")
    check(abs(report["border_area"]["border_faces"] - report["border_area"]["surface"])
          <= 1e-9 * report["border_area"]["surface"], f"{name}: border area {report['border_area']}")
    if name == "hollow":
        check(report["input"]["cavities"] == 1 and report["input"]["shells"] == 2, f"{name}: {report['input']}")
        check(abs(report["volume"]["domain"] - 4 / 3 * np.pi * (0.5 ** 3 - 0.4 ** 3)) < 0.02, f"{name}: volume")
    if name == "fichera":
        s = report["sampling"]
        check(s["vertex_seeds"] == 4 and s["edge_seeds"] > 0, f"{name}: protection seeds {s}")
    if name == "repaired":
        check(report["input"]["reoriented_triangles"] > 0, f"{name}: {report['input']}")
        check("reoriented" in p.stdout, f"{name}: the summary does not mention the repair")

# Byte-identical for 1 and 2 threads; another seed differs.
outs = []
for threads, seed in [(1, 5), (2, 5), (2, 6)]:
    o = os.path.join(tmp, f"t{threads}_{seed}.vtu")
    p = froth("mesh", os.path.join(MODELS, "unit_sphere.STL"), "-r", "0.2", "--seed", str(seed), "--threads",
              str(threads), "-o", o)
    check(p.returncode == 0, f"threads {threads}: {p.stderr}")
    outs.append(open(o, "rb").read())
check(outs[0] == outs[1], "1 and 2 threads give different bytes")
check(outs[0] != outs[2], "seeds 5 and 6 give the same bytes")

# Bad input: a clear message naming the defect, a distinct exit code, no output file.
for args, code, words in [
    ([os.path.join(MODELS, "shared.STL"), "-r", "0.1"], 3, "not manifold"),
    ([os.path.join(MODELS, "featuretype.STL"), "-r", "0.1"], 3, "not closed"),
    ([os.path.join(MODELS, "multibody.stl"), "-r", "0.1"], 3, "inconsistent orientation"),
    ([os.path.join(MODELS, "multibody.stl"), "-r", "0.1"], 3, "the repair option reorients"),
    ([os.path.join(MODELS, "rook.stl"), "-r", "1"], 3, "shared by 4 triangles"),
    # Multi-region input: solids that overlap (one poking into another, a pin through a plate),
    # the same solid twice, solids a rounding error apart at their vertices ...
    (["box:0,0,0,1,1,1", "box:0.5,0.2,0.2,1.5,0.8,0.8", "-r", "0.1"], 3, "box_0 and box_1 overlap near"),
    (["box:0,0,0,1,1,1", "box:0.4,0.4,-0.5,0.6,0.6,1.5", "-r", "0.1"], 3, "box_0 and box_1 overlap near"),
    (["box:0,0,0,1,1,1", "box:0,0,0,1,1,1", "-r", "0.1"], 3, "listed twice the same way"),
    (["box:0,0,0,1,1,1", "box:1.0000001,0,0,2,1,1", "-r", "0.1"], 3, "box_0 and box_1 nearly touch"),
    # ... and a block 1e-8 off a larger face, no vertex near another's.
    (["box:0,0,0,1,1,1", "box:1.00000001,0.2,0.2,2,0.8,0.8", "-r", "0.1"], 3,
     "vertex (1.00000001, 0.2, 0.2) of box_1 is 1e-08 from the triangle"),
    # The two broken kinds of real parts (tests/data/README.md): a non-manifold vertex, an open
    # surface with crossing triangles, folded faces.
    ([os.path.join(DATA, "touching_tetrahedra.off"), "-r", "0.3"], 3, "not manifold at vertex 0"),
    ([os.path.join(DATA, "open_box_crossed.off"), "-r", "0.3"], 3, "not closed"),
    ([os.path.join(DATA, "folded_box.off"), "-r", "0.3"], 3, "intersects itself"),
    (["/nonexistent.stl", "-r", "0.1"], 4, "cannot open"),
    (["box:0,0,0,1,1", "-r", "0.1"], 2, "six finite numbers"),
    (["box:0,0,0,1,1,1", "-r", "-1"], 2, "r must be positive"),
    (["box:0,0,0,1,1,1"], 2, "--cells"),
    (["box:0,0,0,1,1,1", "-r", "0.3", "--seed", "-1"], 2, "not a whole number"),
    (["box:0,0,0,1,1,1", "-r", "0.3", "--threads", "-2"], 2, "not in range"),
    (["box:0,0,0,1,1,1", "-r", "0.3", "--weld", "0.5"], 2, "weld tolerance must be in [0, r)"),
    (["box:0,0,0,1,1,1", "-r", "0.3", "--weld", "-1"], 2, "--weld"),
    (["box:0,0,0,1,1,1", "-r", "0.3", "--feature-angle", "190"], 2, "feature angle must be strictly between 0 and 180"),
    # The grading options mean nothing without --grade (issue 40: they were ignored silently),
    # and a bad grading is refused whatever the part (a box has no thin wall to grade to).
    (["box:0,0,0,1,1,1", "-r", "0.3", "--min-r", "0.1"], 2, "--min-r requires --grade"),
    (["box:0,0,0,1,1,1", "-r", "0.3", "--max-grading", "0.1"], 2, "--max-grading requires --grade"),
    (["box:0,0,0,1,1,1", "-r", "0.3", "--grade", "--max-grading", "0.3"], 2, "maximum grading must be in (0, 0.25)"),
    (["box:0,0,0,1,1,1", "-r", "0.3", "--grade", "--min-r", "0.5"], 2, "min_r must be in (0, r]"),
]:
    out = os.path.join(tmp, "bad.vtu")
    p = froth("mesh", *args, "-o", out)
    check(p.returncode == code, f"{args}: exit code {p.returncode}, expected {code}")
    check(words in p.stderr, f"{args}: message '{p.stderr.strip()}' lacks '{words}'")
    check(not os.path.exists(out), f"{args}: output file left behind")
# r = diag/5 on the I-beam, seed 2: a cell sees the domain on both sides of a wall, in two pieces
# (a property of the sample: seeds 2, 36, 43, 47 and 55 of the first 60 give it). Each piece is a cell
# of its own (cell data piece > 0 for the ones that do not hold the seed), and the mesh is whole.
out, rep = os.path.join(tmp, "pieces.vtu"), os.path.join(tmp, "pieces.json")
p = froth("mesh", os.path.join(MODELS, "shape_ibeam.stl"), "-r", "6.4031242374328485", "--seed", "2", "-o", out,
          "--report", rep)
check(p.returncode == 0 and "several pieces" in p.stdout, f"I-beam in pieces: {p.returncode} {p.stderr} {p.stdout}")
if p.returncode == 0:
    g, report = read_vtk(out), json.load(open(rep))
    piece = vtk_to_numpy(g.GetCellData().GetArray("piece"))
    seeds = vtk_to_numpy(g.GetCellData().GetArray("seed"))
    added = report["mesh"]["cells_added_by_pieces"]
    check(added > 0 and int((piece > 0).sum()) == added, f"I-beam pieces: {added} added, {int((piece > 0).sum())} in the VTU")
    # A piece follows the cell of its seed, with the same seed.
    later = np.nonzero(piece > 0)[0]
    check(all(np.array_equal(seeds[c], seeds[c - piece[c]]) and piece[c - piece[c]] == 0 for c in later),
          "I-beam pieces: a piece's seed is that of the cell before it")
    # A piece does not hold its seed: its fan point (center) is another, and the radius is r.
    center = vtk_to_numpy(g.GetCellData().GetArray("center"))
    radius = vtk_to_numpy(g.GetCellData().GetArray("radius"))
    check(all(not np.array_equal(center[c], seeds[c]) for c in later), "I-beam pieces: a piece's center is its seed")
    check(np.all(radius == 6.4031242374328485), "I-beam pieces: radius is not r")
    vv = vtk_volumes(g)
    check(vv.min() > 0 and abs(vv.sum() - report["volume"]["domain"]) < 1e-9 * report["volume"]["domain"],
          f"I-beam pieces: VTK's volumes {vv.min()} .. sum {vv.sum()} vs {report['volume']['domain']}")
# Cells of empty kernel have an infinite aspect ratio, which JSON cannot hold: the reports count
# them apart (not_finite) and an ensemble of such meshes, run twice, completes both times (it
# aborted reading its members' reports back).
ens = os.path.join(tmp, "tray_ens")
for attempt in range(2):
    p = froth("ensemble", os.path.join(MODELS, "1002_tray_bottom.STL"), "-r", "25.1", "-n", "2", "--seed", "1", "-o", ens)
    check(p.returncode == 0, f"tray ensemble, run {attempt}: {p.returncode} {p.stderr}")
if p.returncode == 0:
    member = json.load(open(os.path.join(ens, "member_00000.json")))
    infinite = sum(c["aspect"].get("not_finite", 0) for c in member["quality"]["cells"].values())
    check(infinite > 0, "tray ensemble: no cell with an infinite aspect ratio counted")
    check(len(json.load(open(os.path.join(ens, "ensemble.json")))["members"]) == 2, "tray ensemble: members")
# Options no member can be meshed with (r too small for the domain) are refused before the
# ensemble's folder is made. (A member that fails on its own, which only an internal error can make
# it do, is listed under failed_members and the others go on.)
ens = os.path.join(tmp, "failing_ens")
p = froth("ensemble", "box:0,0,0,1,1,1", "-r", "1e-4", "-n", "2", "--seed", "1", "-o", ens)
check(p.returncode == 2 and "use r of" in p.stderr and not os.path.exists(ens),
      f"ensemble with r too small: {p.returncode} {p.stderr}")

# A graded ensemble resumes as a uniform one does, and its members record the grading: the same
# folder without --grade holds an ensemble made with other inputs, refused (exit 2, nothing
# touched) unless --overwrite, which builds every member again and leaves no old member behind.
ens = os.path.join(tmp, "graded_ens")
runs = [froth("ensemble", os.path.join(MODELS, "round.stl"), "-r", "3.0585", "-n", "3", "--seed", "1", "-o", ens, *g)
        for g in (["--grade"], ["--grade"])]
check(all(p.returncode == 0 for p in runs), f"graded ensemble: {[p.returncode for p in runs]} {runs[0].stderr}")
check("3 built" in runs[0].stdout and "0 built" in runs[1].stdout, f"graded ensemble resumes: {[p.stdout for p in runs]}")
before = {f: os.path.getmtime(os.path.join(ens, f)) for f in os.listdir(ens)}
p = froth("ensemble", os.path.join(MODELS, "round.stl"), "-r", "3.0585", "-n", "2", "--seed", "1", "-o", ens)
check(p.returncode == 2 and "other inputs" in p.stderr and "overwrite option" in p.stderr,
      f"ensemble folder of other inputs: {p.returncode} {p.stderr}")
check(before == {f: os.path.getmtime(os.path.join(ens, f)) for f in os.listdir(ens)},
      "a refused ensemble changed its folder")
open(os.path.join(ens, "notes.txt"), "w").write("mine")
p = froth("ensemble", os.path.join(MODELS, "round.stl"), "-r", "3.0585", "-n", "2", "--seed", "1", "-o", ens, "--overwrite")
check(p.returncode == 0 and "2 built" in p.stdout, f"ensemble --overwrite: {p.returncode} {p.stdout} {p.stderr}")
check(sorted(os.listdir(ens)) == [".froth-lock", "ensemble.json", "ensemble.pvd", "member_00000.json", "member_00000.vtu",
                                  "member_00001.json", "member_00001.vtu", "notes.txt"],
      f"ensemble --overwrite left: {sorted(os.listdir(ens))}")
# A graded mesh records the options that shaped h as field data, and the default floor keeps
# the estimated cells within 3 times a uniform mesh's (the tube's wall, r/10, would take 64
# times as many cells at the floor r/4).
out, rep = os.path.join(tmp, "graded.vtu"), os.path.join(tmp, "graded.json")
p = froth("mesh", os.path.join(MODELS, "round.stl"), "-r", "3.0585", "--seed", "1", "--grade", "-o", out, "--report", rep)
check(p.returncode == 0 and "times a uniform mesh's cells" in p.stdout, f"graded mesh: {p.returncode} {p.stderr}")
if p.returncode == 0:
    sizing = json.load(open(rep))["sizing"]
    fd = read_vtk(out).GetFieldData()
    field = {n: vtk_to_numpy(fd.GetArray(n))[0] for n in ("grade", "min_r", "max_grading")}
    radius = vtk_to_numpy(read_vtk(out).GetCellData().GetArray("radius"))
    check(field["grade"] == 1 and field["min_r"] == sizing["min_r"] and field["max_grading"] == 0.2,
          f"graded field data {field} vs report {sizing}")
    check(sizing["floor_raised"] and 3.0585 / 4 < sizing["min_r"] < 3.0585 and sizing["estimated_cell_ratio"] <= 3,
          f"default floor: {sizing}")
    check(radius.min() >= sizing["min_r"] * (1 - 1e-6) and radius.max() <= 3.0585, f"radius {radius.min()} {radius.max()}")
# Five cospherical seeds (protection seeds on one planar face of ADIS16480): one cell names the
# point where they meet as one vertex, its neighbours as two a rounding error apart; they are
# one vertex (exit 5 "cell vertices are missing from the cell that owns them" before).
rep = os.path.join(tmp, "cospherical.json")
p = froth("mesh", os.path.join(MODELS, "ADIS16480.STL"), "-r", "0.017720980594367015", "--seed", "317", "--no-quality",
          "-o", os.path.join(tmp, "cospherical.vtu"), "--report", rep)
check(p.returncode == 0 and json.load(open(rep))["volume"]["relative_error"] < 1e-9,
      f"cospherical seeds: exit {p.returncode} {p.stderr}")

# --cells N chooses r for about N cells (within 5%), reports the r, and repeats with -r; a dry
# run estimates without meshing; -r and --cells exclude each other, and one of them is needed.
for domain, n in (("box:0,0,0,2,1,1", 5000), (os.path.join(MODELS, "1002_tray_bottom.STL"), 3000)):
    out, rep = os.path.join(tmp, "cells.vtu"), os.path.join(tmp, "cells.json")
    p = froth("mesh", domain, "--cells", str(n), "--seed", "4", "--no-quality", "-o", out, "--report", rep)
    check(p.returncode == 0 and "chosen for about" in p.stdout, f"--cells {n}: {p.returncode} {p.stderr}")
    if p.returncode == 0:
        j = json.load(open(rep))
        check(abs(j["mesh"]["cells"] / n - 1) <= 0.05 and j["input"]["cells_requested"] == n,
              f"--cells {n} on {domain}: {j['mesh']['cells']} cells")
        # Choosing r (one sample) is the first stage after reading, and the total counts it with
        # every other stage (and the untimed moments between them).
        stages = list(j["seconds"])
        check(stages[:2] == ["reading", "choosing r"] and j["seconds"]["choosing r"] > 0 and
              j["seconds_total"] >= sum(j["seconds"].values()) - 1e-6,
              f"--cells {n}: stages {j['seconds']}, total {j['seconds_total']}")
        again = froth("mesh", domain, "-r", repr(j["input"]["r"]), "--seed", "4", "--no-quality", "-o",
                      os.path.join(tmp, "again.vtu"))
        check(again.returncode == 0 and open(out, "rb").read() == open(os.path.join(tmp, "again.vtu"), "rb").read(),
              f"--cells {n}: -r {j['input']['r']} does not repeat the mesh")
p = froth("mesh", "box:0,0,0,1,1,1", "--cells", "1e6", "--dry-run", "-o", os.path.join(tmp, "dry.vtu"))
check(p.returncode == 0 and "about 1e+06 cells" in p.stdout and not os.path.exists(os.path.join(tmp, "dry.vtu")),
      f"dry run: {p.returncode} {p.stdout} {p.stderr}")
p = froth("mesh", "box:0,0,0,1,1,1", "-r", "0.2", "--cells", "100")
check(p.returncode == 2, f"-r with --cells: exit {p.returncode}")
p = froth("mesh", "box:0,0,0,1,1,1")
check(p.returncode == 2 and "--cells" in p.stderr, f"neither -r nor --cells: exit {p.returncode} {p.stderr}")
p = froth("mesh", "box:0,0,0,1,1,1", "-r", "0.3", "-o", "/nonexistent-dir/x.vtu")
check(p.returncode == 4, f"unwritable output: exit code {p.returncode}")
# froth quality: the same report from froth's VTU as the run report; the same again from VTUs that
# VTK itself writes in its other encodings; valid PNG plots; a JSON that meets the schema.
import jsonschema  # noqa: E402

schema = json.load(open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "docs",
                                     "quality-report.schema.json")))
src, rep = os.path.join(tmp, "q.vtu"), os.path.join(tmp, "q_run.json")
p = froth("mesh", os.path.join(MODELS, "unit_sphere.STL"), "-r", "0.2", "--seed", "2", "--weld", "0", "-o", src,
          "--report", rep)
check(p.returncode == 0, f"quality source: {p.stderr}")
run_quality = json.load(open(rep))["quality"]
qjson, plots = os.path.join(tmp, "q.json"), os.path.join(tmp, "plots")
p = froth("quality", src, "--json", qjson, "--plots", plots)
check(p.returncode == 0, f"froth quality: exit {p.returncode}: {p.stderr}")
check("every cell closed" in p.stdout, f"froth quality summary: {p.stdout}")
got = json.load(open(qjson))
try:
    jsonschema.validate(got, schema)
    jsonschema.validate(run_quality, schema)
except jsonschema.ValidationError as e:
    check(False, f"quality JSON does not meet the schema: {e.message}")
for key in ("cells", "dihedral_degrees", "bounds", "shortest_edge"):
    check(got[key] == run_quality[key], f"froth quality on froth's VTU: {key} differs from the run report")
# The tube at r above its wall's thickness: cells wrap around the wall and have no kernel, so
# their aspect ratio is infinite; the summary says so and the report still meets the schema.
tube, tube_rep = os.path.join(tmp, "tube.vtu"), os.path.join(tmp, "tube.json")
p = froth("mesh", os.path.join(MODELS, "round.stl"), "-r", "3", "--weld", "0", "-o", tube, "--report", tube_rep)
check(p.returncode == 0, f"coarse tube: {p.stderr}")
tube_report = json.load(open(tube_rep))
check(tube_report["star_shaped"]["cells_without_kernel"] > 0, f"coarse tube: {tube_report['star_shaped']}")
check("star-shaped from no point" in p.stderr + p.stdout, "coarse tube: the summary does not mention empty kernels")
check("quality   no interior cells;" in p.stdout, f"coarse tube: the summary gives an interior aspect ratio: {p.stdout}")
try:
    jsonschema.validate(tube_report["quality"], schema)
except jsonschema.ValidationError as e:
    check(False, f"the coarse tube's quality JSON does not meet the schema: {e.message}")
for png in ("aspect.png", "dihedral.png"):
    path = os.path.join(plots, png)
    check(os.path.exists(path) and open(path, "rb").read(8) == b"\x89PNG\r\n\x1a\n", f"{png} is not a PNG file")
    if os.path.exists(path):
        import matplotlib.image  # noqa: E402
        check(matplotlib.image.imread(path).shape[0] > 100, f"{png} does not decode")

# The coarse tube's cells of infinite aspect ratio are counted in the histograms' "above", not
# lost in an end bin: every cell is in a bin, below or above.
for kind, data in tube_report["quality"]["cells"].items():
    h = data["aspect_histogram"]
    check(sum(h["counts"]) + h["below"] + h["above"] == data["count"], f"coarse tube {kind}: histogram loses cells")
check(sum(d["aspect_histogram"]["above"] for d in tube_report["quality"]["cells"].values()) > 0,
      "coarse tube: no cell above the aspect histogram's range")

# froth render: a PNG of the bundled example, cut open, of the size asked, not blank, in colours.
picture = os.path.join(tmp, "q.png")
p = froth("render", src, "-o", picture, "--width", "640", "--height", "480")
check(p.returncode == 0 and os.path.exists(picture), f"froth render: {p.returncode} {p.stderr}")
if os.path.exists(picture):
    png = vtk.vtkPNGReader()
    png.SetFileName(picture)
    png.Update()
    image = png.GetOutput()
    pixels = vtk_to_numpy(image.GetPointData().GetScalars())
    colours = len(np.unique(pixels[:, :3], axis=0))
    white = np.all(pixels[:, :3] == 255, axis=1).mean()
    check(image.GetDimensions()[:2] == (640, 480), f"froth render: size {image.GetDimensions()}")
    check(colours > 50 and 0.2 < white < 0.95, f"froth render: {colours} colours, {white:.2f} white")
for bad in ("q.jpg", "q.vtu"):
    p = froth("render", src, "-o", os.path.join(tmp, bad))
    check(p.returncode == 2, f"froth render -o {bad}: {p.returncode} {p.stderr}")

g = read_vtk(src)
for mode, compress, header in [("ascii", False, 64), ("binary", False, 32), ("binary", True, 64),
                               ("appended", True, 32), ("appended-base64", False, 64)]:
    w = vtk.vtkXMLUnstructuredGridWriter()
    out = os.path.join(tmp, f"vtk_{mode}_{compress}_{header}.vtu")
    w.SetFileName(out)
    w.SetInputData(g)
    if mode == "ascii":
        w.SetDataModeToAscii()
    elif mode == "binary":
        w.SetDataModeToBinary()
    else:
        w.SetDataModeToAppended()
        w.SetEncodeAppendedData(mode.endswith("base64"))
    if compress:
        w.SetCompressorTypeToZLib()
    else:
        w.SetCompressorTypeToNone()
    w.SetHeaderTypeToUInt32() if header == 32 else w.SetHeaderTypeToUInt64()
    w.Write()
    qo = os.path.join(tmp, f"vtk_{mode}.json")
    p = froth("quality", out, "--json", qo)
    check(p.returncode == 0, f"froth quality on VTK's {mode} (zlib {compress}, UInt{header}): {p.stderr}")
    if p.returncode == 0:
        other = json.load(open(qo))
        a, b = other["cells"]["interior"]["aspect"], run_quality["cells"]["interior"]["aspect"]
        check(other["cells"]["interior"]["count"] == run_quality["cells"]["interior"]["count"] and
              all(abs(a[k] - b[k]) <= 1e-6 * abs(b[k]) for k in ("min", "mean", "max")),
              f"froth quality on VTK's {mode}: interior aspect {a} vs {b}")

# A tetrahedral VTU and a file that is not VTU at all: clear messages, exit code 3.
tet = vtk.vtkUnstructuredGrid()
pts = vtk.vtkPoints()
for xyz in ((0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)):
    pts.InsertNextPoint(*xyz)
tet.SetPoints(pts)
ids = vtk.vtkIdList()
for i in range(4):
    ids.InsertNextId(i)
tet.InsertNextCell(vtk.VTK_TETRA, ids)
w = vtk.vtkXMLUnstructuredGridWriter()
w.SetFileName(os.path.join(tmp, "tet.vtu"))
w.SetInputData(tet)
w.Write()
for path, words in [(os.path.join(tmp, "tet.vtu"), "not a polyhedron"), (rep, "not valid XML")]:
    p = froth("quality", path)
    check(p.returncode == 3 and words in p.stderr, f"froth quality {path}: exit {p.returncode}, '{p.stderr.strip()}'")
p = froth("quality", "/nonexistent.vtu")
check(p.returncode == 4 and "cannot open" in p.stderr, f"froth quality missing file: {p.returncode}")

# froth ensemble: files, collection and summary; a member regenerated alone is byte-identical;
# a killed run, resumed, gives the same files as an uninterrupted one; a damaged member is rebuilt.
import signal  # noqa: E402
import time  # noqa: E402
import xml.etree.ElementTree as ET  # noqa: E402

ens = os.path.join(tmp, "ens")
args = ["box:0,0,0,1,1,1", "-r", "0.08", "-n", "4", "--seed", "11"]
p = froth("ensemble", *args, "-o", ens)
check(p.returncode == 0, f"ensemble: {p.stderr}")
summary = json.load(open(os.path.join(ens, "ensemble.json")))
check(summary["this_run"] == {"built": 4, "already_complete": 0, "failed": 0}, f"ensemble: {summary['this_run']}")
check("ensemble" in summary["command"] and summary["input"]["members"] == 4, "ensemble.json: command and input")
seeds = [m["seed"] for m in summary["members"]]
check(len(set(seeds)) == 4, "ensemble: member seeds are not distinct")
for m in summary["members"]:
    g = read_vtk(os.path.join(ens, m["file"]))
    check(g.GetNumberOfCells() == m["cells"], f"ensemble member {m['index']}: VTK reads {g.GetNumberOfCells()} cells")
    check(m["volume_relative_error"] <= 1e-9, f"ensemble member {m['index']}: volume")
    check(m["quality"]["bounds"]["theorem1_violations"] == 0, f"ensemble member {m['index']}: quality bounds")
cells = [m["cells"] for m in summary["members"]]
check(summary["spread"]["cells"]["min"] == min(cells) and summary["spread"]["cells"]["max"] == max(cells) and
      abs(summary["spread"]["cells"]["mean"] - sum(cells) / 4) < 1e-9, "ensemble: spread of cell counts")
pvd = ET.parse(os.path.join(ens, "ensemble.pvd")).getroot()
files = [d.get("file") for d in pvd.iter("DataSet")]
check(files == [f"member_{k:05d}.vtu" for k in range(4)], f"ensemble.pvd lists {files}")
alone = os.path.join(tmp, "alone.vtu")
p = froth("mesh", "box:0,0,0,1,1,1", "-r", "0.08", "--seed", str(seeds[2]), "--threads", "1", "-o", alone)
check(p.returncode == 0 and open(alone, "rb").read() == open(os.path.join(ens, "member_00002.vtu"), "rb").read(),
      "member 2 regenerated alone with froth mesh is not byte-identical")
p = froth("ensemble", *args, "-o", ens)
check(json.load(open(os.path.join(ens, "ensemble.json")))["this_run"] == {"built": 0, "already_complete": 4, "failed": 0},
      "ensemble re-run did not skip the complete members")
# Damage a member: it is rebuilt, byte for byte.
member1 = os.path.join(ens, "member_00001.vtu")
good = open(member1, "rb").read()
open(member1, "wb").write(good[: len(good) // 2])
p = froth("ensemble", *args, "-o", ens)
check(json.load(open(os.path.join(ens, "ensemble.json")))["this_run"] == {"built": 1, "already_complete": 3, "failed": 0},
      "ensemble did not rebuild the damaged member")
check(open(member1, "rb").read() == good, "the rebuilt member differs")
# Kill a run after its first members, then resume: the same bytes as the uninterrupted run.
killed = os.path.join(tmp, "killed")
big = ["box:0,0,0,1,1,1", "-r", "0.04", "-n", "5", "--seed", "12"]
proc = subprocess.Popen([FROTH, "ensemble", *big, "-o", killed], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
deadline = time.time() + 120
while time.time() < deadline and not os.path.exists(os.path.join(killed, "member_00001.json")):
    time.sleep(0.01)
# While it runs, a second ensemble on its folder is refused (the folder's lock), touching nothing.
p = froth("ensemble", *big, "-o", killed)
check(p.returncode == 2 and "in use" in p.stderr, f"a second ensemble on a busy folder: {p.returncode} {p.stderr}")
proc.send_signal(signal.SIGKILL)
proc.wait()
complete = sorted(f for f in os.listdir(killed) if f.endswith(".json"))
check(0 < len(complete) < 5, f"the kill came too late or too early: {complete}")
p = froth("ensemble", *big, "-o", killed)
check(p.returncode == 0, f"resumed ensemble: {p.stderr}")
resumed = json.load(open(os.path.join(killed, "ensemble.json")))["this_run"]
check(resumed["already_complete"] >= 1 and resumed["built"] + resumed["already_complete"] == 5,
      f"resumed ensemble: {resumed}")
straight = os.path.join(tmp, "straight")
p = froth("ensemble", *big, "-o", straight)
for k in range(5):
    name = f"member_{k:05d}.vtu"
    check(open(os.path.join(killed, name), "rb").read() == open(os.path.join(straight, name), "rb").read(),
          f"killed and resumed {name} differs from the uninterrupted run's")
check(not [f for f in os.listdir(killed) if ".tmp" in f], "the resumed ensemble left temporary files")

# --partition in one process (no MPI in this build, or one rank): a .pvtu of one piece that VTK
# reads as the serial mesh; a non-.pvtu output is a usage error.
serial_out, part_out = os.path.join(tmp, "serial_box.vtu"), os.path.join(tmp, "part_box.pvtu")
p = froth("mesh", "box:0,0,0,1,1,1", "-r", "0.1", "--seed", "4", "-o", serial_out)
check(p.returncode == 0, f"serial mesh: {p.stderr}")
p = froth("mesh", "box:0,0,0,1,1,1", "-r", "0.1", "--seed", "4", "--partition", "-o", part_out)
check(p.returncode == 0 and "partition over 1 rank in" in p.stdout, f"--partition: {p.returncode} {p.stdout} {p.stderr}")
pr = vtk.vtkXMLPUnstructuredGridReader()
pr.SetFileName(part_out)
pr.Update()
pg, sg = pr.GetOutput(), read_vtk(serial_out)
check(pg.GetNumberOfCells() == sg.GetNumberOfCells() > 0, f"--partition: {pg.GetNumberOfCells()} cells")
check(np.array_equal(vtk_to_numpy(pg.GetCellData().GetArray("volume")), vtk_to_numpy(sg.GetCellData().GetArray("volume"))),
      "--partition: cell volumes differ from the serial mesh's")
check(os.path.exists(os.path.join(tmp, "part_box", "part_box_0.vtu")), "--partition: piece file")
p = froth("mesh", "box:0,0,0,1,1,1", "-r", "0.1", "--partition", "-o", os.path.join(tmp, "part.vtk"))
check(p.returncode == 2 and ".pvtu" in p.stderr, f"--partition -o part.vtk: {p.returncode} {p.stderr}")

# The summary is a short block of labelled lines; --quiet prints nothing on success, --verbose
# adds the stages' details; an output froth cannot write is refused before anything is read.
box = ["mesh", "box:0,0,0,1,1,1", "-r", "0.2", "--seed", "3"]
p = froth(*box, "-o", os.path.join(tmp, "summary.vtu"))
labels = [line.split()[0] for line in p.stdout.splitlines()[1:]]
check(p.returncode == 0 and labels == ["cells", "volume", "quality", "time", "wrote"] and len(p.stdout) < 1000,
      f"summary block: {p.stdout}")
p = froth(*box, "-o", os.path.join(tmp, "quiet.vtu"), "--quiet")
check(p.returncode == 0 and p.stdout == "" and p.stderr == "" and os.path.exists(os.path.join(tmp, "quiet.vtu")),
      f"--quiet: {p.returncode} {p.stdout!r} {p.stderr!r}")
p = froth(*box, "-o", os.path.join(tmp, "verbose.vtu"), "--verbose")
check(p.returncode == 0 and "  stages " in p.stdout and "  welding " in p.stdout, f"--verbose: {p.stdout}")
for bad in ("out.vtk", "out.exo2", "out"):
    p = froth(*box, "-o", os.path.join(tmp, bad))
    check(p.returncode == 2 and "cannot write" in p.stderr and not os.path.exists(os.path.join(tmp, bad)),
          f"-o {bad}: {p.returncode} {p.stderr}")
# On a terminal, stderr shows the stages and a progress bar; on a pipe (above) nothing.
master, slave = pty.openpty()
proc = subprocess.Popen([FROTH, *box, "-o", os.path.join(tmp, "tty.vtu")], stdout=subprocess.PIPE, stderr=slave)
os.close(slave)
shown = b""
while True:
    try:
        chunk = os.read(master, 4096)
    except OSError:
        break
    if not chunk:
        break
    shown += chunk
os.close(master)
out, _ = proc.communicate()
check(proc.returncode == 0 and b"froth: sampling" in shown and b"froth: cells" in shown and b"\r" not in out,
      f"progress on a terminal: {proc.returncode} {shown!r}")
p = froth("mesh", "--help")
check("--seed TEXT=0" in p.stdout, "the default seed is not shown in --help")

leftovers = [f for f in os.listdir(tmp) if ".tmp" in f]
check(not leftovers, f"temporary files left: {leftovers}")

code = harness.summary()
# The outputs (some 160 MB) are kept only for a failure to be looked at.
if failures:
    print(f"outputs kept in {tmp}")
else:
    shutil.rmtree(tmp)
sys.exit(code)
