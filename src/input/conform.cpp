// Corefinement of touching solids (see conform.hpp). CGAL's corefinement inserts, into each
// surface, the curve where it meets the other, coplanar overlaps included, and retriangulates the
// split faces; faces that overlap in a plane come out with the same sub-triangles on both sides.
#include <algorithm>
#include <optional>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Box_intersection_d/Box_with_info_d.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Surface_mesh.h>
#include <fmt/format.h>

#include "froth/error.hpp"
#include "input/conform.hpp"

namespace froth {
namespace {

using Exact = CGAL::Exact_predicates_exact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Exact::Point_3>;
using Face = Mesh::Face_index;
using PatchMap = Mesh::Property_map<Face, int32_t>;
namespace PMP = CGAL::Polygon_mesh_processing;

// A face split by the corefinement hands its patch to its pieces.
struct KeepPatches : PMP::Corefinement::Default_visitor<Mesh> {
  int32_t patch = -1;
  void before_subface_creations(Face old, Mesh& m) { patch = m.property_map<Face, int32_t>("f:patch").first[old]; }
  void after_subface_created(Face added, Mesh& m) { m.property_map<Face, int32_t>("f:patch").first[added] = patch; }
};

Mesh to_mesh(const TriangleSurface& s) {
  Mesh m;
  std::vector<Mesh::Vertex_index> v;
  v.reserve(s.vertices.size());
  for (Vec3 p : s.vertices) v.push_back(m.add_vertex({p.x, p.y, p.z}));
  PatchMap patch = m.add_property_map<Face, int32_t>("f:patch", -1).first;
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    const auto& tri = s.triangles[t];
    const Face f = m.add_face(v[size_t(tri[0])], v[size_t(tri[1])], v[size_t(tri[2])]);
    if (f == Mesh::null_face())
      fail(ErrorKind::Internal, fmt::format("corefinement: triangle {} of a validated solid is not a manifold face", t));
    if (t < s.triangle_patch.size()) patch[f] = s.triangle_patch[t];
  }
  return m;
}

void from_mesh(const Mesh& m, TriangleSurface& s) {
  const PatchMap patch = m.property_map<Face, int32_t>("f:patch").first;
  const bool patched = !s.triangle_patch.empty();
  s.vertices.clear(), s.triangles.clear(), s.triangle_patch.clear();
  std::vector<int32_t> id(m.num_vertices(), -1);
  for (Mesh::Vertex_index v : m.vertices()) {
    const Exact::Point_3& p = m.point(v);
    id[size_t(v)] = int32_t(s.vertices.size());
    s.vertices.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
  }
  for (Face f : m.faces()) {
    std::array<int32_t, 3> tri{};
    int k = 0;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(m.halfedge(f), m)) tri[size_t(k++)] = id[size_t(v)];
    s.triangles.push_back(tri);
    if (patched) s.triangle_patch.push_back(patch[f]);
  }
}

Box bounds(const TriangleSurface& s) {
  Box b{s.vertices[0], s.vertices[0]};
  for (Vec3 p : s.vertices)
    for (int a = 0; a < 3; ++a) b.lo[a] = std::min(b.lo[a], p[a]), b.hi[a] = std::max(b.hi[a], p[a]);
  return b;
}

bool boxes_meet(const Box& a, const Box& b) {
  for (int k = 0; k < 3; ++k)
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
  return true;
}

using Inexact = CGAL::Exact_predicates_inexact_constructions_kernel;
using P3 = Inexact::Point_3;

// Do two triangles meet only in what they share (nothing, a vertex, an edge or all three)? Exact
// predicates on the input's doubles. Were they to meet in more, that is a point other than a
// shared vertex on one's boundary inside the other: on an edge away from the shared vertices,
// or on an edge from a shared vertex, which then runs into the other triangle's corner there.
bool meet_in_shared_only(const std::array<P3, 3>& a, const std::array<P3, 3>& b) {
  int shared_in_a[3] = {-1, -1, -1};  // per corner of a, the corner of b at the same point
  int shared = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[i] == b[j]) shared_in_a[i] = j, ++shared;
  if (shared == 3) return true;
  const Inexact::Triangle_3 ta(a[0], a[1], a[2]), tb(b[0], b[1], b[2]);
  if (shared == 0) return !CGAL::do_intersect(ta, tb);
  if (shared == 2) {  // across their common edge, unless coplanar and on one side of it
    int i = 0;
    while (shared_in_a[i] >= 0) ++i;
    int j = 0;
    while (j == shared_in_a[(i + 1) % 3] || j == shared_in_a[(i + 2) % 3]) ++j;
    const P3 &p = a[(i + 1) % 3], &q = a[(i + 2) % 3];
    if (CGAL::orientation(p, q, a[i], b[j]) != CGAL::COPLANAR) return true;
    return CGAL::coplanar_orientation(p, q, a[i]) != CGAL::coplanar_orientation(p, q, b[j]);
  }
  // One shared vertex v: the far edges must miss the other triangle, and no edge from v may run
  // into the other's corner at v.
  int i = 0;
  while (shared_in_a[i] < 0) ++i;
  const int j = shared_in_a[i];
  auto far_edge_meets = [](const std::array<P3, 3>& t, int at, const Inexact::Triangle_3& other) {
    return CGAL::do_intersect(Inexact::Segment_3(t[(at + 1) % 3], t[(at + 2) % 3]), other);
  };
  auto edge_enters_corner = [](const P3& v, const P3& w, const P3& c1, const P3& c2) {
    if (CGAL::orientation(v, c1, c2, w) != CGAL::COPLANAR) return false;
    const auto s1 = CGAL::coplanar_orientation(v, c1, w), s2 = CGAL::coplanar_orientation(v, c2, w);
    return (s1 == CGAL::COLLINEAR || s1 == CGAL::coplanar_orientation(v, c1, c2)) &&
           (s2 == CGAL::COLLINEAR || s2 == CGAL::coplanar_orientation(v, c2, c1));
  };
  if (far_edge_meets(a, i, tb) || far_edge_meets(b, j, ta)) return false;
  for (int k = 1; k <= 2; ++k) {
    if (edge_enters_corner(a[i], a[(i + k) % 3], b[(j + 1) % 3], b[(j + 2) % 3])) return false;
    if (edge_enters_corner(b[j], b[(j + k) % 3], a[(i + 1) % 3], a[(i + 2) % 3])) return false;
  }
  return true;
}

// Do the two surfaces meet only in triangles, edges and vertices they share (so that
// corefinement would change nothing)? Candidate pairs by bounding boxes (closed: touching
// boxes count).
bool already_conform(const TriangleSurface& a, const TriangleSurface& b) {
  using BoxT = CGAL::Box_intersection_d::Box_with_info_d<double, 3, size_t>;
  auto boxes = [](const TriangleSurface& s) {
    std::vector<BoxT> out;
    for (size_t t = 0; t < s.triangles.size(); ++t) {
      CGAL::Bbox_3 bb;
      for (int32_t v : s.triangles[t]) {
        const Vec3 p = s.vertices[size_t(v)];
        bb += CGAL::Bbox_3(p.x, p.y, p.z, p.x, p.y, p.z);
      }
      out.emplace_back(bb, t);
    }
    return out;
  };
  auto corners = [](const TriangleSurface& s, size_t t) {
    std::array<P3, 3> c;
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = s.vertices[size_t(s.triangles[t][size_t(k)])];
      c[size_t(k)] = {p.x, p.y, p.z};
    }
    return c;
  };
  std::vector<BoxT> ba = boxes(a), bb = boxes(b);
  bool conform = true;
  CGAL::box_intersection_d(ba.begin(), ba.end(), bb.begin(), bb.end(), [&](const BoxT& x, const BoxT& y) {
    if (conform) conform = meet_in_shared_only(corners(a, x.info()), corners(b, y.info()));
  });
  return conform;
}

}  // namespace

int conform_touching_solids(std::vector<TriangleSurface>& solids) {
  const size_t n = solids.size();
  std::vector<Box> box(n);
  for (size_t k = 0; k < n; ++k) box[k] = bounds(solids[k]);
  std::vector<std::optional<Mesh>> mesh(n);
  auto mesh_of = [&](size_t k) -> Mesh& {
    if (!mesh[k]) mesh[k] = to_mesh(solids[k]);
    return *mesh[k];
  };
  // A corefinement with a third solid can add vertices where two already conform (along a line
  // where three meet): pairs are redone until no surface changes.
  std::vector<uint8_t> changed(n, 1), changed_next(n, 0);
  std::vector<uint8_t> touched(n, 0);

  for (int pass = 0; pass < 8; ++pass) {
    bool any = false;
    for (size_t i = 0; i < n; ++i)
      for (size_t j = i + 1; j < n; ++j) {
        if (!(changed[i] || changed[j]) || !boxes_meet(box[i], box[j])) continue;
        // Surfaces that meet only where they share triangles (or not at all) need nothing.
        if (!touched[i] && !touched[j] && already_conform(solids[i], solids[j])) continue;
        Mesh &a = mesh_of(i), &b = mesh_of(j);
        if (!PMP::do_intersect(a, b)) continue;
        const size_t fa = a.num_faces(), fb = b.num_faces();
        try {
          PMP::corefine(a, b, CGAL::parameters::visitor(KeepPatches()), CGAL::parameters::visitor(KeepPatches()));
        } catch (const std::exception& e) {
          fail(ErrorKind::InvalidInput, fmt::format("solids {} and {} could not be made to conform where they meet: {}",
                                                    i + 1, j + 1, e.what()));
        }
        if (a.num_faces() != fa) changed_next[i] = 1, touched[i] = 1, any = true;
        if (b.num_faces() != fb) changed_next[j] = 1, touched[j] = 1, any = true;
      }
    if (!any) break;
    changed.swap(changed_next);
    std::fill(changed_next.begin(), changed_next.end(), 0);
  }
  int changed_solids = 0;
  for (size_t k = 0; k < n; ++k)
    if (touched[k]) from_mesh(*mesh[k], solids[k]), ++changed_solids;
  return changed_solids;
}

std::optional<NearMiss> vertex_near_other_face(const std::vector<Vec3>& V, const std::vector<std::array<int32_t, 3>>& T,
                                               const std::vector<std::array<int32_t, 2>>& sides,
                                               const std::vector<std::vector<int32_t>>& regions_at, double tol) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<K::Triangle_3> tris;
  tris.reserve(T.size());
  auto point = [&](int32_t v) { return K::Point_3(V[size_t(v)].x, V[size_t(v)].y, V[size_t(v)].z); };
  for (const auto& t : T) tris.emplace_back(point(t[0]), point(t[1]), point(t[2]));
  using Primitive = CGAL::AABB_triangle_primitive<K, std::vector<K::Triangle_3>::const_iterator>;
  CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>> tree(tris.begin(), tris.end());
  std::optional<NearMiss> found;
  std::vector<Primitive::Id> near;
  for (size_t v = 0; v < V.size() && !found; ++v) {
    if (regions_at[v].empty()) continue;
    const Vec3 p = V[v];
    near.clear();
    tree.all_intersected_primitives(K::Iso_cuboid_3(p.x - tol, p.y - tol, p.z - tol, p.x + tol, p.y + tol, p.z + tol),
                                    std::back_inserter(near));
    for (auto it : near) {
      const size_t t = size_t(it - tris.begin());
      if (T[t][0] == int32_t(v) || T[t][1] == int32_t(v) || T[t][2] == int32_t(v)) continue;
      bool shared = false;
      for (int32_t side : sides[t]) shared |= side >= 0 && std::count(regions_at[v].begin(), regions_at[v].end(), side);
      if (shared) continue;
      const double d = std::sqrt(CGAL::to_double(CGAL::squared_distance(point(int32_t(v)), tris[t])));
      if (d < tol && (!found || d < found->distance)) found = NearMiss{int32_t(v), int32_t(t), d};
    }
  }
  return found;
}

}  // namespace froth
