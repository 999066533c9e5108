// Unbiased maximal Poisson-disk sampling (Ebeida et al. 2012, "A simple algorithm for maximal
// Poisson-disk sampling in high dimensions"), with a schedule defined on the global grid.
#pragma once
#include <functional>
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "common/background_grid.hpp"
#include "froth/domain.hpp"
#include "froth/mesh.hpp"
#include "froth/communicator.hpp"

namespace froth {

struct Sample {
  BackgroundGrid grid;
  std::vector<Vec3> seeds;          // ordered by base cube index
  // Per base cube: index of its seed, -1 if none, or -2 - k if it holds several protection
  // seeds (r_e apart, closer than a cube's diagonal): cube_extra[cube_extra_begin[k] ...].
  // A partitioned run holds only a window of z layers: cube_seed[c - cube_offset] is base cube
  // c's entry, and cubes outside the window hold no seed here.
  std::vector<int32_t> cube_seed;
  int64_t cube_offset = 0;
  std::vector<int32_t> cube_extra_begin, cube_extra;
  // Protection seeds (src/sampling/protect.hpp), sorted by seed index: kind and a direction
  // into the domain. Every other seed is a free one.
  struct Protected {
    int32_t seed;
    CellKind kind;
    Vec3 inward;
  };
  std::vector<Protected> protected_seeds;
  SamplingStats stats;

  // Calls f(seed index) for every seed of a cube_seed entry.
  template <class F>
  void for_seeds_of_entry(int32_t q, F&& f) const {
    if (q >= 0) return f(q);
    if (q == -1) return;
    for (int32_t k = cube_extra_begin[-2 - q]; k < cube_extra_begin[-1 - q]; ++k) f(cube_extra[k]);
  }
  // Calls f(seed index) for every seed in base cube c.
  template <class F>
  void for_seeds_in_cube(int64_t c, F&& f) const {
    c -= cube_offset;
    if (c < 0 || c >= int64_t(cube_seed.size())) return;
    for_seeds_of_entry(cube_seed[c], f);
  }
  // The cube_seed entries at slot + offset for each of `offsets` that hold seeds, in order, into
  // `found` (room for all); their count. The caller keeps every slot + offset inside cube_seed.
  // Read without a branch per cube: most cubes are empty, and a branch on it mispredicts.
  int occupied_entries(int64_t slot, std::span<const int64_t> offsets, int32_t* found) const {
    const int32_t* at = cube_seed.data() + slot;
    int n = 0;
    for (int64_t off : offsets) {
      const int32_t q = at[off];
      found[n] = q;
      n += q != -1;
    }
    return n;
  }
  const Protected* protection_of(int32_t seed) const {
    auto it = std::lower_bound(protected_seeds.begin(), protected_seeds.end(), seed,
                               [](const Protected& p, int32_t s) { return p.seed < s; });
    return it != protected_seeds.end() && it->seed == seed ? &*it : nullptr;
  }
};

// A rank's share of a partitioned sampling: its slab, and the processes to trade halos with.
struct SamplingPartition {
  Slab slab;  // window: the owned layers and kSamplingHaloLayers on each side
  Communicator* comm = nullptr;
  size_t exchanges = 0;  // out: neighbour exchanges made
};

// A maximal r-disk sample of the domain, a pure function of (domain, r, seed). With a partition,
// the seeds of the slab's window only (the owned ones are final; those in the halo are the ones
// that were needed), the same as the serial sample's there; every rank must call it together.
// `progress`, if set, is told after each round of darts the fraction of the domain covered.
Sample sample_maximal_poisson_disk(const Domain& domain, double r, uint64_t seed,
                                   SamplingPartition* partition = nullptr,
                                   const std::function<void(double)>& progress = {});

}  // namespace froth
