#include "common/test_support.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

namespace froth::test {

std::string model(const std::string& name) { return std::string(FROTH_MODELS_DIR) + "/" + name; }

double min_seed_distance(const std::vector<Vec3>& seeds, double r) {
  auto cell = [&](Vec3 p) {
    return std::array<int64_t, 3>{int64_t(std::floor(p.x / r)), int64_t(std::floor(p.y / r)),
                                  int64_t(std::floor(p.z / r))};
  };
  std::map<std::array<int64_t, 3>, std::vector<size_t>> buckets;
  for (size_t i = 0; i < seeds.size(); ++i) buckets[cell(seeds[i])].push_back(i);
  double best = INFINITY;
  for (size_t i = 0; i < seeds.size(); ++i) {
    auto c = cell(seeds[i]);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = buckets.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == buckets.end()) continue;
          for (size_t j : it->second)
            if (j != i) best = std::min(best, norm(seeds[i] - seeds[j]));
        }
  }
  return best;
}

Vec3 face_normal(const PolyMesh& m, int64_t f) {
  Vec3 n;
  int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
  for (int64_t k = b; k < e; ++k) {
    Vec3 p = m.points[m.face_vertices[k]], q = m.points[m.face_vertices[k + 1 < e ? k + 1 : b]];
    n = n + cross(p, q);
  }
  return (1 / norm(n)) * n;
}

double face_area(const PolyMesh& m, int64_t f) {
  const int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
  const Vec3 o = m.points[m.face_vertices[b]];
  Vec3 n{};
  for (int64_t k = b + 1; k + 1 < e; ++k) n = n + cross(m.points[m.face_vertices[k]] - o, m.points[m.face_vertices[k + 1]] - o);
  return norm(n) / 2;
}

Vec3 face_centroid(const PolyMesh& m, int64_t f) {
  Vec3 c;
  int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
  for (int64_t k = b; k < e; ++k) c = c + m.points[m.face_vertices[k]];
  return (1.0 / double(e - b)) * c;
}

std::vector<double> dihedral_angles(const PolyMesh& m, size_t c) {
  std::map<std::pair<int32_t, int32_t>, int64_t> edge_face;
  std::vector<double> out;
  for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
    int64_t b = m.face_vertex_begin[f], e = m.face_vertex_begin[f + 1];
    for (int64_t k = b; k < e; ++k) {
      int32_t u = m.face_vertices[k], v = m.face_vertices[k + 1 < e ? k + 1 : b];
      auto it = edge_face.find({v, u});
      if (it == edge_face.end()) {
        edge_face[{u, v}] = f;
        continue;
      }
      double cosang = std::clamp(dot(face_normal(m, f), face_normal(m, it->second)), -1.0, 1.0);
      out.push_back(180.0 - std::acos(cosang) * 180.0 / M_PI);
    }
  }
  return out;
}

TriangleSurface square_sheet(double x0, double x1, double y0, double y1, double z, int n) {
  TriangleSurface s;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s.vertices.push_back({x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * j / n, z});
  auto id = [&](int i, int j) { return int32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      s.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return s;
}

PolyMesh mesh_of(const Domain& d, double r, uint64_t seed, int threads, RunReport* run) {
  MeshOptions o;
  o.r = r;
  o.seed = seed;
  o.threads = threads;
  o.weld = 0, o.quality = false;  // the cells as built: the tests weld and measure where they mean to
  return generate_mesh(d, o, run);
}

}  // namespace froth::test
