#include "assembly/glue_extensions.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <span>
#include <unordered_map>

#include <fmt/format.h>

#include "common/union_find.hpp"

namespace froth {
namespace {

// A face's 2j + side where it lies on sheet j's copy `side` (0: a, 1: b; a skirt's planes are
// in its sheet's ranges), -1 elsewhere.
int32_t sheet_side_code(int32_t generator, const std::vector<std::array<int32_t, 3>>& sheet_planes) {
  if (!is_border_generator(generator)) return -1;
  const int32_t plane = generator_plane(generator);
  for (size_t j = 0; j < sheet_planes.size(); ++j)
    if (const auto& [begin, middle, end] = sheet_planes[j]; plane >= begin && plane < end)
      return int32_t(2 * j) + (plane < middle ? 0 : 1);
  return -1;
}

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

// Each point's crack sides: 2j + side for each face on sheet j's copy `side` through it (0: a,
// 1: b; a skirt's faces count as its sheet's), sorted, flat per point.
struct CrackSides {
  std::vector<int32_t> begin, code;
  std::span<const int32_t> of(int32_t v) const {
    return {code.data() + begin[size_t(v)], size_t(begin[size_t(v) + 1] - begin[size_t(v)])};
  }
  bool has(int32_t v, int32_t c) const {
    const auto o = of(v);
    return std::binary_search(o.begin(), o.end(), c);
  }
  // The same sides, but for sheet j's.
  bool alike_but(int32_t v, int32_t w, int32_t j) const {
    const auto a = of(v), b = of(w);
    size_t i = 0, k = 0;
    for (;;) {
      while (i < a.size() && a[i] / 2 == j) ++i;
      while (k < b.size() && b[k] / 2 == j) ++k;
      if (i == a.size() || k == b.size()) return i == a.size() && k == b.size();
      if (a[i++] != b[k++]) return false;
    }
  }
};

// `code_of(f)`: the face's 2j + side, or -1 where it is on no sheet.
template <class CodeOf>
CrackSides crack_sides(const PolyMesh& m, CodeOf&& code_of) {
  std::vector<std::array<int32_t, 2>> pairs;
  for (size_t f = 0; f < m.face_count(); ++f)
    if (const int32_t c = code_of(f); c >= 0)
      for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k) pairs.push_back({m.face_vertices[k], c});
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  CrackSides s;
  s.begin.assign(m.points.size() + 1, 0);
  for (const auto& [v, c] : pairs) ++s.begin[size_t(v) + 1], s.code.push_back(c);
  for (size_t v = 0; v < m.points.size(); ++v) s.begin[v + 1] += s.begin[v];
  return s;
}

// For each point of `from`, the nearest point of `to` within `tolerance` that `fits` (the
// smaller id of two as near; -1: none), by a sweep along the axis `to` spreads most along (a
// sheet square to x has all its points at one x).
template <class Fits>
std::vector<int32_t> nearest_fitting(const PolyMesh& m, const std::vector<int32_t>& from, std::vector<int32_t> to,
                                     double tolerance, Fits&& fits) {
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (int32_t v : to)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], m.points[v][a]), hi[a] = std::max(hi[a], m.points[v][a]);
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
  std::sort(to.begin(), to.end(), [&](int32_t a, int32_t b) { return m.points[a][axis] < m.points[b][axis]; });
  std::vector<int32_t> found(from.size(), -1);
  for (size_t i = 0; i < from.size(); ++i) {
    const int32_t v = from[i];
    const Vec3 p = m.points[v];
    auto it = std::lower_bound(to.begin(), to.end(), p[axis] - tolerance,
                               [&](int32_t a, double x) { return m.points[a][axis] < x; });
    double best_d = tolerance;
    for (; it != to.end() && m.points[*it][axis] <= p[axis] + tolerance; ++it) {
      if (*it == v || !fits(v, *it)) continue;
      const double d = norm(m.points[*it] - p);
      if (d < best_d || (d == best_d && (found[i] < 0 || *it < found[i]))) found[i] = *it, best_d = d;
    }
  }
  return found;
}

}  // namespace

std::string glue_extensions(PolyMesh& m, const std::vector<std::array<int32_t, 2>>& planes,
                            const std::vector<std::array<int32_t, 3>>& sheet_planes, double tolerance) {
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

  // 1. Each skirt's copy-b points made the copy-a points at their places: per skirt, a point of
  // its copy b (not of its copy a too: the rim is both copies' already) joined to the nearest of
  // copy a on the same sides of every other sheet (where a skirt crosses another sheet, its
  // copies on either side of that sheet stay apart); each group made its first point on no
  // skirt's copy b.
  const CrackSides sides = crack_sides(m, [&](size_t f) { return sheet_side_code(m.face_generator[f], sheet_planes); });
  std::vector<int32_t> skirt_sheet(planes.size());
  for (size_t k = 0; k < planes.size(); ++k) skirt_sheet[k] = sheet_side_code(plane_generator(planes[k][0]), sheet_planes) / 2;
  UnionFind glued(m.points.size());
  std::vector<uint8_t> on_copy_b(m.points.size(), 0);
  std::vector<int32_t> sheets(skirt_sheet);
  std::sort(sheets.begin(), sheets.end());
  sheets.erase(std::unique(sheets.begin(), sheets.end()), sheets.end());
  for (int32_t j : sheets) {
    std::vector<int32_t> on[2];
    for (size_t f = 0; f < nf; ++f)
      if (const auto [facet, side] = copy_of_face(f); side >= 0 && skirt_sheet[size_t(facet)] == j)
        for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k) on[side].push_back(m.face_vertices[k]);
    for (auto& list : on) {
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
    }
    std::vector<int32_t> from;
    for (int32_t v : on[1])
      if (!std::binary_search(on[0].begin(), on[0].end(), v)) from.push_back(v), on_copy_b[size_t(v)] = 1;
    const std::vector<int32_t> to =
        nearest_fitting(m, from, on[0], tolerance, [&](int32_t v, int32_t w) { return sides.alike_but(v, w, j); });
    for (size_t i = 0; i < from.size(); ++i) {
      if (to[i] < 0) {
        const Vec3 p = m.points[from[i]];
        return fmt::format("a crack's extension point ({}, {}, {}) on one side has no point on the other within {}", p.x,
                           p.y, p.z, tolerance);
      }
      glued.unite(from[i], to[i]);
    }
  }
  std::vector<int32_t> keeper(m.points.size(), -1), merged(m.points.size());
  for (size_t v = 0; v < m.points.size(); ++v)
    if (int32_t& k = keeper[size_t(glued.find(int32_t(v)))]; k < 0 && !on_copy_b[v]) k = int32_t(v);
  for (size_t v = 0; v < m.points.size(); ++v) {
    const int32_t k = keeper[size_t(glued.find(int32_t(v)))];
    merged[v] = k >= 0 ? k : glued.find(int32_t(v));
  }
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

PointTwins crack_point_twins(const PolyMesh& m, const std::vector<std::array<int32_t, 3>>& sheet_planes, double tolerance) {
  const CrackSides sides = crack_sides(m, [&](size_t f) { return sheet_side_code(m.face_generator[f], sheet_planes); });
  // Per sheet, its points on one side only, each with the point at its place on the other side
  // and alike on every other sheet; pairs kept where found both ways.
  std::vector<std::array<int32_t, 3>> pairs;  // (point, sheet, twin)
  std::vector<std::vector<int32_t>> on_sheet(2 * sheet_planes.size());  // per 2j + side: its points on that side only
  for (size_t v = 0; v < m.points.size(); ++v) {
    const auto codes = sides.of(int32_t(v));
    for (size_t i = 0; i < codes.size(); ++i) {
      const bool both = (i + 1 < codes.size() && codes[i + 1] == (codes[i] | 1) && codes[i] % 2 == 0) ||
                        (i > 0 && codes[i - 1] == (codes[i] & ~1) && codes[i] % 2 == 1);
      if (!both) on_sheet[size_t(codes[i])].push_back(int32_t(v));
    }
  }
  for (size_t j = 0; j < sheet_planes.size(); ++j) {
    const std::vector<int32_t>* on = &on_sheet[2 * j];
    auto fits = [&](int32_t v, int32_t w) { return sides.alike_but(v, w, int32_t(j)); };
    const std::vector<int32_t> to_b = nearest_fitting(m, on[0], on[1], tolerance, fits);
    const std::vector<int32_t> to_a = nearest_fitting(m, on[1], on[0], tolerance, fits);
    for (size_t i = 0; i < on[0].size(); ++i) {
      const int32_t t = to_b[i];
      if (t < 0) continue;
      const size_t back = size_t(std::lower_bound(on[1].begin(), on[1].end(), t) - on[1].begin());
      if (to_a[back] != on[0][i]) continue;
      pairs.push_back({on[0][i], int32_t(j), t}), pairs.push_back({t, int32_t(j), on[0][i]});
    }
  }
  return PointTwins::from(std::move(pairs), m.points.size());
}

}  // namespace froth
