// froth::Communicator over MPI's world, for the command line built with -DFROTH_MPI=ON (without
// it the program is one process: froth::SoloCommunicator, and --partition writes one piece).
#pragma once
#include <climits>
#include <cstdint>
#include <vector>

#ifdef FROTH_MPI
#include <mpi.h>
#endif

#include "froth/error.hpp"
#include "froth/communicator.hpp"

namespace froth_cli {

#ifdef FROTH_MPI
class MpiCommunicator : public froth::Communicator {
 public:
  MpiCommunicator() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  void exchange_with_neighbours(const Bytes& to_lower, const Bytes& to_upper, Bytes& from_lower,
                                Bytes& from_upper) override {
    const int lower = rank_ > 0 ? rank_ - 1 : MPI_PROC_NULL, upper = rank_ + 1 < size_ ? rank_ + 1 : MPI_PROC_NULL;
    // Sizes first, then the bytes; up the line, then down.
    unsigned long long up = to_upper.size(), down = to_lower.size(), from_below = 0, from_above = 0;
    MPI_Sendrecv(&up, 1, MPI_UNSIGNED_LONG_LONG, upper, 0, &from_below, 1, MPI_UNSIGNED_LONG_LONG, lower, 0,
                 MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    MPI_Sendrecv(&down, 1, MPI_UNSIGNED_LONG_LONG, lower, 1, &from_above, 1, MPI_UNSIGNED_LONG_LONG, upper, 1,
                 MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    from_lower.assign(from_below, 0);
    from_upper.assign(from_above, 0);
    MPI_Sendrecv(to_upper.data(), count(up), MPI_BYTE, upper, 2, from_lower.data(), count(from_below), MPI_BYTE, lower,
                 2, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    MPI_Sendrecv(to_lower.data(), count(down), MPI_BYTE, lower, 3, from_upper.data(), count(from_above), MPI_BYTE,
                 upper, 3, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  }

  std::vector<Bytes> all_gather(const Bytes& mine) override {
    const int n = count(mine.size());
    std::vector<int> sizes(size_), offsets(size_ + 1, 0);
    MPI_Allgather(&n, 1, MPI_INT, sizes.data(), 1, MPI_INT, MPI_COMM_WORLD);
    for (int k = 0; k < size_; ++k) offsets[k + 1] = offsets[k] + sizes[k];
    Bytes all(size_t(offsets[size_]));
    MPI_Allgatherv(mine.data(), n, MPI_BYTE, all.data(), sizes.data(), offsets.data(), MPI_BYTE, MPI_COMM_WORLD);
    std::vector<Bytes> out(size_);
    for (int k = 0; k < size_; ++k) out[k].assign(all.begin() + offsets[k], all.begin() + offsets[k + 1]);
    return out;
  }

 private:
  static int count(unsigned long long bytes) {
    if (bytes > INT_MAX) froth::fail(froth::ErrorKind::Internal, "a halo message exceeds 2 GiB: use more ranks");
    return int(bytes);
  }
  int rank_ = 0, size_ = 1;
};
#endif

}  // namespace froth_cli
