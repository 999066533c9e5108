#include "input/cracked_domain.hpp"

#include <algorithm>
#include <map>
#include <tuple>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <fmt/format.h>

#include "common/surface_locator.hpp"
#include "common/union_find.hpp"
#include "froth/error.hpp"
#include "input/cgal_meshes.hpp"

namespace froth {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Key = std::array<double, 3>;
Key key_of(Vec3 p) { return {p.x, p.y, p.z}; }
std::string at(Vec3 p) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", p.x, p.y, p.z); }
InexactKernel::Point_3 point(Vec3 p) { return {p.x, p.y, p.z}; }

[[noreturn]] void refuse(const CrackSheet& c, const std::string& what) {
  fail(ErrorKind::InvalidInput, fmt::format("crack {}: {}", c.name, what));
}

// The solid's surface corefined with every sheet that meets it (exact): its lines on the
// boundary become edges of the surface, at the same rounded points as the clipped sheets' (the
// same exact intersections, rounded alike). The solid's vertices keep their numbers. A sheet
// after the first is clipped again to the surface as the sheets before it left it, whose new
// edges cross its line at more points.
TriangleSurface corefined_surface(const Domain& solid, std::vector<CrackSheet>& sheets) {
  ExactSurface surface{to_cgal_mesh<ExactMesh>(solid.surface)};
  bool any = false;
  for (CrackSheet& c : sheets) {
    if (c.on_boundary.empty()) continue;
    if (any) clip_crack_again(c, surface, solid.surface);
    ExactMesh sheet = c.conformed ? c.conformed->mesh : to_cgal_mesh<ExactMesh>(c.given);
    PMP::corefine(sheet, surface.mesh);
    any = true;
  }
  return any ? from_exact_mesh(surface.mesh) : solid.surface;
}

}  // namespace

std::vector<int32_t> parent_triangles(const TriangleSurface& whole, const TriangleSurface& cut) {
  std::vector<int32_t> parent(cut.triangles.size());
  if (cut.triangles == whole.triangles && cut.vertices == whole.vertices) {
    for (size_t t = 0; t < parent.size(); ++t) parent[t] = int32_t(t);
    return parent;
  }
  const InexactMesh mesh = to_cgal_mesh<InexactMesh>(whole);
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<InexactMesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<InexactKernel, Primitive>>;
  Tree tree(faces(mesh).first, faces(mesh).second, mesh);
  tree.accelerate_distance_queries();
  const auto& V = cut.vertices;
  for (size_t t = 0; t < parent.size(); ++t) {
    const auto& T = cut.triangles[t];
    const Vec3 c = (1.0 / 3) * (V[size_t(T[0])] + V[size_t(T[1])] + V[size_t(T[2])]);
    parent[t] = int32_t(tree.closest_point_and_primitive(point(c)).second);
  }
  return parent;
}

namespace {

// The sheet as given, extended beyond each of its free edges that reaches into the solid (its
// front, where it meets the surface from inside) by a skirt `width` wide: a quad per edge in the
// plane of the edge's triangle, its outer corners along the mitred outward direction at each end,
// wound with the sheet. `skirt` marks the added triangles.
TriangleSurface with_skirt(const TriangleSurface& given, const Domain& solid, double width, std::vector<uint8_t>& skirt) {
  TriangleSurface out = given;
  const auto& V = given.vertices;
  const EdgeTriangles uses = edge_triangles(given);
  std::vector<std::array<int32_t, 2>> edges;
  std::map<int32_t, Vec3> outward;  // at each end of a skirted edge, the sum of its edges' directions
  for (const auto& t : given.triangles) {
    const Vec3 n = cross(V[size_t(t[1])] - V[size_t(t[0])], V[size_t(t[2])] - V[size_t(t[0])]);
    for (int k = 0; k < 3; ++k) {
      const int32_t u = t[size_t(k)], v = t[size_t((k + 1) % 3)];
      if (uses.at(std::minmax(u, v)).size() != 1) continue;
      if (!solid.contains(V[size_t(u)]) && !solid.contains(V[size_t(v)]) && !solid.contains(0.5 * (V[size_t(u)] + V[size_t(v)])))
        continue;
      edges.push_back({u, v});
      const Vec3 m = cross(V[size_t(v)] - V[size_t(u)], n);
      const Vec3 unit_m = (1 / norm(m)) * m;
      outward[u] = outward[u] + unit_m, outward[v] = outward[v] + unit_m;
    }
  }
  std::map<int32_t, int32_t> far;
  for (const auto& [v, m] : outward) {
    far[v] = int32_t(out.vertices.size());
    out.vertices.push_back(V[size_t(v)] + (width / norm(m)) * m);
  }
  skirt.assign(given.triangles.size(), 0);
  for (const auto& [u, v] : edges) {
    out.triangles.push_back({v, u, far[u]});
    out.triangles.push_back({v, far[u], far[v]});
    skirt.push_back(1), skirt.push_back(1);
  }
  return out;
}

// A sheet's facet planes: edge-connected groups of exactly coplanar triangles of one `kind`
// (the sheet's or its skirt's), Newell normal along the sheet's normal (side a), offset averaged
// over the corners. Appends to `planes`.
std::vector<int32_t> sheet_facets(const TriangleSurface& s, const std::vector<uint8_t>& kind, std::vector<Plane>& planes) {
  const auto& V = s.vertices;
  const auto& T = s.triangles;
  UnionFind coplanar(T.size());
  for (const auto& [e, tris] : edge_triangles(s)) {
    if (tris.size() != 2 || kind[size_t(tris[0])] != kind[size_t(tris[1])]) continue;
    const auto& p = T[size_t(tris[0])];
    const auto& q = T[size_t(tris[1])];
    const int32_t far = q[0] + q[1] + q[2] - e.first - e.second;
    if (CGAL::orientation(point(V[size_t(p[0])]), point(V[size_t(p[1])]), point(V[size_t(p[2])]),
                          point(V[size_t(far)])) == CGAL::COPLANAR)
      coplanar.unite(tris[0], tris[1]);
  }
  std::map<int32_t, int32_t> group_of_root;
  std::vector<std::pair<Vec3, std::vector<int32_t>>> groups;
  std::vector<int32_t> facet(T.size());
  for (size_t t = 0; t < T.size(); ++t) {
    const auto [it, added] = group_of_root.try_emplace(coplanar.find(int32_t(t)), int32_t(groups.size()));
    if (added) groups.emplace_back();
    facet[t] = it->second;
    auto& g = groups[size_t(it->second)];
    const auto [a, b, c] = T[t];
    g.first = g.first + cross(V[size_t(b)] - V[size_t(a)], V[size_t(c)] - V[size_t(a)]);
    g.second.insert(g.second.end(), {a, b, c});
  }
  const int32_t first = int32_t(planes.size());
  for (const auto& [normal, corners] : groups) {
    const Vec3 n = (1.0 / norm(normal)) * normal;
    double off = 0;
    for (int32_t v : corners) off += dot(n, V[size_t(v)]);
    planes.push_back({n, off / double(corners.size())});
  }
  for (int32_t& f : facet) f += first;
  return facet;
}

// The cut's vertex copies (decided here). Round each vertex, the solid less the sheets falls into
// sectors, and the cut surface has one copy of the vertex per sector. Each side of a triangle
// near a vertex (the solid surface's inner side; either side of a sheet's) lies in one sector;
// two sides are in one sector where they face each other across a wedge round an edge at the
// vertex, found by sorting the edge's triangles round it (exact predicates). So an inner sheet
// vertex has two copies, a front vertex one (the wedge round a front edge joins its triangle's
// two sides), a vertex where a sheet meets the surface two (the surface's fans on either side),
// a vertex on the curve where two sheets cross four, and where one's front crosses the other two.
class CutOpen {
 public:
  // Per sheet, per triangle, its corners' copies on side a and on side b.
  using SheetCopies = std::vector<std::array<std::array<int32_t, 3>, 2>>;

  // `s`: the solid's surface corefined with the sheets, cut open here (its vertices gain the
  // copies, its triangles take their sector's); `sheets` clipped and conformed.
  CutOpen(TriangleSurface& s, const std::vector<CrackSheet>& sheets) : s_(s), sheets_(sheets) {
    number_points();
    join_sectors();
    assign_copies();
  }
  std::vector<SheetCopies> sheet_copies;

 private:
  // Sides: 2t (the normal's side: a sheet's side a, outside the solid for the surface) and 2t + 1.
  int32_t corner(int32_t side, int32_t v) const {
    const auto& t = tri_[size_t(side / 2)];
    return 3 * side + (t[0] == v ? 0 : t[1] == v ? 1 : 2);
  }
  bool on_surface(int32_t side) const { return size_t(side / 2) < s_.triangles.size(); }
  size_t sheet_of(int32_t side) const {
    return size_t(std::upper_bound(sheet_first_.begin(), sheet_first_.end(), size_t(side / 2)) - sheet_first_.begin() - 1);
  }
  Vec3 at_point(int32_t v) const { return point_[size_t(v)]; }

  // One id per point, the surface's first; triangles: the surface's, then each sheet's.
  void number_points() {
    std::map<Key, int32_t> id;
    point_ = s_.vertices;
    for (size_t v = 0; v < point_.size(); ++v) id.emplace(key_of(point_[v]), int32_t(v));
    tri_ = s_.triangles;
    for (const CrackSheet& c : sheets_) {
      sheet_first_.push_back(tri_.size());
      std::vector<int32_t> g(c.surface.vertices.size());
      for (size_t v = 0; v < g.size(); ++v) {
        const auto [it, added] = id.try_emplace(key_of(c.surface.vertices[v]), int32_t(point_.size()));
        if (added) point_.push_back(c.surface.vertices[v]);
        g[v] = it->second;
      }
      for (const auto& e : c.on_boundary)
        for (int32_t v : e)
          if (size_t(g[size_t(v)]) >= s_.vertices.size())
            fail(ErrorKind::Internal, fmt::format("crack {}: its line on the solid's surface at {} is not on the corefined surface",
                                                  c.name, at(c.surface.vertices[size_t(v)])));
      for (const auto& t : c.surface.triangles) tri_.push_back({g[size_t(t[0])], g[size_t(t[1])], g[size_t(t[2])]});
      sheet_global_.push_back(std::move(g));
    }
  }

  // The triangles round each edge in turn (about the edge from its smaller id to its larger);
  // the two sides facing each other across each wedge between neighbours joined at both ends.
  void join_sectors() {
    struct Use {
      int32_t u, w, t;
      bool forward;  // t runs u -> w
    };
    std::vector<Use> uses;
    for (size_t t = 0; t < tri_.size(); ++t)
      for (int q = 0; q < 3; ++q) {
        const int32_t a = tri_[t][size_t(q)], b = tri_[t][size_t((q + 1) % 3)];
        uses.push_back({std::min(a, b), std::max(a, b), int32_t(t), a < b});
      }
    std::sort(uses.begin(), uses.end(), [](const Use& x, const Use& y) { return std::tie(x.u, x.w, x.t) < std::tie(y.u, y.w, y.t); });
    sectors_ = UnionFind(6 * tri_.size());
    std::vector<Use> ring;
    for (size_t i = 0, j = 0; i < uses.size(); i = j) {
      for (j = i; j < uses.size() && uses[j].u == uses[i].u && uses[j].w == uses[i].w; ++j) {}
      ring.assign(uses.begin() + std::ptrdiff_t(i), uses.begin() + std::ptrdiff_t(j));
      const int32_t u = ring[0].u, w = ring[0].w;
      if (ring.size() > 2) sort_round_edge(u, w, ring);
      for (size_t k = 0; k < ring.size(); ++k) {
        const Use& cur = ring[k];
        const Use& next = ring[(k + 1) % ring.size()];
        // The wedge after `cur` (turning about u -> w) faces cur's normal side if it runs
        // u -> w, and next's normal side if next runs w -> u.
        const int32_t after = 2 * cur.t + (cur.forward ? 0 : 1), before = 2 * next.t + (next.forward ? 1 : 0);
        const bool out_a = on_surface(after) && after % 2 == 0, out_b = on_surface(before) && before % 2 == 0;
        if (out_a || out_b) {
          if (out_a != out_b)
            refuse(sheets_[sheet_of(out_a ? before : after)],
                   fmt::format("at {} it leaves the solid without crossing its surface (it grazes it): move it inside "
                               "or across",
                               at(0.5 * (at_point(u) + at_point(w)))));
          continue;
        }
        for (int32_t v : {u, w}) sectors_.unite(corner(after, v), corner(before, v));
      }
    }
  }

  // `ring`'s triangles (more than two on the edge u -> w) in turn about it, from the first's:
  // exact orientations of their third points, half turn by half turn.
  template <class Use>
  void sort_round_edge(int32_t u, int32_t w, std::vector<Use>& ring) const {
    const auto pu = point(at_point(u)), pw = point(at_point(w));
    auto third = [&](const Use& x) {
      const auto& t = tri_[size_t(x.t)];
      return t[0] != u && t[0] != w ? t[0] : t[1] != u && t[1] != w ? t[1] : t[2];
    };
    const Vec3 axis = at_point(w) - at_point(u);
    auto across = [&](int32_t x) {  // the third point's offset square to the edge
      const Vec3 d = at_point(x) - at_point(u);
      return d - (dot(d, axis) / dot(axis, axis)) * axis;
    };
    const int32_t x0 = third(ring[0]);
    auto half = [&](int32_t x) {
      const auto o = CGAL::orientation(pu, pw, point(at_point(x0)), point(at_point(x)));
      return o == CGAL::POSITIVE ? 0 : o == CGAL::NEGATIVE ? 1 : dot(across(x), across(x0)) > 0 ? 0 : 1;
    };
    auto before = [&](const Use& a, const Use& b) {
      const int32_t xa = third(a), xb = third(b);
      const int ha = half(xa), hb = half(xb);
      if (ha != hb) return ha < hb;
      return CGAL::orientation(pu, pw, point(at_point(xa)), point(at_point(xb))) == CGAL::POSITIVE;
    };
    std::sort(ring.begin(), ring.end(), before);
    for (size_t k = 0; k < ring.size(); ++k) {
      const Use& a = ring[k];
      const Use& b = ring[(k + 1) % ring.size()];
      if (a.t != b.t && !before(a, b) && !before(b, a) && dot(across(third(a)), across(third(b))) > 0) {
        const Vec3 where = 0.5 * (at_point(u) + at_point(w));
        if (on_surface(2 * a.t) && on_surface(2 * b.t))
          fail(ErrorKind::Internal, fmt::format("the solid's surface cut by the cracks overlaps itself near {}", at(where)));
        refuse(sheets_[sheet_of(2 * (on_surface(2 * a.t) ? b.t : a.t))],
               fmt::format("near {} it lies on the solid's surface or on another crack: a crack must cross them", at(where)));
      }
    }
  }

  // A copy per sector: a surface vertex keeps its id for the sector holding the first sheet's
  // side a (the first sheet side in the sheets' order), the others new ids in that order; a
  // sheet's vertex off the surface a new id per sector, sheet by sheet, side a first.
  void assign_copies() {
    std::vector<int32_t> copy(6 * tri_.size(), -1);  // per sector root
    auto new_copy = [&](int32_t root, int32_t v) {
      copy[size_t(root)] = int32_t(s_.vertices.size());
      s_.vertices.push_back(at_point(v));
    };
    const size_t ns = s_.triangles.size(), nv = s_.vertices.size();
    struct AtSurface {
      int32_t v;
      int64_t rank;  // sheet sides in order, then the surface's
      int32_t root;
    };
    std::vector<AtSurface> at_surface;
    for (size_t t = 0; t < tri_.size(); ++t)
      for (int side = t < ns ? 1 : 0; side < 2; ++side)
        for (int q = 0; q < 3; ++q)
          if (const int32_t v = tri_[t][size_t(q)]; size_t(v) < nv) {
            const int32_t sd = int32_t(2 * t) + side;
            at_surface.push_back({v, t < ns ? int64_t(2 * tri_.size()) + sd : sd, sectors_.find(3 * sd + q)});
          }
    std::sort(at_surface.begin(), at_surface.end(),
              [](const AtSurface& x, const AtSurface& y) { return std::tie(x.v, x.rank) < std::tie(y.v, y.rank); });
    for (size_t i = 0; i < at_surface.size(); ++i) {
      const AtSurface& x = at_surface[i];
      if (copy[size_t(x.root)] >= 0) continue;
      if (i == 0 || at_surface[i - 1].v != x.v) copy[size_t(x.root)] = x.v;
      else new_copy(x.root, x.v);
    }
    for (size_t k = 0; k < sheets_.size(); ++k) {
      const TriangleSurface& S = sheets_[k].surface;
      std::vector<std::vector<std::pair<int32_t, int>>> corners_at(S.vertices.size());  // (triangle, corner)
      for (size_t t = 0; t < S.triangles.size(); ++t)
        for (int q = 0; q < 3; ++q) corners_at[size_t(S.triangles[t][size_t(q)])].push_back({int32_t(t), q});
      SheetCopies& out = sheet_copies.emplace_back(S.triangles.size());
      for (size_t v = 0; v < S.vertices.size(); ++v)
        for (int side = 0; side < 2; ++side)
          for (const auto& [t, q] : corners_at[v]) {
            const int32_t sd = int32_t(2 * (sheet_first_[k] + size_t(t))) + side;
            const int32_t root = sectors_.find(3 * sd + q);
            if (copy[size_t(root)] < 0) new_copy(root, sheet_global_[k][v]);
            out[size_t(t)][size_t(side)][size_t(q)] = copy[size_t(root)];
          }
    }
    for (size_t t = 0; t < ns; ++t)
      for (int q = 0; q < 3; ++q) s_.triangles[t][size_t(q)] = copy[size_t(sectors_.find(3 * int32_t(2 * t + 1) + q))];
  }

  TriangleSurface& s_;
  const std::vector<CrackSheet>& sheets_;
  std::vector<Vec3> point_;
  std::vector<std::array<int32_t, 3>> tri_;
  std::vector<size_t> sheet_first_;                 // each sheet's first triangle in tri_
  std::vector<std::vector<int32_t>> sheet_global_;  // each sheet's vertices' ids
  UnionFind sectors_{0};
};

}  // namespace

Domain cut_along_cracks(const Domain& solid, std::vector<CrackSheet> sheets, double r) {
  if (solid.regions) return cut_regions_along_cracks(solid, std::move(sheets), r);
  auto set = std::make_shared<CrackSet>();
  set->fronts = std::any_of(sheets.begin(), sheets.end(), [](const CrackSheet& c) { return !c.front.empty(); });
  set->skirt_r = set->fronts ? r : 0;
  // The surfaces cut in: each sheet, or one with a front (once r is known) with its skirt, 2r
  // wide: every cell the front passes through lies within r of its seed, which lies within r of
  // the front, so the skirt's rim passes through none of them. `skirt` marks each cut sheet's
  // skirt triangles.
  std::vector<CrackSheet> cut = sheets;
  std::vector<std::vector<uint8_t>> skirt(sheets.size()), skirt_given_of(sheets.size());
  for (size_t k = 0; k < sheets.size(); ++k) {
    if (set->skirt_r > 0 && !sheets[k].front.empty()) {
      std::vector<uint8_t> skirt_given;
      const TriangleSurface plus = with_skirt(sheets[k].given, solid, 2 * r, skirt_given);
      cut[k] = crack_from_surface(plus, sheets[k].name, solid.surface);
      skirt_given_of[k] = std::move(skirt_given);
    }
  }
  // Skirts cross other sheets where their sheets' fronts come near them: conformed again.
  if (set->skirt_r > 0 && sheets.size() > 1) conform_crack_sheets(cut, solid.surface);
  Domain d;
  d.description = solid.description;
  d.features = solid.features;
  d.convex = false;
  d.reflex_curves = solid.reflex_curves;  // (vertices of the solid's surface, for the counts; protection uses the solid's)
  d.shells = solid.shells, d.cavities = solid.cavities, d.reoriented_triangles = solid.reoriented_triangles;
  d.bounds = solid.bounds, d.origin = solid.origin;
  d.volume = solid.volume, d.surface_area = solid.surface_area;
  d.planes = solid.planes;
  set->plane_begin = {int32_t(d.planes.size())};

  TriangleSurface& s = d.surface;
  s = corefined_surface(solid, cut);
  // (Marked once the sheets are clipped for the last time.)
  for (size_t k = 0; k < sheets.size(); ++k) {
    if (skirt_given_of[k].empty()) skirt[k].assign(cut[k].surface.triangles.size(), 0);
    else
      for (int32_t t : parent_triangles(cut[k].given, cut[k].surface)) skirt[k].push_back(skirt_given_of[k][size_t(t)]);
  }
  const std::vector<int32_t> parent = parent_triangles(solid.surface, s);
  s.patch_names = solid.surface.patch_names;
  s.triangle_patch.clear();
  const bool patched = solid.surface.triangle_patch.size() == solid.surface.triangles.size();
  if (!patched) s.patch_names = {"surface"};
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    d.triangle_plane.push_back(solid.triangle_plane[size_t(parent[t])]);
    s.triangle_patch.push_back(patched ? solid.surface.triangle_patch[size_t(parent[t])] : 0);
  }
  const std::vector<CutOpen::SheetCopies> copies = CutOpen(s, cut).sheet_copies;

  for (size_t k = 0; k < cut.size(); ++k) {
    const CrackSheet& c = cut[k];
    const TriangleSurface& S = c.surface;
    const int32_t patch_a = int32_t(s.patch_names.size());
    s.patch_names.push_back(fmt::format("crack_{}_a", c.name));
    s.patch_names.push_back(fmt::format("crack_{}_b", c.name));
    set->patches.push_back({patch_a, patch_a + 1});
    const bool skirted = std::find(skirt[k].begin(), skirt[k].end(), 1) != skirt[k].end();
    if (skirted) s.patch_names.push_back(fmt::format("crack_{}_extension", c.name));  // (glued: on no face)
    // Copy a faces side a from behind the sheet's normal: wound against the sheet, planes
    // flipped; copy b is the sheet as wound.
    std::vector<Plane> sheet_planes;
    const std::vector<int32_t> facet = sheet_facets(S, skirt[k], sheet_planes);
    const int32_t first = int32_t(d.planes.size()), n = int32_t(sheet_planes.size());
    for (const Plane& p : sheet_planes) d.planes.push_back({-1.0 * p.normal, -p.offset});
    for (const Plane& p : sheet_planes) d.planes.push_back(p);
    set->plane_middle.push_back(first + n);
    set->plane_begin.push_back(first + 2 * n);
    std::vector<uint8_t> skirt_facet(size_t(n), 0);
    for (size_t t = 0; t < S.triangles.size(); ++t) skirt_facet[size_t(facet[t])] = skirt[k][t];
    for (int32_t f = 0; f < n; ++f)
      if (skirt_facet[size_t(f)]) set->extension_planes.push_back({first + f, first + n + f});
    for (int side = 0; side < 2; ++side)
      for (size_t t = 0; t < S.triangles.size(); ++t) {
        const auto [a, b, e] = copies[k][t][size_t(side)];
        s.triangles.push_back(side == 0 ? std::array<int32_t, 3>{a, e, b} : std::array<int32_t, 3>{a, b, e});
        d.triangle_plane.push_back(first + side * n + facet[t]);
        s.triangle_patch.push_back(skirt[k][t] ? patch_a + 2 : patch_a + side);
      }
  }
  d.locator = std::make_shared<SurfaceLocator>(s, true);
  set->sheets = std::move(sheets);
  set->solid = solid;
  d.cracks = std::move(set);
  return d;
}

Domain load_cracks(const Domain& solid, const std::vector<std::string>& paths, const DomainOptions& options) {
  if (paths.empty()) return solid;
  std::vector<CrackSheet> sheets;
  for (const std::string& path : paths) {
    sheets.push_back(load_crack(path, solid.surface, options, solid.origin));
    for (size_t k = 0; k + 1 < sheets.size(); ++k)
      if (sheets[k].name == sheets.back().name)
        fail(ErrorKind::Usage, fmt::format("two cracks are named {} (a crack is named by its file's stem, and its "
                                           "patches by that name): rename one of the files",
                                           sheets.back().name));
  }
  conform_crack_sheets(sheets, solid.surface);
  return cut_along_cracks(solid, std::move(sheets));
}

}  // namespace froth
