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
#include "clip/face_loops.hpp"

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

}  // namespace

// Everything clip() builds, kept from cell to cell: a clipped cell would otherwise allocate a
// few dozen small vectors (the tube's cells stage took a fifth longer).
struct CellClipper::Scratch {
  std::vector<int32_t> tris;
  std::vector<Plane> plane;
  std::vector<Vec3> pts;
  std::vector<Names> keys;
  std::vector<int32_t> table;
  std::vector<std::vector<DirectedEdge>> on_face;
  std::vector<std::pair<uint64_t, int32_t>> crossings;
  std::vector<std::pair<int32_t, DirectedEdge>> border;
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
  std::vector<DirectedEdge> segs, plane_edges, kept;
  std::vector<uint64_t> all;  // directed_edge_key of each face edge
  std::vector<int32_t> chain_leaving;
  std::vector<uint8_t> chain_used;
  UnionFind parts{0};

  // Every point met, by name: an open-addressing table of indices into pts/keys, grown at half
  // full.
  void clear_points() { pts.clear(), keys.clear(), table.assign(256, -1); }
  size_t slot_of(const Names& k) const {
    size_t s = size_t(k.hash() >> 32) & (table.size() - 1);
    while (table[s] >= 0 && !keys[table[s]].same_as(k)) s = (s + 1) & (table.size() - 1);
    return s;
  }
  int32_t intern(const Names& k, Vec3 p) {
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
  }
  // Loops chained in the plane of normal n; false if one does not close.
  bool chain(const std::vector<DirectedEdge>& edges, Vec3 n) {
    return chain_loops(edges, pts.size(), loops, chain_leaving, chain_used, pts, n);
  }
};

// One call of clip(): its cell, where it is, and where the result and an error go.
struct CellClipper::Call {
  int32_t seed;
  Vec3 x, anchor;
  const ConvexCell& cell;
  double half;
  ClippedCell& out;
  std::string& error;
  bool anchor_inside;
  size_t nv, nf;
  Result fail(const std::string& text, Result result = Result::Clipped) const {
    error = fmt::format("cell {} at ({}, {}, {}): {}", seed, x.x, x.y, x.z, text);
    return result;
  }
};

CellClipper::CellClipper(const Domain& domain, const SurfaceGenerators& gens, const TriangleGrid& triangles)
    : domain_(domain), gens_(gens), triangles_(triangles), s_(std::make_unique<Scratch>()) {}
CellClipper::~CellClipper() = default;

CellClipper::Result CellClipper::clip(int32_t seed, Vec3 x, Vec3 anchor, const ConvexCell& cell, double half,
                                      const std::vector<Vec3>& seeds, ClippedCell& out, int32_t& facet_cut,
                                      std::string& error, bool anchor_inside) {
  const size_t nv = cell.vertex_count(), nf = cell.face_count();
  Vec3 lo = cell.vertex(0), hi = lo;
  for (size_t v = 0; v < nv; ++v)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], cell.vertex(v)[a]), hi[a] = std::max(hi[a], cell.vertex(v)[a]);
  Scratch& w = *s_;
  triangles_.triangles_near(x + lo, x + hi, w.tris);
  const Result whole = anchor_inside ? Result::Inside : Result::Outside;  // V, which holds the anchor
  if (w.tris.empty()) return whole;

  // Every triangle that meets the cell's box lies in one facet plane (half the tube's border
  // cells): then V ∩ D is V below the plane (common/facet_planes.hpp). A protection seed lies on
  // the surface, next to a reflex edge: never here.
  if (const int32_t facet = facet_plane_of(domain_, w.tris); anchor == Vec3{} && facet >= 0) {
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
  w.plane.resize(nf);
  for (size_t f = 0; f < nf; ++f) {
    const int32_t g = cell.face_generator(f);
    if (ConvexCell::is_cube_generator(g)) {
      w.plane[f] = {cube_normals[g - ConvexCell::kCubeGenerator], half};
    } else {
      const double d = std::sqrt(norm2(seeds[g] - x));
      w.plane[f] = {(1 / d) * (seeds[g] - x), d / 2};
    }
  }
  Call c{seed, x, anchor, cell, half, out, error, anchor_inside, nv, nf};
  w.clear_points();
  if (const auto stop = clip_triangles(c)) return *stop;
  // No piece of the surface lies in V: V is whole, on the anchor's side of D's surface.
  if (w.border.empty()) return whole;
  if (const auto stop = find_inside_vertices(c)) return *stop;
  if (const auto stop = cut_faces(c)) return *stop;
  if (const auto stop = add_border_faces(c)) return *stop;
  return close_cell(c);
}

// 1. Each nearby triangle clipped by V (Sutherland-Hodgman), its points named as they arise.
std::optional<CellClipper::Result> CellClipper::clip_triangles(const Call& c) {
  Scratch& w = *s_;
  const TriangleSurface& S = domain_.surface;
  const ConvexCell& cell = c.cell;
  auto& on_face = w.on_face;  // cross-section edges per V face
  if (on_face.size() < c.nf) on_face.resize(c.nf);
  for (size_t f = 0; f < c.nf; ++f) on_face[f].clear();
  auto& crossings = w.crossings;  // (V edge's generator pair, point), sorted after step 1
  auto& border = w.border;        // piece edges, by facet plane
  auto& poly = w.poly;
  auto& next = w.next;
  crossings.clear(), border.clear();
  for (int32_t t : w.tris) {
    const auto& tri = S.triangles[t];
    const int32_t facet = gens_.plane(domain_.triangle_plane[t]);
    poly.clear();
    for (int k = 0; k < 3; ++k)
      poly.push_back({S.vertices[tri[k]] - c.x, key_of({gens_.vertex(tri[k])}), gens_.edge(gens_.triangle_edges[t][k])});
    for (size_t f = 0; f < c.nf && !poly.empty(); ++f) {
      const Plane& pl = w.plane[f];
      const int32_t g = cell.face_generator(f);
      // The bounding cube is met only by a piece of V ∩ D beyond r of the seed, where seeds
      // farther than 2r may cut V (assembly/cell_builder.cpp); checked after the loop.
      if (ConvexCell::is_cube_generator(g)) continue;
      bool any_out = false, any_in = false;
      double s[64];
      if (poly.size() > 64) return c.fail("a clipped triangle has more than 64 vertices");
      for (size_t k = 0; k < poly.size(); ++k) {
        s[k] = pl.signed_distance(poly[k].p);
        if (s[k] == 0)  // an exact tie: protection seeds are jittered so that these do not occur
          return c.fail(fmt::format("input triangle {} touches the face on generator {} exactly (degenerate)", t, g));
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
    for (size_t f = 0; f < c.nf; ++f)
      if (ConvexCell::is_cube_generator(cell.face_generator(f)))
        for (const PolyVertex& v : poly)
          if (w.plane[f].signed_distance(v.p) >= 0) return Result::ReachesCube;
    int32_t idx[64];
    for (size_t k = 0; k < poly.size(); ++k) idx[k] = w.intern(poly[k].key, poly[k].p);
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
  return std::nullopt;
}

// 2. Which of V's vertices are inside: parity from the anchor to one, then along V's edges,
// toggling at each crossing.
std::optional<CellClipper::Result> CellClipper::find_inside_vertices(const Call& c) {
  Scratch& w = *s_;
  const ConvexCell& cell = c.cell;
  const size_t nv = c.nv, nf = c.nf;
  auto& crossings = w.crossings;
  cell.vertex_names(w.vnames);
  for (Names& k : w.vnames) std::sort(k.gen, k.gen + k.n);
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
  w.fill.assign(out_begin.begin(), out_begin.end() - 1);
  for (size_t f = 0; f < nf; ++f) {
    const uint16_t* fv = cell.face_begin(f);
    const size_t n = cell.face_size(f);
    for (size_t k = 0; k < n; ++k) out_edge[w.fill[fv[k]]++] = {fv[(k + 1) % n], int32_t(f)};
  }
  for (size_t f = 0; f < nf; ++f) {
    const uint16_t* fv = cell.face_begin(f);
    const size_t n = cell.face_size(f);
    for (size_t k = 0; k < n; ++k) {
      const int32_t u = fv[k], v = fv[(k + 1) % n];
      int32_t twin = -1;  // the face on the other side: the one with the edge v -> u
      for (uint32_t o = out_begin[v]; o < out_begin[v + 1]; ++o)
        if (out_edge[o].first == u) twin = out_edge[o].second;
      if (twin < 0) return c.fail("the Voronoi cell's faces do not close");
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
    if (domain_.locator->side_from(c.x + c.anchor, c.anchor_inside, c.x + cell.vertex(v), w.tris, in)) {
      status[v] = in;
      break;
    }
  }
  if (std::all_of(status.begin(), status.end(), [](int8_t s) { return s < 0; }))
    return c.fail("every segment from the seed to a cell vertex grazes the surface (degenerate)");
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
      return c.fail("the surface crossings along the cell's edges are inconsistent (near-degenerate input)");
  return std::nullopt;
}

// Where a seam crosses a face of V the loops only pass straight on: such a point is dropped (a
// cell cut by one facet plane the quick way has none, and its neighbours must agree with it).
void CellClipper::drop_seam_points(Loops& ls) const {
  const std::vector<Names>& keys = s_->keys;
  size_t to = 0, from = 0;
  for (size_t k = 0; k < ls.size(); ++k) {
    for (; from < ls.begin[k + 1]; ++from) {
      const Names& name = keys[ls.ids[from]];
      if (!(name.n == 2 && (gens_.is_seam(name.gen[0]) || gens_.is_seam(name.gen[1])))) ls.ids[to++] = ls.ids[from];
    }
    ls.begin[k + 1] = uint32_t(to);
  }
  ls.ids.resize(to);
}

// A crack's two copies (input/cracked_domain.hpp) cross an edge of V at one point, a rounding
// error apart in either order: the walk along the edge must leave the side it is on before it
// enters the other, so of two such crossings the one whose facet faces along the edge (an exit)
// goes first.
void CellClipper::order_twin_crossings(std::vector<int32_t>& along, Vec3 dir) const {
  if (!domain_.cracks) return;
  const std::vector<Vec3>& pts = s_->pts;
  const std::vector<Names>& keys = s_->keys;
  auto exits = [&](int32_t q) {
    for (int k = 0; k < keys[q].n; ++k)
      if (const int32_t g = keys[q].gen[k]; g < 0 && g >= -gens_.planes)
        return dot(domain_.planes[size_t(-g - 1)].normal, dir) > 0;
    return false;
  };
  const double tie = 1e-12 * norm2(dir);
  for (size_t k = 0; k + 1 < along.size(); ++k)
    if (dot(pts[along[k + 1]] - pts[along[k]], dir) <= tie && !exits(along[k]) && exits(along[k + 1]))
      std::swap(along[k], along[k + 1]);
}

// A crack's two copies cross a face of V along the same segment, with its own points for
// each copy, except at the rim of a sheet, where the copies meet (a front, or the rim of the
// skirt that extends a front, input/cracked_domain.hpp): a segment of the surface with both ends
// there is crossed both ways, a fin of the face of no area, and both are dropped.
void CellClipper::drop_fins(std::vector<DirectedEdge>& segs) {
  if (segs.size() < 2) return;
  std::vector<DirectedEdge>& sorted = s_->kept;
  sorted = segs;
  std::sort(sorted.begin(), sorted.end());
  std::erase_if(segs, [&](const DirectedEdge& e) {
    return std::binary_search(sorted.begin(), sorted.end(), DirectedEdge{e.to, e.from});
  });
}

// A fin's trace between two points of a sheet's rim whose copies' points between them were seam
// points: two points, no face (the neighbour drops it alike). A longer trace (a curved sheet's
// copies cross a face at points of their own) stays, a face of no area: the fin it bounds is
// a piece of no volume that assembly keeps with the cell and glue_extensions removes.
void CellClipper::drop_two_point_loops(Loops& ls) const {
  Loops kept;
  for (size_t k = 0; k < ls.size(); ++k) {
    const auto loop = ls[k];
    if (loop.size() < 3) continue;
    kept.ids.insert(kept.ids.end(), loop.begin(), loop.end());
    kept.begin.push_back(uint32_t(kept.ids.size()));
  }
  ls = std::move(kept);
}

// 3. Each face of V cut to its part inside D: its inside edge pieces and the cross-section.
// The faces are built in `out` in place: it is only read on success.
std::optional<CellClipper::Result> CellClipper::cut_faces(const Call& c) {
  Scratch& w = *s_;
  const ConvexCell& cell = c.cell;
  w.faces.clear(), c.out.face_gen_.clear(), c.out.face_loop_.clear();
  const FaceLoops faces{w.faces, c.out.face_gen_, c.out.face_loop_};
  const double negligible = tol::negligible_loop_area(c.half);
  std::vector<DirectedEdge>& segs = w.segs;
  for (size_t f = 0; f < c.nf; ++f) {
    const int32_t g = cell.face_generator(f);
    segs.assign(w.on_face[f].begin(), w.on_face[f].end());
    if (domain_.cracks) drop_fins(segs);
    for (uint32_t e = w.edge_begin[f]; e < w.edge_begin[f + 1]; ++e) {
      const int32_t u = w.edges[e].u, v = w.edges[e].w;
      const Vec3 pu = cell.vertex(u), dir = cell.vertex(v) - pu;
      w.along.clear();
      for (uint32_t q = w.edges[e].cross_begin; q < w.edges[e].cross_end; ++q) w.along.push_back(w.crossings[q].second);
      std::sort(w.along.begin(), w.along.end(),
                [&](int32_t a, int32_t b) { return dot(w.pts[a] - pu, dir) < dot(w.pts[b] - pu, dir); });
      order_twin_crossings(w.along, dir);
      bool in = w.status[u];
      int32_t cur = in ? w.intern(w.vnames[u], pu) : -1;
      for (int32_t q : w.along) {
        if (in) segs.push_back({cur, q});
        cur = q;
        in = !in;
      }
      if (in) segs.push_back({cur, w.intern(w.vnames[v], cell.vertex(v))});
    }
    if (segs.empty()) continue;
    if (ConvexCell::is_cube_generator(g)) return Result::ReachesCube;
    if (!w.chain(segs, w.plane[f].normal)) return c.fail(fmt::format("the face on generator {} does not close", g));
    drop_seam_points(w.loops);
    if (domain_.cracks) drop_two_point_loops(w.loops);
    // A hole: the surface passes through the face (a hole or pillar of the domain narrower than
    // r). The neighbour's twin face has the same loops reversed and makes the same cut (its
    // in-plane frame is this one mirrored), so the faces still match.
    if (!add_faces_with_holes(w.loops, w.plane[f].normal, g, w.pts, negligible, faces))
      return c.fail(fmt::format("the face on generator {} has a hole inside none of its loops", g));
  }
  return std::nullopt;
}

// 4. Border faces: the triangle pieces of each facet plane merged (shared edges cancel).
std::optional<CellClipper::Result> CellClipper::add_border_faces(const Call& c) {
  Scratch& w = *s_;
  auto& border = w.border;
  std::sort(border.begin(), border.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : a.second < b.second;
  });
  const FaceLoops faces{w.faces, c.out.face_gen_, c.out.face_loop_};
  const double negligible = tol::negligible_loop_area(c.half);
  for (size_t at = 0; at < border.size();) {
    const int32_t facet = border[at].first;
    w.plane_edges.clear();
    for (; at < border.size() && border[at].first == facet; ++at) w.plane_edges.push_back(border[at].second);
    w.kept.clear();
    for (const DirectedEdge& e : w.plane_edges)
      if (!std::binary_search(w.plane_edges.begin(), w.plane_edges.end(), DirectedEdge{e.to, e.from})) w.kept.push_back(e);
    if (w.kept.empty()) continue;
    const Vec3 n = domain_.planes[-facet - 1].normal;
    if (!w.chain(w.kept, n))
      return c.fail(fmt::format("the border face on facet plane {} does not close", -facet - 1));
    drop_seam_points(w.loops);
    if (!add_faces_with_holes(w.loops, n, facet, w.pts, negligible, faces))
      return c.fail(fmt::format("the border face on facet plane {} has a hole inside none of its loops", -facet - 1));
  }
  return std::nullopt;
}

// 5. The result must be one closed surface: every edge used once each way, all connected.
CellClipper::Result CellClipper::close_cell(const Call& c) {
  Scratch& w = *s_;
  const Loops& faces = w.faces;
  const std::vector<uint8_t>& face_loop = c.out.face_loop_;
  ClippedCell& out = c.out;
  std::vector<uint64_t>& all = w.all;
  all.clear();
  for (size_t f = 0; f < faces.size(); ++f) {
    const auto face = faces[f];
    for (size_t k = 0; k < face.size(); ++k)
      all.push_back(directed_edge_key(uint32_t(face[k]), uint32_t(face[(k + 1) % face.size()])));
  }
  if (!each_edge_once_each_way(all)) return c.fail("the clipped cell is not closed");
  // V ∩ D may fall in several pieces (a wall thinner than the cell, seen from both sides): each
  // becomes a cell of its own after assembly (tessellation's split_pieces), so only count them.
  UnionFind& parts = w.parts;
  parts.reset(w.pts.size());
  for (const uint64_t e : all) parts.unite(int32_t(edge_key_low(e)), int32_t(edge_key_high(e)));
  for (size_t f = 0, outer = 0; f < faces.size(); ++f) {  // a face's holes are of its piece
    if (face_loop[f] == 1) outer = f;
    if (face_loop[f] == 2) parts.unite(faces[outer][0], faces[f][0]);
  }
  std::vector<int32_t>& used_map = w.used_map;
  used_map.assign(w.pts.size(), -1);
  out.points_.clear(), out.names_.clear();
  out.face_start_.assign(1, 0), out.face_vert_.clear();
  out.pieces_ = 0;
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int32_t p : faces[f]) {
      if (used_map[p] < 0) {
        const int32_t root = parts.find(p);
        if (root == p) ++out.pieces_;  // each piece's root is one of its points, met once
        used_map[p] = int32_t(out.points_.size());
        out.points_.push_back(w.pts[p]);
        out.names_.push_back(w.keys[p]);
      }
      out.face_vert_.push_back(uint16_t(used_map[p]));
    }
    out.face_start_.push_back(uint32_t(out.face_vert_.size()));
  }
  if (faces.size() == 0) return c.fail("the cell lies outside the domain");
  if (out.points_.size() > 65535) return c.fail(fmt::format("the cell has {} vertices, over 65,535", out.points_.size()));
  return Result::Clipped;
}

}  // namespace froth
