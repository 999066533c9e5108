// Maximal Poisson-disk sampling with a varying radius h(x) <= r (Mitchell, Rand, Ebeida et al.,
// "Variable radii Poisson-disk sampling", CCCG 2012, with their "prior" disks: a candidate is
// rejected inside the disk of radius h(s) of any earlier seed s). After Ebeida et al. 2012: darts
// form a space-time Poisson process over the cubes not yet covered, in rounds that refine the
// cubes by halving; they are decided in arrival order, so the sample is that of random
// sequential addition run to saturation, and a pure function of (domain, h, seed).
//
// Guarantees, for a field of Lipschitz bound L < 1/2: any two seeds are at least min(h_i, h_j)
// apart (the earlier one's radius); every point of the domain lies in some seed's disk, so a
// point whose nearest seed is s lies within h(s) / (1 - 2L) of it, and always within r.
#pragma once
#include <cstdint>

#include "froth/domain.hpp"
#include "sampling/mps.hpp"
#include "sampling/sizing.hpp"

namespace froth {

// The sample on the uniform sampler's grid (base cubes of side r/sqrt(3)), a base cube holding
// a list of seeds where h < r; protection seeds (reflex edges at h/sqrt(2)) first.
// With a partition, the seeds of the slab's window only, the same as the serial sample's there
// (graded_rounds.hpp); every rank must call it together. `progress`, if set, is told after each
// round of darts the fraction of the domain covered.
Sample sample_graded_poisson_disk(const Domain& domain, const SizingField& h, uint64_t seed,
                                  SamplingPartition* partition = nullptr,
                                  const std::function<void(double)>& progress = {});

}  // namespace froth
