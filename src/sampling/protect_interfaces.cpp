#include "sampling/protect_interfaces.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include <fmt/format.h>

#include "common/random.hpp"
#include "common/surface_locator.hpp"
#include "froth/error.hpp"
#include "input/cracked_domain.hpp"
#include "sampling/protect_cracks.hpp"

namespace froth {
namespace {

Vec3 unit(Vec3 v) { return (1 / norm(v)) * v; }

// Seeds by cube of side twice the largest disk radius, for "is p inside an earlier seed's
// disk": the disks that can hold p meet only the 2 x 2 x 2 cubes nearest p (8 look-ups, not 27).
class SeedHash {
 public:
  explicit SeedHash(double largest) : largest_(largest), side_(2 * largest * (1 + 1e-9)) {}
  void add(Vec3 p, double radius) {
    if (!(radius <= largest_)) fail(ErrorKind::Internal, "SeedHash: a disk above the radius it was built for");
    cells_[key(cell(p))].push_back({p, radius});
  }
  // Is p inside some disk scaled by `scale` (at most 1 + 1e-12)?
  bool any_within(Vec3 p, double scale = 1) const {
    return any_near(p, [&](const Disk& q) { return norm2(q.p - p) < (q.radius * scale) * (q.radius * scale); });
  }
  // Is the triangle inside one disk (a disk is convex: its corners are, and then its centroid
  // is within that disk's radius of its seed)?
  bool covers(const std::array<Vec3, 3>& t) const {
    return any_near((1.0 / 3) * (t[0] + t[1] + t[2]), [&](const Disk& q) {
      const double d2 = q.radius * q.radius;
      return norm2(t[0] - q.p) <= d2 && norm2(t[1] - q.p) <= d2 && norm2(t[2] - q.p) <= d2;
    });
  }

 private:
  struct Disk {
    Vec3 p;
    double radius;
  };
  // Does a disk that may reach p satisfy `test`? Per axis, p's cube and the neighbour on the
  // side of p's nearer face.
  template <class Test>
  bool any_near(Vec3 p, Test&& test) const {
    std::array<int64_t, 3> lo, step;
    for (int a = 0; a < 3; ++a) {
      const double x = p[a] / side_, c = std::floor(x);
      lo[size_t(a)] = int64_t(c), step[size_t(a)] = x - c < 0.5 ? -1 : 1;
    }
    for (int k = 0; k < 8; ++k) {
      const auto it = cells_.find(key({lo[0] + (k & 1 ? step[0] : 0), lo[1] + (k & 2 ? step[1] : 0),
                                       lo[2] + (k & 4 ? step[2] : 0)}));
      if (it == cells_.end()) continue;
      for (const Disk& q : it->second)
        if (test(q)) return true;
    }
    return false;
  }
  std::array<int64_t, 3> cell(Vec3 p) const {
    return {int64_t(std::floor(p.x / side_)), int64_t(std::floor(p.y / side_)), int64_t(std::floor(p.z / side_))};
  }
  static uint64_t key(std::array<int64_t, 3> c) {
    return (uint64_t(c[0]) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(c[1]) * 0xC2B2AE3D27D4EB4Full) ^
           (uint64_t(c[2]) * 0x165667B19E3779F9ull);
  }
  double largest_, side_;
  std::unordered_map<uint64_t, std::vector<Disk>> cells_;
};

// The largest alpha in (0, top] with sqrt(c^2 / alpha^2 - 1) sqrt(1 - 2 alpha L) >= 1 + alpha L
// (interface_factors), by bisection: the left side falls and the right side grows with alpha.
double largest_factor(double c, double top, double L) {
  auto holds = [&](double a) { return std::sqrt(c * c / (a * a) - 1) * std::sqrt(std::max(0.0, 1 - 2 * a * L)) >= 1 + a * L; };
  double lo = 0, hi = top;
  for (int k = 0; k < 100; ++k) {
    const double mid = 0.5 * (lo + hi);
    (holds(mid) ? lo : hi) = mid;
  }
  return lo;
}

// A direction from p into some region (p just off it in that direction is strictly inside one).
Vec3 into_a_region(const RegionSet& set, Vec3 p, const std::vector<Vec3>& candidates, double step) {
  for (Vec3 c : candidates)
    for (const Domain& d : set.solids)
      if (d.contains(p + step * c)) return c;
  return {};
}

// The points (of `seeds`) within 1e-6 r of a segment (reflex corner seeds sit 1e-7 r off their
// vertex), found by cubes of side r around points every r/2 along each segment.
std::vector<size_t> seeds_on(const std::vector<LinePiece>& segments, const std::vector<Vec3>& seeds, double r) {
  auto cube = [r](Vec3 p) {
    return std::array<int64_t, 3>{int64_t(std::floor(p.x / r)), int64_t(std::floor(p.y / r)), int64_t(std::floor(p.z / r))};
  };
  std::map<std::array<int64_t, 3>, std::vector<size_t>> by_cube;
  for (size_t k = 0; k < seeds.size(); ++k) by_cube[cube(seeds[k])].push_back(k);
  std::vector<uint8_t> on(seeds.size(), 0);
  for (const LinePiece& s : segments)
    for (double t = 0;; t = std::min(s.length, t + r / 2)) {
      const auto c = cube(s.a + t * s.dir);
      for (int64_t dz = -1; dz <= 1; ++dz)
        for (int64_t dy = -1; dy <= 1; ++dy)
          for (int64_t dx = -1; dx <= 1; ++dx) {
            const auto it = by_cube.find({c[0] + dx, c[1] + dy, c[2] + dz});
            if (it == by_cube.end()) continue;
            for (size_t k : it->second) {
              const Vec3 w = seeds[k] - s.a;
              const double along = std::clamp(dot(w, s.dir), 0.0, s.length);
              on[k] |= norm(w - along * s.dir) <= 1e-6 * r;
            }
          }
      if (t == s.length) break;
    }
  std::vector<size_t> out;
  for (size_t k = 0; k < seeds.size(); ++k)
    if (on[k]) out.push_back(k);
  return out;
}

}  // namespace

std::array<double, 2> interface_factors(double lipschitz) {
  if (!(lipschitz > 0)) return {0.5, 1 / std::sqrt(2.0)};
  // The nodes' float rounding and the bisection's last bit: a little more slope, a little less.
  const double L = lipschitz * (1 + 1e-6);
  const double facet = largest_factor(1, 1 / std::sqrt(2.0), L) * (1 - 1e-9);
  return {largest_factor(facet, facet / std::sqrt(2.0), L) * (1 - 1e-9), facet};
}

// Samples what is to be protected: a seed just off each corner, the curves in 1D with disks of
// the curve factor, then the triangles in 2D with disks of the facet factor (the paper's §2.2
// recipe, for interfaces now and crack sheets next), all keeping their disks from `prior`.
ProtectionSeeds sample_facets_and_curves(std::vector<ProtectedTriangle> tris, std::vector<LinePiece> segments,
                                         const std::vector<std::pair<Vec3, Vec3>>& corners, double r, uint64_t seed,
                                         const std::vector<Vec3>& prior, double crumb, RandomStream stream,
                                         InterfaceProtectionStats* stats, const std::function<double(Vec3)>& h,
                                         double lipschitz) {
  ProtectionSeeds out;
  // (Not a structured binding: clang 14 cannot capture one in the lambdas below.)
  const std::array<double, 2> factors = interface_factors(h ? lipschitz : 0);
  const double alpha_c = factors[0], alpha_f = factors[1];
  if (stats) stats->curve_factor = alpha_c, stats->facet_factor = alpha_f;
  // The disks about a seed at p: on curves and on facets (uniform: r/2 and r/sqrt(2) exactly).
  const double rc = r / 2, rf = r / std::sqrt(2.0);
  auto curve_disk = [&](Vec3 p) { return h ? alpha_c * std::min(r, h(p)) : rc; };
  auto facet_disk = [&](Vec3 p) { return h ? alpha_f * std::min(r, h(p)) : rf; };
  const CounterRng rng(seed, stream);
  SeedHash hash(rf * (1 + 1e-12));  // the largest disk: alpha_f <= 1/sqrt(2) and h <= r
  for (Vec3 p : prior) hash.add(p, facet_disk(p));
  if (stats) stats->prior_on_curves = seeds_on(segments, prior, r);
  auto add = [&](Vec3 p, CellKind kind, Vec3 in) {
    out.points.push_back(p), out.kinds.push_back(kind), out.inward.push_back(in);
    hash.add(p, facet_disk(p));
    if (kind == CellKind::InterfaceEdge)  // the curves are sampled before the facets
      for (LinePiece& s : segments) remove_disk(s, p, curve_disk(p));
  };
  for (Vec3 p : prior)
    for (LinePiece& s : segments) remove_disk(s, p, curve_disk(p));
  // Corners: a seed each just off the vertex, on the given side (ties between mirror-symmetric
  // corners stay undecidable otherwise, as for reflex corners).
  for (const auto& [v, in] : corners) add(v + 1e-7 * r * in, CellKind::InterfaceEdge, Vec3{});
  // Curves: 1D random sequential addition to saturation with disks of r/2 (protect.cpp); a dart
  // on the uncovered part is outside every earlier disk, whatever their radii.
  saturate_pieces(segments, rng, crumb, [&](size_t k, Vec3 p) { add(p, CellKind::InterfaceEdge, segments[k].inward); });
  if (stats) stats->edge_seeds = out.points.size();
  // Faces: maximal Poisson-disk sampling on the interface triangles with disks of r/sqrt(2)
  // (Ebeida et al. 2012 in 2D): darts uniform by area over the sub-triangles not yet inside one
  // disk, each kept if no earlier seed's disk holds it; then the sub-triangles left are split in
  // four and the darts go on, until every sub-triangle is covered.
  struct Sub {
    std::array<Vec3, 3> p;
    Vec3 inward;
  };
  std::vector<Sub> active;
  auto longest = [](const std::array<Vec3, 3>& p) {
    return std::max({norm(p[1] - p[0]), norm(p[2] - p[1]), norm(p[0] - p[2])});
  };
  auto split4 = [](const Sub& s, std::vector<Sub>& into) {
    const Vec3 a = s.p[0], b = s.p[1], c = s.p[2];
    const Vec3 ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
    into.push_back({{a, ab, ca}, s.inward}), into.push_back({{ab, b, bc}, s.inward});
    into.push_back({{ca, bc, c}, s.inward}), into.push_back({{ab, bc, ca}, s.inward});
  };
  // Starting sub-triangles no longer than the disks' radius: finer ones only multiply the
  // level-0 darts and cover tests.
  for (const ProtectedTriangle& t : tris) {
    std::vector<Sub> work{{t.p, t.inward}};
    while (!work.empty()) {
      Sub s = work.back();
      work.pop_back();
      if (longest(s.p) > rf) split4(s, work);
      else active.push_back(s);
    }
  }
  size_t faces = 0;
  // A sub-triangle is done when one disk holds it, or when it is below 1e-6 r/sqrt(2) and each
  // corner lies in some disk: where two circles cross, a point on both is covered by neither
  // disk's interior alone, and the sub-triangles about it would be split for ever (maximal up to
  // that size, far below anything the cells resolve).
  auto done = [&](const Sub& s) {
    if (hash.covers(s.p)) return true;
    return longest(s.p) < 1e-6 * rf && hash.any_within(s.p[0], 1 + 1e-12) && hash.any_within(s.p[1], 1 + 1e-12) &&
           hash.any_within(s.p[2], 1 + 1e-12);
  };
  // (Bounded: sub-triangles that no disk covers would otherwise grow fourfold a level.)
  for (int level = 0; level < 30 && !active.empty() && active.size() < (size_t(1) << 22); ++level) {
    std::erase_if(active, done);
    if (active.empty()) break;
    std::vector<double> cumulative(active.size());
    double total = 0;
    for (size_t k = 0; k < active.size(); ++k)
      total += norm(cross(active[k].p[1] - active[k].p[0], active[k].p[2] - active[k].p[0])), cumulative[k] = total;
    const size_t darts = 2 * active.size();
    for (size_t dart = 0; dart < darts; ++dart) {
      const auto w = rng.words(dart, uint64_t(level) + 1, 1, 0);
      const double x = CounterRng::unit(w[0]) * total;
      const size_t k = std::min(size_t(std::lower_bound(cumulative.begin(), cumulative.end(), x) - cumulative.begin()),
                                active.size() - 1);
      double u = CounterRng::unit(w[1]), v = CounterRng::unit(w[2]);
      if (u + v > 1) u = 1 - u, v = 1 - v;
      const Sub& s = active[k];
      const Vec3 p = s.p[0] + u * (s.p[1] - s.p[0]) + v * (s.p[2] - s.p[0]);
      if (hash.any_within(p)) continue;
      add(p, CellKind::InterfaceFace, s.inward);
      ++faces;
    }
    std::erase_if(active, done);
    std::vector<Sub> finer;
    for (const Sub& s : active) split4(s, finer);
    active.swap(finer);
  }
  if (stats) stats->face_seeds = faces, stats->uncovered = active.size();
  return out;
}

ProtectionSeeds protect_interfaces(const RegionSet& set, double r, uint64_t seed, const std::vector<Vec3>& prior,
                                   double feature_angle, InterfaceProtectionStats* stats,
                                   const std::function<double(Vec3)>& h, double lipschitz) {
  // The interface triangles, once each (from the region behind their facet's normal), with the
  // facet they are on; and their edges.
  std::vector<ProtectedTriangle> tris;  // inward: against the facet's normal, as the seeds' anchors go
  std::map<std::pair<int32_t, int32_t>, std::vector<int32_t>> facets_at_edge;  // all facets of all regions
  const double cos_feature = std::cos(feature_angle * M_PI / 180);
  for (size_t k = 0; k < set.size(); ++k) {
    const Domain& d = set.solids[k];
    for (size_t t = 0; t < d.surface.triangles.size(); ++t) {
      const auto& v = d.surface.triangles[t];
      const int32_t f = d.triangle_plane[t];
      for (int e = 0; e < 3; ++e) {
        const int32_t a = v[e], b = v[(e + 1) % 3];
        facets_at_edge[{std::min(a, b), std::max(a, b)}].push_back(f);
      }
      if (set.is_interface(f) && set.facet_sides[size_t(f)][0] == int32_t(k))
        tris.push_back({{d.surface.vertices[v[0]], d.surface.vertices[v[1]], d.surface.vertices[v[2]]},
                        -1.0 * set.facet_planes[size_t(f)].normal});
    }
  }
  const std::vector<Vec3>& V = set.solids.empty() ? prior : set.solids[0].surface.vertices;
  // Interface curves: edges of an interface where it meets another interface or the outer
  // boundary (the facets around the edge are not all of one region pair), or bends within one
  // interface by more than the feature angle.
  std::vector<LinePiece> segments;
  std::map<int32_t, int> curve_degree;
  for (auto& [edge, facets] : facets_at_edge) {
    std::sort(facets.begin(), facets.end());
    facets.erase(std::unique(facets.begin(), facets.end()), facets.end());
    bool any_interface = false, curve = false;
    for (int32_t f : facets) any_interface |= set.is_interface(f);
    if (!any_interface || facets.size() < 2) continue;
    auto pair_of = [&](int32_t f) {  // (by value: std::minmax returns references)
      const auto& s = set.facet_sides[size_t(f)];
      return std::pair<int32_t, int32_t>{std::min(s[0], s[1]), std::max(s[0], s[1])};
    };
    for (int32_t f : facets) curve |= pair_of(f) != pair_of(facets[0]);
    if (!curve && facets.size() == 2 &&
        std::abs(dot(set.facet_planes[size_t(facets[0])].normal, set.facet_planes[size_t(facets[1])].normal)) < cos_feature)
      curve = true;
    if (!curve) continue;
    const Vec3 a = V[edge.first], b = V[edge.second];
    const double len = norm(b - a);
    // Off the edge: along a facet's side into the region behind it, tried with exact tests.
    std::vector<Vec3> candidates;
    const Vec3 dir = (1 / len) * (b - a);
    for (int32_t f : facets) {
      const Vec3 n = set.facet_planes[size_t(f)].normal;
      for (double s : {-1.0, 1.0}) {
        const Vec3 along = unit(cross(n, dir));
        candidates.push_back(unit(along + s * 0.5 * n)), candidates.push_back(unit(-1.0 * along + s * 0.5 * n));
      }
    }
    const Vec3 in = into_a_region(set, 0.5 * (a + b), candidates, 1e-6 * r);
    segments.push_back({a, dir, len, in, {{0.0, len}}});
    ++curve_degree[edge.first], ++curve_degree[edge.second];
  }
  // Corners: ends of curves and vertices where more than two curve edges meet, with a direction
  // into a region.
  std::vector<std::pair<Vec3, Vec3>> corners;
  for (const auto& [v, degree] : curve_degree) {
    if (degree == 2) continue;
    std::vector<Vec3> candidates;
    for (int k = 0; k < 256; ++k) {
      const double z = 1 - (2 * k + 1) / 256.0, rho = std::sqrt(1 - z * z), phi = k * 2.399963229728653;
      candidates.push_back({rho * std::cos(phi), rho * std::sin(phi), z});
    }
    const Vec3 in = into_a_region(set, V[v], candidates, 1e-7 * r);
    if (norm2(in) == 0)
      fail(ErrorKind::InvalidInput, fmt::format("found no direction into a region at the interface corner ({}, {}, {})",
                                                V[v].x, V[v].y, V[v].z));
    corners.push_back({V[v], in});
  }
  const double crumb = 1e-12 * std::max(r, set.boundary.bounds.diagonal());
  return sample_facets_and_curves(std::move(tris), std::move(segments), corners, r, seed, prior, crumb,
                                  RandomStream::Interfaces, stats, h, lipschitz);
}

namespace {

// The crack sheets' seeds (protect_cracks), clear of the boundary's, appended to `p`. A seed's
// side a is its inward direction; where the seed is on the solid's surface (on a line where the
// sheet meets it), it is tipped into the solid by the surface's inward normal there.
void add_crack_seeds(const Domain& domain, double r, uint64_t seed, ProtectionSeeds& p, SamplingStats& stats,
                     const std::function<double(Vec3)>& h, double lipschitz) {
  InterfaceProtectionStats cs;
  const CrackSet& set = *domain.cracks;
  ProtectionSeeds q = protect_cracks(set.pieces.empty() ? set.sheets : set.pieces, r, seed, p.points, &cs, h, lipschitz);
  const size_t solid_planes = size_t(set.plane_begin[0]);  // the sheets' come after
  // (A corner seed lies 1e-7 r off its corner, along the sheets' sides a: that far from the
  // surface too where they cross it at a slant.)
  const double near = std::max(1e-9 * domain.bounds.diagonal(), 2e-7 * r);
  std::vector<int32_t> tris;
  for (size_t k = 0; k < q.points.size(); ++k) {
    const Vec3 x = q.points[k];
    const Vec3 reach{near, near, near};
    domain.locator->triangles_near(x - reach, x + reach, tris);
    Vec3 in{};
    for (int32_t t : tris) {
      const size_t plane = size_t(domain.triangle_plane[size_t(t)]);
      if (plane >= solid_planes) continue;
      const Plane& pl = domain.planes[plane];
      if (std::abs(dot(pl.normal, x) - pl.offset) <= near) in = in - pl.normal;
    }
    // On a sheet's line on an interface (a sheet crossing it): into the first region there.
    if (const RegionSet* regions = set.solid.regions.get()) {
      Vec3 into{};
      for (size_t region = 0; region < regions->size() && norm2(into) == 0; ++region) {
        const Domain& solid = regions->solids[region];
        solid.locator->triangles_near(x - reach, x + reach, tris);
        for (int32_t t : tris) {
          const int32_t f = solid.triangle_plane[size_t(t)];
          const Plane& pl = solid.planes[size_t(f)];
          if (regions->is_interface(f) && std::abs(dot(pl.normal, x) - pl.offset) <= near) into = -1.0 * pl.normal;
        }
      }
      in = in + into;
    }
    if (norm2(in) > 0) q.inward[k] = unit(q.inward[k] + unit(in));
  }
  p.points.insert(p.points.end(), q.points.begin(), q.points.end());
  p.kinds.insert(p.kinds.end(), q.kinds.begin(), q.kinds.end());
  p.inward.insert(p.inward.end(), q.inward.begin(), q.inward.end());
  stats.crack_edge_seeds = cs.edge_seeds, stats.crack_face_seeds = cs.face_seeds;
}

}  // namespace

ProtectionSeeds protect_boundary_and_interfaces(const Domain& domain, double r, uint64_t seed, SamplingStats& stats,
                                                const std::function<double(Vec3)>& h, double lipschitz) {
  ProtectionSeeds p;
  // A solid cut along cracks: the reflex features are the solid's (its curves on the uncut surface).
  const Domain& solid = domain.cracks ? domain.cracks->solid : domain;
  if (!solid.convex) p = protect_reflex_features(solid, r, seed, h);
  const size_t reflex = p.points.size();
  stats.vertex_seeds = size_t(std::count(p.kinds.begin(), p.kinds.end(), CellKind::Vertex));
  stats.edge_seeds = reflex - stats.vertex_seeds;
  if (domain.cracks) add_crack_seeds(domain, r, seed, p, stats, h, lipschitz);
  if (!solid.regions) return p;
  InterfaceProtectionStats is;
  const ProtectionSeeds q =
      protect_interfaces(*solid.regions, r, seed, p.points, domain.features.angle_degrees, &is, h, lipschitz);
  for (size_t k : is.prior_on_curves) p.kinds[k] = CellKind::InterfaceEdge;
  p.points.insert(p.points.end(), q.points.begin(), q.points.end());
  p.kinds.insert(p.kinds.end(), q.kinds.begin(), q.kinds.end());
  p.inward.insert(p.inward.end(), q.inward.begin(), q.inward.end());
  stats.interface_edge_seeds = is.edge_seeds, stats.interface_face_seeds = is.face_seeds;
  stats.interface_uncovered = is.uncovered;
  stats.interface_curve_factor = is.curve_factor, stats.interface_facet_factor = is.facet_factor;
  return p;
}

}  // namespace froth
