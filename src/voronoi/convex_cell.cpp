#include "voronoi/convex_cell.hpp"

#include <algorithm>

namespace froth {

void ConvexCell::reset_cube(double h) {
  verts_.clear();
  // Corner c has coordinates (±h) by bits of c; faces -x,+x,-y,+y,-z,+z are generators 0..5.
  for (int c = 0; c < 8; ++c) verts_.push_back({(c & 1) ? h : -h, (c & 2) ? h : -h, (c & 4) ? h : -h});
  static constexpr uint16_t faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  face_gen_.clear();
  face_start_.assign(1, 0);
  face_vert_.clear();
  for (int f = 0; f < 6; ++f) {
    face_gen_.push_back(kCubeGenerator + f);
    face_vert_.insert(face_vert_.end(), faces[f], faces[f] + 4);
    face_start_.push_back(uint32_t(face_vert_.size()));
  }
}

// a is the inner end point, b the outer one.
uint16_t ConvexCell::cut_vertex(uint16_t a, uint16_t b) {
  const uint16_t lo = std::min(a, b), hi = std::max(a, b);
  for (const CutEdge& c : cuts_)
    if (c.a == lo && c.b == hi) return c.v;
  // Interpolated from the inner end point; the memo gives both faces of the edge one vertex.
  const double t = dist_[a] / (dist_[a] - dist_[b]);
  const uint16_t id = uint16_t(verts_.size());
  verts_.push_back(verts_[a] + t * (verts_[b] - verts_[a]));
  cuts_.push_back({lo, hi, id});
  return id;
}

ConvexCell::Clip ConvexCell::clip(Vec3 n, double offset, int32_t generator, double eps) {
  const size_t nv = verts_.size();
  dist_.resize(nv);
  side_.resize(nv);
  bool any_out = false, any_in = false;
  for (size_t v = 0; v < nv; ++v) {
    double s = dot(n, verts_[v]) - offset;
    dist_[v] = s;
    Side sd = s > eps ? Out : (s < -eps ? In : On);
    side_[v] = sd;
    any_out |= sd == Out;
    any_in |= sd == In;
  }
  if (!any_out) return Clip::Unchanged;
  if (!any_in) return Clip::Empty;

  cuts_.clear();
  cap_.clear();
  new_gen_.clear();
  new_start_.assign(1, 0);
  new_vert_.clear();
  for (size_t f = 0; f < face_gen_.size(); ++f) {
    const uint32_t b = face_start_[f], e = face_start_[f + 1];
    bool out = false;
    for (uint32_t i = b; i < e; ++i) out |= side_[face_vert_[i]] == Out;
    if (!out) {
      new_vert_.insert(new_vert_.end(), face_vert_.begin() + b, face_vert_.begin() + e);
      new_gen_.push_back(face_gen_[f]);
      new_start_.push_back(uint32_t(new_vert_.size()));
      continue;
    }
    const size_t start = new_vert_.size();
    int exits = 0, entries = 0;
    uint16_t exit_v = 0, entry_v = 0;
    for (uint32_t i = b; i < e; ++i) {
      uint16_t u = face_vert_[i], w = face_vert_[i + 1 < e ? i + 1 : b];
      Side su = side_[u], sw = side_[w];
      if (su != Out) new_vert_.push_back(u);
      if (su != Out && sw == Out) {
        exit_v = su == On ? u : cut_vertex(u, w);
        if (su == In) new_vert_.push_back(exit_v);
        ++exits;
      } else if (su == Out && sw != Out) {
        entry_v = sw == On ? w : cut_vertex(w, u);
        if (sw == In) new_vert_.push_back(entry_v);
        ++entries;
      }
    }
    if (exits != entries || exits > 1) return Clip::Failed;  // only a non-convex face does this
    if (exits == 1 && exit_v != entry_v) cap_.push_back({entry_v, exit_v});
    if (new_vert_.size() - start >= 3) {
      new_gen_.push_back(face_gen_[f]);
      new_start_.push_back(uint32_t(new_vert_.size()));
    } else {
      new_vert_.resize(start);
    }
  }

  // The cap face on the cutting plane: it runs each clipped face's new edge backwards.
  if (cap_.size() < 3) return Clip::Failed;
  const size_t cap_start = new_vert_.size();
  uint16_t cur = cap_[0].from;
  for (size_t step = 0; step < cap_.size(); ++step) {
    new_vert_.push_back(cur);
    auto it = std::find_if(cap_.begin(), cap_.end(), [&](const CapEdge& c) { return c.from == cur; });
    if (it == cap_.end()) return Clip::Failed;
    cur = it->to;
  }
  if (cur != cap_[0].from) return Clip::Failed;
  (void)cap_start;
  new_gen_.push_back(generator);
  new_start_.push_back(uint32_t(new_vert_.size()));

  // Drop the vertices outside and renumber.
  remap_.assign(verts_.size(), -1);
  size_t kept = 0;
  for (size_t v = 0; v < verts_.size(); ++v) {
    if (v < nv && side_[v] == Out) continue;
    remap_[v] = int32_t(kept);
    verts_[kept++] = verts_[v];
  }
  verts_.resize(kept);
  for (uint16_t& v : new_vert_) v = uint16_t(remap_[v]);
  face_gen_.swap(new_gen_);
  face_start_.swap(new_start_);
  face_vert_.swap(new_vert_);
  if (verts_.size() > 0xFFFF) return Clip::Failed;
  return Clip::Cut;
}

double ConvexCell::max_radius2() const {
  double m = 0;
  for (Vec3 v : verts_) m = std::max(m, norm2(v));
  return m;
}

double ConvexCell::volume() const {
  double v6 = 0;
  for (size_t f = 0; f < face_count(); ++f) {
    const uint16_t* fv = face_begin(f);
    Vec3 a = verts_[fv[0]];
    for (size_t i = 1; i + 1 < face_size(f); ++i) v6 += dot(a, cross(verts_[fv[i]], verts_[fv[i + 1]]));
  }
  return v6 / 6;
}

bool ConvexCell::vertex_names(std::vector<Names>& names) const {
  names.assign(verts_.size(), Names{});
  for (size_t f = 0; f < face_count(); ++f)
    for (size_t k = 0; k < face_size(f); ++k) {
      Names& nm = names[face_begin(f)[k]];
      if (nm.n == kMaxGenerators) return false;
      nm.gen[nm.n++] = face_gen_[f];
    }
  return true;
}

}  // namespace froth
