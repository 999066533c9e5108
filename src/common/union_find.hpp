// Disjoint sets over 0..n-1 with path halving. The smaller id becomes the root, so the sets and
// their roots do not depend on the order of unions.
#pragma once
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace froth {

struct UnionFind {
  std::vector<int32_t> parent;
  explicit UnionFind(size_t n) { reset(n); }
  // Back to n singletons, keeping the storage.
  void reset(size_t n) {
    parent.resize(n);
    std::iota(parent.begin(), parent.end(), 0);
  }
  int32_t find(int32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  }
  // True if a and b were in different sets.
  bool unite(int32_t a, int32_t b) {
    a = find(a), b = find(b);
    if (a == b) return false;
    if (a > b) std::swap(a, b);
    parent[b] = a;
    return true;
  }
};

}  // namespace froth
