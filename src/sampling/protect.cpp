#include "sampling/protect.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "common/random.hpp"
#include "common/surface_locator.hpp"
#include "froth/error.hpp"

namespace froth {
namespace {

// One straight piece of a reflex curve and the parts of it no protection disk covers yet, as
// sorted, disjoint parameter intervals (arc length from a).
struct Piece {
  Vec3 a, dir;  // dir has unit length
  double length;
  Vec3 inward;
  std::vector<std::pair<double, double>> uncovered;
};

// Removes from the piece the points within `radius` of p.
void cover(Piece& piece, Vec3 p, double radius) {
  const Vec3 ap = p - piece.a;
  const double m = dot(piece.dir, ap), disc = m * m - norm2(ap) + radius * radius;
  if (disc <= 0) return;
  const double lo = m - std::sqrt(disc), hi = m + std::sqrt(disc);
  std::vector<std::pair<double, double>> kept;
  for (auto [u, v] : piece.uncovered) {
    if (v <= lo || u >= hi) {
      kept.push_back({u, v});
      continue;
    }
    if (u < lo) kept.push_back({u, lo});
    if (v > hi) kept.push_back({hi, v});
  }
  piece.uncovered.swap(kept);
}

Vec3 unit(Vec3 v) { return (1 / norm(v)) * v; }

}  // namespace

ProtectionSeeds protect_reflex_features(const Domain& domain, double r, uint64_t seed) {
  ProtectionSeeds out;
  if (domain.reflex_curves.empty()) return out;
  const auto& S = domain.surface;
  const double re = r / std::sqrt(2.0);
  // Outward unit normal of each triangle; triangles at each directed edge.
  std::map<std::pair<int32_t, int32_t>, int32_t> at_edge;
  std::vector<Vec3> normal(S.triangles.size());
  for (size_t t = 0; t < S.triangles.size(); ++t) {
    const auto& tri = S.triangles[t];
    normal[t] = unit(cross(S.vertices[tri[1]] - S.vertices[tri[0]], S.vertices[tri[2]] - S.vertices[tri[0]]));
    for (int k = 0; k < 3; ++k) at_edge[{tri[k], tri[(k + 1) % 3]}] = int32_t(t);
  }

  std::vector<Piece> pieces;
  std::vector<int32_t> ends;
  for (const auto& curve : domain.reflex_curves) {
    const bool closed = curve.front() == curve.back() && curve.size() > 2;
    if (!closed) ends.push_back(curve.front()), ends.push_back(curve.back());
    for (size_t k = 0; k + 1 < curve.size(); ++k) {
      const Vec3 a = S.vertices[curve[k]], b = S.vertices[curve[k + 1]];
      const double len = norm(b - a);
      // Into the domain from a reflex edge: against the sum of its two facets' outward normals.
      const Vec3 in = unit(-1.0 * (normal[at_edge.at({curve[k], curve[k + 1]})] +
                                   normal[at_edge.at({curve[k + 1], curve[k]})]));
      pieces.push_back({a, (1 / len) * (b - a), len, in, {{0.0, len}}});
    }
  }
  std::sort(ends.begin(), ends.end());
  ends.erase(std::unique(ends.begin(), ends.end()), ends.end());

  auto add = [&](Vec3 p, CellKind kind, Vec3 in) {
    out.points.push_back(p), out.kinds.push_back(kind), out.inward.push_back(in);
    for (Piece& piece : pieces) cover(piece, p, re);
  };

  // Curve ends: a vertex seed each, pointing into the domain along the first of a few
  // directions that an exact inside test confirms.
  for (int32_t v : ends) {
    const Vec3 p = S.vertices[v];
    std::vector<Vec3> candidates;
    Vec3 sum{};
    std::vector<int32_t> around;
    for (const auto& [e, t] : at_edge)
      if (e.first == v) around.push_back(t);
    for (int32_t t : around) sum = sum - normal[t];
    if (norm(sum) > 0) candidates.push_back(unit(sum));
    for (size_t i = 0; i < around.size(); ++i)
      for (size_t j = i + 1; j < around.size(); ++j)
        if (norm(normal[around[i]] + normal[around[j]]) > 1e-6)
          candidates.push_back(unit(-1.0 * (normal[around[i]] + normal[around[j]])));
    Vec3 in{};
    for (Vec3 c : candidates)
      if (domain.locator->inside(p + 1e-6 * r * c)) {
        in = c;
        break;
      }
    if (norm2(in) == 0)
      fail(ErrorKind::InvalidInput,
           fmt::format("{}: found no direction into the solid at the reflex corner, vertex {} ({}, {}, {})",
                       domain.description, v, p.x, p.y, p.z));
    add(p, CellKind::Vertex, in);
  }

  // 1D random sequential addition to saturation: each dart is uniform on the still uncovered
  // part of all curves, so it is always accepted (the law of MPS), then its disk is removed.
  // Gaps shorter than round-off of the coordinates are left: maximal up to round-off.
  const CounterRng rng(seed, RandomStream::Protection);
  const double crumb = 1e-12 * std::max(r, domain.bounds.diagonal());
  for (uint64_t dart = 0;; ++dart) {
    double total = 0;
    for (Piece& piece : pieces) {
      std::erase_if(piece.uncovered, [&](const auto& iv) { return iv.second - iv.first <= crumb; });
      for (auto [u, v] : piece.uncovered) total += v - u;
    }
    if (total <= 0) break;
    double x = CounterRng::unit(rng.words(dart, 0, 0, 0)[0]) * total;
    const Piece* hit = nullptr;
    double t = 0;
    for (const Piece& piece : pieces) {
      for (auto [u, v] : piece.uncovered) {
        if (x <= v - u) {
          hit = &piece, t = std::min(u + x, v);
          break;
        }
        x -= v - u;
      }
      if (hit) break;
    }
    if (!hit) break;  // round-off at the very end of the last interval
    add(hit->a + t * hit->dir, CellKind::Edge, hit->inward);
  }
  return out;
}

}  // namespace froth
