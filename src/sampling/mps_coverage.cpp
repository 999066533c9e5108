// Which cubes the seeds already cover, so that refinement can drop them: one-ball marks at the
// first levels, then exact tests against two or three balls (sampling/mps_sampler.hpp).
#include "sampling/mps_sampler.hpp"

namespace froth::mps {

uint32_t Sampler::children_in_one_ball(Vec3 lo, double h, const std::vector<Vec3>& near) const {
  uint32_t inside = 0;
  for (const Vec3& q : near) {
    double far2[3][2];  // per axis, per half of the parent
    for (int a = 0; a < 3; ++a) {
      const double x = q[a], l = lo[a];
      const double f0 = std::max(x - l, l + h - x), f1 = std::max(x - l - h, l + 2 * h - x);
      far2[a][0] = f0 * f0;
      far2[a][1] = f1 * f1;
    }
#ifdef __SSE2__
    // Two children (x = 0, 1) per vector compare, the sums grouped as below.
    const __m128d x = _mm_loadu_pd(far2[0]), limit = _mm_set1_pd(r2_);
    for (int yz = 0; yz < 4; ++yz) {
      const __m128d sum = _mm_add_pd(_mm_add_pd(x, _mm_set1_pd(far2[1][yz & 1])), _mm_set1_pd(far2[2][yz >> 1]));
      inside |= uint32_t(_mm_movemask_pd(_mm_cmple_pd(sum, limit))) << (2 * yz);
    }
#else
    for (int c = 0; c < 8; ++c) inside |= uint32_t(far2[0][c & 1] + far2[1][c >> 1 & 1] + far2[2][c >> 2] <= r2_) << c;
#endif
  }
  return inside;
}

void Sampler::mark_grandchildren_in_one_ball(size_t first) {
  const auto& g = s_.grid;
  const int64_t layer = int64_t(g.nx) * g.ny;
  const int k_begin = int(s_.cube_offset / layer), k_end = k_begin + int(s_.cube_seed.size() / layer);
  // A seed marks cubes up to two layers from its own. The seeds are split by slabs of
  // kMarkSlab layers, and the slabs of one parity are marked in parallel: their seeds' cubes
  // are apart, so no two threads write one cube and the marks need no atomic OR (that was a
  // fifth of the marking time). Marks are ORed, so the order does not matter. (A mark lost
  // would only keep a covered cube: work, not a different sample.)
  constexpr int kMarkSlab = 4;
  const int slabs = std::max(1, (k_end - k_begin + kMarkSlab - 1) / kMarkSlab);
  auto slab_of = [&](Vec3 q) {
    int i, j, k;
    g.locate(q, i, j, k);
    return size_t(std::clamp((k - k_begin) / kMarkSlab, 0, slabs - 1));
  };
  std::vector<uint32_t> slab_begin(size_t(slabs) + 1, 0), by_slab(s_.seeds.size() - first), slab(by_slab.size());
  for (size_t id = first; id < s_.seeds.size(); ++id) ++slab_begin[(slab[id - first] = uint32_t(slab_of(s_.seeds[id]))) + 1];
  for (int sl = 0; sl < slabs; ++sl) slab_begin[sl + 1] += slab_begin[sl];
  std::vector<uint32_t> fill(slab_begin.begin(), slab_begin.end() - 1);
  for (size_t id = first; id < s_.seeds.size(); ++id) by_slab[fill[slab[id - first]]++] = uint32_t(id);
  for (int parity = 0; parity < 2; ++parity) {
#pragma omp parallel for schedule(dynamic, 1)
    for (int sl = parity; sl < slabs; sl += 2)
      for (uint32_t at = slab_begin[sl]; at < slab_begin[sl + 1]; ++at) mark_around(s_.seeds[by_slab[at]], k_begin, k_end);
  }
}

void Sampler::mark_around(Vec3 q, int k_begin, int k_end) {
  const auto& g = s_.grid;
  const double h = g.side / 4;
  int c[3];
  g.locate(q, c[0], c[1], c[2]);
  // Per axis, for the cubes d = -2..2 steps from q's and each of their quarters: the squared
  // distance from q to the quarter's farther face (as in children_in_one_ball), and its
  // smallest value over the cube's four quarters.
  double far2[3][5][4], nearest2[3][5];
  for (int a = 0; a < 3; ++a)
    for (int d = 0; d < 5; ++d) {
      const double x = q[a], l = g.origin[a] + (c[a] + d - 2) * g.side;
      for (int u = 0; u < 4; ++u) {
        const double f = std::max(x - (l + u * h), l + (u + 1) * h - x);
        far2[a][d][u] = f * f;
      }
      nearest2[a][d] = std::min({far2[a][d][0], far2[a][d][1], far2[a][d][2], far2[a][d][3]});
    }
  // Only cubes with a grandchild in the ball (the smallest terms along each axis fit), other
  // than q's own, which holds a seed and is never refined.
  for (int dk = 0; dk < 5; ++dk) {
    const int k = c[2] + dk - 2;
    if (k < k_begin || k >= k_end) continue;
    for (int dj = 0; dj < 5; ++dj) {
      const int j = c[1] + dj - 2;
      if (j < 0 || j >= g.ny || nearest2[2][dk] + nearest2[1][dj] > r2_) continue;
      for (int di = 0; di < 5; ++di) {
        const int i = c[0] + di - 2;
        if (i < 0 || i >= g.nx || nearest2[2][dk] + nearest2[1][dj] + nearest2[0][di] > r2_) continue;
        if (di == 2 && dj == 2 && dk == 2) continue;
        uint64_t in = 0;
#ifdef __SSE2__
        // A row's four tests as two vector compares (the compiler kept them scalar, a
        // compare and a flag per grandchild: most of the marking time); the same tests.
        const __m128d x01 = _mm_loadu_pd(&far2[0][di][0]), x23 = _mm_loadu_pd(&far2[0][di][2]);
#endif
        for (int z = 0; z < 4; ++z)
          for (int y = 0; y < 4; ++y) {
            const double room = r2_ - far2[2][dk][z] - far2[1][dj][y];
#ifdef __SSE2__
            const __m128d limit = _mm_set1_pd(room);
            const uint64_t row = uint64_t(_mm_movemask_pd(_mm_cmple_pd(x01, limit)) |
                                          _mm_movemask_pd(_mm_cmple_pd(x23, limit)) << 2);
#else
            uint64_t row = 0;
            for (int x = 0; x < 4; ++x) row |= uint64_t(far2[0][di][x] <= room) << x;
#endif
            in |= row << (4 * y + 16 * z);
          }
        if (!in) continue;
        if (uint64_t* m = grandchild_marks_.at(i, j, k)) *m |= in;
      }
    }
  }
}

bool Sampler::sites_cover(const std::vector<Vec3>& near, const Sites& s, const Vec3 (*edges)[2], int count, Vec3 lo, Vec3 hi,
                 const Plane* cut) const {
  const int* site = s.id;
  const int sites = s.n;
  const double limit = r2_ * (1 - 1e-12);
  for (int i = 0; i < sites; ++i)
    for (int j = i + 1; j < sites; ++j) {
      const Vec3 qa = near[site[i]], qb = near[site[j]];
      const Vec3 n = qb - qa;
      const double mid = (norm2(qb) - norm2(qa)) / 2;  // bisector: dot(n, p) = mid
      for (int e = 0; e < count; ++e) {
        const double su = dot(n, edges[e][0]) - mid, sv = dot(n, edges[e][1]) - mid;
        if ((su < 0) == (sv < 0)) continue;
        const Vec3 x = edges[e][0] + (su / (su - sv)) * (edges[e][1] - edges[e][0]);
        const double d2 = norm2(x - qa);
        if (sites == 3 && norm2(x - near[site[3 - i - j]]) < d2) continue;  // inside the third's piece
        if (d2 >= limit) return false;
      }
    }
  if (sites < 3) return true;
  // The line equidistant from the three, through their circumcentre normal to their plane, as
  // centre + t * axis: its part in P is an interval of t, whose ends are its crossings with P's
  // faces.
  const Vec3 a = near[site[0]], b = near[site[1]] - a, c = near[site[2]] - a;
  const Vec3 axis = cross(b, c);
  const double w = norm2(axis);
  if (!(w > 1e-24 * r2_ * r2_)) return false;  // (nearly) collinear: give up
  const Vec3 centre = a + (1 / (2 * w)) * cross(norm2(b) * c - norm2(c) * b, axis);
  double t0 = -INFINITY, t1 = INFINITY;
  auto keep_below = [&](Vec3 n, double offset) {  // t with dot(n, centre + t axis) <= offset
    const double s0 = dot(n, centre) - offset, ds = dot(n, axis);
    if (ds == 0) {
      if (s0 > 0) t0 = INFINITY;
    } else if (ds > 0) {
      t1 = std::min(t1, -s0 / ds);
    } else {
      t0 = std::max(t0, -s0 / ds);
    }
  };
  for (int ax = 0; ax < 3; ++ax) {
    Vec3 e{};
    e[ax] = 1;
    keep_below(e, hi[ax]);
    keep_below(-1.0 * e, -lo[ax]);
  }
  if (cut) keep_below(cut->normal, cut->offset);
  if (t0 <= t1)
    for (double t : {t0, t1})
      if (norm2(centre + t * axis - a) >= limit) return false;
  return true;
}

bool Sampler::covered(const std::vector<Vec3>& near, CornerCache& cc, int dx, int dy, int dz) const {
  Vec3 corner[8];
  Sites sites;
  for (int k = 0; k < 8; ++k) {
    const int p = CornerCache::child_corner(dx, dy, dz, k);
    const int n = nearest_to_corner(p, near, cc);
    if (cc.dist2[p] > r2_) return false;  // a corner is uncovered
    corner[k] = cc.point(p);
    if (!sites.add(n)) return false;  // four or more nearest seeds: give up (keep the cube)
  }
  if (sites.n < 2) return false;
  Vec3 edges[12][2];
  for (int e = 0; e < 12; ++e) edges[e][0] = corner[kCubeEdges[e][0]], edges[e][1] = corner[kCubeEdges[e][1]];
  // Corners are classified by nearest seed but the bisector tests by sign; they agree up to
  // round-off, and a tie point is within r of both seeds by the checks above.
  return sites_cover(near, sites, edges, 12, corner[0], corner[7], nullptr);
}

bool Sampler::covered_below_plane(const std::vector<Vec3>& near, CornerCache& cc, int dx, int dy, int dz,
                         const Plane& pl) const {
  const Vec3 lo = cc.point(((dz * 3) + dy) * 3 + dx);
  const double h = cc.h;
  const Plane below{pl.normal, pl.offset + round_off_band(pl, lo, h)};  // P's cutting plane
  Vec3 corner[8];
  double sd[8];
  int lattice[8];  // the corners' points in the parent's lattice
  for (int k = 0; k < 8; ++k) {
    lattice[k] = CornerCache::child_corner(dx, dy, dz, k);
    corner[k] = cc.point(lattice[k]);
    sd[k] = below.signed_distance(corner[k]);
  }
  Vec3 vert[20], seg[24][2];
  int nv = 0, ns = 0, cross_at[12];
  Sites sites;
  for (int k = 0; k < 8; ++k) {
    if (sd[k] > 0) continue;
    const int n = nearest_to_corner(lattice[k], near, cc);
    if (cc.dist2[lattice[k]] > r2_ || !sites.add(n)) return false;
    vert[nv++] = corner[k];
  }
  const int corners_inside = nv;
  if (nv == 0) return false;  // the plane only grazes the child: keep it
  for (int e = 0; e < 12; ++e) {
    const int a = kCubeEdges[e][0], b = kCubeEdges[e][1];
    cross_at[e] = -1;
    if ((sd[a] <= 0) && (sd[b] <= 0)) {
      seg[ns][0] = corner[a], seg[ns++][1] = corner[b];
    } else if ((sd[a] <= 0) != (sd[b] <= 0)) {
      const Vec3 x = corner[a] + (sd[a] / (sd[a] - sd[b])) * (corner[b] - corner[a]);
      cross_at[e] = nv;
      vert[nv++] = x;
      seg[ns][0] = sd[a] <= 0 ? corner[a] : corner[b], seg[ns++][1] = x;
    }
  }
  // The plane's section of each face joins its two crossings (other counts: degenerate, keep).
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      int on[4], m = 0;
      for (int e = 0; e < 12; ++e) {
        const int a = kCubeEdges[e][0], b = kCubeEdges[e][1];
        if ((a >> axis & 1) == side && (b >> axis & 1) == side && cross_at[e] >= 0) on[m++] = cross_at[e];
      }
      if (m == 2) seg[ns][0] = vert[on[0]], seg[ns++][1] = vert[on[1]];
      else if (m != 0) return false;
    }
  // The crossings' nearest seeds (the corners' are cached).
  for (int v = corners_inside; v < nv; ++v) {
    double d2;
    const int n = nearest_seed(vert[v], near, d2);
    if (d2 > r2_ || !sites.add(n)) return false;
  }
  return sites.n < 2 || sites_cover(near, sites, seg, ns, corner[0], corner[7], &below);
}

}  // namespace froth::mps
