"""Valid inputs that reach no fixed limit (issue 25, 'limit' row; long tier): a convex prism of
4000 sides, meshed at a radius where one cell holds all 4002 of its faces, and a UV sphere of
two million triangles whose poles are fans of slivers. Each must mesh with every cell closed and
the cells' volumes summing to the part's. Run with Debian's /usr/bin/python3."""
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

FROTH = os.path.abspath(sys.argv[1])
tmp = tempfile.mkdtemp()
failures, passed = [], 0


def write_stl(path, tris):
    """Binary STL of an (n, 3, 3) array of triangles."""
    rec = np.zeros(len(tris), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["v"] = tris
    with open(path, "wb") as f:
        f.write(b"\0" * 80)
        f.write(np.uint32(len(tris)).tobytes())
        f.write(rec.tobytes())


def prism(sides):
    """Regular prism of radius 1 and height 1: fan caps (slivers meeting at the axis), quad sides."""
    t = 2 * np.pi * np.arange(sides) / sides
    a = np.stack([np.cos(t), np.sin(t)], axis=1)
    b = np.roll(a, -1, axis=0)
    z0, z1 = np.zeros((sides, 1)), np.ones((sides, 1))
    A0, B0, A1, B1 = (np.hstack([a, z0]), np.hstack([b, z0]), np.hstack([a, z1]), np.hstack([b, z1]))
    c0, c1 = np.zeros((sides, 3)), np.tile([0.0, 0.0, 1.0], (sides, 1))
    return np.concatenate([np.stack(x, axis=1) for x in
                           ((c0, B0, A0), (c1, A1, B1), (A0, B0, B1), (A0, B1, A1))])


def uv_sphere(rings, segments):
    """Unit sphere: `rings` bands of `segments` quads, the first and last bands fans at the poles."""
    th = np.pi * np.arange(rings + 1) / rings
    ph = 2 * np.pi * np.arange(segments) / segments
    P = np.stack([np.outer(np.sin(th), np.cos(ph)), np.outer(np.sin(th), np.sin(ph)),
                  np.outer(np.cos(th), np.ones(segments))], axis=2)
    P[0], P[-1] = [0, 0, 1], [0, 0, -1]
    i, j = np.meshgrid(np.arange(rings), np.arange(segments), indexing="ij")
    jn = (j + 1) % segments
    a, b, c, d = P[i, j], P[i + 1, j], P[i + 1, jn], P[i, jn]
    upper = np.stack([a, b, d], axis=2)[1:].reshape(-1, 3, 3)
    lower = np.stack([b, c, d], axis=2)[:-1].reshape(-1, 3, 3)
    return np.concatenate([upper, lower])


def check(what, path, r, cells=None, faces=None):
    global passed
    report = os.path.join(tmp, "report.json")
    p = subprocess.run([FROTH, "mesh", path, "-r", str(r), "-o", os.path.join(tmp, "out.vtu"), "--report", report,
                        "--no-quality", "--quiet"], capture_output=True, text=True)
    if p.returncode != 0:
        failures.append(f"{what}: exit {p.returncode}: {p.stderr.strip()[:300]}")
        return
    d = json.load(open(report))
    problems = []
    if d["volume"]["relative_error"] > 1e-9:
        problems.append(f"volume error {d['volume']['relative_error']:.3g}")
    if cells is not None and d["mesh"]["cells"] != cells:
        problems.append(f"{d['mesh']['cells']} cells, expected {cells}")
    if faces is not None and d["mesh"]["faces"] < faces:
        problems.append(f"{d['mesh']['faces']} faces, expected at least {faces}")
    if problems:
        failures.append(f"{what}: {'; '.join(problems)}")
    else:
        passed += 1
    print(f"{what}: {d['mesh']['cells']} cells, {d['mesh']['faces']} faces, {d['seconds_total']:.1f} s")


path = os.path.join(tmp, "prism.stl")
write_stl(path, prism(4000))
check("4000-sided prism at r = 0.5", path, 0.5)
check("4000-sided prism at r = 3 (one cell of 4002 faces)", path, 3, cells=1, faces=4002)
path = os.path.join(tmp, "sphere.stl")
write_stl(path, uv_sphere(1000, 1000))
check("sphere of 1998000 triangles at r = 0.1", path, 0.1)

shutil.rmtree(tmp)
for f in failures:
    print("FAIL:", f)
print(f"{'FAILED' if failures else 'passed'}: {passed} limit checks")
sys.exit(1 if failures else 0)
