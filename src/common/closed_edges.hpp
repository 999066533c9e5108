// Is a set of polygons one closed, consistently oriented surface, edge by edge? Each directed
// edge (from, to) is one sortable key: the undirected pair, then the direction, so that sorted
// keys come in pairs of one undirected edge, one of each direction, when the surface is closed.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

namespace froth {

// The key of directed edge (from, to); ids below 2^31.
inline uint64_t directed_edge_key(uint32_t from, uint32_t to) {
  return uint64_t(std::min(from, to)) << 32 | uint64_t(std::max(from, to)) << 1 | uint64_t(from > to);
}
// The ends of the edge of `key`, smaller first.
inline uint32_t edge_key_low(uint64_t key) { return uint32_t(key >> 32); }
inline uint32_t edge_key_high(uint64_t key) { return uint32_t(key) >> 1; }

// Sorts `keys` and tells whether every edge is run exactly once each way.
inline bool each_edge_once_each_way(std::vector<uint64_t>& keys) {
  std::sort(keys.begin(), keys.end());
  if (keys.size() % 2) return false;
  for (size_t k = 0; k < keys.size(); k += 2)
    if (keys[k + 1] != (keys[k] | 1) || (keys[k] & 1) || (k + 2 < keys.size() && keys[k + 2] >> 1 == keys[k] >> 1))
      return false;
  return true;
}

// The same test without sorting, for the mesh check (sorting each cell's edges was a third of
// its time): the directed edges go into a small hash table of undirected edges, each with the
// directions seen. Reused from cell to cell: clear() empties only the slots used.
class EdgeUses {
 public:
  void clear() {
    for (uint32_t s : used_) key_[s] = kEmpty, seen_[s] = 0;
    used_.clear();
    repeated_ = false;
  }
  void add(uint32_t from, uint32_t to) {
    if (2 * (used_.size() + 1) > key_.size()) grow();
    const uint8_t direction = from < to ? 1 : 2;
    const size_t s = slot(uint64_t(std::min(from, to)) << 32 | std::max(from, to));
    repeated_ |= (seen_[s] & direction) != 0;
    seen_[s] |= direction;
  }
  // Was every edge run exactly once each way?
  bool each_once_each_way() const {
    if (repeated_) return false;
    for (uint32_t s : used_)
      if (seen_[s] != 3) return false;
    return true;
  }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t(0);
  size_t slot(uint64_t key) {
    const size_t mask = key_.size() - 1;
    size_t s = size_t((key * 0x9E3779B97F4A7C15ull) >> 40) & mask;
    while (key_[s] != key && key_[s] != kEmpty) s = (s + 1) & mask;
    if (key_[s] == kEmpty) key_[s] = key, used_.push_back(uint32_t(s));
    return s;
  }
  void grow() {
    std::vector<uint64_t> keys;
    std::vector<uint8_t> seen;
    for (uint32_t s : used_) keys.push_back(key_[s]), seen.push_back(seen_[s]);
    key_.assign(std::max<size_t>(256, 2 * key_.size()), kEmpty);
    seen_.assign(key_.size(), 0);
    used_.clear();
    for (size_t k = 0; k < keys.size(); ++k) seen_[slot(keys[k])] = seen[k];
  }
  std::vector<uint64_t> key_;
  std::vector<uint8_t> seen_;
  std::vector<uint32_t> used_;
  bool repeated_ = false;
};

}  // namespace froth
