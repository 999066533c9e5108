// Corefinement of touching solids (see conform.hpp). CGAL's corefinement inserts, into each
// surface, the curve where it meets the other, coplanar overlaps included, and retriangulates the
// split faces; faces that overlap in a plane come out with the same sub-triangles on both sides.
#include <optional>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
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
  int corefined = 0;
  for (int pass = 0; pass < 8; ++pass) {
    bool any = false;
    for (size_t i = 0; i < n; ++i)
      for (size_t j = i + 1; j < n; ++j) {
        if (!(changed[i] || changed[j]) || !boxes_meet(box[i], box[j])) continue;
        Mesh &a = mesh_of(i), &b = mesh_of(j);
        if (!PMP::do_intersect(a, b)) continue;
        const size_t fa = a.num_faces(), fb = b.num_faces();
        try {
          PMP::corefine(a, b, CGAL::parameters::visitor(KeepPatches()), CGAL::parameters::visitor(KeepPatches()));
        } catch (const std::exception& e) {
          fail(ErrorKind::InvalidInput, fmt::format("solids {} and {} could not be made to conform where they meet: {}",
                                                    i + 1, j + 1, e.what()));
        }
        if (pass == 0) ++corefined;
        if (a.num_faces() != fa) changed_next[i] = 1, touched[i] = 1, any = true;
        if (b.num_faces() != fb) changed_next[j] = 1, touched[j] = 1, any = true;
      }
    if (!any) break;
    changed.swap(changed_next);
    std::fill(changed_next.begin(), changed_next.end(), 0);
  }
  for (size_t k = 0; k < n; ++k)
    if (touched[k]) from_mesh(*mesh[k], solids[k]);
  return corefined;
}

}  // namespace froth
