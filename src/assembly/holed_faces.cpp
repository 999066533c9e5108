#include "common/face_scratch.hpp"
#include "assembly/holed_faces.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <deque>

#include <fmt/format.h>

namespace froth {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<int32_t, K>;
using Fb = CGAL::Triangulation_face_base_with_info_2<int, K, CGAL::Constrained_triangulation_face_base_2<K>>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// Loops of one face never cross: an intersection of constraints is an error, not a new point.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::No_constraint_intersection_tag>;

// A loop in the form both cells reach: rotated to start at its smallest point id and run toward
// the smaller of that point's two neighbours.
std::vector<int32_t> canonical(std::vector<int32_t> loop) {
  std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
  if (loop.size() > 2 && loop[1] > loop.back()) std::reverse(loop.begin() + 1, loop.end());
  return loop;
}

Vec3 newell(const PolyMesh& m, const std::vector<int32_t>& loop) {
  Vec3 n{};
  const Vec3 o = m.points[loop[0]];
  for (size_t k = 1; k + 1 < loop.size(); ++k) n = n + cross(m.points[loop[k]] - o, m.points[loop[k + 1]] - o);
  return n;
}

// The triangles of one face's loops (the first is the outer one, as the cell winds it).
bool triangulate(const PolyMesh& m, const std::vector<std::vector<int32_t>>& loops,
                 std::vector<std::array<int32_t, 3>>& out, std::string& error) {
  std::vector<std::vector<int32_t>> forms;
  for (const auto& l : loops) forms.push_back(canonical(l));
  std::sort(forms.begin(), forms.end());
  // Projected along the largest component of the largest loop's normal: dropping a coordinate
  // is exact, so both cells triangulate the same plane points.
  Vec3 n{};
  for (const auto& f : forms)
    if (const Vec3 a = newell(m, f); norm2(a) > norm2(n)) n = a;
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(n[k]) > std::abs(n[axis])) axis = k;
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  std::vector<int32_t> ids;
  for (const auto& f : forms) ids.insert(ids.end(), f.begin(), f.end());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  Cdt cdt;
  std::vector<Cdt::Vertex_handle> handle;
  for (int32_t id : ids) {
    handle.push_back(cdt.insert(K::Point_2(m.points[id][u], m.points[id][v])));
    handle.back()->info() = id;
  }
  if (cdt.number_of_vertices() != ids.size()) {
    error = "two of its points project to one";
    return false;
  }
  auto vertex = [&](int32_t id) { return handle[size_t(std::lower_bound(ids.begin(), ids.end(), id) - ids.begin())]; };
  try {
    for (const auto& f : forms)
      for (size_t k = 0; k < f.size(); ++k) cdt.insert_constraint(vertex(f[k]), vertex(f[(k + 1) % f.size()]));
  } catch (const Cdt::Intersection_of_constraints_exception&) {
    error = "its loops cross";
    return false;
  }
  // Nesting depth by a walk from the outside: crossing a loop adds one; odd depth is the face.
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::deque<std::pair<Cdt::Face_handle, int>> todo{{cdt.infinite_face(), 0}};
  while (!todo.empty()) {
    auto [f, depth] = todo.front();
    todo.pop_front();
    if (f->info() >= 0) continue;
    f->info() = depth;
    for (int e = 0; e < 3; ++e) {
      const Cdt::Face_handle g = f->neighbor(e);
      if (g->info() >= 0) continue;
      if (cdt.is_constrained({f, e})) todo.push_back({g, depth + 1});
      else todo.push_front({g, depth});
    }
  }
  // The cell's own winding: the outer loop's normal along the projection axis.
  const bool flip = newell(m, loops[0])[axis] < 0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (f->info() % 2 == 0) continue;
    const int32_t a = f->vertex(0)->info(), b = f->vertex(1)->info(), c = f->vertex(2)->info();
    out.push_back(flip ? std::array<int32_t, 3>{a, c, b} : std::array<int32_t, 3>{a, b, c});
  }
  return true;
}

}  // namespace

std::string triangulate_holed_faces(PolyMesh& m, const std::vector<HoledFace>& holed) {
  if (holed.empty()) return {};
  std::vector<std::vector<std::array<int32_t, 3>>> tris(holed.size());
  std::vector<std::string> errors(holed.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (size_t h = 0; h < holed.size(); ++h) {
    std::vector<std::vector<int32_t>> loops;
    for (int64_t f = holed[h].face; f < holed[h].face + int64_t(holed[h].loops); ++f)
      loops.emplace_back(m.face_vertices.begin() + m.face_vertex_begin[f], m.face_vertices.begin() + m.face_vertex_begin[f + 1]);
    triangulate(m, loops, tris[h], errors[h]);
  }
  for (size_t h = 0; h < holed.size(); ++h)
    if (!errors[h].empty())
      return fmt::format("a face with holes (mesh face {}, generator {}) cannot be triangulated: {}", holed[h].face,
                         m.face_generator[holed[h].face], errors[h]);

  // The face arrays again, each group replaced by its triangles.
  Buffer<int32_t> generator, vertices;
  std::vector<int32_t> region;
  Buffer<int64_t> vertex_begin;
  std::vector<int64_t> cell_begin(m.cell_count() + 1);
  size_t next = 0;  // the next group
  size_t cell = 0;
  for (int64_t f = 0; f < int64_t(m.face_count());) {
    while (cell < m.cell_count() && m.cell_face_begin[cell] <= f) cell_begin[cell++] = int64_t(generator.size());
    if (next < holed.size() && holed[next].face == f) {
      for (const auto& t : tris[next]) {
        generator.push_back(m.face_generator[f]);
        if (!scratch_of(m).face_region.empty()) region.push_back(scratch_of(m).face_region[f]);
        vertex_begin.push_back(int64_t(vertices.size()));
        vertices.insert(vertices.end(), t.begin(), t.end());
      }
      f += holed[next++].loops;
      continue;
    }
    generator.push_back(m.face_generator[f]);
    if (!scratch_of(m).face_region.empty()) region.push_back(scratch_of(m).face_region[f]);
    vertex_begin.push_back(int64_t(vertices.size()));
    vertices.insert(vertices.end(), m.face_vertices.begin() + m.face_vertex_begin[f],
                    m.face_vertices.begin() + m.face_vertex_begin[f + 1]);
    ++f;
  }
  while (cell <= m.cell_count()) cell_begin[cell++] = int64_t(generator.size());
  vertex_begin.push_back(int64_t(vertices.size()));
  m.face_generator = std::move(generator);
  if (!scratch_of(m).face_region.empty()) scratch_of(m).face_region = std::move(region);
  m.face_vertex_begin = std::move(vertex_begin);
  m.face_vertices = std::move(vertices);
  m.cell_face_begin = std::move(cell_begin);
  return {};
}

}  // namespace froth
