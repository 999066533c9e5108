// Structural checks of the finished mesh: closed cells, matched interior faces, positive volumes.
#include "froth/validate.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>

#include <fmt/format.h>

#include "common/closed_edges.hpp"
#include "common/face_plane.hpp"
#include "quality/inscribed_ball.hpp"

namespace froth {

double cell_volume(const PolyMesh& m, size_t c) {
  // Each face is fanned from its centroid: the twin face in the neighbour has the same vertices
  // and so the same triangles, and their contributions cancel exactly in the total even when
  // welding has left faces slightly non-planar.
  double v6 = 0;
  const Vec3 o = m.seeds[c];  // any origin works; the seed keeps the numbers small
  for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
    const int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
    if (e - b == 3) {
      v6 += dot(m.points[m.face_vertices[b]] - o,
                cross(m.points[m.face_vertices[b + 1]] - o, m.points[m.face_vertices[b + 2]] - o));
      continue;
    }
    Vec3 centroid{};
    for (int64_t k = b; k < e; ++k) centroid = centroid + (m.points[m.face_vertices[k]] - o);
    centroid = (1.0 / double(e - b)) * centroid;
    for (int64_t k = b; k < e; ++k)
      v6 += dot(centroid, cross(m.points[m.face_vertices[k]] - o, m.points[m.face_vertices[k + 1 < e ? k + 1 : b]] - o));
  }
  return v6 / 6;
}

double face_area(const PolyMesh& m, size_t f) {
  const int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
  const Vec3 o = m.points[m.face_vertices[b]];
  Vec3 n{};
  for (int64_t k = b + 1; k + 1 < e; ++k)
    n = n + cross(m.points[m.face_vertices[k]] - o, m.points[m.face_vertices[k + 1]] - o);
  return norm(n) / 2;
}

double border_area(const PolyMesh& m) {
  double area = 0;
  for (size_t f = 0; f < m.face_count(); ++f)
    if (is_border_generator(m.face_generator[f])) area += face_area(m, f);
  return area;
}

namespace {

// The best-fit plane of each face of cell c (unit normal, offset), relative to `origin`; returns
// the largest distance of a plane beyond the origin (0 if none is). Faces of area below
// `min_area` are left out: a sliver's plane is round-off, and a fan over it has no volume anyway.
double cell_planes(const PolyMesh& m, size_t c, Vec3 origin, double min_area, std::vector<Vec3>& normals,
                   std::vector<double>& offsets) {
  double beyond = 0;
  normals.clear();
  offsets.clear();
  for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
    const int64_t b = m.face_vertex_begin[f], n = m.face_vertex_begin[f + 1] - b;
    const FacePlane p = best_fit_plane(size_t(n), [&](size_t k) { return m.points[m.face_vertices[b + int64_t(k)]] - origin; });
    if (p.area < min_area) continue;
    normals.push_back(p.normal);
    offsets.push_back(dot(p.normal, p.centroid));
    beyond = std::max(beyond, -offsets.back());
  }
  return beyond;
}

}  // namespace

std::vector<Vec3> fan_centers(const PolyMesh& m, double tolerance) {
  std::vector<Vec3> centers(m.cell_count());
#pragma omp parallel
  {
    std::vector<Vec3> normals;
    std::vector<double> offsets;
#pragma omp for schedule(dynamic, 64)
    for (size_t c = 0; c < m.cell_count(); ++c) {
      const Vec3 x = m.seeds[c];
      cell_planes(m, c, x, tolerance * tolerance, normals, offsets);
      // The seed, when it is inside every face plane by the tolerance (a seed on the surface is
      // not: a fan from it has flat tetrahedra); else the centre of the largest ball in the
      // kernel; for a kernel that holds no ball of radius `tolerance` (empty, or too thin to fan
      // from), none: NaN.
      Vec3 o = x;
      if (!offsets.empty() && *std::min_element(offsets.begin(), offsets.end()) <= tolerance) {
        const InscribedBall ball = largest_inscribed_ball(normals, offsets);
        o = ball.ok && ball.radius > tolerance ? x + ball.center : Vec3{NAN, NAN, NAN};
        // The program's answer checked against every plane: a centre it puts outside one (it
        // did, by 0.13 r, on a welded edge cell of LCD-knob.stl) is no centre.
        for (size_t k = 0; k < normals.size() && !std::isnan(o.x); ++k)
          if (dot(normals[k], ball.center) > offsets[k] - tolerance) o = Vec3{NAN, NAN, NAN};
      }
      centers[c] = o;
    }
  }
  return centers;
}

StarShape star_shape(const PolyMesh& m, double tolerance, size_t begin, size_t end) {
  size_t bad = 0, no_kernel = 0;
  double worst = 0;
  end = std::min(end, m.cell_count());
#pragma omp parallel reduction(+ : bad, no_kernel) reduction(max : worst)
  {
    std::vector<Vec3> normals;
    std::vector<double> offsets;  // of the face planes, relative to the seed
#pragma omp for schedule(static)
    for (size_t c = begin; c < end; ++c) {
      const double cell_worst = cell_planes(m, c, m.seeds[c], tolerance * tolerance, normals, offsets);
      if (cell_worst > tolerance) {
        ++bad;
        const InscribedBall kernel = largest_inscribed_ball(normals, offsets);
        no_kernel += !(kernel.ok && kernel.radius > tolerance);
      }
      worst = std::max(worst, cell_worst);
    }
  }
  return {bad, worst, no_kernel};
}

namespace {

// Is face g (in the neighbour) face f run backwards?
bool is_reversed_twin(const PolyMesh& m, int64_t f, int64_t g) {
  int64_t fb = m.face_vertex_begin[f], n = m.face_vertex_begin[f + 1] - fb;
  int64_t gb = m.face_vertex_begin[g];
  if (m.face_vertex_begin[g + 1] - gb != n) return false;
  int64_t j = 0;
  while (j < n && m.face_vertices[gb + j] != m.face_vertices[fb]) ++j;
  if (j == n) return false;
  for (int64_t k = 1; k < n; ++k) {  // walk g backwards from the shared start
    j = j == 0 ? n - 1 : j - 1;
    if (m.face_vertices[fb + k] != m.face_vertices[gb + j]) return false;
  }
  return true;
}

}  // namespace

MeshCheck check_mesh(const PolyMesh& m) {
  MeshCheck out;
  std::mutex mu;
  size_t first_cell = m.cell_count();
  size_t unmatched = 0, open = 0, nonpositive = 0;
  // Each face toward a later cell is looked for in that cell (reading a neighbour's faces is
  // the check's main cost: once per pair, not twice); the faces toward earlier cells must then
  // be exactly the twins found.
  size_t twins = 0, toward_earlier = 0;
#pragma omp parallel
  {
    EdgeUses edges;
#pragma omp for schedule(dynamic, 256) reduction(+ : unmatched, open, nonpositive, twins, toward_earlier)
    for (size_t c = 0; c < m.cell_count(); ++c) {
      // The faces of the later neighbours of the cell two ahead asked for now: they lie up to a
      // few layers of cells away in memory (cells are in grid order), out of the core's cache,
      // and the reads through them (faces, then vertices) are dependent loads the core cannot
      // overlap; two ahead measured best (commit 3143e00). (Written inline: GCC finds a function
      // that only prefetches pure and drops the calls.)
      if (const size_t a = c + 2; a < m.cell_count()) {
        for (int64_t f = m.cell_face_begin[a]; f < m.cell_face_begin[a + 1]; ++f) {
          const int32_t g = m.face_generator[f];
          if (g < 0 || size_t(g) < a || is_other_piece_generator(g)) continue;
          const int64_t first = m.cell_face_begin[g], last = m.cell_face_begin[g + 1];
          __builtin_prefetch(&m.face_generator[first]);
          __builtin_prefetch(&m.face_vertex_begin[first]);
          __builtin_prefetch(&m.face_vertex_begin[last]);
          constexpr int64_t kPerLine = 64 / sizeof(m.face_vertices[0]);
          for (int64_t v = m.face_vertex_begin[first], end = m.face_vertex_begin[last]; v < end; v += kPerLine)
            __builtin_prefetch(&m.face_vertices[v]);
        }
      }
      std::string problem;
      edges.clear();
      for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
        int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
        for (int64_t k = b; k < e; ++k)
          edges.add(uint32_t(m.face_vertices[k]), uint32_t(m.face_vertices[k + 1 < e ? k + 1 : b]));
        int32_t g = m.face_generator[f];
        if (g < 0 || is_other_piece_generator(g)) continue;  // a border face, or one matched by another piece
        if (size_t(g) < c) {
          ++toward_earlier;
          continue;
        }
        bool twin = false;
        for (int64_t h = m.cell_face_begin[g]; h < m.cell_face_begin[g + 1] && !twin; ++h)
          twin = m.face_generator[h] == int32_t(c) && is_reversed_twin(m, f, h);
        twins += twin;
        if (!twin) {
          ++unmatched;
          if (problem.empty()) problem = fmt::format("cell {}: face toward cell {} has no identical twin there", c, g);
        }
      }
      if (!edges.each_once_each_way()) {
        ++open;
        if (problem.empty()) problem = fmt::format("cell {}: faces do not close", c);
      }
      const double volume = m.volumes.size() == m.cell_count() ? m.volumes[c] : cell_volume(m, c);
      if (!(volume > 0)) {
        ++nonpositive;
        if (problem.empty()) problem = fmt::format("cell {}: volume is not positive", c);
      }
      if (!problem.empty()) {
        std::lock_guard lock(mu);
        if (c < first_cell) first_cell = c, out.first_problem = problem;
      }
    }
  }
  // A twin found is a face toward an earlier cell, and a distinct one (two faces of a cell
  // with one twin would run the same edges twice: not closed).
  if (toward_earlier > twins) {
    unmatched += toward_earlier - twins;
    if (out.first_problem.empty())
      out.first_problem = fmt::format("{} faces toward earlier cells are the twin of no face there", toward_earlier - twins);
  }
  out.unmatched_faces = unmatched;
  out.open_cells = open;
  out.nonpositive_cells = nonpositive;
  return out;
}

}  // namespace froth
