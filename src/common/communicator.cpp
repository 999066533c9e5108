// Plain values over the ranks (froth/communicator.hpp), by all_gather.
#include "froth/communicator.hpp"

#include <algorithm>
#include <cstring>

namespace froth {
namespace {

// Every rank's value of a plain type, in rank order.
template <class T>
std::vector<T> gather_values(Communicator& comm, T mine) {
  Communicator::Bytes bytes(sizeof mine);
  std::memcpy(bytes.data(), &mine, sizeof mine);
  std::vector<T> out;
  for (const auto& b : comm.all_gather(bytes)) {
    T v;
    std::memcpy(&v, b.data(), sizeof v);
    out.push_back(v);
  }
  return out;
}

}  // namespace

std::vector<uint64_t> Communicator::gather(uint64_t mine) { return gather_values(*this, mine); }

uint64_t Communicator::sum(uint64_t mine) {
  uint64_t total = 0;
  for (uint64_t v : gather(mine)) total += v;
  return total;
}

double Communicator::max(double mine) {
  for (double v : gather_values(*this, mine)) mine = std::max(mine, v);
  return mine;
}

}  // namespace froth
