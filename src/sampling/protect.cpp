#include "sampling/protect.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>

#include <fmt/format.h>

#include "common/random.hpp"
#include "common/surface_locator.hpp"
#include "froth/error.hpp"

namespace froth {
namespace {

Vec3 unit(Vec3 v) { return (1 / norm(v)) * v; }

}  // namespace

void remove_disk(LinePiece& piece, Vec3 p, double radius) {
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

void saturate_pieces(std::vector<LinePiece>& pieces, const CounterRng& rng, double crumb,
                     const std::function<void(size_t, Vec3)>& accept) {
  for (uint64_t dart = 0;; ++dart) {
    double total = 0;
    for (LinePiece& piece : pieces) {
      std::erase_if(piece.uncovered, [&](const auto& iv) { return iv.second - iv.first <= crumb; });
      for (auto [u, v] : piece.uncovered) total += v - u;
    }
    if (total <= 0) return;
    double x = CounterRng::unit(rng.words(dart, 0, 0, 1)[0]) * total;
    size_t hit = pieces.size();
    double t = 0;
    for (size_t k = 0; k < pieces.size() && hit == pieces.size(); ++k)
      for (auto [u, v] : pieces[k].uncovered) {
        if (x <= v - u) {
          hit = k, t = std::min(u + x, v);
          break;
        }
        x -= v - u;
      }
    if (hit == pieces.size()) return;  // round-off at the very end of the last interval
    accept(hit, pieces[hit].a + t * pieces[hit].dir);
  }
}

ProtectionSeeds protect_reflex_features(const Domain& domain, double r, uint64_t seed,
                                        const std::function<double(Vec3)>& h) {
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

  // Pieces, grouped into lines: runs of a curve between its true corners, where it turns by more
  // than the feature angle. A tessellated arc (a hole's rim, a concave fillet's edge) is one
  // line, sampled along its length, not a vertex seed at every facet's corner. A curve gets a
  // vertex seed at each end and corner, and a seed covers only the line it lies on (the lines
  // that end at it, for a vertex seed): a point of one reflex edge must be closest to a seed on
  // that line, not to one on its neighbour. Disks are Euclidean, so seeds of one line keep r_e
  // apart however it bends.
  std::vector<LinePiece> pieces;
  std::vector<int32_t> line_of_piece;
  std::map<int32_t, std::vector<int32_t>> lines_at_vertex;  // vertex seeds and the lines they end
  int32_t lines = 0;
  const double corner_cosine = std::cos(
      (domain.features.angle_degrees > 0 ? domain.features.angle_degrees : kDefaultFeatureAngle) * M_PI / 180);
  auto bends = [&](int32_t a, int32_t b, int32_t c) {
    return dot(unit(S.vertices[b] - S.vertices[a]), unit(S.vertices[c] - S.vertices[b])) < corner_cosine;
  };
  for (const auto& curve : domain.reflex_curves) {
    const bool closed = curve.front() == curve.back() && curve.size() > 2;
    const size_t n = curve.size() - 1;  // pieces
    // Where lines start: the curve's ends and its bends.
    std::vector<char> split(n, 0);
    for (size_t k = 0; k < n; ++k) {
      if (k == 0) split[k] = !closed || n < 3 || bends(curve[n - 1], curve[0], curve[1]);
      else split[k] = bends(curve[k - 1], curve[k], curve[k + 1]);
    }
    size_t first = std::find(split.begin(), split.end(), 1) - split.begin();
    if (first == n) first = 0, split[0] = 1;  // a closed loop with no bend: start anywhere
    for (size_t q = 0; q < n; ++q) {
      const size_t k = (first + q) % n;
      if (split[k]) {  // a new line starts at vertex curve[k]; the previous one ends there
        if (q > 0) lines_at_vertex[curve[k]].push_back(lines - 1);
        lines_at_vertex[curve[k]].push_back(lines++);
      }
      const Vec3 a = S.vertices[curve[k]], b = S.vertices[curve[k + 1]];
      const double len = norm(b - a);
      // Into the domain from a reflex edge: against the sum of its two facets' outward normals.
      const Vec3 in = unit(-1.0 * (normal[at_edge.at({curve[k], curve[k + 1]})] +
                                   normal[at_edge.at({curve[k + 1], curve[k]})]));
      pieces.push_back({a, (1 / len) * (b - a), len, in, {{0.0, len}}});
      line_of_piece.push_back(lines - 1);
    }
    // The last line ends at the curve's end, which is where the first starts on a closed curve.
    lines_at_vertex[closed ? curve[first] : curve[n]].push_back(lines - 1);
  }

  auto add = [&](Vec3 p, CellKind kind, Vec3 in, const std::vector<int32_t>& on_lines) {
    out.points.push_back(p), out.kinds.push_back(kind), out.inward.push_back(in);
    for (size_t k = 0; k < pieces.size(); ++k)
      if (std::find(on_lines.begin(), on_lines.end(), line_of_piece[k]) != on_lines.end())
        remove_disk(pieces[k], p, h ? h(p) / std::sqrt(2.0) : re);
  };

  const CounterRng rng(seed, RandomStream::Protection);
  // Curve ends and bends: a vertex seed each, pointing into the domain along the first of a few
  // directions that an exact inside test confirms.
  for (const auto& [v, on_lines] : lines_at_vertex) {
    const Vec3 p = S.vertices[v];
    std::vector<Vec3> candidates;
    Vec3 sum{};
    std::vector<int32_t> around;
    for (auto it = at_edge.lower_bound({v, INT32_MIN}); it != at_edge.end() && it->first.first == v; ++it)
      around.push_back(it->second);  // the triangles around v, one per edge leaving it
    for (int32_t t : around) sum = sum - normal[t];
    if (norm(sum) > 0) candidates.push_back(unit(sum));
    for (size_t i = 0; i < around.size(); ++i)
      for (size_t j = i + 1; j < around.size(); ++j)
        if (norm(normal[around[i]] + normal[around[j]]) > 1e-6)
          candidates.push_back(unit(-1.0 * (normal[around[i]] + normal[around[j]])));
    // Then directions spread over the sphere (a Fibonacci lattice), for needle-like corners.
    for (int k = 0; k < 512; ++k) {
      const double z = 1 - (2 * k + 1) / 512.0, rho = std::sqrt(1 - z * z), phi = k * 2.399963229728653;
      candidates.push_back({rho * std::cos(phi), rho * std::sin(phi), z});
    }
    Vec3 in{};
    for (double step : {1e-6 * r, 1e-9 * r}) {
      for (Vec3 c : candidates)
        if (domain.locator->inside(p + step * c)) {
          in = c;
          break;
        }
      if (norm2(in) > 0) break;
    }
    if (norm2(in) == 0)
      fail(ErrorKind::InvalidInput,
           fmt::format("{}: found no direction into the solid at the reflex corner, vertex {} ({}, {}, {})",
                       domain.description, v, p.x, p.y, p.z));
    // The seed sits 1e-7 r inside its vertex, in a random direction around `in`: a symmetric
    // model would otherwise put corner seeds in exact mirror positions, whose exact ties (a
    // point equidistant from two of them) the cells could name differently. The offset is far
    // above round-off and far below anything the mesh resolves.
    Vec3 q = p + 1e-7 * r * in;
    for (uint64_t k = 0; k < 16; ++k) {
      const auto w = rng.words(uint64_t(v), k, 0, 2);
      const double z = 2 * CounterRng::unit(w[0]) - 1, phi = 2 * M_PI * CounterRng::unit(w[1]);
      const Vec3 jitter{std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z};
      const Vec3 cand = p + 1e-7 * r * unit(in + 0.5 * jitter);
      if (domain.locator->inside(cand)) {
        q = cand;
        break;
      }
    }
    add(q, CellKind::Vertex, Vec3{}, on_lines);  // inside already: its own anchor
  }

  // The lines sampled to saturation, each seed covering its own line.
  const double crumb = 1e-12 * std::max(r, domain.bounds.diagonal());
  saturate_pieces(pieces, rng, crumb, [&](size_t k, Vec3 p) {
    add(p, CellKind::Edge, pieces[k].inward, {line_of_piece[k]});
  });
  return out;
}

}  // namespace froth
