"""Cracks (issue 38), read back by readers that are not froth: a through crack in the unit box and
across plate_holes.STL (a real part, the crack's line on its surface running round its holes), a
closed sheet (a lens), a penny (a front all round inside the solid), an edge crack (a front from
face to face), a curved crack and two crossing through cracks in the box; in two cubes side by side
(a multi-region solid) cracks inside the first and across the interface; at r = 1/12 and 1/20 of
the solid's size and seeds 1 and 2. Checked on each mesh (VTK), for each sheet:
- the report's crack faces on each side sum to the sheet's area inside the solid (1e-9), and so do
  the --boundary file's faces on patches crack_NAME_a and crack_NAME_b;
- no face of two cells lies on the sheet; the faces of the two sides share points only on the front;
- every cell has a kernel (none slit by the front), where the solid has no feature thinner than r;
- the cells' volumes sum to the solid's (1e-9), each region's to its own and each interface's
  faces to its area from both sides; every cell closed and interior face matched (the summary's
  line).
Then: checkMesh on the box's polyMesh (the crack's two sides as two patches), the Exodus file's
side sets, an ensemble of two members, and a sheet with three triangles on an edge (exit 3).
Usage: test_cracks.py FROTH MODELS_DIR CRACKS_DIR"""
import json
import os
import sys
import tempfile

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

from harness import SEEDS, check, checkmesh, face_stream, froth, read_vtk, summary

MODELS, CRACKS = sys.argv[2], sys.argv[3]
REGIONS = sys.argv[4:] == ["regions"]  # only the multi-region cases


def polygon_area(points):
    p = np.asarray(points)
    return 0.5 * np.linalg.norm(np.sum(np.cross(p, np.roll(p, -1, axis=0)), axis=0))


def on_sheet_plane(normal, offset, lo=(-1e300,) * 3, hi=(1e300,) * 3):
    """On the plane, within the box [lo, hi] (a sheet's extent in it)."""
    n = np.asarray(normal, float)
    return lambda p: abs(np.dot(n, p) - offset) < 1e-9 * max(1.0, abs(offset)) and all(
        lo[k] - 1e-12 <= p[k] <= hi[k] + 1e-12 for k in range(3))


def on_triangles(path, tol=1e-9):
    """On the triangles of an OBJ sheet (within tol)."""
    v, t = [], []
    for line in open(path):
        w = line.split()
        if w and w[0] == "v":
            v.append([float(x) for x in w[1:4]])
        elif w and w[0] == "f":
            t.append([int(x) - 1 for x in w[1:4]])
    tris = np.asarray(v)[np.asarray(t)]

    def on(p):
        for a, b, c in tris:
            n = np.cross(b - a, c - a)
            n = n / np.linalg.norm(n)
            if abs(np.dot(p - a, n)) > tol:
                continue
            q = p - np.dot(p - a, n) * n  # barycentric test in the plane
            if all(np.dot(np.cross(e1 - e0, q - e0), n) >= -tol for e0, e1 in ((a, b), (b, c), (c, a))):
                return True
        return False
    return on


def on_box_edge(lo, hi):
    """On the rim of the rectangle [lo, hi] of a plane: a front there."""
    return lambda p: any(abs(p[k] - lo[k]) < 1e-12 or abs(p[k] - hi[k]) < 1e-12 for k in range(2))


def lens_level(p):
    return abs(p[0] - 0.5) / 0.3 + abs(p[1] - 0.5) / 0.3 + abs(p[2] - 0.5) / 0.08


def on_lens(p):
    return abs(lens_level(p) - 1) < 1e-9


def sides_alike(faces_a, faces_b, tol):
    """How many faces of side a have no face of side b on the same points (within tol): welding
    moves a crack's two copies alike, so each side's faces are the other's."""
    if len(faces_a) != len(faces_b):
        return abs(len(faces_a) - len(faces_b)) + 1
    centres_b = np.array([f.mean(axis=0) for f in faces_b])
    unmatched = 0
    for f in faces_a:
        g = faces_b[int(np.argmin(np.linalg.norm(centres_b - f.mean(axis=0), axis=1)))]
        near = len(f) == len(g) and all(np.min(np.linalg.norm(g - x, axis=1)) <= tol for x in f)
        unmatched += not near
    return unmatched


def side_faces(boundary, name, label):
    """The polygons of the boundary file's patches crack_<name>_a and _b, per side."""
    b = read_vtk(boundary)
    names = b.GetFieldData().GetAbstractArray("patch_names")
    names = [names.GetValue(k) for k in range(names.GetNumberOfValues())]
    patch = vtk_to_numpy(b.GetCellData().GetArray("patch"))
    pts = vtk_to_numpy(b.GetPoints().GetData())
    faces = {"a": [], "b": []}
    for side in "ab":
        k = names.index(f"crack_{name}_{side}") if f"crack_{name}_{side}" in names else -1
        check(k >= 0, f"{label}: patch crack_{name}_{side} in {names}")
        for c in np.nonzero(patch == k)[0]:
            ids = b.GetCell(int(c)).GetPointIds()
            faces[side].append(pts[[ids.GetId(q) for q in range(ids.GetNumberOfIds())]])
    return faces


def check_welded_alike(label, solid, sheets, r, seed, weld, work):
    """A weld far above the default merges points near the sheets that the default leaves apart:
    the mesh stays valid and the two sides of each sheet weld alike (each cluster on one side is
    mirrored on the other, across each sheet where they cross). Such a weld may move the front
    (it cuts the corners of a polygonal front), so the sheet's area is not asked for here.
    `sheets`: (path, name) pairs."""
    boundary = os.path.join(work, f"{label}_{seed}_boundary.vtu")
    cracks = [a for path, _ in sheets for a in ("--crack", path)]
    solids = [solid] if isinstance(solid, str) else solid
    p = froth("mesh", *solids, *cracks, "-r", repr(r), "--seed", str(seed), "--weld", repr(weld),
              "-o", os.path.join(work, f"{label}_{seed}.vtu"), "--boundary", boundary)
    check(p.returncode == 0, f"{label} seed {seed}: exit {p.returncode}: {p.stderr}")
    if p.returncode != 0:
        return
    check("every cell closed, every interior face matched" in p.stdout, f"{label}: the summary's checks")
    for _, name in sheets:
        faces = side_faces(boundary, name, label)
        unlike = sides_alike(faces["a"], faces["b"], 1e-8 * r)
        check(unlike == 0 and faces["a"], f"{label} seed {seed}: {unlike} crack faces of {name}'s side a unlike side b's")


def check_case(label, solid, sheet, name, r, seed, on_sheet, sheet_normal, on_front, work, extra=()):
    check_cracks(label, solid, [(sheet, name, on_sheet, sheet_normal, on_front)], r, seed, work, extra)


def check_cracks(label, solid, sheets, r, seed, work, extra=()):
    """Each sheet of `sheets` (path, name, on_sheet, sheet_normal, on_front) cut into the mesh of
    `solid` as it must be, where they cross too."""
    out = os.path.join(work, f"{label}_{seed}.vtu")
    boundary = os.path.join(work, f"{label}_{seed}_boundary.vtu")
    report = os.path.join(work, f"{label}_{seed}.json")
    cracks = [a for sheet in sheets for a in ("--crack", sheet[0])]
    solids = [solid] if isinstance(solid, str) else solid  # (several: a multi-region solid)
    p = froth("mesh", *solids, *cracks, "-r", repr(r), "--seed", str(seed), "-o", out, "--boundary", boundary,
              "--report", report, *extra)
    check(p.returncode == 0, f"{label} seed {seed}: exit {p.returncode}: {p.stderr}")
    if p.returncode != 0:
        return
    check("every cell closed, every interior face matched" in p.stdout, f"{label}: the summary's checks")
    run = json.load(open(report))
    if "--grade" in extra:
        check(run["sizing"]["graded"], f"{label} seed {seed}: not graded ({run['sizing']})")
    fronts = {"penny": 2 * (0.5 + 0.4), "edge": 0.45 * 2 + 0.6, "box_through": 0, "plate_through": 0, "lens": 0,
              "plate_penny": 2 * (80 + 70), "box_upright": 0, "penny_upright": 2 * (0.5 + 0.4)}
    for k, (_, name, on_sheet, _, _) in enumerate(sheets):
        crack = run["cracks"][k]
        check(crack["name"] == name, f"{label}: report's crack {k} is {crack['name']}, not {name}")
        area = crack["area"]
        if name in fronts:
            check(abs(crack["front_length"] - fronts[name]) <= 1e-9, f"{label}: {name}'s front length {crack['front_length']}")
        check(crack["faces_on_front"] == 0, f"{label} seed {seed}: {crack['faces_on_front']} crack faces on the front alone")
        for side in ("a", "b"):
            check(abs(crack[f"area_from_{side}"] - area) <= 1e-9 * area,
                  f"{label} seed {seed}: report's {name} side {side} {crack[f'area_from_{side}']} against {area}")
        # The boundary file's crack patches.
        faces = side_faces(boundary, name, label)
        for side in "ab":
            total = 0.0
            for c, poly in enumerate(faces[side]):
                check(all(on_sheet(x) for x in poly), f"{label}: boundary face {c} of crack_{name}_{side} off the sheet")
                total += polygon_area(poly)
            check(abs(total - area) <= 1e-9 * area,
                  f"{label} seed {seed}: boundary file's {name} side {side} {total} against {area}")
        unlike = sides_alike(faces["a"], faces["b"], 1e-8 * r)
        check(unlike == 0, f"{label} seed {seed}: {unlike} crack faces of {name}'s side a unlike side b's (welded apart)")
    check(abs(run["volume"]["cells_sum"] - run["volume"]["domain"]) <= 1e-9 * run["volume"]["domain"],
          f"{label} seed {seed}: volume {run['volume']}")
    for region in run.get("regions", []):
        check(abs(region["volume"] - region["enclosed_volume"]) <= 1e-9 * region["enclosed_volume"],
              f"{label} seed {seed}: region {region['name']}'s cells {region['volume']} of {region['enclosed_volume']}")
    for interface in run.get("interfaces", []):
        check(max(abs(interface[f"area_from_{s}"] - interface["area"]) for s in ("first", "second"))
              <= 1e-9 * interface["area"], f"{label} seed {seed}: interface {interface}")
    # The mesh: its field data names the cracks; faces on a sheet are in one cell each, and the
    # two sides of a sheet share no point off its front.
    g = read_vtk(out)
    names = g.GetFieldData().GetAbstractArray("crack_names")
    check(names is not None and [names.GetValue(k) for k in range(names.GetNumberOfValues())] == [s[1] for s in sheets],
          f"{label}: field data crack_names")
    gp = vtk_to_numpy(g.GetPoints().GetData())
    seen = {}
    for c in range(g.GetNumberOfCells()):
        for f in face_stream(g, c):
            seen.setdefault(tuple(sorted(f)), []).append((c, f))
    side_points = [[set(), set()] for _ in sheets]
    matched_on = 0
    for key, uses in seen.items():
        poly = gp[list(uses[0][1])]
        on = [k for k, sheet in enumerate(sheets) if all(sheet[2](x) for x in poly) and sheet[2](poly.mean(axis=0))]
        if not on:
            continue
        if len(uses) > 1:
            matched_on += 1
            continue
        # Its side: its outward normal along the sheet's normal there or against it.
        c, f = uses[0]
        outward = np.sum(np.cross(poly, np.roll(poly, -1, axis=0)), axis=0)
        side_points[on[0]][int(np.dot(outward, sheets[on[0]][3](poly.mean(axis=0))) > 0)].update(f)
    check(matched_on == 0, f"{label} seed {seed}: {matched_on} faces of two cells on a sheet")
    for k, sheet in enumerate(sheets):
        shared = [v for v in side_points[k][0] & side_points[k][1] if not sheet[4](gp[v])]
        check(len(side_points[k][0]) > 0 and not shared,
              f"{label} seed {seed}: {len(shared)} points on both sides of {sheet[1]} off its front")
    # Every cell has a kernel: none is slit by a front inside it. (Not asked of the plate, thinner
    # than r, nor of the lens, whose material tapers to nothing at its rim: a feature thinner than
    # r that cells wrap around, as in any part.)
    kernel = vtk_to_numpy(g.GetCellData().GetArray("kernel"))
    check(kernel.min() == 1 or label.startswith(("plate", "lens")),
          f"{label} seed {seed}: {np.sum(kernel == 0)} cells without a kernel")


def multi_region(work, box, up, nowhere, upright, penny, penny_upright):
    """Cracks in a multi-region solid (the long tier: cli_cracks_regions)."""
    # A multi-region solid (two unit cubes side by side, sharing the face x = 1): a penny, a
    # through crack and an edge crack in the first, and the penny with the through crack crossing it.
    two_boxes = [box, "box:1,0,0,2,1,1"]
    edge = (os.path.join(CRACKS, "edge.obj"), "edge", on_sheet_plane((0, 0, 1), 0.5, (0, 0.2, 0), (0.45, 0.8, 1)), up,
            on_box_edge((-1, 0.2), (0.45, 0.8)))
    for label, sheets in (("regions_penny", [penny]), ("regions_through", [upright]), ("regions_edge", [edge]),
                          ("regions_crossing", [penny, penny_upright])):
        for fraction in (12, 20):
            for seed in SEEDS:
                check_cracks(f"{label}_{fraction}", two_boxes, sheets, 1 / fraction, seed, work)
    curved = (os.path.join(CRACKS, "curved.obj"), "curved", on_triangles(os.path.join(CRACKS, "curved.obj")),
              lambda p: (p[0] - 0.5, 0, p[2] + 0.3), on_box_edge((0.2, 0.3), (0.8, 0.7)))
    for seed in SEEDS:
        check_welded_alike("regions_penny_weld", two_boxes, [penny[:2]], 1 / 20, seed, 0.3 / 20, work)
        check_cracks("regions_curved_convex_12", two_boxes, [curved], 1 / 12, seed, work, ("--convex",))
    # Across the interface: a through crack of both cubes (z = 0.41), and a crack from the face
    # x = 0 across the interface to its front at x = 1.55 (y = 0.63), each region cut along its part.
    def quad(name, corners):
        path = os.path.join(work, name + ".obj")
        with open(path, "w") as f:
            f.write("".join("v %r %r %r\n" % c for c in corners) + "f 1 2 3\nf 1 3 4\n")
        return path
    through_both = (quad("across", [(-0.2, -0.1, 0.41), (2.3, -0.1, 0.41), (2.3, 1.2, 0.41), (-0.2, 1.2, 0.41)]), "across",
              on_sheet_plane((0, 0, 1), 0.41), up, nowhere)
    deep = (quad("deep", [(-0.2, 0.63, -0.1), (-0.2, 0.63, 1.1), (1.55, 0.63, 1.1), (1.55, 0.63, -0.1)]), "deep",
            on_sheet_plane((0, 1, 0), 0.63, (0, 0, 0), (1.55, 1, 1)), lambda p: (0, 1, 0),
            lambda p: abs(p[0] - 1.55) < 1e-9)
    for label, sheets in (("regions_across", [through_both]), ("regions_deep", [deep])):
        for fraction in (12, 20):
            for seed in SEEDS:
                check_cracks(f"{label}_{fraction}", two_boxes, sheets, 1 / fraction, seed, work)
    for seed in SEEDS:
        check_welded_alike("regions_across_weld", two_boxes, [through_both[:2]], 1 / 20, seed, 0.3 / 20, work)
    # Not yet: a sheet that ends at an interface, one whose front crosses it, or a front whose
    # skirt (2r) would reach it; a sheet lying on one is the input's defect.
    p = froth("mesh", *two_boxes, "--crack", quad("ends", [(-0.2, 0.2, 0.5), (1, 0.2, 0.5), (1, 0.8, 0.5), (-0.2, 0.8, 0.5)]),
              "-r", "0.1", "-o", os.path.join(work, "ri.vtu"))
    check(p.returncode == 2 and "ends at the interface between regions box_0 and box_1" in p.stderr,
          f"a crack ending at an interface: exit {p.returncode}: {p.stderr}")
    p = froth("mesh", *two_boxes, "--crack", quad("tip", [(0.6, 0.2, 0.5), (1.4, 0.2, 0.5), (1.4, 0.8, 0.5), (0.6, 0.8, 0.5)]),
              "-r", "0.05", "-o", os.path.join(work, "rt.vtu"))
    check(p.returncode == 2 and "within 2r = 0.1 of the interface" in p.stderr,
          f"a penny across an interface: exit {p.returncode}: {p.stderr}")
    p = froth("mesh", *two_boxes, "--crack", quad("on", [(1, 0.2, 0.2), (1, 0.8, 0.2), (1, 0.8, 0.8), (1, 0.2, 0.8)]),
              "-r", "0.1", "-o", os.path.join(work, "ro.vtu"))
    check(p.returncode == 3 and "lies on the interface" in p.stderr, f"a crack on an interface: exit {p.returncode}: {p.stderr}")
    p = froth("mesh", *two_boxes, "--crack", penny[0], "-r", "0.15", "-o", os.path.join(work, "rs.vtu"))
    check(p.returncode == 2 and "within 2r = 0.3 of the interface" in p.stderr,
          f"a front 0.25 from an interface at r = 0.15: exit {p.returncode}: {p.stderr}")


def main():
    work = tempfile.mkdtemp(prefix="froth_cracks_")
    box = "box:0,0,0,1,1,1"
    plate = os.path.join(MODELS, "plate_holes.STL")  # 203.2 x 304.8 x 12.7
    up, across, out_of_lens = (lambda p: (0, 0, 1)), (lambda p: (0, 1, 0)), (lambda p: p - 0.5)
    nowhere = lambda p: False  # noqa: E731 (no front)
    cases = [("box_through", box, "box_through.obj", "box_through", 1.0, on_sheet_plane((0, 0, 1), 0.5), up, nowhere),
             ("lens", box, "lens.obj", "lens", 1.0, on_lens, out_of_lens, nowhere),
             ("plate_through", plate, "plate_through.obj", "plate_through", 304.8, on_sheet_plane((0, 1, 0), 152.4),
              across, nowhere),
             # A front inside the solid all round (a penny), and from a face (an edge crack).
             ("penny", box, "penny.obj", "penny", 1.0, on_sheet_plane((0, 0, 1), 0.5, (0.25, 0.3, 0), (0.75, 0.7, 1)), up,
              on_box_edge((0.25, 0.3), (0.75, 0.7))),
             ("edge", box, "edge.obj", "edge", 1.0, on_sheet_plane((0, 0, 1), 0.5, (0, 0.2, 0), (0.45, 0.8, 1)), up,
              on_box_edge((-1, 0.2), (0.45, 0.8))),
             # A curved sheet (a strip of a cylinder about y), its front all round.
             ("curved", box, "curved.obj", "curved", 1.0, on_triangles(os.path.join(CRACKS, "curved.obj")),
              lambda p: (p[0] - 0.5, 0, p[2] + 0.3), on_box_edge((0.2, 0.3), (0.8, 0.7)))]
    for label, solid, sheet, name, size, on_sheet, sheet_normal, on_front in cases:
        for fraction in (12, 20):
            for seed in SEEDS:
                check_case(f"{label}_{fraction}", solid, os.path.join(CRACKS, sheet), name, size / fraction, seed, on_sheet,
                           sheet_normal, on_front, work)
    # Crossing sheets (a branching crack), cut open four ways along their crossing: two through
    # cracks crossing from face to face (the box falls into four pieces); a penny upright across
    # the through crack (its front crosses it, and so does the skirt beyond its front); and two
    # pennies crossing (their fronts and skirts cross each other's sheets).
    xdir = lambda p: (1, 0, 0)  # noqa: E731
    through = (os.path.join(CRACKS, "box_through.obj"), "box_through", on_sheet_plane((0, 0, 1), 0.5), up, nowhere)
    upright = (os.path.join(CRACKS, "box_upright.obj"), "box_upright", on_sheet_plane((1, 0, 0), 0.37), xdir, nowhere)
    penny = (os.path.join(CRACKS, "penny.obj"), "penny", on_sheet_plane((0, 0, 1), 0.5, (0.25, 0.3, 0), (0.75, 0.7, 1)),
             up, on_box_edge((0.25, 0.3), (0.75, 0.7)))
    on_upright_front = lambda p: abs(p[0] - 0.6) < 1e-9 and on_box_edge((0.25, 0.3), (0.75, 0.7))((p[1], p[2]))  # noqa: E731
    penny_upright = (os.path.join(CRACKS, "penny_upright.obj"), "penny_upright",
                     on_sheet_plane((1, 0, 0), 0.6, (0, 0.25, 0.3), (1, 0.75, 0.7)), xdir, on_upright_front)
    if REGIONS:
        multi_region(work, box, up, nowhere, upright, penny, penny_upright)
        return summary()
    crossings = [("crossing", [through, upright]), ("crossing_penny", [through, penny_upright]),
                 ("crossing_pennies", [penny, penny_upright])]
    for label, sheets in crossings:
        for fraction in (12, 20):
            for seed in SEEDS:
                check_cracks(f"{label}_{fraction}", box, sheets, 1 / fraction, seed, work)
        for seed in SEEDS:
            check_welded_alike(f"{label}_weld", box, [s[:2] for s in sheets], 1 / 20, seed, 0.3 / 20, work)
    p = froth("mesh", box, "--crack", through[0], "--crack", upright[0], "-r", "0.1", "--convex", "-o",
              os.path.join(work, "cv.vtu"))
    check(p.returncode == 2 and "crossing cracks" in p.stderr, f"--convex with crossing cracks: exit {p.returncode}: {p.stderr}")
    # Graded (--grade): the plate is thinner than 2r, so h shrinks in it (to 0.57-0.63 r); the
    # sheets' disks are the interfaces' factors times h. And convex cells (--convex): a cut
    # through a crack face splits its twin across the crack alike. A through crack, and a
    # delamination whose front runs round inside the plate.
    plate_front = lambda p: (min(abs(p[0] - 60), abs(p[0] - 140), abs(p[1] - 60), abs(p[1] - 130))  # noqa: E731
                             < 1e-9 * 304.8)
    in_plate = [("plate_through", on_sheet_plane((0, 1, 0), 152.4), across, nowhere),
                ("plate_penny", on_sheet_plane((0, 0, 1), 5, (60, 60, 0), (140, 130, 1e3)), up, plate_front)]
    for option in ("--grade", "--convex"):
        for name, on_sheet, normal, on_front in in_plate:
            for fraction in (12, 20):
                for seed in SEEDS:
                    check_case(f"{name}{option.replace('-', '_')}_{fraction}", plate, os.path.join(CRACKS, f"{name}.obj"),
                               name, 304.8 / fraction, seed, on_sheet, normal, on_front, work, (option,))
    # A sheet narrower than the cells (a penny 6.35 tall across the 12.7 plate, at r = 25.4): its
    # faces have only front points, the same as their twins'; the report counts them and the
    # summary says so.
    narrow = os.path.join(work, "narrow.obj")
    with open(narrow, "w") as f:
        f.write("v 40 60 3.175\nv 160 60 3.175\nv 160 60 9.525\nv 40 60 9.525\nf 1 2 3\nf 1 3 4\n")
    report = os.path.join(work, "narrow.json")
    p = froth("mesh", plate, "--crack", narrow, "-r", "25.4", "--seed", "1", "-o", os.path.join(work, "narrow.vtu"),
              "--report", report)
    crack = json.load(open(report))["cracks"][0] if p.returncode == 0 else {}
    check(crack.get("faces_on_front", 0) > 0 and "have every point on the front" in p.stdout,
          f"narrow sheet: {crack}, {p.stdout[-600:]} {p.stderr}")
    # Convex cells where the crack itself makes cells non-convex: a curved sheet in the box.
    for seed in SEEDS:
        check_case("curved_convex_12", box, os.path.join(CRACKS, "curved.obj"), "curved", 1 / 12, seed,
                   on_triangles(os.path.join(CRACKS, "curved.obj")), lambda p: (p[0] - 0.5, 0, p[2] + 0.3),
                   on_box_edge((0.2, 0.3), (0.8, 0.7)), work, ("--convex",))
    # At 0.3 r (default 1e-4 r) the two sides of these welded apart before the weld mirrored them.
    for label, solid, sheet, name, size, *_ in cases:
        if label in ("box_through", "penny", "curved"):
            for seed in SEEDS:
                check_welded_alike(f"{label}_weld", solid, [(os.path.join(CRACKS, sheet), name)], size / 20, seed,
                                   0.3 * size / 20, work)

    through = os.path.join(CRACKS, "box_through.obj")
    # OpenFOAM: the two sides as two patches, a baffle checkMesh reads.
    case = os.path.join(work, "case")
    p = froth("mesh", box, "--crack", through, "-r", "0.1", "-o", os.path.join(case, "constant", "polyMesh"), "-q")
    check(p.returncode == 0, f"polyMesh: {p.stderr}")
    out = checkmesh(case).stdout
    check("Mesh OK." in out and "crack_box_through_a" in out and "crack_box_through_b" in out,
          f"checkMesh on the cracked box: {out[-2000:]}")
    # The npz facet graph pairs each crack face with the face across the crack, in the other cell.
    for sheet_name in ("box_through", "penny"):
        npz = os.path.join(work, f"{sheet_name}.npz")
        p = froth("mesh", box, "--crack", os.path.join(CRACKS, f"{sheet_name}.obj"), "-r", "0.08", "-o", npz, "-q")
        check(p.returncode == 0, f"npz: {p.stderr}")
        if p.returncode != 0:
            continue
        g = np.load(npz)
        names = list(g["patch_names"])
        on_crack = np.isin(g["border_patch"], [names.index(f"crack_{sheet_name}_a"), names.index(f"crack_{sheet_name}_b")])
        across = g["border_across"]
        pairs = across[on_crack]
        check(on_crack.sum() > 0 and np.all(pairs >= 0) and np.all(across[~on_crack] == -1),
              f"npz {sheet_name}: {np.sum(pairs < 0)} of {on_crack.sum()} crack faces with none across")
        if np.all(pairs >= 0):
            b = np.nonzero(on_crack)[0]
            check(np.array_equal(across[pairs], b) and np.all(g["border_patch"][pairs] != g["border_patch"][b])
                  and np.all(g["border_cell"][pairs] != g["border_cell"][b])
                  and np.allclose(g["border_area"][pairs], g["border_area"][b], rtol=1e-9)
                  and np.allclose(g["border_normal"][pairs], -g["border_normal"][b], atol=1e-9),
                  f"npz {sheet_name}: border_across pairs faces of one side, one cell, or unlike faces")
    # froth render draws the crack's faces in red over the cut; the uncut box has no such red.
    reds = []
    for label, sheet_args in (("penny", ["--crack", os.path.join(CRACKS, "penny.obj")]), ("plain", [])):
        vtu, png = os.path.join(work, f"render_{label}.vtu"), os.path.join(work, f"render_{label}.png")
        p = froth("mesh", box, *sheet_args, "-r", "0.08", "-o", vtu, "-q")
        q = froth("render", vtu, "-o", png, "-q") if p.returncode == 0 else p
        check(q.returncode == 0, f"render {label}: {q.stderr}")
        if q.returncode == 0:
            reader = vtk.vtkPNGReader()
            reader.SetFileName(png)
            reader.Update()
            rgb = vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars()).astype(float)
            reds.append(int(np.sum((rgb[:, 0] > 80) & (rgb[:, 0] > 2.5 * rgb[:, 1]) & (rgb[:, 0] > 2.5 * rgb[:, 2]))))
    check(len(reds) == 2 and reds[0] > 5000 and reds[1] == 0, f"render: crack-red pixels {reds} (penny, plain box)")
    # Exodus II: a side set per side.
    exo = os.path.join(work, "cracked.exo")
    p = froth("mesh", box, "--crack", through, "-r", "0.1", "-o", exo, "-q")
    check(p.returncode == 0, f"exodus: {p.stderr}")
    reader = vtk.vtkExodusIIReader()
    reader.SetFileName(exo)
    reader.UpdateInformation()
    sets = [reader.GetObjectName(vtk.vtkExodusIIReader.SIDE_SET, k).split(" ")[0]
            for k in range(reader.GetNumberOfObjects(vtk.vtkExodusIIReader.SIDE_SET))]
    check("crack_box_through_a" in sets and "crack_box_through_b" in sets, f"exodus side sets {sets}")
    # An ensemble cuts every member.
    ens = os.path.join(work, "ensemble")
    p = froth("ensemble", box, "--crack", through, "-r", "0.1", "--members", "2", "-o", ens, "-q")
    members = sorted(f for f in os.listdir(ens) if f.endswith(".vtu")) if p.returncode == 0 else []
    check(len(members) == 2, f"ensemble: {p.stderr}")
    for m in members:
        names = read_vtk(os.path.join(ens, m)).GetFieldData().GetAbstractArray("patch_names")
        check(names is None or "crack_box_through_a" in [names.GetValue(k) for k in range(names.GetNumberOfValues())],
              f"ensemble member {m}: crack patches")

    # Refused: a sheet that is no crack.
    p = froth("mesh", box, "--crack", os.path.join(CRACKS, "fin.obj"), "-r", "0.1", "-o", os.path.join(work, "f.vtu"))
    check(p.returncode == 3 and "shared by 3 triangles" in p.stderr, f"fin: exit {p.returncode}: {p.stderr}")
    return summary()


if __name__ == "__main__":
    sys.exit(main())
