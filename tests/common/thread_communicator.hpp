// Ranks as threads of one process, for testing the partitioned pipeline without MPI.
#pragma once
#include <barrier>
#include <vector>

#include "froth/partition.hpp"

namespace froth::test {

class ThreadWorld {
 public:
  explicit ThreadWorld(int ranks) : sync_(ranks), up_(ranks), down_(ranks), gathered_(ranks) {
    for (int r = 0; r < ranks; ++r) ranks_.emplace_back(*this, r);
  }
  Communicator& rank(int r) { return ranks_[r]; }

 private:
  class Rank : public Communicator {
   public:
    Rank(ThreadWorld& w, int r) : w_(w), r_(r) {}
    int rank() const override { return r_; }
    int size() const override { return int(w_.ranks_.size()); }
    void exchange_with_neighbours(const Bytes& to_lower, const Bytes& to_upper, Bytes& from_lower,
                                  Bytes& from_upper) override {
      w_.down_[r_] = to_lower;
      w_.up_[r_] = to_upper;
      w_.sync_.arrive_and_wait();
      from_lower = r_ > 0 ? w_.up_[r_ - 1] : Bytes{};
      from_upper = r_ + 1 < size() ? w_.down_[r_ + 1] : Bytes{};
      w_.sync_.arrive_and_wait();  // nobody writes again before everyone has read
    }
    std::vector<Bytes> all_gather(const Bytes& mine) override {
      w_.gathered_[r_] = mine;
      w_.sync_.arrive_and_wait();
      std::vector<Bytes> all = w_.gathered_;
      w_.sync_.arrive_and_wait();
      return all;
    }

   private:
    ThreadWorld& w_;
    int r_;
  };

  std::barrier<> sync_;
  std::vector<Communicator::Bytes> up_, down_, gathered_;
  std::vector<Rank> ranks_;
};

}  // namespace froth::test
