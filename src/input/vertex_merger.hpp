// Vertices merged exactly: bit-equal coordinates (with -0 == +0) are one vertex, whatever the
// input format. Nothing is snapped.
#pragma once
#include <cstdint>
#include <cstring>
#include <unordered_map>

#include "froth/domain.hpp"

namespace froth {

struct BitKey {
  uint64_t a, b, c;
  bool operator==(const BitKey&) const = default;
};
struct BitKeyHash {
  size_t operator()(const BitKey& k) const {
    uint64_t h = k.a * 0x9E3779B97F4A7C15ull;
    h ^= (k.b + 0x632BE59BD9B4E019ull + (h << 6) + (h >> 2));
    h ^= (k.c + 0x85EBCA77C2B2AE63ull + (h << 6) + (h >> 2));
    return h;
  }
};

class VertexMerger {
 public:
  explicit VertexMerger(TriangleSurface& s) : s_(s) {}
  int32_t add(Vec3 p) {
    BitKey k{bits(p.x), bits(p.y), bits(p.z)};
    auto [it, inserted] = ids_.try_emplace(k, static_cast<int32_t>(s_.vertices.size()));
    if (inserted) s_.vertices.push_back(p);
    return it->second;
  }

 private:
  static uint64_t bits(double v) {
    if (v == 0) v = 0;  // -0 and +0 are one coordinate
    uint64_t u;
    std::memcpy(&u, &v, sizeof u);
    return u;
  }
  TriangleSurface& s_;
  std::unordered_map<BitKey, int32_t, BitKeyHash> ids_;
};

}  // namespace froth
