#include "pipeline/border_patches.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace froth {
namespace {

// Distance from p to triangle t (its plane, and beyond the triangle its nearest edge point).
double distance_to_triangle(const TriangleSurface& s, int32_t t, Vec3 p) {
  const Vec3 a = s.vertices[s.triangles[t][0]], b = s.vertices[s.triangles[t][1]], c = s.vertices[s.triangles[t][2]];
  auto segment = [&](Vec3 u, Vec3 v) {
    const Vec3 d = v - u;
    const double l = dot(d, d), x = l > 0 ? std::clamp(dot(p - u, d) / l, 0.0, 1.0) : 0.0;
    const Vec3 q = u + x * d - p;
    return std::sqrt(dot(q, q));
  };
  const Vec3 n = cross(b - a, c - a);
  const double nn = dot(n, n);
  if (nn > 0) {  // inside the triangle: the distance to its plane
    const Vec3 q = p - (dot(p - a, n) / nn) * n;
    const bool inside = dot(cross(b - a, q - a), n) >= 0 && dot(cross(c - b, q - b), n) >= 0 &&
                        dot(cross(a - c, q - c), n) >= 0;
    if (inside) return std::abs(dot(p - a, n)) / std::sqrt(nn);
  }
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

Vec3 face_mean(const PolyMesh& m, int64_t f) {
  Vec3 sum{};
  for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k) sum = sum + m.points[m.face_vertices[k]];
  return (1.0 / double(m.face_vertex_begin[f + 1] - m.face_vertex_begin[f])) * sum;
}

}  // namespace

void assign_border_patches(const Domain& d, PolyMesh& m) {
  const TriangleSurface& s = d.surface;
  m.patch_names = s.patch_names;
  if (m.patch_names.empty()) m.patch_names = {"walls"};
  m.face_patch.clear();
  const bool known = s.triangle_patch.size() == s.triangles.size();
  if (!known || m.patch_names.size() == 1) return;  // one patch: face_patch stays empty
  // Each facet plane's patch, -2 where patches share the plane.
  std::vector<int32_t> plane_patch(d.planes.size(), -1);
  std::vector<std::vector<int32_t>> plane_triangles(d.planes.size());
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    const int32_t p = d.triangle_plane[t], patch = known ? s.triangle_patch[t] : 0;
    plane_triangles[size_t(p)].push_back(int32_t(t));
    plane_patch[size_t(p)] = plane_patch[size_t(p)] == -1 || plane_patch[size_t(p)] == patch ? patch : -2;
  }
  m.face_patch.assign(m.face_count(), -1);
#pragma omp parallel for schedule(dynamic, 4096)
  for (size_t f = 0; f < m.face_count(); ++f) {
    const int32_t g = m.face_generator[f];
    if (!is_border_generator(g)) continue;
    const size_t plane = size_t(generator_plane(g));
    if (plane >= plane_patch.size()) continue;  // (not a domain plane: no patch known)
    int32_t patch = plane_patch[plane];
    if (patch == -2) {
      const Vec3 at = face_mean(m, int64_t(f));
      double best = std::numeric_limits<double>::infinity();
      for (int32_t t : plane_triangles[plane])
        if (const double dist = distance_to_triangle(s, t, at); dist < best) best = dist, patch = s.triangle_patch[t];
    }
    m.face_patch[f] = std::max(patch, 0);
  }
}

}  // namespace froth
