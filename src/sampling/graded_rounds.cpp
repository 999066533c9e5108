// A graded round decided across ranks (sampling/graded_rounds.hpp).
#include "sampling/graded_rounds.hpp"

#include "common/wire_bytes.hpp"
#include "froth/error.hpp"

namespace froth {
namespace {

enum : uint8_t { Undecided, Accepted, Rejected };
enum : uint8_t { Own, FromLower, FromUpper };

}  // namespace

AcceptedDarts accept_across_ranks(const std::vector<GradedDart>& own, const SeedBlocks& grid, const SizingField& h,
                                  double reach_factor, const SamplingPartition& partition, size_t& exchanges) {
  const BackgroundGrid& g = grid.grid();
  const Slab& slab = partition.slab;
  auto cube_of = [&](Vec3 p) {
    int i, j, k;
    g.locate(p, i, j, k);
    return g.index(i, j, k);
  };
  const int64_t layer = int64_t(g.nx) * g.ny;
  // The darts in the layers a neighbour's window holds go to that neighbour (in arrival order).
  auto for_lower = [&](int64_t cube) { return cube / layer < slab.owned_begin + kSamplingHaloLayers; };
  auto for_upper = [&](int64_t cube) { return cube / layer >= slab.owned_end - kSamplingHaloLayers; };
  std::vector<GradedDart> to_lower, to_upper;
  for (const GradedDart& d : own) {
    const int64_t cube = cube_of(d.p);
    if (for_lower(cube)) to_lower.push_back(d);
    if (for_upper(cube)) to_upper.push_back(d);
  }
  Communicator::Bytes below, above;
  partition.comm->exchange_with_neighbours(to_bytes(to_lower.data(), to_lower.size()),
                                           to_bytes(to_upper.data(), to_upper.size()), below, above);
  ++exchanges;

  // All darts in arrival order, each with its source; each side's keep their order, so both
  // ranks list the darts whose decisions they trade in the same order.
  std::vector<GradedDart> all = own;
  std::vector<uint8_t> source(own.size(), Own);
  for (const auto& [bytes, from] : {std::pair{&below, FromLower}, std::pair{&above, FromUpper}}) {
    const std::vector<GradedDart> theirs = from_bytes<GradedDart>(*bytes);
    all.insert(all.end(), theirs.begin(), theirs.end());
    source.resize(all.size(), from);
  }
  std::vector<uint32_t> order(all.size());
  for (size_t c = 0; c < order.size(); ++c) order[c] = uint32_t(c);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return arrives_before(all[a], all[b]); });
  const size_t n = all.size();
  std::vector<GradedDart> dart(n);
  std::vector<uint8_t> from(n);
  std::vector<double> radius(n);
  std::vector<uint32_t> send_lower, send_upper, from_lower, from_upper;
  // The darts by base cube (then arrival), so the darts near a point are read row by row.
  std::vector<std::pair<int64_t, uint32_t>> by_cube(n);
  for (size_t c = 0; c < n; ++c) {
    dart[c] = all[order[c]], from[c] = source[order[c]], radius[c] = h.at(dart[c].p);
    const int64_t cube = cube_of(dart[c].p);
    by_cube[c] = {cube, uint32_t(c)};
    if (from[c] == FromLower) from_lower.push_back(uint32_t(c));
    else if (from[c] == FromUpper) from_upper.push_back(uint32_t(c));
    else {
      if (for_lower(cube)) send_lower.push_back(uint32_t(c));
      if (for_upper(cube)) send_upper.push_back(uint32_t(c));
    }
  }
  std::sort(by_cube.begin(), by_cube.end());

  // Passes in arrival order: a dart is rejected by an earlier accepted dart whose disk holds it,
  // accepted once every earlier dart whose disk holds it is rejected, and otherwise waits for a
  // neighbour's decision. The earliest undecided dart anywhere can always be decided, so the
  // passes end, with the serial sampler's decisions.
  std::vector<uint8_t> state(n, Undecided);
  for (;;) {
    bool undecided = false;
    for (size_t c = 0; c < n; ++c) {
      if (from[c] != Own || state[c] != Undecided) continue;
      const Vec3 p = dart[c].p;
      bool blocked = false, rejected = false;
      grid.for_rows_near(p, graded_reach(h, reach_factor, p, 0), [&](int k, int j, int i0, int i1) {
        auto it = std::lower_bound(by_cube.begin(), by_cube.end(), std::pair{g.index(i0, j, k), uint32_t(0)});
        for (const int64_t end = g.index(i1, j, k); it != by_cube.end() && it->first <= end; ++it) {
          const uint32_t o = it->second;
          if (o >= c || norm2(p - dart[o].p) >= radius[o] * radius[o]) continue;
          if (state[o] == Accepted) return rejected = true;
          blocked |= state[o] == Undecided;
        }
        return false;
      });
      state[c] = rejected ? Rejected : blocked ? Undecided : Accepted;
      undecided |= state[c] == Undecided;
    }
    // Trade decisions, then stop when no rank has an undecided dart (the trade before that last
    // check delivered the final ones).
    auto states = [&](const std::vector<uint32_t>& darts) {
      Communicator::Bytes out(darts.size());
      for (size_t k = 0; k < darts.size(); ++k) out[k] = state[darts[k]];
      return out;
    };
    partition.comm->exchange_with_neighbours(states(send_lower), states(send_upper), below, above);
    ++exchanges;
    if (below.size() != from_lower.size() || above.size() != from_upper.size())
      fail(ErrorKind::Internal, "a partitioned graded round: the neighbours' decisions do not match their darts");
    for (size_t k = 0; k < from_lower.size(); ++k) state[from_lower[k]] = below[k];
    for (size_t k = 0; k < from_upper.size(); ++k) state[from_upper[k]] = above[k];
    if (!partition.comm->any(undecided)) break;
  }
  AcceptedDarts out;
  for (size_t c = 0; c < n; ++c)
    if (state[c] == Accepted) out.point.push_back(dart[c].p), out.radius.push_back(radius[c]);
  return out;
}

}  // namespace froth
