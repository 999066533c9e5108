#include "clip/clip_cell.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <span>

#include <fmt/format.h>

#include "common/closed_edges.hpp"
#include "common/facet_planes.hpp"
#include "common/surface_locator.hpp"
#include "common/tolerances.hpp"
#include "common/union_find.hpp"

namespace froth {

SurfaceGenerators::SurfaceGenerators(const Domain& d) {
  const auto& T = d.surface.triangles;
  planes = int32_t(d.planes.size());
  std::map<std::pair<int32_t, int32_t>, int32_t> id;
  std::vector<int32_t> first_plane;  // of the first triangle met on each edge
  triangle_edges.resize(T.size());
  for (size_t t = 0; t < T.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = T[t][k], b = T[t][(k + 1) % 3];
      const auto [it, added] = id.try_emplace({std::min(a, b), std::max(a, b)}, int32_t(id.size()));
      triangle_edges[t][k] = it->second;
      if (added) first_plane.push_back(d.triangle_plane[t]), seam.push_back(0);
      else seam[size_t(it->second)] = first_plane[size_t(it->second)] == d.triangle_plane[t];
    }
  edges = int32_t(id.size());
}

SurfaceGenerators::SurfaceGenerators(const Domain& d, const std::vector<std::pair<int32_t, int32_t>>& all_edges) {
  const auto& T = d.surface.triangles;
  planes = int32_t(d.planes.size());
  edges = int32_t(all_edges.size());
  seam.assign(all_edges.size(), 0);
  std::vector<int32_t> first_plane(all_edges.size(), -1);
  triangle_edges.resize(T.size());
  for (size_t t = 0; t < T.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = T[t][k], b = T[t][(k + 1) % 3];
      const auto it = std::lower_bound(all_edges.begin(), all_edges.end(), std::pair{std::min(a, b), std::max(a, b)});
      const int32_t e = int32_t(it - all_edges.begin());
      triangle_edges[t][k] = e;
      if (first_plane[size_t(e)] < 0) first_plane[size_t(e)] = d.triangle_plane[t];
      else seam[size_t(e)] = first_plane[size_t(e)] == d.triangle_plane[t];
    }
}

namespace {

using Names = ConvexCell::Names;

Names key_of(std::initializer_list<int32_t> gens) {
  Names k;
  for (int32_t g : gens) k.gen[k.n++] = g;
  std::sort(k.gen, k.gen + k.n);
  return k;
}


// The unordered pair {a, b} as one key.
uint64_t generator_pair(int32_t a, int32_t b) {
  if (a > b) std::swap(a, b);
  return uint64_t(uint32_t(a)) << 32 | uint32_t(b);
}

// Generators of V's own faces: seeds and the bounding cube (input elements are other negatives).
bool is_cell_generator(int32_t g) { return g >= 0 || ConvexCell::is_cube_generator(g); }

struct PolyVertex {
  Vec3 p;
  Names key;
  int32_t out_label;  // the generator the edge to the next vertex lies on (input edge or cell face)
};

struct Edge {
  int32_t from, to;
  bool operator<(const Edge& o) const { return from != o.from ? from < o.from : to < o.to; }
};

// Newell vector area of a loop.
Vec3 loop_area(const std::vector<Vec3>& pts, std::span<const int32_t> loop) {
  Vec3 a{};
  for (size_t k = 0; k < loop.size(); ++k) a = a + cross(pts[loop[k]], pts[loop[(k + 1) % loop.size()]]);
  return 0.5 * a;
}

// Closed loops of point ids, flat: loop k is ids[begin[k] .. begin[k + 1]).
struct Loops {
  std::vector<int32_t> ids;
  std::vector<uint32_t> begin{0};
  size_t size() const { return begin.size() - 1; }
  std::span<const int32_t> operator[](size_t k) const { return {ids.data() + begin[k], begin[k + 1] - begin[k]}; }
  void clear() { ids.clear(), begin.assign(1, 0); }
};

using Point2 = std::pair<double, double>;

// In-plane coordinates of p for a plane with unit normal n.
Point2 in_plane(Vec3 p, Vec3 n) {
  const Vec3 u = std::abs(n.x) < 0.6 ? Vec3{0, -n.z, n.y} : Vec3{-n.y, n.x, 0};
  const Vec3 uu = (1 / norm(u)) * u, vv = cross(n, uu);
  return {dot(p, uu), dot(p, vv)};
}

// Chains directed edges at a point where a face's region touches itself (a pinch: the point has
// several edges leaving it), in a plane of unit normal n. The region lies left of its edges, so
// at a pinch the loop that arrived along one of the region's wedges leaves along the other side
// of that wedge: the leaving edge first met turning clockwise from the way back. Loops then
// touch at the pinch instead of crossing there, and the same loops come out for either normal.
bool chain_pinched_loops(const std::vector<Edge>& edges, const std::vector<Vec3>& pts, Vec3 n, Loops& loops) {
  loops.clear();
  std::vector<size_t> order(edges.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return edges[a].from < edges[b].from; });
  auto leaving = [&](int32_t p) {
    auto lo = std::lower_bound(order.begin(), order.end(), p, [&](size_t e, int32_t q) { return edges[e].from < q; });
    auto hi = lo;
    while (hi != order.end() && edges[*hi].from == p) ++hi;
    return std::pair{lo, hi};
  };
  auto angle = [&](int32_t from, int32_t to) {
    const auto [ax, ay] = in_plane(pts[from], n);
    const auto [bx, by] = in_plane(pts[to], n);
    return std::atan2(by - ay, bx - ax);
  };
  std::vector<uint8_t> used(edges.size(), 0);
  for (size_t start = 0; start < edges.size(); ++start) {
    if (used[start]) continue;
    size_t e = start;
    while (!used[e]) {
      used[e] = 1;
      loops.ids.push_back(edges[e].from);
      const int32_t p = edges[e].to;
      const double back = angle(p, edges[e].from);
      size_t next = edges.size();
      double best = INFINITY;
      const auto [lo, hi] = leaving(p);
      for (auto it = lo; it != hi; ++it) {
        if (used[*it] && *it != start) continue;
        double turn = back - angle(p, edges[*it].to);  // clockwise from the way back, in (0, 2 pi]
        while (turn <= 0) turn += 2 * M_PI;
        while (turn > 2 * M_PI) turn -= 2 * M_PI;
        if (turn < best) best = turn, next = *it;
      }
      if (next == edges.size()) return false;
      if (next == start) break;
      e = next;
    }
    if (edges[e].to != edges[start].from) return false;
    loops.begin.push_back(uint32_t(loops.ids.size()));
  }
  return true;
}

// Chains directed edges between points 0 .. points-1 into closed loops (each starting at the
// first of its edges in `edges`); false if a chain does not close. `leaving` (the edge leaving
// each point, -1 if none: all -1 between calls) and `used` are scratch. A point with several
// edges leaving it (a pinch) is chained by chain_pinched_loops in the plane of normal n.
bool chain_loops(const std::vector<Edge>& edges, size_t points, Loops& loops, std::vector<int32_t>& leaving,
                 std::vector<uint8_t>& used, const std::vector<Vec3>& pts, Vec3 n) {
  loops.clear();
  if (leaving.size() < points) leaving.resize(points, -1);
  bool pinched = false;
  size_t set = 0;
  for (; set < edges.size(); ++set) {
    if (leaving[edges[set].from] >= 0) {
      pinched = true;
      break;
    }
    leaving[edges[set].from] = int32_t(set);
  }
  bool ok = !pinched;
  used.assign(edges.size(), 0);
  for (size_t k = 0; ok && k < edges.size(); ++k) {
    const int32_t start = edges[k].from;
    int32_t i = leaving[start];
    if (used[i]) continue;
    int32_t p = start;
    while (i >= 0 && !used[i]) {
      used[i] = 1;
      loops.ids.push_back(p);
      p = edges[i].to;
      i = leaving[p];
    }
    if (i < 0 || p != start) ok = false;
    else loops.begin.push_back(uint32_t(loops.ids.size()));
  }
  for (size_t k = 0; k < set; ++k) leaving[edges[k].from] = -1;
  return pinched ? chain_pinched_loops(edges, pts, n, loops) : ok;
}

// Is p inside the polygon `loop` (counter-clockwise about n)? Even-odd rule in the plane.
bool encloses(const std::vector<Vec3>& pts, const std::vector<int32_t>& loop, Vec3 p, Vec3 n) {
  const auto [px, py] = in_plane(p, n);
  bool in = false;
  for (size_t k = 0; k < loop.size(); ++k) {
    const auto [ax, ay] = in_plane(pts[loop[k]], n);
    const auto [bx, by] = in_plane(pts[loop[(k + 1) % loop.size()]], n);
    if ((ay > py) != (by > py) && px < ax + (py - ay) / (by - ay) * (bx - ax)) in = !in;
  }
  return in;
}

}  // namespace

// Everything clip() builds, kept from cell to cell: a clipped cell would otherwise allocate a
// few dozen small vectors (the tube's cells stage took a fifth longer).
struct CellClipper::Scratch {
  std::vector<int32_t> tris;
  std::vector<Plane> plane;
  std::vector<Vec3> pts;
  std::vector<Names> keys;
  std::vector<int32_t> table;
  std::vector<std::vector<Edge>> on_face;
  std::vector<std::pair<uint64_t, int32_t>> crossings;
  std::vector<std::pair<int32_t, Edge>> border;
  std::vector<PolyVertex> poly, next;
  std::vector<Names> vnames;
  struct VEdge {
    int32_t u, w;
    uint32_t cross_begin, cross_end;  // into crossings
    size_t count() const { return cross_end - cross_begin; }
  };
  std::vector<VEdge> edges;
  std::vector<uint32_t> edge_begin, out_begin, fill;
  std::vector<std::pair<int32_t, int32_t>> out_edge;
  std::vector<int8_t> status;
  std::vector<int32_t> along, used_map;
  Loops faces, loops;
  std::vector<Edge> segs, plane_edges, kept;
  std::vector<uint64_t> all;  // directed_edge_key of each face edge
  std::vector<int32_t> chain_leaving;
  std::vector<uint8_t> chain_used;
  UnionFind parts{0};
};

CellClipper::CellClipper(const Domain& domain, const SurfaceGenerators& gens, const TriangleGrid& triangles)
    : domain_(domain), gens_(gens), triangles_(triangles), s_(std::make_unique<Scratch>()) {}
CellClipper::~CellClipper() = default;

CellClipper::Result CellClipper::clip(int32_t seed, Vec3 x, Vec3 anchor, const ConvexCell& cell, double half,
                                      const std::vector<Vec3>& seeds, ClippedCell& out, int32_t& facet_cut,
                                      std::string& error, bool anchor_inside) {
  const SurfaceLocator& locator = *domain_.locator;
  const TriangleSurface& S = domain_.surface;
  const size_t nv = cell.vertex_count(), nf = cell.face_count();
  Vec3 lo = cell.vertex(0), hi = lo;
  for (size_t v = 0; v < nv; ++v)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], cell.vertex(v)[a]), hi[a] = std::max(hi[a], cell.vertex(v)[a]);
  Scratch& w = *s_;
  std::vector<int32_t>& tris = w.tris;
  triangles_.triangles_near(x + lo, x + hi, tris);
  const Result whole = anchor_inside ? Result::Inside : Result::Outside;  // V, which holds the anchor
  if (tris.empty()) return whole;

  // Every triangle that meets the cell's box lies in one facet plane (half the tube's border
  // cells): then V ∩ D is V below the plane (common/facet_planes.hpp). A protection seed lies on
  // the surface, next to a reflex edge: never here.
  if (const int32_t facet = facet_plane_of(domain_, tris); anchor == Vec3{} && facet >= 0) {
    const Plane& P = domain_.planes[facet];
    const double offset = P.offset - dot(P.normal, x), margin = tol::clear_of_facet(half, domain_.bounds.diagonal());
    bool clear = true, any_above = false, any_below = false;
    for (size_t v = 0; v < nv; ++v) {
      const double s = dot(P.normal, cell.vertex(v)) - offset;
      clear &= std::abs(s) > margin;
      any_above |= s > 0;
      any_below |= s < 0;
    }
    if (clear) {
      facet_cut = facet;
      return !any_below ? Result::Outside : any_above ? Result::HalfSpace : Result::Inside;
    }
  }

  // The planes of V's faces, computed exactly as the cell builder cut them.
  static const Vec3 cube_normals[6] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
  std::vector<Plane>& plane = w.plane;
  plane.resize(nf);
  for (size_t f = 0; f < nf; ++f) {
    const int32_t g = cell.face_generator(f);
    if (ConvexCell::is_cube_generator(g)) {
      plane[f] = {cube_normals[g - ConvexCell::kCubeGenerator], half};
    } else {
      const double d = std::sqrt(norm2(seeds[g] - x));
      plane[f] = {(1 / d) * (seeds[g] - x), d / 2};
    }
  }
  auto fail_with = [&](std::string text, Result result = Result::Clipped) {
    error = fmt::format("cell {} at ({}, {}, {}): {}", seed, x.x, x.y, x.z, text);
    return result;
  };

  // Every point met, by name: an open-addressing table of indices into pts/keys, grown at
  // half full.
  std::vector<Vec3>& pts = w.pts;
  std::vector<Names>& keys = w.keys;
  std::vector<int32_t>& table = w.table;
  pts.clear(), keys.clear(), table.assign(256, -1);
  auto slot_of = [&](const Names& k) {
    size_t s = size_t(k.hash() >> 32) & (table.size() - 1);
    while (table[s] >= 0 && !keys[table[s]].same_as(k)) s = (s + 1) & (table.size() - 1);
    return s;
  };
  auto intern = [&](const Names& k, Vec3 p) {
    size_t s = slot_of(k);
    if (table[s] >= 0) return table[s];
    pts.push_back(p), keys.push_back(k);
    if (2 * pts.size() > table.size()) {
      table.assign(2 * table.size(), -1);
      for (size_t q = 0; q < keys.size(); ++q) table[slot_of(keys[q])] = int32_t(q);
    } else {
      table[s] = int32_t(pts.size() - 1);
    }
    return int32_t(pts.size() - 1);
  };

  // 1. Each nearby triangle clipped by V (Sutherland-Hodgman), its points named as they arise.
  auto& on_face = w.on_face;  // cross-section edges per V face
  if (on_face.size() < nf) on_face.resize(nf);
  for (size_t f = 0; f < nf; ++f) on_face[f].clear();
  auto& crossings = w.crossings;  // (V edge's generator pair, point), sorted after step 1
  auto& border = w.border;        // piece edges, by facet plane
  auto& poly = w.poly;
  auto& next = w.next;
  crossings.clear(), border.clear();
  for (int32_t t : tris) {
    const auto& tri = S.triangles[t];
    const int32_t facet = gens_.plane(domain_.triangle_plane[t]);
    poly.clear();
    for (int k = 0; k < 3; ++k)
      poly.push_back({S.vertices[tri[k]] - x, key_of({gens_.vertex(tri[k])}), gens_.edge(gens_.triangle_edges[t][k])});
    for (size_t f = 0; f < nf && !poly.empty(); ++f) {
      const Plane& pl = plane[f];
      const int32_t g = cell.face_generator(f);
      // The bounding cube is met only by a piece of V ∩ D beyond r of the seed, where seeds
      // farther than 2r may cut V (assembly/cell_builder.cpp); checked after the loop.
      if (ConvexCell::is_cube_generator(g)) continue;
      bool any_out = false, any_in = false;
      double s[64];
      if (poly.size() > 64) return fail_with("a clipped triangle has more than 64 vertices");
      for (size_t k = 0; k < poly.size(); ++k) {
        s[k] = pl.signed_distance(poly[k].p);
        if (s[k] == 0)  // an exact tie: protection seeds are jittered so that these do not occur
          return fail_with(fmt::format("input triangle {} touches the face on generator {} exactly (degenerate)", t, g));
        (s[k] > 0 ? any_out : any_in) = true;
      }
      if (!any_out) continue;
      if (!any_in) { poly.clear(); break; }
      next.clear();
      for (size_t k = 0; k < poly.size(); ++k) {
        const PolyVertex& a = poly[k];
        const PolyVertex& b = poly[(k + 1) % poly.size()];
        const double sa = s[k], sb = s[(k + 1) % poly.size()];
        if (sa < 0) next.push_back(a);
        if ((sa < 0) != (sb < 0)) {
          const Vec3 p = a.p + (sa / (sa - sb)) * (b.p - a.p);
          const int32_t line = a.out_label;
          Names k2 = is_cell_generator(line) ? key_of({line, g, facet}) : key_of({line, g});
          next.push_back({p, k2, sa < 0 ? g : line});
        }
      }
      poly.swap(next);
    }
    if (poly.size() < 3) continue;
    for (size_t f = 0; f < nf; ++f)
      if (ConvexCell::is_cube_generator(cell.face_generator(f)))
        for (const PolyVertex& v : poly)
          if (plane[f].signed_distance(v.p) >= 0) return Result::ReachesCube;
    int32_t idx[64];
    for (size_t k = 0; k < poly.size(); ++k) idx[k] = intern(poly[k].key, poly[k].p);
    for (size_t k = 0; k < poly.size(); ++k) {
      const int32_t u = idx[k], v = idx[(k + 1) % poly.size()], label = poly[k].out_label;
      border.push_back({facet, {u, v}});
      if (is_cell_generator(label)) {
        size_t f = 0;
        while (cell.face_generator(f) != label) ++f;  // V has a face on every label it cut with
        on_face[f].push_back({v, u});
      }
      // A point on two of V's faces is where V's edge between them crosses the triangle.
      const Names& kk = poly[k].key;
      int32_t on[3], m = 0;
      for (int q = 0; q < kk.n; ++q)
        if (is_cell_generator(kk.gen[q])) on[m++] = kk.gen[q];
      if (m == 2) crossings.push_back({generator_pair(on[0], on[1]), u});
    }
  }

  // No piece of the surface lies in V: V is whole, on the anchor's side of D's surface.
  if (border.empty()) return whole;

  // 2. Which of V's vertices are inside: parity from the anchor to one, then along V's edges,
  // toggling at each crossing.
  std::vector<Names>& vnames = w.vnames;
  cell.vertex_names(vnames);
  for (Names& k : vnames) std::sort(k.gen, k.gen + k.n);
  // V's directed edges face by face (edge k of face f is edges[edge_begin[f] + k]), each with
  // the surface crossings on it: those named by the generators of its two faces.
  std::sort(crossings.begin(), crossings.end());
  auto& edges = w.edges;
  auto& edge_begin = w.edge_begin;
  edges.clear(), edge_begin.assign(nf + 1, 0);
  // The directed edges leaving each vertex (three, generically), with their faces.
  auto& out_begin = w.out_begin;
  out_begin.assign(nv + 1, 0);
  for (size_t f = 0; f < nf; ++f)
    for (size_t k = 0; k < cell.face_size(f); ++k) ++out_begin[cell.face_begin(f)[k] + 1];
  for (size_t v = 0; v < nv; ++v) out_begin[v + 1] += out_begin[v];
  auto& out_edge = w.out_edge;  // (to, face)
  out_edge.resize(out_begin[nv]);
  {
    auto& fill = w.fill;
    fill.assign(out_begin.begin(), out_begin.end() - 1);
    for (size_t f = 0; f < nf; ++f) {
      const uint16_t* fv = cell.face_begin(f);
      const size_t n = cell.face_size(f);
      for (size_t k = 0; k < n; ++k) out_edge[fill[fv[k]]++] = {fv[(k + 1) % n], int32_t(f)};
    }
  }
  for (size_t f = 0; f < nf; ++f) {
    const uint16_t* fv = cell.face_begin(f);
    const size_t n = cell.face_size(f);
    for (size_t k = 0; k < n; ++k) {
      const int32_t u = fv[k], v = fv[(k + 1) % n];
      int32_t twin = -1;  // the face on the other side: the one with the edge v -> u
      for (uint32_t o = out_begin[v]; o < out_begin[v + 1]; ++o)
        if (out_edge[o].first == u) twin = out_edge[o].second;
      if (twin < 0) return fail_with("the Voronoi cell's faces do not close");
      const uint64_t key = generator_pair(cell.face_generator(f), cell.face_generator(size_t(twin)));
      const auto lo = std::lower_bound(crossings.begin(), crossings.end(), std::pair<uint64_t, int32_t>{key, INT32_MIN});
      auto hi = lo;
      while (hi != crossings.end() && hi->first == key) ++hi;
      edges.push_back({u, v, uint32_t(lo - crossings.begin()), uint32_t(hi - crossings.begin())});
    }
    edge_begin[f + 1] = uint32_t(edges.size());
  }
  std::vector<int8_t>& status = w.status;
  status.assign(nv, -1);
  for (size_t v = 0; v < nv; ++v) {
    bool in;
    if (locator.side_from(x + anchor, anchor_inside, x + cell.vertex(v), tris, in)) {
      status[v] = in;
      break;
    }
  }
  if (std::all_of(status.begin(), status.end(), [](int8_t s) { return s < 0; }))
    return fail_with("every segment from the seed to a cell vertex grazes the surface (degenerate)");
  for (bool changed = true; changed;) {
    changed = false;
    for (const Scratch::VEdge& e : edges) {
      if (status[e.u] < 0 || status[e.w] >= 0) continue;
      status[e.w] = int8_t(status[e.u] ^ (e.count() & 1));
      changed = true;
    }
  }
  for (const Scratch::VEdge& e : edges)
    if (status[e.w] != (status[e.u] ^ int8_t(e.count() & 1)))
      return fail_with("the surface crossings along the cell's edges are inconsistent (near-degenerate input)");

  // 3. Each face of V cut to its part inside D: its inside edge pieces and the cross-section.
  std::vector<int32_t>& face_gen = out.face_gen_;  // built in place: `out` is only read on success
  Loops& faces = w.faces;
  Loops& loops = w.loops;
  face_gen.clear(), faces.clear();
  // Adds the loops of one plane (normal n) as faces on generator g. A loop turning clockwise
  // about n is a hole in another: a polygon with a hole is no VTK face, so the face is kept as
  // its outer loop followed by its holes (face_loop_ 1, then 2 each), which the assembly
  // triangulates from the global points (assembly/holed_faces), the same way in both cells.
  std::vector<uint8_t>& face_loop = out.face_loop_;
  face_loop.clear();
  auto add_faces_with_holes = [&](const Loops& plane_loops, Vec3 n, int32_t g) {
    auto add = [&](std::span<const int32_t> loop, uint8_t kind) {
      face_gen.push_back(g);
      face_loop.push_back(kind);
      faces.ids.insert(faces.ids.end(), loop.begin(), loop.end());
      faces.begin.push_back(uint32_t(faces.ids.size()));
    };
    // A loop turning clockwise by more than round-off. One of (nearly) no area, its points
    // (nearly) one, where a face passes exactly through a domain vertex, is a face like any
    // other: welding removes it.
    auto is_hole = [&](std::span<const int32_t> loop) {
      double perimeter = 0;
      for (size_t k = 0; k < loop.size(); ++k) perimeter += norm(pts[loop[(k + 1) % loop.size()]] - pts[loop[k]]);
      return dot(loop_area(pts, loop), n) < -1e-12 * perimeter * perimeter;
    };
    bool any_hole = false;
    for (size_t k = 0; k < plane_loops.size(); ++k) any_hole |= is_hole(plane_loops[k]);
    if (!any_hole) {  // the usual case
      for (size_t k = 0; k < plane_loops.size(); ++k) add(plane_loops[k], 0);
      return true;
    }
    std::vector<std::vector<int32_t>> outer, holes;
    for (size_t k = 0; k < plane_loops.size(); ++k) {
      const auto loop = plane_loops[k];
      (is_hole(loop) ? holes : outer).emplace_back(loop.begin(), loop.end());
    }
    // Each hole in the smallest outer loop around it (outer loops of one plane do not cross).
    // Loops may touch at a vertex (pinched faces), so the hole is located by a point just off
    // its longest edge on the face's side (the left, as for every boundary loop), not by a
    // vertex, which may lie on the outer loop itself.
    // A clockwise sliver around no outer loop, far below the cell's size, comes of crossings
    // that nearly coincide at a domain vertex (the hinge at r = diag/2: a 1e-6 triangle): it is
    // kept as a face of its own, which welding removes.
    std::vector<std::vector<size_t>> holes_of(outer.size());
    std::vector<size_t> stray;
    for (size_t h = 0; h < holes.size(); ++h) {
      const std::vector<int32_t>& hole = holes[h];
      size_t longest = 0;
      for (size_t k = 1; k < hole.size(); ++k)
        if (norm2(pts[hole[(k + 1) % hole.size()]] - pts[hole[k]]) >
            norm2(pts[hole[(longest + 1) % hole.size()]] - pts[hole[longest]]))
          longest = k;
      const Vec3 a = pts[hole[longest]], b = pts[hole[(longest + 1) % hole.size()]];
      const Vec3 probe = 0.5 * (a + b) + 1e-6 * cross(n, b - a);
      size_t host = outer.size();
      double host_area = INFINITY;
      for (size_t o = 0; o < outer.size(); ++o) {
        const double area = dot(loop_area(pts, outer[o]), n);
        if (area < host_area && encloses(pts, outer[o], probe, n)) host = o, host_area = area;
      }
      if (host < outer.size()) {
        holes_of[host].push_back(h);
      } else if (std::abs(dot(loop_area(pts, hole), n)) < tol::negligible_loop_area(half)) {
        stray.push_back(h);
      } else {
        return false;
      }
    }
    for (size_t o = 0; o < outer.size(); ++o) {
      add(outer[o], holes_of[o].empty() ? 0 : 1);
      for (size_t h : holes_of[o]) add(holes[h], 2);
    }
    for (size_t h : stray) add(holes[h], 0);
    return true;
  };
  // Where a seam crosses a face of V the loops only pass straight on: such a point is dropped
  // (a cell cut by one facet plane the quick way has none, and its neighbours must agree with
  // it).
  auto drop_seam_points = [&](Loops& ls) {
    size_t to = 0, from = 0;
    for (size_t k = 0; k < ls.size(); ++k) {
      for (; from < ls.begin[k + 1]; ++from) {
        const Names& name = keys[ls.ids[from]];
        if (!(name.n == 2 && (gens_.is_seam(name.gen[0]) || gens_.is_seam(name.gen[1])))) ls.ids[to++] = ls.ids[from];
      }
      ls.begin[k + 1] = uint32_t(to);
    }
    ls.ids.resize(to);
  };
  std::vector<int32_t>& along = w.along;
  std::vector<Edge>& segs = w.segs;
  for (size_t f = 0; f < nf; ++f) {
    const int32_t g = cell.face_generator(f);
    segs.assign(on_face[f].begin(), on_face[f].end());
    for (uint32_t e = edge_begin[f]; e < edge_begin[f + 1]; ++e) {
      const int32_t u = edges[e].u, v = edges[e].w;
      const Vec3 pu = cell.vertex(u), dir = cell.vertex(v) - pu;
      along.clear();
      for (uint32_t c = edges[e].cross_begin; c < edges[e].cross_end; ++c) along.push_back(crossings[c].second);
      std::sort(along.begin(), along.end(),
                [&](int32_t a, int32_t b) { return dot(pts[a] - pu, dir) < dot(pts[b] - pu, dir); });
      bool in = status[u];
      int32_t cur = in ? intern(vnames[u], pu) : -1;
      for (int32_t q : along) {
        if (in) segs.push_back({cur, q});
        cur = q;
        in = !in;
      }
      if (in) segs.push_back({cur, intern(vnames[v], cell.vertex(v))});
    }
    if (segs.empty()) continue;
    if (ConvexCell::is_cube_generator(g)) return Result::ReachesCube;
    if (!chain_loops(segs, pts.size(), loops, w.chain_leaving, w.chain_used, pts, plane[f].normal))
      return fail_with(fmt::format("the face on generator {} does not close", g));
    drop_seam_points(loops);
    // A hole: the surface passes through the face (a hole or pillar of the domain narrower than
    // r). The neighbour's twin face has the same loops reversed and makes the same cut (its
    // in-plane frame is this one mirrored), so the faces still match.
    if (!add_faces_with_holes(loops, plane[f].normal, g))
      return fail_with(fmt::format("the face on generator {} has a hole inside none of its loops", g));
  }

  // 4. Border faces: the triangle pieces of each facet plane merged (shared edges cancel).
  std::sort(border.begin(), border.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : a.second < b.second;
  });
  std::vector<Edge>& plane_edges = w.plane_edges;
  std::vector<Edge>& kept = w.kept;
  for (size_t at = 0; at < border.size();) {
    const int32_t facet = border[at].first;
    plane_edges.clear();
    for (; at < border.size() && border[at].first == facet; ++at) plane_edges.push_back(border[at].second);
    kept.clear();
    for (const Edge& e : plane_edges)
      if (!std::binary_search(plane_edges.begin(), plane_edges.end(), Edge{e.to, e.from})) kept.push_back(e);
    if (kept.empty()) continue;
    if (!chain_loops(kept, pts.size(), loops, w.chain_leaving, w.chain_used, pts, domain_.planes[-facet - 1].normal))
      return fail_with(fmt::format("the border face on facet plane {} does not close", -facet - 1));
    drop_seam_points(loops);
    if (!add_faces_with_holes(loops, domain_.planes[-facet - 1].normal, facet))
      return fail_with(fmt::format("the border face on facet plane {} has a hole inside none of its loops", -facet - 1));
  }

  // 5. The result must be one closed surface: every edge used once each way, all connected.
  std::vector<uint64_t>& all = w.all;
  all.clear();
  for (size_t f = 0; f < faces.size(); ++f) {
    const auto face = faces[f];
    for (size_t k = 0; k < face.size(); ++k)
      all.push_back(directed_edge_key(uint32_t(face[k]), uint32_t(face[(k + 1) % face.size()])));
  }
  if (!each_edge_once_each_way(all)) return fail_with("the clipped cell is not closed");
  // V ∩ D may fall in several pieces (a wall thinner than the cell, seen from both sides): each
  // becomes a cell of its own after assembly (tessellation's split_pieces), so only count them.
  UnionFind& parts = w.parts;
  parts.reset(pts.size());
  for (const uint64_t e : all) parts.unite(int32_t(edge_key_low(e)), int32_t(edge_key_high(e)));
  for (size_t f = 0, outer = 0; f < faces.size(); ++f) {  // a face's holes are of its piece
    if (face_loop[f] == 1) outer = f;
    if (face_loop[f] == 2) parts.unite(faces[outer][0], faces[f][0]);
  }
  std::vector<int32_t>& used_map = w.used_map;
  used_map.assign(pts.size(), -1);
  out.points_.clear(), out.names_.clear();
  out.face_start_.assign(1, 0), out.face_vert_.clear();
  out.pieces_ = 0;
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int32_t p : faces[f]) {
      if (used_map[p] < 0) {
        const int32_t root = parts.find(p);
        if (root == p) ++out.pieces_;  // each piece's root is one of its points, met once
        used_map[p] = int32_t(out.points_.size());
        out.points_.push_back(pts[p]);
        out.names_.push_back(keys[p]);
      }
      out.face_vert_.push_back(uint16_t(used_map[p]));
    }
    out.face_start_.push_back(uint32_t(out.face_vert_.size()));
  }
  if (faces.size() == 0) return fail_with("the cell lies outside the domain");
  if (out.points_.size() > 65535) return fail_with(fmt::format("the cell has {} vertices, over 65,535", out.points_.size()));
  return Result::Clipped;
}

}  // namespace froth
