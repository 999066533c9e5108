// Protection of a multi-region solid's interfaces (paper §2.2, "Non-manifold geometry"): the
// curves where an interface meets another or the outer boundary (or bends by more than the
// feature angle) get a seed at each corner and are maximally sampled in 1D with disks of r/2;
// then the interface facets are maximally Poisson-disk sampled in 2D with disks of r/sqrt(2),
// uniform by area. A free seed keeps r from all of them, so it is at least r/sqrt(2) from a
// planar interface (r^2 - (r/sqrt(2))^2 = r^2/2 above the farthest point of the disks' cover)
// and every interface point is closest to an interface seed: interfaces cut only interface
// seeds' cells, in two pieces that agree on the interface. The argument is exact on planar
// facets and holds up to the curvature on tessellated curved ones.
#pragma once
#include <cstdint>
#include <vector>

#include "froth/domain.hpp"
#include "sampling/protect.hpp"

namespace froth {

struct InterfaceProtectionStats {
  size_t edge_seeds = 0, face_seeds = 0;
  size_t uncovered = 0;  // sub-triangles no disk covers at the finest level (0: maximal)
  // Indices into `prior` of the seeds on an interface curve (where it is a reflex edge of the
  // outer boundary too): they are that curve's seeds there, so their cells are interface cells.
  std::vector<size_t> prior_on_curves;
};

// A pure function of (regions, r, seed). Seeds keep their radius (r/2 on curves, r/sqrt(2) on
// facets) from each other and from `prior` (the outer boundary's reflex protection seeds).
ProtectionSeeds protect_interfaces(const RegionSet& regions, double r, uint64_t seed, const std::vector<Vec3>& prior,
                                   double feature_angle, InterfaceProtectionStats* stats = nullptr);

}  // namespace froth
