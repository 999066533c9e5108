#include "common/face_scratch.hpp"
#include "convex/convex_split.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "common/face_plane.hpp"
#include "common/tolerances.hpp"
#include "common/union_find.hpp"
#include "froth/error.hpp"

namespace froth {
namespace {

// A face being split: its vertices (counter-clockwise from outside), its generator (another
// cell, or a domain plane) and its plane, exact where the generator gives it (the seeds'
// bisector, the domain facet, the cut), so that a face of a few rounding errors' size still has
// a sound plane.
struct Face {
  std::vector<int32_t> v;
  int32_t gen = 0;
  Plane plane;
  int32_t cap_to = -1;  // a cut's new face: the piece (of the attempt) on its other side
  int32_t from = -1;    // the cell's face it is (a part of), within an attempt
};
using Cell = std::vector<Face>;

// A polygon's best-fit plane (common/face_plane.hpp), from its first vertex so that a small face
// far from the origin keeps its digits.
FacePlane polygon_plane(const std::vector<int32_t>& v, const auto& at) {
  const Vec3 o = at(v.front());
  FacePlane p = best_fit_plane(v.size(), [&](size_t k) { return at(v[k]) - o; });
  p.centroid = p.centroid + o;
  return p;
}

double volume(const Cell& cell, const auto& at) {
  const Vec3 o = at(cell.front().v.front());
  double v6 = 0;
  for (const Face& f : cell) {
    Vec3 c{};
    for (int32_t p : f.v) c = c + (at(p) - o);
    c = (1.0 / double(f.v.size())) * c;
    for (size_t k = 0; k < f.v.size(); ++k) v6 += dot(c, cross(at(f.v[k]) - o, at(f.v[(k + 1) % f.v.size()]) - o));
  }
  return v6 / 6;
}

// A cell's thickness, 2 volume / surface area: a slab's thickness, a cube's third of its side.
double thickness(const Cell& cell, double volume, const auto& at) {
  double area = 0;
  for (const Face& f : cell) area += polygon_plane(f.v, at).area;
  return area > 0 ? 2 * volume / area : 0;
}

// A cut that would leave a piece thinner than this fraction of its cell is refused.
constexpr double kSliver = 1e-4;

std::vector<int32_t> sorted_vertices(const std::vector<int32_t>& v) {
  std::vector<int32_t> s = v;
  std::sort(s.begin(), s.end());
  return s;
}

class Splitter {
 public:
  Splitter(PolyMesh& m, const std::vector<Plane>& domain_planes, double r)
      : m_(m), domain_planes_(domain_planes), r_(r), tol_(tol::convex(r)), n0_(m.cell_count()),
        min_thickness_(1e-9 * r), min_volume_(1e-13 * r * r * r), twin_(single_twins(scratch_of(m).point_twins, m.points.size())) {
    if (!twin_.empty()) twin_.resize(m.points.size(), -1);
    double extent = 0;
    for (const Vec3& p : m.points) extent = std::max({extent, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    step_ = 1e-6 * (r + extent);
  }

  RunReport::ConvexSplit run() {
    RunReport::ConvexSplit stats;
    stats.requested = true;
    std::vector<uint8_t> nonconvex(n0_, 0);
#pragma omp parallel for schedule(dynamic, 256)
    for (size_t c = 0; c < n0_; ++c) nonconvex[c] = !violating_faces(original(int32_t(c))).empty();
    std::vector<int32_t> work;
    for (size_t c = 0; c < n0_; ++c)
      if (nonconvex[c]) work.push_back(int32_t(c));
    if (work.empty()) return stats;
    index_vertices(work);
    std::vector<int32_t> stack(work.rbegin(), work.rend());
    while (!stack.empty()) {
      const int32_t id = stack.back();
      stack.pop_back();
      const std::vector<int32_t> pieces = split_once(id);
      if (pieces.empty()) {
        const double beyond = worst_violation(cell(id));
        if (beyond > tol_) {
          ++stats.left_nonconvex;
          stats.left_violation = std::max(stats.left_violation, beyond / r_);
        }
        continue;
      }
      for (auto p = pieces.rbegin(); p != pieces.rend(); ++p) stack.push_back(*p);
    }
    rebuild(stats);
    return stats;
  }

 private:
  Vec3 point(int32_t id, const std::vector<Vec3>& fresh) const {
    return id >= 0 ? m_.points[size_t(id)] : fresh[size_t(-id - 1)];
  }

  Plane plane_of(size_t c, int64_t f) const {
    const int32_t g = m_.face_generator[size_t(f)];
    std::vector<int32_t> v(m_.face_vertices.begin() + m_.face_vertex_begin[f], m_.face_vertices.begin() + m_.face_vertex_begin[f + 1]);
    const auto at = [&](int32_t p) { return m_.points[size_t(p)]; };
    Plane exact;
    bool known = false;
    if (g >= 0 && m_.seeds[size_t(g)] != m_.seeds[c]) {
      const Vec3 d = m_.seeds[size_t(g)] - m_.seeds[c];
      exact.normal = (1.0 / norm(d)) * d;
      exact.offset = dot(exact.normal, 0.5 * (m_.seeds[size_t(g)] + m_.seeds[c]));
      known = true;
    } else if (g < 0 && m_.border_planes_known && size_t(generator_plane(g)) < domain_planes_.size()) {
      exact = domain_planes_[size_t(generator_plane(g))];
      known = true;
    }
    const FacePlane fit = polygon_plane(v, at);
    // A multi-region solid's interface face lies on its facet, whatever cell is across it (the
    // same seed's part in the other region, or a neighbour's): out of this cell.
    const int32_t facet = scratch_of(m_).face_interface_facet.empty() ? -1 : scratch_of(m_).face_interface_facet[size_t(f)];
    if (facet >= 0 && size_t(facet) < domain_planes_.size()) {
      exact = domain_planes_[size_t(facet)];
      if (dot(exact.normal, fit.normal) < 0) exact = {-1.0 * exact.normal, -exact.offset};
      known = true;
    }
    if (known) {  // graded or clipped faces may lie elsewhere: the exact plane only if it fits
      double off = 0;
      for (int32_t p : v) off = std::max(off, std::abs(exact.signed_distance(at(p))));
      if (off <= tol_) return exact;
    }
    return {fit.normal, dot(fit.normal, fit.centroid)};
  }

  Cell original(int32_t c) const {
    Cell cell;
    for (int64_t f = m_.cell_face_begin[size_t(c)]; f < m_.cell_face_begin[size_t(c) + 1]; ++f) {
      Face face;
      face.v.assign(m_.face_vertices.begin() + m_.face_vertex_begin[f], m_.face_vertices.begin() + m_.face_vertex_begin[f + 1]);
      face.gen = m_.face_generator[size_t(f)];
      face.plane = plane_of(size_t(c), f);
      cell.push_back(std::move(face));
    }
    return cell;
  }

  Cell& cell(int32_t id) {
    auto it = edited_.find(id);
    if (it == edited_.end()) it = edited_.emplace(id, original(id)).first;
    return it->second;
  }

  // The farthest any vertex of the cell lies beyond any of its face planes.
  double worst_violation(const Cell& cell) const {
    double worst = 0;
    for (const Face& f : cell)
      for (const Face& g : cell)
        for (int32_t p : g.v) worst = std::max(worst, f.plane.signed_distance(m_.points[size_t(p)]));
    return worst;
  }

  // The faces some vertex of the cell lies beyond by more than the tolerance, largest first.
  std::vector<Plane> violating_faces(const Cell& cell) const {
    std::vector<std::pair<double, Plane>> found;
    const auto at = [&](int32_t p) { return m_.points[size_t(p)]; };
    for (const Face& f : cell) {
      bool beyond = false;
      for (const Face& g : cell) {
        for (int32_t p : g.v) beyond = beyond || f.plane.signed_distance(at(p)) > tol_;
        if (beyond) break;
      }
      if (beyond) found.push_back({polygon_plane(f.v, at).area, f.plane});
    }
    std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<Plane> out;
    for (const auto& [area, plane] : found) out.push_back(plane);
    return out;
  }

  // Every cell through each vertex of the non-convex cells (the cells whose faces a cut's new
  // vertex on an edge must enter).
  void index_vertices(const std::vector<int32_t>& cells) {
    for (int32_t c : cells)
      for (int64_t k = m_.face_vertex_begin[m_.cell_face_begin[size_t(c)]]; k < m_.face_vertex_begin[m_.cell_face_begin[size_t(c) + 1]]; ++k) {
        incident_[m_.face_vertices[size_t(k)]];
        incident_[crack_twin(m_.face_vertices[size_t(k)])];  // a cut's point there has a twin across the crack
      }
    for (size_t c = 0; c < n0_; ++c)
      for (int64_t k = m_.face_vertex_begin[m_.cell_face_begin[c]]; k < m_.face_vertex_begin[m_.cell_face_begin[c + 1]]; ++k) {
        auto it = incident_.find(m_.face_vertices[size_t(k)]);
        if (it != incident_.end() && (it->second.empty() || it->second.back() != int32_t(c))) it->second.push_back(int32_t(c));
      }
  }

  struct Attempt {
    std::vector<Vec3> fresh;                          // new vertices, ids -1, -2, ...
    std::vector<std::pair<int32_t, int32_t>> edges;   // the edge each lies on
    std::vector<Cell> pieces;
    std::vector<std::vector<int32_t>> face_with_cuts;  // each face of the cell, the new vertices in it
    double thinnest = INFINITY;  // the thinnest piece's thickness over the cell's
  };

  // The cell cut by `cut` into pieces, or false where the cut is not clean.
  bool attempt(const Cell& cell, const Plane& cut, Attempt& a, bool slivers) const {
    const double snap = 0.5 * tol_;
    std::unordered_map<int32_t, double> s;
    bool plus = false, minus = false;
    for (const Face& f : cell)
      for (int32_t p : f.v) {
        const double d = cut.signed_distance(m_.points[size_t(p)]);
        s[p] = std::abs(d) <= snap ? 0.0 : d;
        plus = plus || d > snap, minus = minus || d < -snap;
      }
    if (!plus || !minus) return false;
    std::map<std::pair<int32_t, int32_t>, int32_t> on_edge;
    const auto sign = [&](int32_t p) { return p < 0 ? 0 : (s[p] > 0) - (s[p] < 0); };
    const auto at = [&](int32_t p) { return point(p, a.fresh); };
    std::vector<Face> side[2];  // [0]: below the plane, [1]: above
    for (size_t fi = 0; fi < cell.size(); ++fi) {
      const Face& f = cell[fi];
      std::vector<int32_t> poly;
      for (size_t k = 0; k < f.v.size(); ++k) {
        const int32_t p = f.v[k], q = f.v[(k + 1) % f.v.size()];
        poly.push_back(p);
        if (sign(p) * sign(q) >= 0) continue;
        const auto key = std::minmax(p, q);
        auto it = on_edge.find(key);
        if (it == on_edge.end()) {
          const Vec3 x = at(key.first), y = at(key.second);
          const double t = s[key.first] / (s[key.first] - s[key.second]);
          a.fresh.push_back(x + t * (y - x));
          a.edges.push_back(key);
          it = on_edge.emplace(key, -int32_t(a.fresh.size())).first;
        }
        poly.push_back(it->second);
      }
      a.face_with_cuts.push_back(poly);
      int runs = 0, nplus = 0, nminus = 0;
      for (size_t k = 0; k < poly.size(); ++k) {
        nplus += sign(poly[k]) > 0, nminus += sign(poly[k]) < 0;
        runs += sign(poly[k]) > 0 && sign(poly[(k + poly.size() - 1) % poly.size()]) <= 0;
      }
      Face whole = f;
      whole.v = poly;
      whole.from = int32_t(fi);
      if (nplus == 0 || nminus == 0) {
        const bool above = nplus > 0 || (nminus == 0 && dot(f.plane.normal, cut.normal) < 0);
        side[above].push_back(std::move(whole));
        continue;
      }
      if (runs != 1) return false;  // a non-convex face the plane crosses more than twice
      const size_t n = poly.size();
      size_t i = 0;
      while (!(sign(poly[i]) > 0 && sign(poly[(i + n - 1) % n]) <= 0)) ++i;
      size_t j = i;
      while (sign(poly[(j + 1) % n]) > 0) j = (j + 1) % n;
      Face hi = whole, lo = whole;
      hi.v.clear(), lo.v.clear();
      for (size_t k = (i + n - 1) % n;; k = (k + 1) % n) {
        hi.v.push_back(poly[k]);
        if (k == (j + 1) % n) break;
      }
      for (size_t k = (j + 1) % n;; k = (k + 1) % n) {
        lo.v.push_back(poly[k]);
        if (k == (i + n - 1) % n) break;
      }
      side[1].push_back(std::move(hi));
      side[0].push_back(std::move(lo));
    }
    // Each side's edges without their reverse bound the cut's new faces.
    std::vector<std::vector<int32_t>> caps[2];
    for (int k = 0; k < 2; ++k) {
      std::map<std::pair<int32_t, int32_t>, int> directed;
      for (const Face& f : side[k])
        for (size_t e = 0; e < f.v.size(); ++e) ++directed[{f.v[e], f.v[(e + 1) % f.v.size()]}];
      std::map<int32_t, int32_t> next;
      for (const auto& [e, count] : directed) {
        if (count != 1) return false;
        if (directed.count({e.second, e.first})) continue;
        if (sign(e.first) != 0 || sign(e.second) != 0 || !next.emplace(e.first, e.second).second) return false;
      }
      while (!next.empty()) {
        std::vector<int32_t> loop{next.begin()->first};
        for (int32_t p = next.begin()->second; p != loop.front(); p = next.at(p)) {
          if (!next.count(p) || loop.size() > next.size()) return false;
          loop.push_back(p);
        }
        for (int32_t p : loop) next.erase(p);
        std::reverse(loop.begin(), loop.end());  // the cap closes the side: its edges run the other way
        if (loop.size() < 3 || dot(polygon_plane(loop, at).normal, cut.normal) * (k == 0 ? 1 : -1) <= 0) return false;
        caps[k].push_back(std::move(loop));
      }
    }
    if (caps[0].size() != caps[1].size() || caps[0].empty() || nested(caps[0], cut, at)) return false;
    // Pieces: the connected parts of each side with its caps.
    std::vector<int32_t> cap_piece[2];
    for (int k = 0; k < 2; ++k) {
      for (const auto& loop : caps[k]) {
        Face cap;
        cap.v = loop;
        cap.plane = cut;
        if (k == 1) cap.plane.normal = -1.0 * cut.normal, cap.plane.offset = -cut.offset;
        side[k].push_back(std::move(cap));
      }
      UnionFind sets(side[k].size());
      std::map<std::pair<int32_t, int32_t>, int32_t> edge_face;
      for (size_t fi = 0; fi < side[k].size(); ++fi)
        for (size_t e = 0; e < side[k][fi].v.size(); ++e) {
          const auto key = std::minmax(side[k][fi].v[e], side[k][fi].v[(e + 1) % side[k][fi].v.size()]);
          auto [it, fresh] = edge_face.emplace(key, int32_t(fi));
          if (!fresh) sets.unite(it->second, int32_t(fi));
        }
      std::map<int32_t, size_t> piece_of_root;
      const size_t first_cap = side[k].size() - caps[k].size();
      for (size_t fi = 0; fi < side[k].size(); ++fi) {
        auto [it, fresh] = piece_of_root.emplace(sets.find(int32_t(fi)), a.pieces.size());
        if (fresh) a.pieces.emplace_back();
        a.pieces[it->second].push_back(side[k][fi]);
        if (fi >= first_cap) cap_piece[k].push_back(int32_t(it->second));
      }
    }
    // Each cap's twin is the other side's cap with the same vertices.
    for (size_t i = 0; i < caps[0].size(); ++i) {
      const std::vector<int32_t> key = sorted_vertices(caps[0][i]);
      size_t j = 0;
      while (j < caps[1].size() && sorted_vertices(caps[1][j]) != key) ++j;
      if (j == caps[1].size()) return false;
      for (Face& f : a.pieces[size_t(cap_piece[0][i])])
        if (f.from < 0 && f.cap_to < 0 && sorted_vertices(f.v) == key) f.cap_to = cap_piece[1][j];
      for (Face& f : a.pieces[size_t(cap_piece[1][j])])
        if (f.from < 0 && f.cap_to < 0 && sorted_vertices(f.v) == key) f.cap_to = cap_piece[0][i];
    }
    const auto at_all = [&](int32_t p) { return point(p, a.fresh); };
    // No sliver: a piece thinner than 1e-9 r, or smaller than 1e-13 r^3, is lost in the
    // round-off of its own volume (taken from the seed, up to 2 r away: 1e-15 r^3); one far
    // thinner than its cell is a cut past a step of the input's round-off (a float STL's
    // coplanar facets 1e-7 r apart), worse for a solver than the step it removes.
    const double whole = volume(cell, at_all);
    const double cell_thickness = thickness(cell, whole, at_all);
    double sum = 0;
    for (const Cell& piece : a.pieces) {
      const double v = volume(piece, at_all);
      if (!(v >= min_volume_) || !(thickness(piece, v, at_all) >= min_thickness_)) return false;
      a.thinnest = std::min(a.thinnest, thickness(piece, v, at_all) / cell_thickness);
      sum += v;
    }
    if (!slivers && a.thinnest < kSliver) return false;
    return std::abs(sum - whole) <= 1e-9 * std::abs(whole);
  }

  // Whether one cap loop lies inside another (the cut would leave a face with a hole).
  static bool nested(const std::vector<std::vector<int32_t>>& loops, const Plane& cut, const auto& at) {
    if (loops.size() < 2) return false;
    int drop = 0;
    for (int k = 1; k < 3; ++k)
      if (std::abs(cut.normal[k]) > std::abs(cut.normal[drop])) drop = k;
    const int u = (drop + 1) % 3, w = (drop + 2) % 3;
    const auto inside = [&](Vec3 p, const std::vector<int32_t>& loop) {
      bool in = false;
      for (size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
        const Vec3 a = at(loop[i]), b = at(loop[j]);
        if ((a[w] > p[w]) != (b[w] > p[w]) && p[u] < (b[u] - a[u]) * (p[w] - a[w]) / (b[w] - a[w]) + a[u]) in = !in;
      }
      return in;
    };
    for (size_t i = 0; i < loops.size(); ++i)
      for (size_t j = 0; j < loops.size(); ++j)
        if (i != j && inside(at(loops[i].front()), loops[j])) return true;
    return false;
  }

  // Cuts the cell once by the face plane that cuts it cleanly with the most room: the one whose
  // nearest vertex off it is farthest from it, so that no piece is a sliver where another plane
  // would do. Where every clean cut leaves a sliver, a cell non-convex by more than the input's
  // round-off is still cut, by the plane whose thinnest piece is thickest; one non-convex by
  // less (a step between facets meant to be coplanar) is left. The pieces' ids (the first keeps
  // the cell's), or none.
  std::vector<int32_t> split_once(int32_t id) {
    const Cell whole = cell(id);
    std::vector<std::pair<double, Plane>> ranked;
    for (const Plane& cut : violating_faces(whole)) {
      double clearance = INFINITY;
      for (const Face& f : whole)
        for (int32_t p : f.v) {
          const double d = std::abs(cut.signed_distance(m_.points[size_t(p)]));
          if (d > 0.5 * tol_) clearance = std::min(clearance, d);
        }
      ranked.push_back({clearance, cut});
    }
    std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (const auto& [clearance, cut] : ranked) {
      Attempt a;
      if (attempt(whole, cut, a, false)) return commit(id, whole, a);
    }
    if (worst_violation(whole) <= step_) return {};
    Attempt best;
    for (const auto& [clearance, cut] : ranked) {
      Attempt a;
      if (attempt(whole, cut, a, true) && (best.pieces.empty() || a.thinnest > best.thinnest)) best = std::move(a);
    }
    return best.pieces.empty() ? std::vector<int32_t>{} : commit(id, whole, best);
  }

  // A crack point's copy across the crack (the point itself on the front and off the cracks).
  int32_t crack_twin(int32_t p) const {
    return size_t(p) < twin_.size() && twin_[size_t(p)] >= 0 ? twin_[size_t(p)] : p;
  }

  // A cut's new point p on edge (u, w) of a crack face gets a twin on the twin edge across the
  // crack, entered into every face through that edge as p was into those through (u, w), so the
  // crack's two sides keep the same points (a point on the front is shared, as the front is).
  void add_crack_twin(int32_t p, int32_t u, int32_t w, int32_t id) {
    if (twin_.empty()) return;
    twin_.resize(m_.points.size(), -1);
    const int32_t tu = crack_twin(u), tw = crack_twin(w);
    if (tu == u && tw == w) return;
    const int32_t q = int32_t(m_.points.size());
    m_.points.push_back(m_.points[size_t(p)]);
    twin_.resize(m_.points.size(), -1);
    twin_[size_t(p)] = q, twin_[size_t(q)] = p;
    std::vector<int32_t>& around = incident_[q];
    for (int32_t y : incident_.at(tu)) {
      if (y == id) continue;  // (a cell on both sides of one sheet: none, the fronts' cells being cut)
      for (Face& f : cell(y))
        for (size_t e = 0; e < f.v.size(); ++e) {
          const int32_t x = f.v[e], z = f.v[(e + 1) % f.v.size()];
          if ((x == tu && z == tw) || (x == tw && z == tu)) {
            f.v.insert(f.v.begin() + std::ptrdiff_t(e + 1), q);
            if (around.empty() || around.back() != y) around.push_back(y);
            break;
          }
        }
    }
  }

  // Each crack face of the cell that the cut split has a twin across the crack, in another cell,
  // on the twin points: it is split the same way, each part kept by that cell (whose own
  // faces are unchanged otherwise), so the crack's faces still pair one to one.
  void split_crack_twins(int32_t id, const Cell& whole, const Attempt& a, int32_t base) {
    if (twin_.empty()) return;
    for (size_t fi = 0; fi < whole.size(); ++fi) {
      if (whole[fi].gen >= 0) continue;
      std::vector<const Face*> parts;
      for (const Cell& piece : a.pieces)
        for (const Face& f : piece)
          if (f.from == int32_t(fi)) parts.push_back(&f);
      if (parts.size() < 2) continue;
      std::vector<int32_t> across;
      bool crack = false;
      for (int32_t p : a.face_with_cuts[fi]) {
        const int32_t real = p >= 0 ? p : base + (-p - 1);
        across.push_back(crack_twin(real));
        crack = crack || across.back() != real;
      }
      if (!crack) continue;
      const std::vector<int32_t> key = sorted_vertices(across);
      for (int32_t y : incident_.at(across.front())) {
        if (y == id) continue;
        Cell& other = cell(y);
        size_t t = 0;
        while (t < other.size() && !(other[t].gen < 0 && sorted_vertices(other[t].v) == key)) ++t;
        if (t == other.size()) continue;
        const Face twin = other[t];
        other.erase(other.begin() + std::ptrdiff_t(t));
        for (const Face* f : parts) {
          Face half = twin;
          half.v.clear();
          for (auto p = f->v.rbegin(); p != f->v.rend(); ++p) half.v.push_back(crack_twin(*p));
          other.push_back(std::move(half));
        }
        break;
      }
    }
  }

  std::vector<int32_t> commit(int32_t id, const Cell& whole, Attempt& a) {
    // The new vertices enter every face through their edge, in every cell around it.
    const int32_t base = int32_t(m_.points.size());
    const auto real = [&](int32_t p) { return p >= 0 ? p : base + (-p - 1); };
    for (size_t k = 0; k < a.fresh.size(); ++k) {
      m_.points.push_back(a.fresh[k]);
      const auto [u, w] = a.edges[k];
      const int32_t p = base + int32_t(k);
      std::vector<int32_t>& around = incident_[p];
      for (int32_t y : incident_.at(u)) {
        if (y == id) continue;
        Cell& other = cell(y);
        bool has = false;
        for (Face& f : other)
          for (size_t e = 0; e < f.v.size(); ++e) {
            const int32_t x = f.v[e], z = f.v[(e + 1) % f.v.size()];
            if ((x == u && z == w) || (x == w && z == u)) {
              f.v.insert(f.v.begin() + std::ptrdiff_t(e + 1), p);
              has = true;
              break;
            }
          }
        if (has) around.push_back(y);
      }
    }
    for (size_t k = 0; k < a.fresh.size(); ++k) add_crack_twin(base + int32_t(k), a.edges[k].first, a.edges[k].second, id);
    std::vector<int32_t> ids{id};
    const int32_t origin = id < int32_t(n0_) ? id : int32_t(parent_[size_t(id) - n0_]);
    for (size_t k = 1; k < a.pieces.size(); ++k) {
      ids.push_back(int32_t(n0_ + parent_.size()));
      parent_.push_back(uint32_t(origin));
      children_[origin].push_back(ids.back());
    }
    for (Cell& piece : a.pieces)
      for (Face& f : piece) {
        for (int32_t& p : f.v) p = real(p);
        if (f.cap_to >= 0) f.gen = ids[size_t(f.cap_to)];
      }
    // The neighbours' twins: split where the cell's face was, pointed at the piece they face.
    for (size_t fi = 0; fi < whole.size(); ++fi) {
      const int32_t y = whole[fi].gen;
      if (y < 0) continue;
      std::vector<int32_t> mine = a.face_with_cuts[fi];
      for (int32_t& p : mine) p = real(p);
      const std::vector<int32_t> key = sorted_vertices(mine);
      Cell& other = cell(y);
      size_t t = 0;
      while (t < other.size() && !(other[t].gen == id && sorted_vertices(other[t].v) == key)) ++t;
      if (t == other.size())
        fail(ErrorKind::Internal, fmt::format("convex split: cell {}'s face toward cell {} has no twin there", id, y));
      const Face twin = other[t];
      other.erase(other.begin() + std::ptrdiff_t(t));
      for (size_t k = 0; k < a.pieces.size(); ++k)
        for (const Face& f : a.pieces[k])
          if (f.from == int32_t(fi)) {
            Face back = twin;
            back.v.assign(f.v.rbegin(), f.v.rend());
            back.gen = ids[k];
            other.push_back(std::move(back));
          }
    }
    split_crack_twins(id, whole, a, base);
    for (size_t k = 0; k < a.pieces.size(); ++k) {
      for (Face& f : a.pieces[k]) f.from = -1, f.cap_to = -1;
      if (k > 0)
        for (const Face& f : a.pieces[k])
          for (int32_t p : f.v) {
            std::vector<int32_t>& around = incident_[p];
            if (std::find(around.begin(), around.end(), ids[k]) == around.end()) around.push_back(ids[k]);
          }
      edited_[ids[k]] = std::move(a.pieces[k]);
    }
    for (size_t k = 0; k < a.fresh.size(); ++k) incident_[base + int32_t(k)].push_back(id);
    return ids;
  }

  void rebuild(RunReport::ConvexSplit& stats) {
    std::vector<int32_t> final_index(n0_ + parent_.size());
    std::vector<int32_t> order;
    for (size_t c = 0; c < n0_; ++c) {
      final_index[c] = int32_t(order.size());
      order.push_back(int32_t(c));
      auto it = children_.find(int32_t(c));
      if (it == children_.end()) continue;
      stats.cells_split += 1;
      stats.pieces += it->second.size() + 1;
      stats.max_pieces = std::max(stats.max_pieces, it->second.size() + 1);
      for (int32_t k : it->second) final_index[size_t(k)] = int32_t(order.size()), order.push_back(k);
    }
    PolyMesh out;
    out.points = std::move(m_.points);
    out.cell_face_begin = {0};
    out.face_vertex_begin = {0};
    const auto origin = [&](int32_t id) { return id < int32_t(n0_) ? size_t(id) : size_t(parent_[size_t(id) - n0_]); };
    double smallest = INFINITY;
    for (int32_t id : order) {
      const size_t c = origin(id);
      out.seeds.push_back(m_.seeds[c]);
      out.kinds.push_back(m_.kinds[c]);
      if (!m_.piece.empty()) out.piece.push_back(m_.piece[c]);
      if (!m_.radii.empty()) out.radii.push_back(m_.radii[c]);
      if (!m_.near_graded.empty()) out.near_graded.push_back(m_.near_graded[c]);
      if (!m_.region.empty()) out.region.push_back(m_.region[c]);
      out.parent.push_back(uint32_t(c));
      auto it = edited_.find(id);
      if (it == edited_.end()) {
        for (int64_t f = m_.cell_face_begin[c]; f < m_.cell_face_begin[c + 1]; ++f) {
          const int32_t g = m_.face_generator[size_t(f)];
          out.face_generator.push_back(g >= 0 ? final_index[size_t(g)] : g);
          out.face_vertices.insert(out.face_vertices.end(), m_.face_vertices.begin() + m_.face_vertex_begin[f],
                                   m_.face_vertices.begin() + m_.face_vertex_begin[f + 1]);
          out.face_vertex_begin.push_back(int64_t(out.face_vertices.size()));
        }
      } else {
        if (id >= int32_t(n0_) || children_.count(id))
          smallest = std::min(smallest, volume(it->second, [&](int32_t p) { return out.points[size_t(p)]; }));
        for (const Face& f : it->second) {
          out.face_generator.push_back(f.gen >= 0 ? final_index[size_t(f.gen)] : f.gen);
          out.face_vertices.insert(out.face_vertices.end(), f.v.begin(), f.v.end());
          out.face_vertex_begin.push_back(int64_t(out.face_vertices.size()));
        }
      }
      out.cell_face_begin.push_back(int64_t(out.face_generator.size()));
    }
    stats.smallest_piece_volume = std::isfinite(smallest) ? smallest / (r_ * r_ * r_) : 0;
    out.r = m_.r;
    out.random_seed = m_.random_seed;
    out.border_planes_known = m_.border_planes_known;
    out.patch_names = std::move(m_.patch_names);
    out.region_names = std::move(m_.region_names);
    m_ = std::move(out);
  }

  PolyMesh& m_;
  const std::vector<Plane>& domain_planes_;
  double r_, tol_;
  size_t n0_;
  double min_thickness_, min_volume_;  // 1e-9 r, 1e-13 r^3
  double step_;  // non-convexity up to this is the input's round-off: 1e-6 (r + the largest coordinate)
  std::unordered_map<int32_t, Cell> edited_;
  std::vector<uint32_t> parent_;  // of the cells made here (ids from n0_): the original cell
  std::unordered_map<int32_t, std::vector<int32_t>> children_;
  std::unordered_map<int32_t, std::vector<int32_t>> incident_;  // vertex -> cells through it
  // A cracked solid's point twins (FaceScratch::point_twins, one each: crossing cracks are not
  // split convex), grown with the cuts' points; empty without cracks.
  std::vector<int32_t> twin_;
  static std::vector<int32_t> single_twins(const PointTwins& twins, size_t points) {
    if (twins.empty()) return {};
    std::vector<int32_t> one(points, -1);
    for (size_t v = 0; v < points; ++v) {
      const auto of = twins.of(int32_t(v));
      if (of.size() > 1) fail(ErrorKind::Internal, "convex split: a point with twins across two cracks");
      if (!of.empty()) one[v] = of[0][1];
    }
    return one;
  }
};

}  // namespace

RunReport::ConvexSplit split_nonconvex_cells(PolyMesh& mesh, const std::vector<Plane>& domain_planes, double r) {
  return Splitter(mesh, domain_planes, r).run();
}

}  // namespace froth
