#include "sampling/protect_cracks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

#include "common/random.hpp"

namespace froth {
namespace {

Vec3 normal_of(const TriangleSurface& s, const std::array<int32_t, 3>& t) {
  const Vec3 n = cross(s.vertices[size_t(t[1])] - s.vertices[size_t(t[0])], s.vertices[size_t(t[2])] - s.vertices[size_t(t[0])]);
  return (1 / norm(n)) * n;
}

}  // namespace

ProtectionSeeds protect_cracks(const std::vector<CrackSheet>& sheets, double r, uint64_t seed,
                               const std::vector<Vec3>& prior, InterfaceProtectionStats* stats,
                               const std::function<double(Vec3)>& h, double lipschitz) {
  std::vector<ProtectedTriangle> tris;
  std::vector<LinePiece> segments;
  // Curve edges by their rounded end points, once each (a crossing is listed by both sheets),
  // with the normal of a sheet along them; and each curve vertex's degree, with such a normal.
  using Point = std::array<double, 3>;
  std::map<std::pair<Point, Point>, Vec3> curve_edges;
  std::map<Point, std::pair<int, Vec3>> degree;
  double extent = r;  // the largest coordinate, for the curves' round-off gaps
  for (const CrackSheet& c : sheets) {
    const TriangleSurface& S = c.surface;
    // Each vertex's normal: its first triangle's (the side a of the piece, wound one way).
    std::vector<Vec3> vertex_normal(S.vertices.size());
    for (const auto& t : S.triangles) {
      const Vec3 n = normal_of(S, t);
      if (!std::isfinite(n.x + n.y + n.z)) continue;  // (rounded to no area by a corefinement)
      tris.push_back({{S.vertices[size_t(t[0])], S.vertices[size_t(t[1])], S.vertices[size_t(t[2])]}, n});
      for (int32_t v : t)
        if (norm2(vertex_normal[size_t(v)]) == 0) vertex_normal[size_t(v)] = n;
    }
    // Its sharp edges too (turning by more than the default feature angle, as the solid's
    // feature edges do): a closed sheet's rim is a reflex edge of the material around it.
    std::vector<std::array<int32_t, 2>> sharp;
    const double sharp_cos = std::cos(kDefaultFeatureAngle * M_PI / 180);
    for (const auto& [e, ts] : edge_triangles(S))
      if (ts.size() == 2 && dot(normal_of(S, S.triangles[size_t(ts[0])]), normal_of(S, S.triangles[size_t(ts[1])])) < sharp_cos)
        sharp.push_back({e.first, e.second});
    const std::vector<std::array<int32_t, 2>>* curves[] = {&c.front, &c.on_boundary, &c.on_sheets, &sharp};
    // A seed's side: the sheets' sides a summed where they cross, so that its anchor (a hair
    // along it, assembly) is off both, in the sector between their sides a.
    std::set<std::pair<Point, Point>> on_this_sheet;
    std::set<Point> at_this_sheet;
    for (const auto* list : curves)
      for (const auto& e : *list) {
        const Vec3 a = S.vertices[size_t(e[0])], b = S.vertices[size_t(e[1])];
        Point pa{a.x, a.y, a.z}, pb{b.x, b.y, b.z};
        if (pb < pa) std::swap(pa, pb);
        const Vec3 n = vertex_normal[size_t(e[0])];
        const auto [edge, added] = curve_edges.try_emplace({pa, pb}, n);
        if (added)
          for (const Point& q : {pa, pb}) ++degree[q].first;
        else if (!on_this_sheet.count(edge->first))
          edge->second = edge->second + n;  // a crossing: between the sheets' sides a
        on_this_sheet.insert(edge->first);
        for (int32_t v : e)
          if (const Vec3 p = S.vertices[size_t(v)]; at_this_sheet.insert({p.x, p.y, p.z}).second)
            degree[{p.x, p.y, p.z}].second = degree[{p.x, p.y, p.z}].second + vertex_normal[size_t(v)];
      }
    for (Vec3 p : S.vertices) extent = std::max({extent, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  }
  for (const auto& [edge, n] : curve_edges) {
    const Vec3 a{edge.first[0], edge.first[1], edge.first[2]}, b{edge.second[0], edge.second[1], edge.second[2]};
    const double len = norm(b - a);
    segments.push_back({a, (1 / len) * (b - a), len, (1 / norm(n)) * n, {{0.0, len}}});
  }
  // Corners: the ends of open curves and the points where more than two curve edges meet (the
  // front meeting the boundary, a crossing's ends), a seed each on side a.
  std::vector<std::pair<Vec3, Vec3>> corners;
  for (const auto& [p, d] : degree)
    if (d.first != 2) corners.push_back({{p[0], p[1], p[2]}, (1 / norm(d.second)) * d.second});
  return sample_facets_and_curves(std::move(tris), std::move(segments), corners, r, seed, prior,
                                  1e-12 * extent, RandomStream::Cracks, stats, h, lipschitz);
}

}  // namespace froth
