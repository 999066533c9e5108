// A round of the graded sampler (graded_mps.cpp) decided across the ranks of a partitioned run:
// the same decisions as the serial sampler's one-by-one pass in arrival order, with each rank
// deciding the darts of its own slab. A dart conflicts only with earlier darts whose disks hold
// it, within h <= r < kSamplingHaloLayers layers, so each rank trades with its neighbours the
// darts of the layers next to them, then their decisions, as the uniform sampler does
// (mps_acceptance.cpp).
#pragma once
#include <algorithm>
#include <tuple>
#include <vector>

#include "froth/geometry.hpp"
#include "sampling/mps.hpp"
#include "sampling/seed_blocks.hpp"
#include "sampling/sizing.hpp"

namespace froth {

struct GradedDart {
  double time;
  Vec3 p;
};

// Arrival order: by time, ties (never seen: times are 53-bit draws) by position.
inline bool arrives_before(const GradedDart& a, const GradedDart& b) {
  return a.time != b.time ? a.time < b.time : std::tie(a.p.x, a.p.y, a.p.z) < std::tie(b.p.x, b.p.y, b.p.z);
}

// How far from p a seed can be whose disk reaches within `extra` of p: |p - q| < h(q) + extra
// and h(q) <= h(p) + lambda |p - q| give (h(p) + extra) / (1 - lambda) = (h(p) + extra)
// reach_factor, and never more than r + extra. The slack covers the sizing nodes' float rounding.
inline double graded_reach(const SizingField& h, double reach_factor, Vec3 p, double extra) {
  return std::min(h.r() + extra, (h.at(p) + extra) * reach_factor + 1e-9 * h.r());
}

struct AcceptedDarts {
  std::vector<Vec3> point;     // in arrival order: this rank's new seeds and its neighbours' near its slab
  std::vector<double> radius;  // h at each
};

// Of `own` (this rank's candidates, in arrival order: darts no seed before the round covers), and
// the neighbours' near this slab, those that no earlier accepted one's disk holds. `grid` walks
// the base cubes around a point; `reach_factor` as in graded_reach. Every rank calls it together;
// `exchanges` counts the trades.
AcceptedDarts accept_across_ranks(const std::vector<GradedDart>& own, const SeedBlocks& grid, const SizingField& h,
                                  double reach_factor, const SamplingPartition& partition, size_t& exchanges);

}  // namespace froth
