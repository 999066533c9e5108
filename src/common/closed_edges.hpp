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

}  // namespace froth
