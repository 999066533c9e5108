// Protection of a multi-region solid's interfaces (paper §2.2, "Non-manifold geometry"): the
// curves where an interface meets another or the outer boundary (or bends by more than the
// feature angle) get a seed at each corner and are maximally sampled in 1D with disks of r/2;
// then the interface facets are maximally Poisson-disk sampled in 2D with disks of r/sqrt(2),
// uniform by area. A free seed keeps r from all of them, so it is at least r/sqrt(2) from a
// planar interface (r^2 - (r/sqrt(2))^2 = r^2/2 above the farthest point of the disks' cover)
// and every interface point is closest to an interface seed: interfaces cut only interface
// seeds' cells, in two pieces that agree on the interface. The argument is exact on planar
// facets and holds up to the curvature on tessellated curved ones.
//
// With a sizing field h of Lipschitz bound L (sampling/sizing.hpp), the disks are alpha_c h(p)
// on curves and alpha_f h(p) on facets around each seed p (an earlier seed's disk rules, as in
// the graded sampler), and free seeds keep h(p). The factors shrink from 1/2 and 1/sqrt(2) so
// that the argument above survives h changing between neighbouring seeds (interface_factors).
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "froth/domain.hpp"
#include "froth/mesh.hpp"
#include "common/random.hpp"
#include "sampling/protect.hpp"

namespace froth {

struct InterfaceProtectionStats {
  size_t edge_seeds = 0, face_seeds = 0;
  size_t uncovered = 0;  // sub-triangles no disk covers at the finest level (0: maximal)
  double curve_factor = 0.5, facet_factor = 0.7071067811865476;  // alpha_c, alpha_f
  // Indices into `prior` of the seeds on an interface curve (where it is a reflex edge of the
  // outer boundary too): they are that curve's seeds there, so their cells are interface cells.
  std::vector<size_t> prior_on_curves;
};

// The disks' factors {alpha_c, alpha_f} for a field of Lipschitz bound L: {1/2, 1/sqrt(2)} at
// L = 0. A free seed f over a facet point p covered by seed s (|p - s| <= alpha_f h(s),
// |f - s| >= h(s)) is at height z >= b alpha_f h(s), b = sqrt(1/alpha_f^2 - 1); a facet point
// x at distance t from p lies in the disk of some s' with h(s') <= h(s) + L |s - s'|, so
// alpha_f h(s') <= (a (1 + e) + e t) / (1 - e), a = alpha_f h(s), e = alpha_f L. The least of
// (1 - e) sqrt(t^2 + b^2 a^2) - e t over t is a b sqrt(1 - 2e): x is nearer s' than f when
// b sqrt(1 - 2e) >= 1 + e, the largest such alpha_f. The same with facet seeds keeping
// alpha_f h(c) from a curve seed c gives alpha_c, with b = sqrt(alpha_f^2 / alpha_c^2 - 1).
std::array<double, 2> interface_factors(double lipschitz);

// A triangle to sample, with the direction its seeds' anchors lie in (off the triangle).
struct ProtectedTriangle {
  std::array<Vec3, 3> p;
  Vec3 inward;
};

// The sampling of protect_interfaces, for any triangles, curves (`segments`, their uncovered
// parts the whole) and corners (a point and the direction its seed is put off it): corner seeds,
// then 1D MPS of the curves with disks of alpha_c h, then 2D MPS of the triangles with disks of
// alpha_f h, keeping their disks from `prior`. Gaps up to `crumb` are left on curves. The darts
// come from `stream` of the seed, one stream per kind of feature.
ProtectionSeeds sample_facets_and_curves(std::vector<ProtectedTriangle> tris, std::vector<LinePiece> segments,
                                         const std::vector<std::pair<Vec3, Vec3>>& corners, double r, uint64_t seed,
                                         const std::vector<Vec3>& prior, double crumb, RandomStream stream,
                                         InterfaceProtectionStats* stats, const std::function<double(Vec3)>& h = {},
                                         double lipschitz = 0);

// A pure function of (regions, r, seed, h). Seeds keep their disks (radius r/2 on curves and
// r/sqrt(2) on facets, or the factors times h) from each other and from `prior` (the outer
// boundary's reflex protection seeds).
ProtectionSeeds protect_interfaces(const RegionSet& regions, double r, uint64_t seed, const std::vector<Vec3>& prior,
                                   double feature_angle, InterfaceProtectionStats* stats = nullptr,
                                   const std::function<double(Vec3)>& h = {}, double lipschitz = 0);

}  // namespace froth

namespace froth {

// Every protection seed: the outer boundary's reflex ones (protect.hpp), then for a
// multi-region solid its interfaces', which keep their disks from them; the counts go to `stats`.
ProtectionSeeds protect_boundary_and_interfaces(const Domain& domain, double r, uint64_t seed, SamplingStats& stats,
                                                const std::function<double(Vec3)>& h = {}, double lipschitz = 0);

}  // namespace froth
