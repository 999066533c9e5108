#include "voronoi/convex_cell.hpp"

#include <algorithm>
#include <cmath>

namespace froth {

namespace {
double det3(Vec3 a, Vec3 b, Vec3 c) { return dot(a, cross(b, c)); }
}  // namespace

void ConvexCell::reset_cube(double h) {
  // Faces -x, +x, -y, +y, -z, +z are planes (and generators) 0..5.
  static const Vec3 normals[6] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
  // Corner c has coordinates (±h) by bits of c and lies on one plane per axis, ordered so that
  // the normals are counter-clockwise seen from outside (positive determinant); adjacency is
  // the triangle holding the reversed edge. The same for every cube: built once.
  static const std::array<Tri, 8> cube = [] {
    std::array<Tri, 8> t{};
    for (int c = 0; c < 8; ++c) {
      t[c].p[0] = uint8_t((c & 1) ? 1 : 0);
      t[c].p[1] = uint8_t((c & 2) ? 3 : 2);
      t[c].p[2] = uint8_t((c & 4) ? 5 : 4);
      if (det3(normals[t[c].p[0]], normals[t[c].p[1]], normals[t[c].p[2]]) < 0) std::swap(t[c].p[1], t[c].p[2]);
    }
    for (int a = 0; a < 8; ++a)
      for (int k = 0; k < 3; ++k)
        for (int o = 0; o < 8; ++o)
          for (int j = 0; j < 3; ++j)
            if (t[o].p[(j + 1) % 3] == t[a].p[(k + 2) % 3] && t[o].p[(j + 2) % 3] == t[a].p[(k + 1) % 3])
              t[a].adj[k] = uint16_t(o);
    return t;
  }();
  planes_.clear();
  for (int f = 0; f < 6; ++f) planes_.push_back({normals[f], h, kCubeGenerator + f});
  tri_.assign(cube.begin(), cube.end());
  pos_.clear();
  for (int c = 0; c < 8; ++c) pos_.push_back({(c & 1) ? h : -h, (c & 2) ? h : -h, (c & 4) ? h : -h});
  border_from_.fill(kNone);
  coincident_ = false;
  faces_valid_ = rmax_valid_ = false;
}

ConvexCell::Clip ConvexCell::clip(Vec3 n, double offset, int32_t generator, double eps, const TieBreaker* ties,
                                  int32_t self) {
  const size_t nt = tri_.size();
  sd_.resize(nt);
  out_.resize(nt);
  // The removed vertices, listed as they are found (without a branch: a few of some thirty go),
  // become the first slots of the new triangles.
  slots_.resize(nt);
  size_t n_out = 0;
  bool any_in = false;
  // The signed distances in a loop of their own, which the compiler vectorises (in the loop
  // below they would be scalar).
  double* sd = sd_.data();
  const Vec3* pos = pos_.data();
  for (size_t t = 0; t < nt; ++t) sd[t] = dot(n, pos[t]) - offset;
  const double band = ties && generator >= 0 ? ties->band() : -1;
  bool near = false;
  for (size_t t = 0; t < nt; ++t) {
    const double s = sd[t];
    const bool o = s > eps;
    out_[t] = o;
    slots_[n_out] = uint16_t(t);
    n_out += o;
    any_in |= s < -eps;
    near |= std::abs(s) <= band;
  }
  bool any_exact = false;
  if (near) {
    // Seed vertices near the plane, decided exactly (TieBreaker); the rest as above.
    exact_.assign(nt, 0);
    n_out = 0, any_in = false;
    for (size_t t = 0; t < nt; ++t) {
      const double s = sd[t];
      int decided = 0;
      const Tri& v = tri_[t];
      if (std::abs(s) <= band && planes_[v.p[0]].gen >= 0 && planes_[v.p[1]].gen >= 0 && planes_[v.p[2]].gen >= 0)
        decided = ties->conflict(self, planes_[v.p[0]].gen, planes_[v.p[1]].gen, planes_[v.p[2]].gen, generator);
      exact_[t] = decided != 0;
      any_exact |= decided != 0;
      const bool o = decided ? decided > 0 : s > eps;
      out_[t] = o;
      if (o) slots_[n_out++] = uint16_t(t);
      any_in |= decided ? decided < 0 : s < -eps;
    }
  }
  if (n_out == 0) return Clip::Unchanged;
  if (!any_in) return Clip::Empty;
  if (planes_.size() >= kMaxPlanes && !compact_planes()) return Clip::Failed;
  faces_valid_ = rmax_valid_ = false;

  // The border of the removed region: edges from a removed vertex to a kept one. Each runs
  // from plane u to plane v (in the removed triangle's order); for a convex cut they form one
  // cycle through the planes the new face crosses.
  border_.clear();
  double new_face_radius2 = 0;
  Clip result = Clip::Cut;
  for (size_t r = 0; r < n_out && result == Clip::Cut; ++r) {
    const uint16_t t = slots_[r];
    for (int k = 0; k < 3; ++k) {
      const uint16_t o = tri_[t].adj[k];
      if (out_[o]) continue;
      const uint8_t u = tri_[t].p[(k + 1) % 3], v = tri_[t].p[(k + 2) % 3];
      int slot = 0;
      while (slot < 3 && tri_[o].adj[slot] != t) ++slot;
      if (slot == 3 || border_from_[u] != kNone) {
        result = Clip::Failed;  // not a simple cycle: only round-off on a non-convex cell does this
        break;
      }
      border_from_[u] = uint16_t(border_.size());
      // The new vertex on the edge from o (kept) to t (removed); a vertex on the plane is its
      // own crossing (snapping).
      Vec3 p = pos_[o];
      if (any_exact && (exact_[o] || exact_[t])) {
        // A tie decided exactly: the crossing strictly inside the edge, never at a vertex
        // (snapped points would be merged into a vertex of more seeds).
        const double den = sd_[o] - sd_[t];
        const double along = std::clamp(den < 0 ? sd_[o] / den : 0.5, 1e-9, 1 - 1e-9);
        p = p + along * (pos_[t] - pos_[o]);
      } else if (sd_[o] < -eps) {
        p = p + (sd_[o] / (sd_[o] - sd_[t])) * (pos_[t] - pos_[o]);
      }
      border_.push_back({u, v, uint8_t(slot), o, p});
      new_face_radius2 = std::max(new_face_radius2, norm2(p));
    }
  }
  const size_t nb = border_.size();
  if (result == Clip::Cut && (nb < 3 || nt + nb >= kNone)) result = Clip::Failed;
  // Every edge must continue from its end plane, and one walk must visit them all.
  if (result == Clip::Cut) {
    size_t b = 0, steps = 0;
    do {
      const uint16_t next = border_from_[border_[b].v];
      if (next == kNone) break;
      b = next;
      ++steps;
    } while (b != 0 && steps <= nb);
    if (b != 0 || steps != nb) result = Clip::Failed;
  }
  if (result != Clip::Cut) {
    for (const Border& e : border_) border_from_[e.u] = kNone;
    return result;
  }

  new_face_radius2_ = new_face_radius2;
  // New triangles (u, v, P) take the removed triangles' slots first.
  const uint8_t P = uint8_t(planes_.size());
  planes_.push_back({n, offset, generator});
  const size_t removed = n_out;
  slots_.resize(removed);
  for (size_t b = removed; b < nb; ++b) slots_.push_back(uint16_t(nt + b - removed));
  if (nb > removed) {
    tri_.resize(nt + nb - removed);
    pos_.resize(nt + nb - removed);
  }
  for (size_t b = 0; b < nb; ++b) {
    const Border& e = border_[b];
    const uint16_t id = slots_[b], next = slots_[border_from_[e.v]];
    Tri& t = tri_[id];
    t.p[0] = e.u;
    t.p[1] = e.v;
    t.p[2] = P;
    t.adj[0] = next;     // edge (v, P): shared with the next new triangle
    t.adj[2] = e.outer;  // edge (u, v): shared with the kept vertex
    tri_[next].adj[1] = id;  // the next triangle's edge (P, v') faces back here
    tri_[e.outer].adj[e.outer_slot] = id;
    pos_[id] = e.pos;
    // An edge of zero length (snapping) from the new vertex: to the kept one, or to the next new
    // one; the test merge_coincident() makes on every edge, written without branches (with
    // Vec3's == and ||, the cells took 5% longer).
    const Vec3 q = pos_[e.outer], r = border_[border_from_[e.v]].pos;
    coincident_ |= ((e.pos.x == q.x) & (e.pos.y == q.y) & (e.pos.z == q.z)) |
                   ((e.pos.x == r.x) & (e.pos.y == r.y) & (e.pos.z == r.z));
  }
  for (const Border& e : border_) border_from_[e.u] = kNone;

  // Fill the remaining holes with triangles from the end.
  if (removed > nb) {
    const size_t size = nt - (removed - nb);
    std::vector<uint8_t>& hole = out_;  // reuse: out_[t] now marks free slots
    for (size_t b = 0; b < nb; ++b) hole[slots_[b]] = 0;
    size_t h = 0;
    for (size_t m = size; m < nt; ++m) {
      if (hole[m]) continue;
      while (!hole[h]) ++h;
      tri_[h] = tri_[m];
      pos_[h] = pos_[m];
      for (int k = 0; k < 3; ++k) {
        Tri& a = tri_[tri_[h].adj[k]];
        for (int j = 0; j < 3; ++j)
          if (a.adj[j] == m) a.adj[j] = uint16_t(h);
      }
      hole[h] = 0;
    }
    tri_.resize(size);
    pos_.resize(size);
  }
  return Clip::Cut;
}

// Drops the planes no vertex lies on any more (cut away entirely) and renumbers the rest.
bool ConvexCell::compact_planes() {
  std::array<uint8_t, 256> used{}, id{};
  for (const Tri& t : tri_)
    for (uint8_t p : t.p) used[p] = 1;
  size_t kept = 0;
  for (size_t p = 0; p < planes_.size(); ++p) {
    if (!used[p]) continue;
    id[p] = uint8_t(kept);
    planes_[kept++] = planes_[p];
  }
  planes_.resize(kept);
  for (Tri& t : tri_)
    for (uint8_t& p : t.p) p = id[p];
  faces_valid_ = false;
  return kept < kMaxPlanes;
}

double ConvexCell::max_radius2() const {
  if (!rmax_valid_) {
    double m = 0;
    for (Vec3 v : pos_) m = std::max(m, norm2(v));
    rmax2_ = m;
    rmax_valid_ = true;
  }
  return rmax2_;
}

uint16_t ConvexCell::find(uint16_t t) const {
  while (parent_[t] != t) t = parent_[t] = parent_[parent_[t]];
  return t;
}

// Triangles at the same position (a snapped degenerate vertex) are one vertex: the union of
// the triangles joined by edges of zero length.
void ConvexCell::merge_coincident() const {
  Faces& f = faces_;
  const size_t nt = tri_.size();
  parent_.resize(nt);
  for (size_t t = 0; t < nt; ++t) parent_[t] = uint16_t(t);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      const uint16_t o = tri_[t].adj[k];
      if (o > t && pos_[o] == pos_[t]) {
        const uint16_t a = find(uint16_t(t)), b = find(o);
        if (a != b) parent_[std::max(a, b)] = std::min(a, b);
      }
    }
  f.points.clear();
  f.vertex_of_tri.assign(nt, kNone);
  for (size_t t = 0; t < nt; ++t) {
    const uint16_t root = find(uint16_t(t));
    if (f.vertex_of_tri[root] == kNone) {
      f.vertex_of_tri[root] = uint16_t(f.points.size());
      f.points.push_back(pos_[root]);
    }
    f.vertex_of_tri[t] = f.vertex_of_tri[root];
  }
}

void ConvexCell::build_faces() const {
  Faces& f = faces_;
  const size_t nt = tri_.size();
  if (!coincident_) {  // nearly every cell: no edge of zero length, every triangle its own vertex
    f.points.assign(pos_.begin(), pos_.end());
    f.vertex_of_tri.resize(nt);
    for (size_t t = 0; t < nt; ++t) f.vertex_of_tri[t] = uint16_t(t);
  } else {
    merge_coincident();
  }
  // Faces: the triangles around each plane, walked counter-clockwise seen from outside.
  plane_tri_.assign(planes_.size(), kNone);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
      if (plane_tri_[tri_[t].p[k]] == kNone) plane_tri_[tri_[t].p[k]] = uint16_t(t);
  f.face_gen.clear();
  f.face_start.assign(1, 0);
  f.face_vert.clear();
  for (size_t p = 0; p < planes_.size(); ++p) {
    const uint16_t start = plane_tri_[p];
    if (start == kNone) continue;
    const size_t begin = f.face_vert.size();
    uint16_t t = start;
    size_t steps = 0;
    do {
      const uint16_t v = f.vertex_of_tri[t];
      if (f.face_vert.size() == begin || f.face_vert.back() != v) f.face_vert.push_back(v);
      const Tri& at = tri_[t];
      const int s = (at.p[1] == p) + 2 * (at.p[2] == p);  // p's slot, found without a branch
      t = at.adj[s == 2 ? 0 : s + 1];  // across the edge (p[s+2], p[s]): the next vertex of the face
    } while (t != start && ++steps <= nt);
    if (f.face_vert.size() - begin > 1 && f.face_vert.back() == f.face_vert[begin]) f.face_vert.pop_back();
    if (f.face_vert.size() - begin < 3) {  // collapsed to an edge or a point by snapping
      f.face_vert.resize(begin);
      continue;
    }
    f.face_gen.push_back(planes_[p].gen);
    f.face_start.push_back(uint32_t(f.face_vert.size()));
  }
  faces_valid_ = true;
}

double ConvexCell::volume() const {
  const Faces& f = final();
  double v6 = 0;
  for (size_t k = 0; k < face_count(); ++k) {
    const uint16_t* fv = face_begin(k);
    Vec3 a = f.points[fv[0]];
    for (size_t i = 1; i + 1 < face_size(k); ++i) v6 += dot(a, cross(f.points[fv[i]], f.points[fv[i + 1]]));
  }
  return v6 / 6;
}

bool ConvexCell::vertex_names(std::vector<Names>& names) const {
  names.assign(vertex_count(), Names{});
  std::vector<std::pair<uint32_t, int32_t>> beyond;  // (vertex, generator) past a name's capacity
  for (size_t k = 0; k < face_count(); ++k)
    for (size_t i = 0; i < face_size(k); ++i) {
      Names& nm = names[face_begin(k)[i]];
      if (nm.n == kMaxGenerators) beyond.push_back({face_begin(k)[i], face_generator(k)});
      else nm.gen[nm.n++] = face_generator(k);
    }
  if (beyond.empty()) return true;
  // A vertex on more faces than a name holds: a domain vertex where many facet planes meet (a
  // cone's apex). Three planes through a point name it, so the name keeps every seed and the
  // smallest plane generators that fit; every cell there sees the same seeds and planes, so
  // every cell shortens the name the same way.
  std::sort(beyond.begin(), beyond.end());
  for (size_t a = 0; a < beyond.size();) {
    const uint32_t v = beyond[a].first;
    Names& nm = names[v];
    std::vector<int32_t> all(nm.gen, nm.gen + nm.n);
    for (; a < beyond.size() && beyond[a].first == v; ++a) all.push_back(beyond[a].second);
    std::vector<int32_t> seeds, planes;
    for (int32_t g : all) (g >= 0 ? seeds : planes).push_back(g);
    if (seeds.size() + 3 > size_t(kMaxGenerators)) return false;
    std::sort(planes.begin(), planes.end());
    planes.resize(size_t(kMaxGenerators) - seeds.size());
    nm.n = 0;
    for (int32_t g : seeds) nm.gen[nm.n++] = g;
    for (int32_t g : planes) nm.gen[nm.n++] = g;
  }
  return true;
}

}  // namespace froth
