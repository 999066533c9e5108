#!/usr/bin/env python3
"""Hard test shapes for the random-trial campaign (scripts/trials.py): closed, valid triangle
surfaces with the features real parts bring and that break mesh generators.

  python3 scripts/hard_shapes.py OUT_DIR [--seed S]

writes one OFF file per shape into OUT_DIR, the same bytes for the same seed. The shapes, each
about one unit across (r is a twentieth to a fortieth of that at the trials' cell counts):
  - walls_*: blocks on a rectilinear grid whose spacings include walls and slots 0.002 to 0.02
    thick (0.05 to 0.5 r), pockets and steps: a union of grid cells, so every face is planar
    and every reflex edge sharp;
  - pocket_body_*: a block with a pocket holding a second body 1e-5 to 1e-4 from its walls;
  - sliver_fan_*: prisms on polygons of up to 400 sides, caps fanned from one rim vertex;
  - thread_*: V-thread helices on a rod (a radial function over a cylinder, capped);
  - organic_*: noisy star-shaped blobs (low-frequency lobes plus tessellation noise);
  - nested_*: a shell inside another, both wound outward (the cavity comes from nesting).
"""
import argparse
import math
import os
import random


def write_off(path, vertices, triangles):
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(vertices), len(triangles)))
        for v in vertices:
            f.write("%.17g %.17g %.17g\n" % v)
        for t in triangles:
            f.write("3 %d %d %d\n" % t)


def grid_union(xs, ys, zs, filled):
    """The boundary of a union of grid cells (filled[i][j][k]), as outward triangles. Cells
    that touch only along an edge or at a corner make a non-manifold surface: the caller's
    occupancy avoids them (checked by manifold_ok)."""
    nx, ny, nz = len(xs) - 1, len(ys) - 1, len(zs) - 1
    index, vertices, triangles = {}, [], []

    def vid(i, j, k):
        key = (i, j, k)
        if key not in index:
            index[key] = len(vertices)
            vertices.append((xs[i], ys[j], zs[k]))
        return index[key]

    def full(i, j, k):
        return 0 <= i < nx and 0 <= j < ny and 0 <= k < nz and filled[i][j][k]

    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if not filled[i][j][k]:
                    continue
                for axis in range(3):
                    for side in (0, 1):
                        d = [0, 0, 0]
                        d[axis] = 1 if side else -1
                        if full(i + d[0], j + d[1], k + d[2]):
                            continue
                        # The face's four corners, counter-clockwise seen from outside.
                        a, b = (axis + 1) % 3, (axis + 2) % 3
                        base = [i, j, k]
                        base[axis] += side
                        quad = []
                        for (u, v) in ((0, 0), (1, 0), (1, 1), (0, 1)):
                            c = list(base)
                            c[a] += u
                            c[b] += v
                            quad.append(vid(*c))
                        if not side:
                            quad.reverse()
                        triangles.append((quad[0], quad[1], quad[2]))
                        triangles.append((quad[0], quad[2], quad[3]))
    return vertices, triangles


def manifold_ok(triangles):
    edges = {}
    for t in triangles:
        for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            edges[e] = edges.get(e, 0) + 1
    if any(c != 1 for c in edges.values()) or any((b, a) not in edges for (a, b) in edges):
        return False
    # No two sheets through one vertex (cells touching at a corner only).
    around = {}
    for t in triangles:
        for k in range(3):
            around.setdefault(t[k], []).append((t[(k + 1) % 3], t[(k + 2) % 3]))
    for fan in around.values():
        nxt = dict(fan)
        start = fan[0][0]
        seen, v = 0, start
        while True:
            v = nxt[v]
            seen += 1
            if v == start or seen > len(fan):
                break
        if seen != len(fan):
            return False
    return True


def spacings(rng, n, thin):
    """n grid steps summing to one, `thin` of them 0.002 to 0.02 (walls and slots)."""
    steps = [rng.uniform(0.5, 1.5) for _ in range(n)]
    thin_at = rng.sample(range(n), thin)
    total = sum(s for k, s in enumerate(steps) if k not in thin_at)
    thin_len = [math.exp(rng.uniform(math.log(0.002), math.log(0.02))) for _ in thin_at]
    scale = (1 - sum(thin_len)) / total
    out = [0.0]
    for k in range(n):
        out.append(out[-1] + (thin_len[thin_at.index(k)] if k in thin_at else steps[k] * scale))
    return out


def walls(rng):
    # A height map of columns on the grid (floors, steps, pockets, fins and slots), with no two
    # columns meeting only along a vertical edge (a non-manifold edge).
    n = rng.randint(4, 7)
    xs, ys = spacings(rng, n, rng.randint(1, 2)), spacings(rng, n, rng.randint(0, 2))
    zs = [z * 0.6 for z in spacings(rng, 4, rng.randint(0, 1))]
    height = [[rng.randint(1, 4) for j in range(n)] for i in range(n)]
    for changed in range(1000):
        fixed = False
        for i in range(n - 1):
            for j in range(n - 1):
                h = [height[i][j], height[i + 1][j], height[i + 1][j + 1], height[i][j + 1]]
                for k in range(4):
                    # Level k filled on one diagonal only: raise a column of the other.
                    on = [h[q] > k for q in range(4)]
                    if on == [True, False, True, False] or on == [False, True, False, True]:
                        a = 1 if on[0] else 0
                        ci, cj = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)][a]
                        height[ci][cj] = k + 1
                        fixed = True
                        break
        if not fixed:
            break
    filled = [[[k < height[i][j] for k in range(4)] for j in range(n)] for i in range(n)]
    v, t = grid_union(xs, ys, zs, filled)
    assert manifold_ok(t) and connected(t)
    return v, t


def connected(triangles):
    parent = {}

    def find(a):
        while parent.setdefault(a, a) != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for t in triangles:
        parent[find(t[1])] = find(t[0])
        parent[find(t[2])] = find(t[0])
    return len({find(a) for a in parent}) == 1


def box(lo, hi, outward=True):
    xs, ys, zs = [lo[0], hi[0]], [lo[1], hi[1]], [lo[2], hi[2]]
    v, t = grid_union(xs, ys, zs, [[[True]]])
    return v, t if outward else [(a, c, b) for (a, b, c) in t]


def merge(*parts):
    vertices, triangles = [], []
    for v, t in parts:
        o = len(vertices)
        vertices += v
        triangles += [(a + o, b + o, c + o) for (a, b, c) in t]
    return vertices, triangles


def pocket_body(rng):
    # A cup (a block with a pocket open at the top) and a block inside the pocket, `gap` from
    # the pocket's walls on some sides.
    w = rng.uniform(0.05, 0.15)
    xs = [0, w, 1 - w, 1]
    ys = [0, w, 0.8 - w, 0.8]
    zs = [0, w, 0.5]
    filled = [[[not (i == 1 and j == 1 and k == 1) for k in range(2)] for j in range(3)] for i in range(3)]
    cup = grid_union(xs, ys, zs, filled)
    gap = math.exp(rng.uniform(math.log(1e-5), math.log(1e-4)))
    lo = [w + gap, w + gap, w + gap]
    hi = [rng.uniform(0.4, 1 - w - gap), 0.8 - w - (gap if rng.random() < 0.5 else 0.1), rng.uniform(0.3, 0.6)]
    return merge(cup, box(lo, hi))


def sliver_fan(rng):
    n = rng.choice([64, 150, 400])
    rx, ry, h = 0.5, rng.uniform(0.2, 0.5), rng.uniform(0.05, 0.6)
    ring = [(rx * math.cos(2 * math.pi * k / n), ry * math.sin(2 * math.pi * k / n)) for k in range(n)]
    v = [(x, y, 0.0) for x, y in ring] + [(x, y, h) for x, y in ring]
    t = []
    for k in range(n):
        a, b = k, (k + 1) % n
        t += [(a, b, n + b), (a, n + b, n + a)]
    for k in range(1, n - 1):  # caps fanned from vertex 0: needles along the rim
        t.append((0, k + 1, k))
        t.append((n, n + k, n + k + 1))
    return v, t


def thread(rng):
    pitch = rng.uniform(0.05, 0.15)
    depth = pitch * rng.uniform(0.3, 0.6)
    r0, length = rng.uniform(0.15, 0.3), rng.uniform(0.6, 1.0)
    nt = rng.choice([48, 72, 96])
    nz = int(length / pitch * rng.choice([6, 10, 16]))

    def radius(theta, z):
        u = (z / pitch - theta / (2 * math.pi)) % 1.0
        return r0 + depth * (1 - 2 * abs(u - 0.5))

    v = []
    for iz in range(nz + 1):
        z = length * iz / nz
        for it in range(nt):
            th = 2 * math.pi * it / nt
            rr = radius(th, z)
            v.append((rr * math.cos(th), rr * math.sin(th), z))
    t = []
    for iz in range(nz):
        for it in range(nt):
            a, b = iz * nt + it, iz * nt + (it + 1) % nt
            t += [(a, b, b + nt), (a, b + nt, a + nt)]
    bottom, top = len(v), len(v) + 1
    v += [(0.0, 0.0, 0.0), (0.0, 0.0, length)]
    for it in range(nt):
        t.append((bottom, (it + 1) % nt, it))
        t.append((top, nz * nt + it, nz * nt + (it + 1) % nt))
    return v, t


def icosphere(levels):
    p = (1 + 5 ** 0.5) / 2
    v = [(-1, p, 0), (1, p, 0), (-1, -p, 0), (1, -p, 0), (0, -1, p), (0, 1, p), (0, -1, -p), (0, 1, -p),
         (p, 0, -1), (p, 0, 1), (-p, 0, -1), (-p, 0, 1)]
    v = [tuple(c / math.sqrt(1 + p * p) for c in q) for q in v]
    t = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        mid, nt = {}, []

        def m(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                q = [(v[a][k] + v[b][k]) / 2 for k in range(3)]
                s = math.sqrt(sum(c * c for c in q))
                mid[key] = len(v)
                v.append(tuple(c / s for c in q))
            return mid[key]

        for a, b, c in t:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            nt += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        t = nt
    return v, t


def blob(rng, levels, scale, noise):
    v, t = icosphere(levels)
    lobes = [(tuple(rng.gauss(0, 1) for _ in range(3)), rng.uniform(0.05, 0.25), rng.uniform(2, 6)) for _ in range(5)]
    out = []
    for q in v:
        f = 1.0
        for d, amp, sharp in lobes:
            n = math.sqrt(sum(c * c for c in d))
            f += amp * max(0.0, sum(q[k] * d[k] for k in range(3)) / n) ** sharp
        f *= 1 + rng.uniform(-noise, noise)
        out.append(tuple(scale * f * c for c in q))
    return out, t


def organic(rng):
    return blob(rng, rng.choice([3, 4]), 0.5, rng.choice([1e-3, 1e-2]))


def nested(rng):
    outer = blob(rng, 3, 0.5, 1e-3)
    inner_v, inner_t = blob(rng, 3, rng.uniform(0.15, 0.3), 1e-3)
    shift = [rng.uniform(-0.05, 0.05) for _ in range(3)]
    inner_v = [tuple(q[k] + shift[k] for k in range(3)) for q in inner_v]
    return merge(outer, (inner_v, inner_t))  # both wound outward


SHAPES = [("walls", walls, 5), ("pocket_body", pocket_body, 3), ("sliver_fan", sliver_fan, 3), ("thread", thread, 3),
          ("organic", organic, 3), ("nested", nested, 2)]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    for name, make, count in SHAPES:
        for k in range(count):
            rng = random.Random("%d/%s/%d" % (a.seed, name, k))
            v, t = make(rng)
            write_off(os.path.join(a.out, "%s_%d.off" % (name, k)), v, t)


if __name__ == "__main__":
    main()
