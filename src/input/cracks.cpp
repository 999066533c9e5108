// Crack sheets read, validated and clipped to the solid (cracks.hpp). The clip is CGAL's
// (Polygon Mesh Processing, exact constructions): the sheet keeps its part inside the solid's
// closed surface, cut exactly where it crosses it, the new points rounded to doubles.
#include "input/cracks.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/clip.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <fmt/format.h>

#include "common/union_find.hpp"
#include "input/cgal_meshes.hpp"
#include "froth/error.hpp"

namespace froth {
namespace {

using Inexact = InexactKernel;
using Mesh = InexactMesh;
namespace PMP = CGAL::Polygon_mesh_processing;

[[noreturn]] void bad(const std::string& name, const std::string& what) {
  fail(ErrorKind::InvalidInput, fmt::format("crack {}: {}", name, what));
}

std::string at(Vec3 p) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", p.x, p.y, p.z); }

double triangle_area(const TriangleSurface& s, const std::array<int32_t, 3>& t) {
  const Vec3 a = s.vertices[size_t(t[0])], b = s.vertices[size_t(t[1])], c = s.vertices[size_t(t[2])];
  return 0.5 * norm(cross(b - a, c - a));
}

double area_of(const TriangleSurface& s) {
  double sum = 0;
  for (const auto& t : s.triangles) sum += triangle_area(s, t);
  return sum;
}

// The sheet's free edges (of one triangle), each oriented as its triangle runs it (so that a
// front is a directed curve around side a), put on the boundary where `on_boundary` says and on
// the front otherwise; the front's length summed.
template <class OnBoundary>
void sort_free_edges(CrackSheet& c, OnBoundary&& on_boundary) {
  c.front.clear(), c.on_boundary.clear();
  c.front_length = 0;
  const TriangleSurface& S = c.surface;
  for (const auto& entry : edge_triangles(S)) {  // (not a structured binding: clang 14 cannot capture one)
    if (entry.second.size() != 1) continue;
    const int32_t u = entry.first.first, v = entry.first.second;
    const auto& t = S.triangles[size_t(entry.second[0])];
    std::array<int32_t, 2> edge{u, v};
    for (int k = 0; k < 3; ++k)
      if (t[size_t(k)] == v && t[size_t((k + 1) % 3)] == u) edge = {v, u};
    const Vec3 a = S.vertices[size_t(u)], b = S.vertices[size_t(v)];
    if (on_boundary(a, b)) {
      c.on_boundary.push_back(edge);
    } else {
      c.front.push_back(edge);
      c.front_length += norm(b - a);
    }
  }
}

// Finite, of positive area, edge-manifold, one fan at each vertex; each edge-connected piece
// wound one way (a sheet has no outside: the first triangle of a piece decides), or refused.
void check_and_orient(TriangleSurface& s, const std::string& name) {
  auto& V = s.vertices;
  auto& T = s.triangles;
  if (T.empty()) bad(name, "no triangles");
  for (size_t v = 0; v < V.size(); ++v)
    if (!std::isfinite(V[v].x) || !std::isfinite(V[v].y) || !std::isfinite(V[v].z))
      bad(name, fmt::format("vertex {} has a coordinate that is not a finite number", v));
  for (size_t t = 0; t < T.size(); ++t) {
    const auto [a, b, c] = T[t];
    if (a == b || b == c || a == c ||
        CGAL::collinear(Inexact::Point_3(V[a].x, V[a].y, V[a].z), Inexact::Point_3(V[b].x, V[b].y, V[b].z),
                        Inexact::Point_3(V[c].x, V[c].y, V[c].z)))
      bad(name, fmt::format("triangle {} has zero area, at {}", t, at(V[size_t(a)])));
  }
  const EdgeTriangles edges = edge_triangles(s);
  for (const auto& [e, tris] : edges)
    if (tris.size() > 2)
      bad(name, fmt::format("the edge from {} to {} is shared by {} triangles (a sheet's edge may have one or two); "
                            "split the sheet into sheets that meet along it",
                            at(V[size_t(e.first)]), at(V[size_t(e.second)]), tris.size()));
  // One fan of triangles around each vertex (joined across its edges).
  UnionFind fans(3 * T.size());
  auto corner = [&](int32_t t, int32_t v) { return 3 * t + (T[t][0] == v ? 0 : T[t][1] == v ? 1 : 2); };
  for (const auto& [e, tris] : edges)
    if (tris.size() == 2)
      for (int32_t v : {e.first, e.second}) fans.unite(corner(tris[0], v), corner(tris[1], v));
  std::vector<int32_t> fan_of(V.size(), -1);
  for (size_t c = 0; c < 3 * T.size(); ++c) {
    const int32_t v = T[c / 3][c % 3], fan = fans.find(int32_t(c));
    if (fan_of[size_t(v)] < 0) fan_of[size_t(v)] = fan;
    else if (fan_of[size_t(v)] != fan)
      bad(name, fmt::format("at vertex {} {} its triangles make separate fans (the sheet touches itself at a point)", v,
                            at(V[size_t(v)])));
  }
  // Winding: a triangle and its neighbour run their shared edge opposite ways.
  std::vector<std::vector<std::pair<int32_t, bool>>> across(T.size());
  for (const auto& entry : edges) {  // (not a structured binding: clang 14 cannot capture one)
    const auto& e = entry.first;
    const std::vector<int32_t>& tris = entry.second;
    if (tris.size() != 2) continue;
    auto forward = [&](int32_t t) {
      for (int k = 0; k < 3; ++k)
        if (T[t][size_t(k)] == e.first && T[t][size_t((k + 1) % 3)] == e.second) return true;
      return false;
    };
    const bool same = forward(tris[0]) == forward(tris[1]);
    across[size_t(tris[0])].push_back({tris[1], same});
    across[size_t(tris[1])].push_back({tris[0], same});
  }
  std::vector<int8_t> flip(T.size(), -1);
  for (size_t start = 0; start < T.size(); ++start) {
    if (flip[start] >= 0) continue;
    flip[start] = 0;
    std::vector<int32_t> stack{int32_t(start)};
    while (!stack.empty()) {
      const int32_t t = stack.back();
      stack.pop_back();
      for (const auto& [u, same] : across[size_t(t)]) {
        const int8_t want = int8_t(flip[size_t(t)] ^ int8_t(same));
        if (flip[size_t(u)] < 0) flip[size_t(u)] = want, stack.push_back(u);
        else if (flip[size_t(u)] != want)
          bad(name, fmt::format("it cannot be wound one way (one-sided, like a Moebius strip; see triangles {} and {})",
                                t, u));
      }
    }
  }
  for (size_t t = 0; t < T.size(); ++t)
    if (flip[t]) std::swap(T[t][1], T[t][2]);
  // Self-intersections, exact predicates.
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  const Mesh m = to_cgal_mesh<Mesh>(s);
  PMP::self_intersections(m, std::back_inserter(pairs));
  if (!pairs.empty()) {
    const auto [f, g] = pairs.front();
    bad(name, fmt::format("it intersects itself: triangles {} and {} meet away from a shared edge or vertex, near {}",
                          size_t(f), size_t(g), at(V[size_t(T[size_t(f)][0])])));
  }
}

}  // namespace

EdgeTriangles edge_triangles(const TriangleSurface& s) {
  EdgeTriangles edges;
  for (size_t t = 0; t < s.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = s.triangles[t][size_t(k)], b = s.triangles[t][size_t((k + 1) % 3)];
      edges[{std::min(a, b), std::max(a, b)}].push_back(int32_t(t));
    }
  return edges;
}

namespace {

// Points that the rounding to doubles made one (two exact points closer than a rounding error,
// where sheets cross near another's edge) made one vertex, and the triangles left with a repeated
// vertex (no area) dropped.
void merge_rounded_alike(TriangleSurface& s) {
  std::map<std::array<double, 3>, int32_t> first;
  std::vector<int32_t> id(s.vertices.size());
  bool any = false;
  for (size_t v = 0; v < s.vertices.size(); ++v) {
    const Vec3 p = s.vertices[v];
    const auto [it, added] = first.try_emplace({p.x, p.y, p.z}, int32_t(v));
    id[v] = it->second, any |= !added;
  }
  if (!any) return;
  std::vector<std::array<int32_t, 3>> kept;
  for (auto t : s.triangles) {
    for (int32_t& v : t) v = id[size_t(v)];
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) kept.push_back(t);
  }
  s.triangles = std::move(kept);
  // (Vertices no triangle uses any more are left: nothing reads them.)
}

// `crack`'s part inside the solid, from its sheet as an exact mesh (the given sheet, or that
// sheet corefined with others): CGAL clips the open sheet by the closed surface (exact), keeping
// what lies on the surface too, which is then refused. Sets surface, area, clipped_at and the
// free edges.
// `nothing_inside`: set, and the crack left as it is, where nothing of it is inside (instead of
// refusing it).
void clip_to_solid(CrackSheet& crack, ExactMesh cut, ExactMesh clipper, const TriangleSurface& solid,
                   bool* nothing_inside = nullptr) {
  const std::string& name = crack.name;
  const TriangleSurface& s = crack.given;
  PMP::clip(cut, clipper, CGAL::parameters::clip_volume(false), CGAL::parameters::do_not_modify(true));
  TriangleSurface inside = from_exact_mesh(cut);
  merge_rounded_alike(inside);
  const double area = area_of(inside);
  if (nothing_inside) *nothing_inside = inside.triangles.empty() || !(area > 1e-12 * crack.input_area);
  if (nothing_inside && *nothing_inside) return;
  crack.surface = std::move(inside);
  crack.area = area;
  if (crack.surface.triangles.empty() || !(crack.area > 1e-12 * crack.input_area))
    bad(name, fmt::format("it lies outside the solid (its first vertex is at {}): a crack must be inside the part",
                          at(s.vertices.empty() ? Vec3{} : s.vertices[0])));
  crack.clipped_at = {NAN, NAN, NAN};
  if (crack.area < crack.input_area * (1 - 1e-12)) {  // a vertex of the sheet the clip did not keep
    std::vector<std::array<double, 3>> kept;
    for (Vec3 q : crack.surface.vertices) kept.push_back({q.x, q.y, q.z});
    std::sort(kept.begin(), kept.end());
    for (Vec3 p : s.vertices)
      if (!std::binary_search(kept.begin(), kept.end(), std::array<double, 3>{p.x, p.y, p.z})) {
        crack.clipped_at = p;
        break;
      }
  }

  // Where the clipped sheet touches the solid's surface: distances by an AABB tree over it.
  const Mesh solid_mesh = to_cgal_mesh<Mesh>(solid);
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Inexact, Primitive>>;
  Tree tree(faces(solid_mesh).first, faces(solid_mesh).second, solid_mesh);
  tree.accelerate_distance_queries();
  Box b{solid.vertices[0], solid.vertices[0]};
  for (Vec3 p : solid.vertices)
    for (int a = 0; a < 3; ++a) b.lo[a] = std::min(b.lo[a], p[a]), b.hi[a] = std::max(b.hi[a], p[a]);
  const double tol = 1e-9 * b.diagonal();
  auto on_solid = [&](Vec3 p) { return tree.squared_distance({p.x, p.y, p.z}) <= tol * tol; };
  const auto& V = crack.surface.vertices;
  for (const auto& t : crack.surface.triangles) {
    const Vec3 centroid = (1.0 / 3) * (V[size_t(t[0])] + V[size_t(t[1])] + V[size_t(t[2])]);
    if (on_solid(centroid) && on_solid(V[size_t(t[0])]) && on_solid(V[size_t(t[1])]) && on_solid(V[size_t(t[2])]))
      bad(name, fmt::format("it lies on the solid's boundary near {}: a crack must be inside the part, not on its "
                            "surface",
                            at(centroid)));
  }
  sort_free_edges(crack, [&](Vec3 a, Vec3 c) { return on_solid(a) && on_solid(c) && on_solid(0.5 * (a + c)); });
}

}  // namespace

CrackSheet crack_from_surface(const TriangleSurface& sheet, const std::string& name, const TriangleSurface& solid) {
  CrackSheet crack;
  crack.name = name;
  TriangleSurface s = sheet;
  check_and_orient(s, name);
  crack.input_area = area_of(s);
  crack.given = s;
  clip_to_solid(crack, to_cgal_mesh<ExactMesh>(s), to_cgal_mesh<ExactMesh>(solid), solid);
  return crack;
}

bool clip_crack_again(CrackSheet& crack, const ExactSurface& surface, const TriangleSurface& solid, bool may_miss) {
  using Point = std::array<double, 3>;
  std::vector<std::array<Point, 2>> crossings;
  for (const auto& e : crack.on_sheets) {
    const Vec3 a = crack.surface.vertices[size_t(e[0])], b = crack.surface.vertices[size_t(e[1])];
    crossings.push_back({Point{a.x, a.y, a.z}, Point{b.x, b.y, b.z}});
  }
  bool missed = false;
  clip_to_solid(crack, crack.conformed ? crack.conformed->mesh : to_cgal_mesh<ExactMesh>(crack.given), surface.mesh, solid,
                may_miss ? &missed : nullptr);
  if (missed) return false;
  std::map<Point, int32_t> id;
  for (size_t v = 0; v < crack.surface.vertices.size(); ++v) {
    const Vec3 p = crack.surface.vertices[v];
    id.emplace(Point{p.x, p.y, p.z}, int32_t(v));
  }
  crack.on_sheets.clear();
  for (const auto& [a, b] : crossings) {
    const auto ia = id.find(a), ib = id.find(b);
    if (ia == id.end() || ib == id.end())
      fail(ErrorKind::Internal, fmt::format("crack {}: clipped again, it lost a point of its crossing at ({}, {}, {})",
                                            crack.name, a[0], a[1], a[2]));
    crack.on_sheets.push_back({ia->second, ib->second});
  }
  return true;
}

CrackSheet load_crack(const std::string& path, const TriangleSurface& solid, const DomainOptions& options, Vec3 origin) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  TriangleSurface sheet;
  if (ext == ".stl") sheet = read_stl(path, options.max_memory_bytes);
  else if (ext == ".off" || ext == ".obj" || ext == ".ply") sheet = read_polygon_file(path, options.max_memory_bytes);
  else
    fail(ErrorKind::Usage, fmt::format("crack {}: unsupported format '{}' (froth reads STL, OFF, OBJ and PLY)", path, ext));
  for (Vec3& p : sheet.vertices) p = p - origin;
  return crack_from_surface(sheet, std::filesystem::path(path).stem().string(), solid);
}

void conform_crack_sheets(std::vector<CrackSheet>& sheets, const TriangleSurface& solid) {
  const size_t n = sheets.size();
  if (n < 2) return;
  // The sheets as given are corefined (exact) and clipped again: a point where two sheets cross
  // the solid's surface is then the same exact point as on the surface corefined with both
  // (cracked_domain.cpp), rounded alike.
  std::vector<ExactMesh> mesh;
  std::vector<double> area_before;
  for (const CrackSheet& c : sheets) mesh.push_back(to_cgal_mesh<ExactMesh>(c.given)), area_before.push_back(c.area);
  std::vector<uint8_t> changed(n, 0);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      if (!PMP::do_intersect(mesh[i], mesh[j])) continue;
      const size_t fi = mesh[i].number_of_faces(), fj = mesh[j].number_of_faces();
      try {
        PMP::corefine(mesh[i], mesh[j]);
      } catch (const std::exception& e) {
        fail(ErrorKind::InvalidInput,
             fmt::format("cracks {} and {}: their crossing could not be found ({})", sheets[i].name, sheets[j].name, e.what()));
      }
      changed[i] |= mesh[i].number_of_faces() != fi, changed[j] |= mesh[j].number_of_faces() != fj;
    }
  // Each sheet's edges, as pairs of rounded points, to find the curves two sheets share.
  using PointPair = std::pair<std::array<double, 3>, std::array<double, 3>>;
  auto key = [](Vec3 a, Vec3 b) {
    std::array<double, 3> p{a.x, a.y, a.z}, q{b.x, b.y, b.z};
    return p < q ? PointPair{p, q} : PointPair{q, p};
  };
  std::vector<std::map<PointPair, std::array<int32_t, 2>>> edges(n);
  for (size_t i = 0; i < n; ++i) {
    sheets[i].on_sheets.clear();
    if (changed[i]) {
      sheets[i].conformed = std::make_shared<const ExactSurface>(ExactSurface{mesh[i]});
      clip_to_solid(sheets[i], std::move(mesh[i]), to_cgal_mesh<ExactMesh>(solid), solid);
    }
    const TriangleSurface& S = sheets[i].surface;
    for (const auto& [e, tris] : edge_triangles(S))
      edges[i][key(S.vertices[size_t(e.first)], S.vertices[size_t(e.second)])] = {e.first, e.second};
  }
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j) {
      if (i == j) continue;
      for (const auto& [k, e] : edges[i])
        if (edges[j].count(k)) sheets[i].on_sheets.push_back(e);
    }
  // Sheets overlapping in a plane share whole triangles after the corefinement.
  std::map<std::array<std::array<double, 3>, 3>, size_t> first_sheet;
  for (size_t i = 0; i < n; ++i)
    for (const auto& t : sheets[i].surface.triangles) {
      std::array<std::array<double, 3>, 3> corners;
      for (int k = 0; k < 3; ++k) {
        const Vec3 p = sheets[i].surface.vertices[size_t(t[size_t(k)])];
        corners[size_t(k)] = {p.x, p.y, p.z};
      }
      std::sort(corners.begin(), corners.end());
      const auto [it, added] = first_sheet.try_emplace(corners, i);
      if (!added && it->second != i)
        fail(ErrorKind::InvalidInput,
             fmt::format("cracks {} and {} overlap in a plane near ({:.6g}, {:.6g}, {:.6g}): give the overlap once",
                         sheets[it->second].name, sheets[i].name, corners[0][0], corners[0][1], corners[0][2]));
    }
  for (size_t i = 0; i < n; ++i) {
    CrackSheet& c = sheets[i];
    std::sort(c.on_sheets.begin(), c.on_sheets.end());
    c.on_sheets.erase(std::unique(c.on_sheets.begin(), c.on_sheets.end()), c.on_sheets.end());
    if (std::abs(c.area - area_before[i]) > 1e-9 * area_before[i])
      fail(ErrorKind::Internal,
           fmt::format("crack {}: corefinement changed its area from {} to {}", c.name, area_before[i], c.area));
  }
}

}  // namespace froth
