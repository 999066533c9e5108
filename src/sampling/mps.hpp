// Unbiased maximal Poisson-disk sampling (Ebeida et al. 2012, "A simple algorithm for maximal
// Poisson-disk sampling in high dimensions"), with a schedule defined on the global grid.
#pragma once
#include <cstdint>
#include <vector>

#include "common/background_grid.hpp"
#include "froth/domain.hpp"
#include "froth/mesh.hpp"

namespace froth {

struct Sample {
  BackgroundGrid grid;
  std::vector<Vec3> seeds;          // ordered by base cube index
  std::vector<int32_t> cube_seed;   // per base cube: index of its seed, or -1
  SamplingStats stats;
};

// A maximal r-disk sample of the domain, a pure function of (domain, r, seed).
Sample sample_maximal_poisson_disk(const Domain& domain, double r, uint64_t seed);

}  // namespace froth
