#include "assembly/glue_extensions.hpp"

#include <algorithm>
#include <map>
#include <numeric>
#include <unordered_map>

#include <fmt/format.h>

namespace froth {
namespace {

// A face's loop without repeated points and without spikes (a, b, a): what a fin dropped from a
// cell leaves where it met the cell's other faces.
void drop_spikes(std::vector<int32_t>& loop) {
  for (bool changed = true; changed && loop.size() >= 3;) {
    changed = false;
    const size_t n = loop.size();
    for (size_t i = 0; i < n && !changed; ++i) {
      const size_t j = (i + 1) % n, k = (i + 2) % n;
      if (loop[i] == loop[j]) {
        loop.erase(loop.begin() + std::ptrdiff_t(j));
        changed = true;
      } else if (loop[i] == loop[k]) {  // drop b and the second a
        const size_t first = std::min(j, k), second = std::max(j, k);
        loop.erase(loop.begin() + std::ptrdiff_t(second));
        loop.erase(loop.begin() + std::ptrdiff_t(first));
        changed = true;
      }
    }
  }
}

// Each point of a face on copy b (side_of(f) == 1) that is not on copy a (side_of == 0) too:
// the copy-a point within `tolerance` of it, nearest first, written to at[point]; an error text
// naming the first point without one, if `each_has_one`.
template <class SideOf>
std::string match_copy_points(const PolyMesh& m, SideOf&& side_of, double tolerance, std::vector<int32_t>& at,
                              bool each_has_one = true) {
  std::vector<int32_t> on[2];
  for (size_t f = 0; f < m.face_count(); ++f)
    if (const int side = side_of(f); side == 0 || side == 1)
      for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k) on[side].push_back(m.face_vertices[k]);
  for (auto& list : on) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  std::vector<int32_t> by_x = on[0];
  std::sort(by_x.begin(), by_x.end(), [&](int32_t a, int32_t b) { return m.points[a].x < m.points[b].x; });
  for (int32_t v : on[1]) {
    if (std::binary_search(on[0].begin(), on[0].end(), v)) continue;
    const Vec3 p = m.points[v];
    auto it = std::lower_bound(by_x.begin(), by_x.end(), p.x - tolerance,
                               [&](int32_t a, double x) { return m.points[a].x < x; });
    int32_t best = -1;
    double best_d = tolerance;
    for (; it != by_x.end() && m.points[*it].x <= p.x + tolerance; ++it)
      if (const double d = norm(m.points[*it] - p); d <= best_d) best = *it, best_d = d;
    if (best >= 0) at[size_t(v)] = best;
    else if (each_has_one)
      return fmt::format("a crack's extension point ({}, {}, {}) on one side has no point on the other within {}", p.x, p.y,
                         p.z, tolerance);
  }
  return "";
}

}  // namespace

std::string glue_extensions(PolyMesh& m, const std::vector<std::array<int32_t, 2>>& planes, double tolerance) {
  if (planes.empty()) return "";
  std::unordered_map<int32_t, std::pair<int32_t, int>> copy_of;  // face generator -> (skirt facet, copy)
  for (size_t k = 0; k < planes.size(); ++k)
    for (int side = 0; side < 2; ++side) copy_of[plane_generator(planes[k][size_t(side)])] = {int32_t(k), side};
  const size_t nc = m.cell_count(), nf = m.face_count();
  std::vector<int32_t> cell_of(nf);
  for (size_t c = 0; c < nc; ++c)
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) cell_of[size_t(f)] = int32_t(c);
  auto copy_of_face = [&](size_t f) {
    const auto it = copy_of.find(m.face_generator[f]);
    return it == copy_of.end() ? std::pair<int32_t, int>{-1, -1} : it->second;
  };

  // 1. Each copy-b point made the copy-a point at its place (the skirt's rim is both copies'
  // already).
  std::vector<int32_t> merged(m.points.size());
  std::iota(merged.begin(), merged.end(), 0);
  if (const std::string error = match_copy_points(m, [&](size_t f) { return copy_of_face(f).second; }, tolerance, merged);
      !error.empty())
    return error;
  for (int32_t& v : m.face_vertices) v = merged[size_t(v)];

  // 2. The skirt's faces in pairs, one of each copy on the same points: matched between their
  // cells, or dropped where both are one cell's.
  std::map<std::pair<int32_t, std::vector<int32_t>>, int64_t> on_a;
  auto key = [&](size_t f, int32_t facet) {
    std::vector<int32_t> pts(m.face_vertices.begin() + m.face_vertex_begin[f], m.face_vertices.begin() + m.face_vertex_begin[f + 1]);
    std::sort(pts.begin(), pts.end());
    return std::pair{facet, pts};
  };
  for (size_t f = 0; f < nf; ++f)
    if (const auto [facet, side] = copy_of_face(f); side == 0) on_a[key(f, facet)] = int64_t(f);
  std::vector<uint8_t> drop(nf, 0);
  for (size_t f = 0; f < nf; ++f) {
    const auto [facet, side] = copy_of_face(f);
    if (side != 1) continue;
    const auto it = on_a.find(key(f, facet));
    if (it == on_a.end())
      return fmt::format("a face of cell {} on a crack's extension has no twin on the other side", cell_of[f]);
    const size_t twin = size_t(it->second);
    const int32_t a = cell_of[twin], b = cell_of[f];
    if (a == b) drop[twin] = drop[f] = 1;
    else m.face_generator[twin] = b, m.face_generator[f] = a;
    on_a.erase(it);
  }
  if (!on_a.empty())
    return fmt::format("a face of cell {} on a crack's extension has no twin on the other side", cell_of[size_t(on_a.begin()->second)]);

  // 3. The faces again, without the dropped ones and the spikes they leave; the points no face
  // uses any more (copy b's) dropped.
  std::vector<int64_t> cell_face_begin{0}, face_vertex_begin{0};
  std::vector<int32_t> face_generator, face_vertices, loop;
  for (size_t c = 0; c < nc; ++c) {
    for (int64_t f = m.cell_face_begin[c]; f < m.cell_face_begin[c + 1]; ++f) {
      if (drop[size_t(f)]) continue;
      loop.assign(m.face_vertices.begin() + m.face_vertex_begin[f], m.face_vertices.begin() + m.face_vertex_begin[f + 1]);
      drop_spikes(loop);
      if (loop.size() < 3) continue;
      face_generator.push_back(m.face_generator[f]);
      face_vertices.insert(face_vertices.end(), loop.begin(), loop.end());
      face_vertex_begin.push_back(int64_t(face_vertices.size()));
    }
    cell_face_begin.push_back(int64_t(face_generator.size()));
  }
  std::vector<int32_t> id(m.points.size(), -1);
  for (int32_t v : face_vertices) id[size_t(v)] = 0;
  int32_t next = 0;
  for (size_t v = 0; v < id.size(); ++v)
    if (id[v] == 0) m.points[next] = m.points[v], id[v] = next++;
  m.points.resize(size_t(next));
  for (int32_t& v : face_vertices) v = id[size_t(v)];
  m.cell_face_begin.assign(cell_face_begin.begin(), cell_face_begin.end());
  m.face_generator.assign(face_generator.begin(), face_generator.end());
  m.face_vertex_begin.assign(face_vertex_begin.begin(), face_vertex_begin.end());
  m.face_vertices.assign(face_vertices.begin(), face_vertices.end());
  return "";
}

std::vector<int32_t> crack_point_twins(const PolyMesh& m, const std::vector<std::array<int32_t, 3>>& sheet_planes,
                                       double tolerance) {
  std::vector<int32_t> twin(m.points.size(), -1);
  auto side_of = [&](size_t f) {
    const int32_t g = m.face_generator[f];
    if (!is_border_generator(g)) return -1;
    const int32_t plane = generator_plane(g);
    for (const auto& [begin, middle, end] : sheet_planes)
      if (plane >= begin && plane < end) return plane < middle ? 0 : 1;
    return -1;
  };
  match_copy_points(m, side_of, tolerance, twin, false);
  // Pairs both ways; two copy-b points at one copy-a point have no twin.
  std::vector<int32_t> found(twin.size(), 0);
  for (int32_t a : twin)
    if (a >= 0) ++found[size_t(a)];
  for (size_t v = 0; v < twin.size(); ++v)
    if (twin[v] >= 0 && found[size_t(twin[v])] > 1) twin[v] = -1;
  for (size_t v = 0; v < twin.size(); ++v)
    if (twin[v] >= 0 && found[size_t(twin[v])] == 1) twin[size_t(twin[v])] = int32_t(v);
  return twin;
}

}  // namespace froth
