// The processes a run is spread over: ranks 0 .. size-1 in a line, each owning a slab of the
// sampling grid's z layers (froth/partition.hpp). Sampling, the partitioned pipeline and the
// command line's ensembles talk through it; the library has no MPI dependency (froth's command
// line provides an MPI implementation, the tests one made of threads).
#pragma once
#include <cstdint>
#include <vector>

namespace froth {

// Every rank makes the same sequence of calls.
class Communicator {
 public:
  using Bytes = std::vector<uint8_t>;
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Sends to_lower to rank - 1 and to_upper to rank + 1 (dropped at the ends of the line) and
  // returns what rank - 1 sent up in from_lower and what rank + 1 sent down in from_upper.
  virtual void exchange_with_neighbours(const Bytes& to_lower, const Bytes& to_upper, Bytes& from_lower,
                                        Bytes& from_upper) = 0;
  // Every rank's bytes, in rank order, on every rank.
  virtual std::vector<Bytes> all_gather(const Bytes& mine) = 0;

  // Plain values over all ranks, by all_gather (every rank calls them together).
  std::vector<uint64_t> gather(uint64_t mine);  // every rank's, in rank order
  uint64_t sum(uint64_t mine);
  double max(double mine);
  int max(int mine) { return int(max(double(mine))); }  // exact: ints are doubles
  bool any(bool mine) { return sum(mine) > 0; }
};

// One process: the line of one rank.
class SoloCommunicator : public Communicator {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  void exchange_with_neighbours(const Bytes&, const Bytes&, Bytes& from_lower, Bytes& from_upper) override {
    from_lower.clear();
    from_upper.clear();
  }
  std::vector<Bytes> all_gather(const Bytes& mine) override { return {mine}; }
};

// A rank's slab and its halos, in layers of base cubes (z index of the sampling grid).
struct Slab {
  int owned_begin = 0, owned_end = 0;    // layers this rank owns
  int window_begin = 0, window_end = 0;  // with the halo, clamped to the grid
};

// The sampling halo: darts and seeds within r of an owned cube, r / side = sqrt(3) < 2 layers.
constexpr int kSamplingHaloLayers = 2;

}  // namespace froth
