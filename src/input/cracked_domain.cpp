#include "input/cracked_domain.hpp"

#include <algorithm>
#include <map>

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
// same exact intersections, rounded alike). The solid's vertices keep their numbers.
TriangleSurface corefined_surface(const Domain& solid, const std::vector<CrackSheet>& sheets) {
  ExactMesh surface = to_cgal_mesh<ExactMesh>(solid.surface);
  bool any = false;
  for (const CrackSheet& c : sheets) {
    if (c.on_boundary.empty()) continue;
    ExactMesh sheet = to_cgal_mesh<ExactMesh>(c.given);
    PMP::corefine(sheet, surface);
    any = true;
  }
  return any ? from_exact_mesh(surface) : solid.surface;
}

// For each triangle of `cut` (a surface split from `whole`, as a corefinement or a clip splits
// it), the triangle of `whole` it lies in: the nearest to its centroid, which lies inside it.
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

// Where a sheet meets the solid's surface along a line, the surface is cut open there: at each
// line vertex (not on the front, where the crack closes) the surface's triangles fall into two
// fans, one on each side of the sheet; the fan on side b takes a new copy of the vertex. Returns
// each line vertex's copy for side b (itself where the vertex is not doubled).
std::map<int32_t, int32_t> cut_along_lines(TriangleSurface& cut, const std::vector<CrackSheet>& sheets,
                                           const std::map<Key, int32_t>& cut_vertex) {
  struct LineEdge {
    int32_t other;       // the edge's other end on the cut surface
    size_t sheet;
    int32_t sheet_tri;   // the sheet's triangle on the edge
  };
  std::map<int32_t, std::vector<LineEdge>> lines;  // line vertex -> its line edges
  std::map<int32_t, size_t> front_at;              // cut vertices on a front
  for (size_t k = 0; k < sheets.size(); ++k) {
    const CrackSheet& c = sheets[k];
    const TriangleSurface& S = c.surface;
    auto cut_id = [&](int32_t v) {
      const auto it = cut_vertex.find(key_of(S.vertices[size_t(v)]));
      if (it == cut_vertex.end())
        fail(ErrorKind::Internal, fmt::format("crack {}: its line on the solid's surface at {} is not on the corefined surface",
                                              c.name, at(S.vertices[size_t(v)])));
      return it->second;
    };
    std::map<std::pair<int32_t, int32_t>, int32_t> tri_of_edge;
    for (size_t t = 0; t < S.triangles.size(); ++t)
      for (int q = 0; q < 3; ++q) tri_of_edge[{S.triangles[t][size_t(q)], S.triangles[t][size_t((q + 1) % 3)]}] = int32_t(t);
    for (const auto& e : c.on_boundary) {
      const int32_t t = tri_of_edge.at({e[0], e[1]});
      const int32_t a = cut_id(e[0]), b = cut_id(e[1]);
      lines[a].push_back({b, k, t});
      lines[b].push_back({a, k, t});
    }
    for (const auto& e : c.front)
      for (int32_t v : e) {
        const auto it = cut_vertex.find(key_of(S.vertices[size_t(v)]));
        if (it != cut_vertex.end()) front_at[it->second] = k;
      }
  }
  std::map<int32_t, int32_t> side_b;
  if (lines.empty()) return side_b;
  // The surface's triangle corners at each line vertex.
  const auto& T = cut.triangles;
  std::map<int32_t, std::vector<std::pair<int32_t, int>>> corners;  // vertex -> (triangle, corner)
  for (size_t t = 0; t < T.size(); ++t)
    for (int q = 0; q < 3; ++q)
      if (lines.count(T[t][size_t(q)])) corners[T[t][size_t(q)]].push_back({int32_t(t), q});
  std::vector<std::pair<std::pair<int32_t, int>, int32_t>> moves;  // (triangle, corner) to side b's copy
  for (const auto& entry : lines) {  // (not a structured binding: clang 14 cannot capture one)
    const int32_t w = entry.first;
    const std::vector<LineEdge>& line_edges = entry.second;
    const Vec3 pw = cut.vertices[size_t(w)];
    for (const LineEdge& e : line_edges)
      if (sheets[e.sheet].name != sheets[line_edges[0].sheet].name)
        refuse(sheets[e.sheet], fmt::format("it meets crack {} on the solid's surface at {}: cracks that meet there "
                                            "are not supported yet",
                                            sheets[line_edges[0].sheet].name, at(pw)));
    side_b[w] = w;
    if (front_at.count(w)) continue;  // the front meets the surface: the crack closes here
    const CrackSheet& c = sheets[line_edges[0].sheet];
    // Fans: corners joined across the edges at w that are not line edges.
    const auto& cs = corners[w];
    UnionFind fans(cs.size());
    auto is_line = [&](int32_t x) {
      return std::any_of(line_edges.begin(), line_edges.end(), [x](const LineEdge& e) { return e.other == x; });
    };
    std::map<int32_t, size_t> first_with;  // other end of an edge at w -> first corner using it
    for (size_t i = 0; i < cs.size(); ++i) {
      const auto& tri = T[size_t(cs[i].first)];
      for (int32_t x : {tri[size_t((cs[i].second + 1) % 3)], tri[size_t((cs[i].second + 2) % 3)]}) {
        if (is_line(x)) continue;
        const auto [it, added] = first_with.try_emplace(x, i);
        if (!added) fans.unite(int32_t(it->second), int32_t(i));
      }
    }
    // Each fan's side: a triangle of it on a line edge against the sheet's triangle there.
    std::map<int32_t, int> fan_side;  // root -> +1 side a, -1 side b
    for (size_t i = 0; i < cs.size(); ++i) {
      const auto& tri = T[size_t(cs[i].first)];
      const int32_t next = tri[size_t((cs[i].second + 1) % 3)], prev = tri[size_t((cs[i].second + 2) % 3)];
      for (const LineEdge& e : line_edges) {
        if (e.other != next && e.other != prev) continue;
        const int32_t far = e.other == next ? prev : next;
        const auto& st = c.surface.triangles[size_t(e.sheet_tri)];
        const auto& SV = c.surface.vertices;
        const auto o = CGAL::orientation(point(SV[size_t(st[0])]), point(SV[size_t(st[1])]), point(SV[size_t(st[2])]),
                                         point(cut.vertices[size_t(far)]));
        if (o != CGAL::COPLANAR) fan_side.try_emplace(fans.find(int32_t(i)), o == CGAL::POSITIVE ? 1 : -1);
      }
    }
    std::map<int32_t, int> sides;
    for (size_t i = 0; i < cs.size(); ++i) sides[fans.find(int32_t(i))] = 0;
    for (auto& [root, s] : sides) s = fan_side.count(root) ? fan_side[root] : 0;
    const auto a = std::count_if(sides.begin(), sides.end(), [](const auto& rs) { return rs.second > 0; });
    const auto b = std::count_if(sides.begin(), sides.end(), [](const auto& rs) { return rs.second < 0; });
    if (sides.size() != 2 || a != 1 || b != 1)
      refuse(c, fmt::format("where it meets the solid's surface at {} the surface does not part into one side on each "
                            "face of the crack ({} fans): the crack must cross the surface, not graze it",
                            at(pw), sides.size()));
    const int32_t copy = int32_t(cut.vertices.size());
    cut.vertices.push_back(pw);
    side_b[w] = copy;
    for (size_t i = 0; i < cs.size(); ++i)
      if (sides[fans.find(int32_t(i))] < 0) moves.push_back({cs[i], copy});
  }
  // (Moved once every fan is known: a fan is found by the line's edges as they were.)
  for (const auto& [corner, copy] : moves) cut.triangles[size_t(corner.first)][size_t(corner.second)] = copy;
  return side_b;
}

}  // namespace

Domain cut_along_cracks(const Domain& solid, std::vector<CrackSheet> sheets, double r) {
  if (solid.regions)
    fail(ErrorKind::Usage, "cracks in a multi-region solid are not supported yet: give one closed solid with the cracks");
  for (const CrackSheet& c : sheets)
    if (!c.on_sheets.empty())
      refuse(c, "it crosses another crack: crossing cracks are not supported yet (give them one at a time)");
  auto set = std::make_shared<CrackSet>();
  set->fronts = std::any_of(sheets.begin(), sheets.end(), [](const CrackSheet& c) { return !c.front.empty(); });
  set->skirt_r = set->fronts ? r : 0;
  // The surfaces cut in: each sheet, or one with a front (once r is known) with its skirt, 2r
  // wide: every cell the front passes through lies within r of its seed, which lies within r of
  // the front, so the skirt's rim passes through none of them. `skirt` marks each cut sheet's
  // skirt triangles.
  std::vector<CrackSheet> cut = sheets;
  std::vector<std::vector<uint8_t>> skirt(sheets.size());
  for (size_t k = 0; k < sheets.size(); ++k) {
    if (set->skirt_r > 0 && !sheets[k].front.empty()) {
      std::vector<uint8_t> skirt_given;
      const TriangleSurface plus = with_skirt(sheets[k].given, solid, 2 * r, skirt_given);
      cut[k] = crack_from_surface(plus, sheets[k].name, solid.surface);
      for (int32_t t : parent_triangles(plus, cut[k].surface)) skirt[k].push_back(skirt_given[size_t(t)]);
    } else {
      skirt[k].assign(cut[k].surface.triangles.size(), 0);
    }
  }
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
  const std::vector<int32_t> parent = parent_triangles(solid.surface, s);
  s.patch_names = solid.surface.patch_names;
  s.triangle_patch.clear();
  const bool patched = solid.surface.triangle_patch.size() == solid.surface.triangles.size();
  if (!patched) s.patch_names = {"surface"};
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    d.triangle_plane.push_back(solid.triangle_plane[size_t(parent[t])]);
    s.triangle_patch.push_back(patched ? solid.surface.triangle_patch[size_t(parent[t])] : 0);
  }
  std::map<Key, int32_t> cut_vertex;
  for (size_t v = 0; v < s.vertices.size(); ++v) cut_vertex.emplace(key_of(s.vertices[v]), int32_t(v));
  const std::map<int32_t, int32_t> side_b = cut_along_lines(s, cut, cut_vertex);

  for (size_t k = 0; k < cut.size(); ++k) {
    const CrackSheet& c = cut[k];
    const TriangleSurface& S = c.surface;
    // Each sheet vertex on copy a and copy b: a line vertex is the surface's (doubled for b),
    // a front vertex one new vertex for both, any other two new ones.
    std::vector<uint8_t> on_front(S.vertices.size(), 0);
    for (const auto& e : c.front) on_front[size_t(e[0])] = on_front[size_t(e[1])] = 1;
    std::vector<uint8_t> on_line(S.vertices.size(), 0);
    for (const auto& e : c.on_boundary) on_line[size_t(e[0])] = on_line[size_t(e[1])] = 1;
    std::vector<std::array<int32_t, 2>> copy(S.vertices.size());
    for (size_t v = 0; v < S.vertices.size(); ++v) {
      if (on_line[v]) {
        const int32_t w = cut_vertex.at(key_of(S.vertices[v]));
        copy[v] = {w, side_b.at(w)};
        continue;
      }
      copy[v][0] = int32_t(s.vertices.size());
      s.vertices.push_back(S.vertices[v]);
      if (on_front[v]) {
        copy[v][1] = copy[v][0];
      } else {
        copy[v][1] = int32_t(s.vertices.size());
        s.vertices.push_back(S.vertices[v]);
      }
    }
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
        const auto& T = S.triangles[t];
        const int32_t a = copy[size_t(T[0])][side], b = copy[size_t(T[1])][side], e = copy[size_t(T[2])][side];
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
  conform_crack_sheets(sheets);
  return cut_along_cracks(solid, std::move(sheets));
}

}  // namespace froth
