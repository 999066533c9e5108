#!/usr/bin/env python3
"""The random-trial campaign: froth run as users draw it, over many parts.

  python3 scripts/trials.py N [--seed S] [--froth build/froth] [--work DIR] [--jobs J]
                              [--cells LO HI] [--check] [--quiet] [--crossing] [--cracked-regions]

Each trial draws (part, cell count, seed, --grade, random cracks, --convex or --weld, threads) from a stream
seeded by S and runs `froth mesh` on it. The parts are the valid test models (tests/data/models, the heater's five
regions as one multi-region run), the real public parts of tests/data/corpus, and the hard shapes
of scripts/hard_shapes.py (made in the work folder). A trial fails if froth exits with any code but
0: every part is valid. With --check each mesh is also read back with VTK (/usr/bin/python3 with
python3-vtk9, scripts/check_mesh.py) and its stated local guarantees checked. Every failing trial
is printed as the command that replays it; the last line is the count. Exit 1 if any failed.
"""
import argparse
import concurrent.futures
import gzip
import hashlib
import json
import math
import os
import random
import shlex
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS = os.path.join(ROOT, "tests", "data", "models")
CORPUS = os.path.join(ROOT, "tests", "data", "corpus")
# The valid test models (the others are broken on purpose).
VALID_MODELS = ["unit_cube.STL", "unit_sphere.STL", "7_8ths_cube.stl", "shape_ibeam.stl", "torus.STL",
                "plate_holes.STL", "round.stl", "hollow_sphere.off", "two_objects_mixed_case_names.stl",
                "joined_tetrahedra.obj", "step.off", "1002_tray_bottom.STL", "ADIS16480.STL", "hinge.stl"]
HEATER = ["bottomAir.stl", "topAir.stl", "heater.stl", "leftSolid.stl", "rightSolid.stl"]


def unpack_corpus(work):
    """The corpus parts, unpacked into work/parts and checked against SHA256SUMS."""
    out = os.path.join(work, "parts")
    os.makedirs(out, exist_ok=True)
    sums = {}
    with open(os.path.join(CORPUS, "SHA256SUMS")) as f:
        for line in f:
            digest, name = line.split()
            sums[name] = digest
    paths = []
    for name, digest in sorted(sums.items()):
        path = os.path.join(out, name)
        if not os.path.exists(path) or hashlib.sha256(open(path, "rb").read()).hexdigest() != digest:
            data = gzip.open(os.path.join(CORPUS, name + ".gz")).read()
            if hashlib.sha256(data).hexdigest() != digest:
                sys.exit("trials: %s.gz does not match its SHA256SUMS line" % name)
            with open(path, "wb") as f:
                f.write(data)
        paths.append(path)
    return paths


def parts(work):
    hard = os.path.join(work, "hard")
    subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "hard_shapes.py"), hard], check=True)
    out = [[os.path.join(MODELS, m)] for m in VALID_MODELS]
    out.append([os.path.join(MODELS, "multi_region_heater", m) for m in HEATER])
    out += [[p] for p in unpack_corpus(work)]
    out += [[os.path.join(hard, f)] for f in sorted(os.listdir(hard))]
    return out


def triangles(path):
    """A surface file's triangles (STL, OBJ, OFF; polygons as fans) as triples of coordinate
    tuples, or None for another format."""
    ext = os.path.splitext(path)[1].lower()
    data = open(path, "rb").read()
    corners = []  # polygons as lists of points
    if ext == ".stl":
        if data[:5] == b"solid" and b"facet" in data[:1000]:
            xs = [tuple(map(float, l.split()[1:4])) for l in data.decode(errors="replace").splitlines()
                  if l.strip().startswith("vertex")]
        else:
            import struct
            xs = []
            for t in range(struct.unpack_from("<I", data, 80)[0]):
                v = struct.unpack_from("<12f", data, 84 + 50 * t)
                xs += [v[3:6], v[6:9], v[9:12]]
        corners = [xs[i:i + 3] for i in range(0, len(xs) - 2, 3)]
    elif ext == ".obj":
        lines = data.decode(errors="replace").splitlines()
        xs = [tuple(map(float, l.split()[1:4])) for l in lines if l.startswith("v ")]
        for l in lines:
            if l.startswith("f "):
                ids = [int(w.split("/")[0]) for w in l.split()[1:]]
                corners.append([xs[i - 1 if i > 0 else len(xs) + i] for i in ids])
    elif ext == ".off":
        words = [l.split("#")[0].split() for l in data.decode(errors="replace").splitlines()]
        words = [w for w in words if w]
        first = 1 if words[0][0].upper() == "OFF" and len(words[0]) == 1 else 0
        head = words[first] if first else words[0][1:]
        n, f = int(head[0]), int(head[1])
        xs = [tuple(map(float, w[:3])) for w in words[first + 1:first + 1 + n]]
        for w in words[first + 1 + n:first + 1 + n + f]:
            corners.append([xs[int(i)] for i in w[1:1 + int(w[0])]])
    else:
        return None
    return [(p[0], p[i], p[i + 1]) for p in corners for i in range(1, len(p) - 1)]


def bounds(tris):
    """The box around triangles' corners."""
    xs = [x for t in tris for x in t]
    return [min(x[k] for x in xs) for k in range(3)], [max(x[k] for x in xs) for k in range(3)]


def shares_triangles(tris):
    """Whether a triangle is listed twice: solids touching along it, a multi-region part."""
    seen = set()
    for t in tris:
        key = tuple(sorted(t))
        if key in seen:
            return True
        seen.add(key)
    return False


def inside(tris, p):
    """Whether p is inside the closed surface `tris`: the parity of the triangles a ray from p
    crosses (Moller-Trumbore), along a direction no CAD face is likely to hold."""
    d = (0.5773502691896258, 0.5801346643, 0.5746)
    crossings = 0
    for a, b, c in tris:
        e1 = [b[k] - a[k] for k in range(3)]
        e2 = [c[k] - a[k] for k in range(3)]
        h = [d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]]
        det = sum(e1[k] * h[k] for k in range(3))
        if abs(det) < 1e-300:
            continue
        s = [p[k] - a[k] for k in range(3)]
        u = sum(s[k] * h[k] for k in range(3)) / det
        if u < 0 or u > 1:
            continue
        q = [s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]]
        v = sum(d[k] * q[k] for k in range(3)) / det
        if v < 0 or u + v > 1:
            continue
        crossings += sum(e2[k] * q[k] for k in range(3)) / det > 0
    return crossings % 2 == 1


def crack_sheet(rng, part, path):
    """A crack for `part`: a plane through a random point of the middle of its box, facing a
    random way, as a square (8 triangles, OBJ) reaching past the box on every side (a through
    crack) or, half the time, 0.2 to 0.8 times the box's size across (a front inside the part,
    or from its surface: a penny or an edge crack). The point is inside the part: a crack that
    misses the solid is refused, as it should be, and is not a run a user would draw."""
    tris = triangles(part)
    # (A single file's regions are not told apart here: see region_crack_sheet for several files.)
    if not tris or shares_triangles(tris):
        return False
    lo, hi = bounds(tris)
    for _ in range(20):
        centre = [lo[k] + (0.2 + 0.6 * rng.random()) * (hi[k] - lo[k]) for k in range(3)]
        if inside(tris, centre):
            break
    else:
        return False
    n = random_normal(rng)
    half = math.sqrt(sum((hi[k] - lo[k]) ** 2 for k in range(3)))
    if rng.random() < 0.5:
        half *= 0.1 + 0.3 * rng.random()
    square_sheet(path, centre, half, n)
    return True


def distance_to_triangle(p, t):
    """The distance from p to triangle t (its nearest point: inside it, or on an edge)."""
    a, b, c = t
    sub = lambda x, y: [x[k] - y[k] for k in range(3)]  # noqa: E731
    dot = lambda x, y: sum(x[k] * y[k] for k in range(3))  # noqa: E731

    def to_segment(u, v):
        d = sub(v, u)
        s = max(0.0, min(1.0, dot(sub(p, u), d) / dot(d, d))) if dot(d, d) > 0 else 0.0
        return math.sqrt(sum((u[k] + s * d[k] - p[k]) ** 2 for k in range(3)))
    e1, e2 = sub(b, a), sub(c, a)
    n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
    nn = dot(n, n)
    if nn > 0:
        h = dot(sub(p, a), n) / nn
        q = [p[k] - h * n[k] for k in range(3)]
        edges = ((a, b), (b, c), (c, a))
        if all(dot(n, [(v[1] - u[1]) * (q[2] - u[2]) - (v[2] - u[2]) * (q[1] - u[1]),
                       (v[2] - u[2]) * (q[0] - u[0]) - (v[0] - u[0]) * (q[2] - u[2]),
                       (v[0] - u[0]) * (q[1] - u[1]) - (v[1] - u[1]) * (q[0] - u[0])]) >= 0 for u, v in edges):
            return abs(h) * math.sqrt(nn)
    return min(to_segment(a, b), to_segment(b, c), to_segment(c, a))


def square_sheet(path, centre, half, n):
    """A square 2 half wide about `centre`, facing n, as 8 triangles (OBJ)."""
    a = [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0]
    u = [n[1] * a[2] - n[2] * a[1], n[2] * a[0] - n[0] * a[2], n[0] * a[1] - n[1] * a[0]]
    un = math.sqrt(sum(c * c for c in u))
    u = [c / un for c in u]
    v = [n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]]
    with open(path, "w") as f:
        for j in range(3):
            for i in range(3):
                p = [centre[k] + (i - 1) * half * u[k] + (j - 1) * half * v[k] for k in range(3)]
                f.write("v %.17g %.17g %.17g\n" % tuple(p))
        for j in range(2):
            for i in range(2):
                q = 3 * j + i + 1
                f.write("f %d %d %d\nf %d %d %d\n" % (q, q + 1, q + 4, q, q + 4, q + 3))


def random_normal(rng):
    n = [rng.gauss(0, 1) for _ in range(3)]
    norm = math.sqrt(sum(c * c for c in n))
    return [c / norm for c in n]


def region_crack_sheet(rng, part, cells, path):
    """A crack through a random point of one region of a multi-region part (its files), facing a
    random way: half the time a through crack reaching past the part on every side (it crosses
    the interfaces it meets), otherwise a penny inside the region, off the others by more than its
    skirt (2r beyond the front, 2 sqrt(2) r at a corner): a sheet that ends at an interface, or
    whose front comes near one, is refused (not supported yet), and is not drawn. r is taken above
    what `cells` gives (bulk packing 0.3841 of disks r/2; the heater's r at 2,000 and 20,000 cells is
    1.13 and 1.05 times that)."""
    regions = [triangles(f) for f in part]
    if any(not t for t in regions):
        return False
    volume = sum(abs(sum(a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                         + a[2] * (b[0] * c[1] - b[1] * c[0]) for a, b, c in t)) / 6 for t in regions)
    r = 1.2 * 2 * (0.3841 * volume * 3 / (4 * math.pi * cells)) ** (1 / 3)
    tris = rng.choice(regions)
    lo, hi = bounds(tris)
    # The roomiest of a few random points inside (regions are often thin layers).
    room, centre = 0.0, None
    for _ in range(10):
        p = [lo[k] + (0.1 + 0.8 * rng.random()) * (hi[k] - lo[k]) for k in range(3)]
        if inside(tris, p):
            d = min(distance_to_triangle(p, t) for t in tris) - 3 * r
            if d > room:
                room, centre = d, p
    if centre is None:
        return False
    if rng.random() < 0.5:  # across every region it meets, reaching past the part on every side
        lo, hi = bounds([t for tris in regions for t in tris])
        square_sheet(path, centre, math.sqrt(sum((hi[k] - lo[k]) ** 2 for k in range(3))), random_normal(rng))
    else:
        square_sheet(path, centre, (0.3 + 0.7 * rng.random()) * room / math.sqrt(2), random_normal(rng))
    return True


def draw(rng, all_parts, lo, hi, work, k, crossing=False, cracked_regions=False):
    part = rng.choice([p for p in all_parts if len(p) > 1] if cracked_regions else all_parts)
    cells = int(round(math.exp(rng.uniform(math.log(lo), math.log(hi)))))
    options = ["--cells", str(cells), "--seed", str(rng.getrandbits(32))]
    # A fifth of the single-solid trials cut along a random crack (a third of those along two); a
    # quarter of all graded.
    if len(part) == 1 and (rng.random() < 0.2 or crossing):
        sheet = os.path.join(work, "crack_%d.obj" % k)
        if crack_sheet(rng, part[0], sheet):
            options += ["--crack", sheet]
            # A third of them along a second crack too, crossing the first where they meet.
            second = os.path.join(work, "crack_%d_b.obj" % k)
            if (rng.random() < 1 / 3 or crossing) and crack_sheet(rng, part[0], second):
                options += ["--crack", second]
    # A fifth of the multi-region trials cut along a penny inside one region.
    if len(part) > 1 and (rng.random() < 0.2 or cracked_regions) and region_crack_sheet(rng, part, cells, os.path.join(work, "crack_%d.obj" % k)):
        options += ["--crack", os.path.join(work, "crack_%d.obj" % k)]
    if rng.random() < 0.25:
        options.append("--grade")
    weld = rng.random()
    if weld < 0.1 and options.count("--crack") < 2:  # (crossing cracks are not split convex yet)
        options.append("--convex")  # (its weld tolerance is 0)
    elif weld < 0.3:
        options += ["--weld", "0"]
    options += ["--threads", str(rng.choice([1, 2]))]
    return part, options


def subprocess_check(vtu):
    """The checker in its own interpreter (when this one lacks VTK): its output when it fails."""
    c = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "scripts", "check_mesh.py"), vtu],
                       capture_output=True, text=True)
    return (c.stdout + c.stderr).strip().splitlines() if c.returncode != 0 else []


def in_process_check(vtu):
    import check_mesh
    try:
        return check_mesh.check(vtu)[0]
    except Exception as e:  # a mesh VTK cannot read, or one the checks cannot parse
        return ["check_mesh: %s: %s" % (type(e).__name__, e)]


def checker(jobs):
    """How each mesh is checked: in `jobs` worker processes that import VTK once (a second per
    trial saved), or, where this interpreter has no VTK, by /usr/bin/python3 per mesh."""
    sys.path.insert(0, os.path.join(ROOT, "scripts"))
    try:
        import check_mesh  # noqa: F401
    except ImportError:
        return subprocess_check, None
    pool = concurrent.futures.ProcessPoolExecutor(jobs)
    return (lambda vtu: pool.submit(in_process_check, vtu).result()), pool


def run_trial(froth, work, k, part, options, check, timeout):
    vtu = os.path.join(work, "trial_%d.vtu" % k)
    report = os.path.join(work, "trial_%d.json" % k)
    cmd = [froth, "mesh", *part, *options, "-o", vtu, "--report", report, "--quiet"]
    t0 = time.time()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        rc, message = p.returncode, (p.stderr.strip().splitlines() or [""])[-1]
    except subprocess.TimeoutExpired:
        rc, message = "timeout", "no answer within %d s" % timeout
    seconds = time.time() - t0
    problems = []
    if rc == 0 and check:
        problems = check(vtu)[-5:]
        # The report's sums: the cells' volume is the domain's, each crack's faces on each side its area.
        run = json.load(open(report))
        volume = run["volume"]
        if abs(volume["cells_sum"] - volume["domain"]) > 1e-9 * volume["domain"]:
            problems.append("report: cells' volume %r against the domain's %r" % (volume["cells_sum"], volume["domain"]))
        for c in run.get("cracks", []):
            for side in "ab":
                if abs(c["area_from_" + side] - c["area"]) > 1e-9 * c["area"]:
                    problems.append("report: crack %s side %s %r against %r" % (c["name"], side, c["area_from_" + side], c["area"]))
    for f in (vtu, report):
        if os.path.exists(f):
            os.remove(f)
    replay = " ".join(shlex.quote(os.path.relpath(a, ROOT) if os.path.isabs(a) and a.startswith(ROOT) else a)
                      for a in [froth, "mesh", *part, *options])
    return {"trial": k, "rc": rc, "message": message, "seconds": round(seconds, 3), "replay": replay,
            "problems": problems}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("n", type=int)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--froth", default=os.path.join(ROOT, "build", "froth"))
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "trials"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--cells", type=float, nargs=2, default=[1e3, 5e4], metavar=("LO", "HI"))
    ap.add_argument("--check", action="store_true", help="read each mesh back and check its stated guarantees")
    ap.add_argument("--timeout", type=int, default=900)
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--crossing", action="store_true", help="cut every single-solid trial along two random cracks")
    ap.add_argument("--cracked-regions", action="store_true",
                    help="draw only multi-region parts, each cut along a penny inside one region where one fits")
    a = ap.parse_args()
    froth = os.path.abspath(a.froth)
    os.makedirs(a.work, exist_ok=True)
    all_parts = parts(a.work)
    rng = random.Random(a.seed)
    trials = [draw(rng, all_parts, *a.cells, a.work, k, a.crossing, a.cracked_regions) for k in range(a.n)]
    log = open(os.path.join(a.work, "trials_seed%d.jsonl" % a.seed), "w")
    failed = 0
    check, check_pool = checker(a.jobs) if a.check else (None, None)
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = [pool.submit(run_trial, froth, a.work, k, part, opt, check, a.timeout)
                   for k, (part, opt) in enumerate(trials)]
        for fut in futures:
            r = fut.result()
            log.write(json.dumps(r) + "\n")
            log.flush()
            bad = r["rc"] != 0 or r["problems"]
            failed += bool(bad)
            if bad:
                print("FAIL trial %d (exit %s): %s\n  %s" % (r["trial"], r["rc"], r["replay"],
                                                          r["message"] or "; ".join(r["problems"])), flush=True)
                for line in r["problems"]:
                    print("    " + line)
            elif not a.quiet:
                print("ok   trial %d %.1f s: %s" % (r["trial"], r["seconds"], r["replay"]), flush=True)
    if check_pool:
        check_pool.shutdown()
    print("trials: %d of %d failed (seed %d, %d parts, cells %g to %g%s)" %
          (failed, a.n, a.seed, len(all_parts), a.cells[0], a.cells[1], ", checked" if a.check else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
