#include "features/features.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace froth {

FeatureSummary SurfaceFeatures::summary() const {
  FeatureSummary s;
  s.angle_degrees = angle_degrees;
  s.flat_edges = flat_edges, s.convex_edges = convex_edges, s.reflex_edges = reflex_edges;
  s.flat_reflex_edges = flat_reflex_edges;
  s.curves = curves.size();
  s.corners = corners.size();
  for (const FeatureCurve& c : curves) (c.cls == EdgeClass::Reflex ? s.reflex_curves : s.convex_curves)++;
  return s;
}

SurfaceFeatures classify_features(const TriangleSurface& s, double angle_degrees) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  auto point = [&](int32_t v) { return Kernel::Point_3(s.vertices[v].x, s.vertices[v].y, s.vertices[v].z); };
  SurfaceFeatures out;
  out.angle_degrees = angle_degrees;
  const double cos_limit = std::cos(angle_degrees * M_PI / 180);
  // Directed edges (a, b, triangle), sorted; the twin (b, a) is the other triangle at the edge.
  // (A flat list: a map was a tenth of reading a 476,000-triangle part.) Where a directed edge
  // repeats (an input refused later), the last triangle is kept, as a map's assignment did.
  struct Directed {
    int32_t a, b, t;
    auto operator<=>(const Directed&) const = default;
  };
  std::vector<Directed> owner;
  owner.reserve(3 * s.triangles.size());
  for (size_t t = 0; t < s.triangles.size(); ++t)
    for (int e = 0; e < 3; ++e) owner.push_back({s.triangles[t][e], s.triangles[t][(e + 1) % 3], int32_t(t)});
  std::sort(owner.begin(), owner.end());
  size_t kept = 0;
  for (size_t i = 0; i < owner.size(); ++i)
    if (i + 1 == owner.size() || owner[i + 1].a != owner[i].a || owner[i + 1].b != owner[i].b) owner[kept++] = owner[i];
  owner.resize(kept);
  auto twin_of = [&](int32_t a, int32_t b) {
    const auto it = std::lower_bound(owner.begin(), owner.end(), Directed{a, b, INT32_MIN});
    return it != owner.end() && it->a == a && it->b == b ? it->t : -1;
  };
  auto normal = [&](int32_t t) {
    const auto& tri = s.triangles[t];
    const Vec3 n = cross(s.vertices[tri[1]] - s.vertices[tri[0]], s.vertices[tri[2]] - s.vertices[tri[0]]);
    return (1 / norm(n)) * n;
  };
  auto third = [&](int32_t t, int32_t a, int32_t b) {
    for (int32_t v : s.triangles[t])
      if (v != a && v != b) return v;
    return a;
  };
  // Feature edges as an adjacency list per vertex.
  std::map<int32_t, std::vector<std::pair<int32_t, EdgeClass>>> graph;
  for (const auto& [a, b, t0] : owner) {
    if (a > b) continue;  // each undirected edge once
    const int32_t t1 = twin_of(b, a);
    if (t1 < 0) continue;
    // Reflex if t1's far vertex lies above t0's plane (outward normals): orientation() is the
    // sign of det(q - p, r - p, s - p), that is of dot(normal, s - p).
    const auto& tri = s.triangles[t0];
    const bool reflex = CGAL::orientation(point(tri[0]), point(tri[1]), point(tri[2]), point(third(t1, a, b))) ==
                        CGAL::POSITIVE;
    if (dot(normal(t0), normal(t1)) >= cos_limit) {
      ++out.flat_edges;
      out.flat_reflex_edges += reflex;
      continue;
    }
    const EdgeClass cls = reflex ? EdgeClass::Reflex : EdgeClass::Convex;
    (reflex ? out.reflex_edges : out.convex_edges)++;
    graph[a].push_back({b, cls});
    graph[b].push_back({a, cls});
  }
  // Corners: not exactly two feature edges, or two of different classes.
  std::map<int32_t, bool> corner;
  for (const auto& [v, nb] : graph) {
    const bool c = nb.size() != 2 || nb[0].second != nb[1].second;
    corner[v] = c;
    if (c) out.corners.push_back(v);
  }
  // Curves: walk from each corner along each of its feature edges to the next corner; then the
  // closed loops that have no corner.
  std::map<std::pair<int32_t, int32_t>, bool> used;
  auto walk = [&](int32_t start, int32_t next, EdgeClass cls) {
    FeatureCurve curve{cls, {start}, false};
    int32_t prev = start, cur = next;
    used[{std::min(prev, cur), std::max(prev, cur)}] = true;
    while (true) {
      curve.vertices.push_back(cur);
      if (corner[cur] || cur == start) break;
      int32_t step = -1;
      for (const auto& [w, c] : graph[cur])
        if (w != prev && !used[{std::min(cur, w), std::max(cur, w)}]) step = w;
      if (step < 0) break;
      used[{std::min(cur, step), std::max(cur, step)}] = true;
      prev = cur, cur = step;
    }
    curve.closed = curve.vertices.front() == curve.vertices.back() && !corner[curve.vertices.front()];
    out.curves.push_back(std::move(curve));
  };
  for (int32_t c : out.corners)
    for (const auto& [w, cls] : graph[c])
      if (!used[{std::min(c, w), std::max(c, w)}]) walk(c, w, cls);
  for (const auto& [v, nb] : graph)
    for (const auto& [w, cls] : nb)
      if (!used[{std::min(v, w), std::max(v, w)}]) walk(v, w, cls);
  return out;
}

}  // namespace froth
