// Triangle surfaces as CGAL Surface_meshes and back, for the input stages that corefine and clip
// with CGAL's Polygon Mesh Processing (cracks, the cut along them).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include "froth/domain.hpp"

namespace froth {

using ExactKernel = CGAL::Exact_predicates_exact_constructions_kernel;
using InexactKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using ExactMesh = CGAL::Surface_mesh<ExactKernel::Point_3>;
using InexactMesh = CGAL::Surface_mesh<InexactKernel::Point_3>;

// An exact mesh where a header cannot name CGAL's types (input/cracks.hpp).
struct ExactSurface {
  ExactMesh mesh;
};

// Vertex k and face t of the mesh are vertex k and triangle t of the surface.
template <class M>
M to_cgal_mesh(const TriangleSurface& s) {
  M m;
  std::vector<typename M::Vertex_index> v;
  for (Vec3 p : s.vertices) v.push_back(m.add_vertex({p.x, p.y, p.z}));
  for (const auto& t : s.triangles) m.add_face(v[size_t(t[0])], v[size_t(t[1])], v[size_t(t[2])]);
  return m;
}

// The mesh's triangles with its points rounded to doubles, vertices in the mesh's
// order (so a mesh that only gained vertices keeps its first ones' numbers).
inline TriangleSurface from_exact_mesh(const ExactMesh& m) {
  TriangleSurface s;
  std::vector<int32_t> id(m.number_of_vertices() + m.number_of_removed_vertices(), -1);
  for (ExactMesh::Vertex_index v : m.vertices()) {
    // Rounded from the exact value, not from the lazy number's interval (which depends on how
    // the point was constructed): a point two computations reach rounds alike in both.
    const ExactKernel::Point_3& p = m.point(v);
    id[size_t(v)] = int32_t(s.vertices.size());
    s.vertices.push_back({CGAL::to_double(CGAL::exact(p.x())), CGAL::to_double(CGAL::exact(p.y())),
                          CGAL::to_double(CGAL::exact(p.z()))});
  }
  for (ExactMesh::Face_index f : m.faces()) {
    std::array<int32_t, 3> t{};
    int k = 0;
    for (ExactMesh::Vertex_index v : CGAL::vertices_around_face(m.halfedge(f), m)) t[size_t(k++)] = id[size_t(v)];
    s.triangles.push_back(t);
  }
  return s;
}

}  // namespace froth
