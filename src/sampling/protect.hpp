// Protection of reflex features (paper §2.2): a seed on every end of a reflex feature curve, and
// each curve maximally Poisson-disk sampled in 1D with r_e = r/sqrt(2). A seed off the curves
// that keeps distance r from these is then at least r_e from every curve, so every point of a
// reflex edge is closest to a seed on it: the edge lies inside edge and vertex cells, and the
// other cells never wrap around it.
#pragma once
#include <cstdint>
#include <vector>

#include "froth/domain.hpp"
#include "froth/mesh.hpp"

namespace froth {

struct ProtectionSeeds {
  std::vector<Vec3> points;
  std::vector<CellKind> kinds;  // Vertex (a curve's end) or Edge
  // Protection directions: for each seed, a unit vector pointing into the domain from it.
  std::vector<Vec3> inward;
};

// A pure function of (domain, r, seed). Seeds on different curves also keep r_e from each other
// (Euclidean), except curve ends, which are always seeded.
ProtectionSeeds protect_reflex_features(const Domain& domain, double r, uint64_t seed);

}  // namespace froth
