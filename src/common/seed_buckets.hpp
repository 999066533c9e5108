// Seeds bucketed in cubes of side r. Points pairwise at least r apart fit at most 8 to such a
// cube (its corners), so a bucket is a fixed array of 8 ids, and a query for the seeds within
// reach of a point or box reads a few contiguous buckets instead of walking the fine sampling
// grid (cubes of side r/sqrt(3), ~0.15 seeds each). Each bucket also keeps its seeds' offsets
// from the bucket's corner as floats (exact to ~1e-7 r), a prefilter that spares most reads of
// the (unordered) seed array; callers still decide with the exact coordinates. Protection seeds
// (r_e apart, or closer at a domain's corners) can crowd a bucket: the ones beyond 8 go to a
// sorted overflow list, read only for the buckets marked full.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "froth/error.hpp"
#include "froth/geometry.hpp"

namespace froth {

class SeedBuckets {
 public:
  static constexpr int kCapacity = 8;

  SeedBuckets() = default;
  SeedBuckets(const Box& box, double r) : origin_(box.lo), side_(r) {
    Vec3 s = box.size();
    n_[0] = std::max(1, int(std::ceil(s.x / r)));
    n_[1] = std::max(1, int(std::ceil(s.y / r)));
    n_[2] = std::max(1, int(std::ceil(s.z / r)));
    slot_.assign(size_t(n_[0]) * n_[1] * n_[2], -1);
  }

  void insert(int32_t id, Vec3 p) {
    int i = axis(p.x - origin_.x, 0), j = axis(p.y - origin_.y, 1), k = axis(p.z - origin_.z, 2);
    const size_t at = index(i, j, k);
    if (slot_[at] < 0) {
      slot_[at] = int32_t(buckets_.size());
      buckets_.emplace_back();
    }
    Bucket& b = buckets_[slot_[at]];
    uint8_t& n = b.count;
    if (n >= kCapacity) {
      n = kCapacity + 1;
      auto it = std::upper_bound(overflow_.begin(), overflow_.end(), at,
                                 [](size_t a, const Overflow& o) { return a < o.bucket; });
      overflow_.insert(it, {at, id});
      return;
    }
    Vec3 c = corner(i, j, k);
    b.x[n] = float(p.x - c.x);
    b.y[n] = float(p.y - c.y);
    b.z[n] = float(p.z - c.z);
    b.id[n++] = id;
  }

  // Calls f(id) for every seed that may lie within `reach` of the box [lo, hi] (a superset of
  // those that do: the float prefilter errs on the side of keeping). If f returns bool, true
  // stops the walk, and for_each_near says whether it was stopped.
  template <class F>
  bool for_each_near(Vec3 lo, Vec3 hi, double reach, F&& f) const {
    constexpr bool stoppable = std::is_same_v<decltype(f(int32_t(0))), bool>;
    auto visit = [&](int32_t id) {
      if constexpr (stoppable) return f(id);
      else return f(id), false;
    };
    int a[3], b[3];
    for (int d = 0; d < 3; ++d) {
      a[d] = axis(lo[d] - reach - origin_[d], d);
      b[d] = axis(hi[d] + reach - origin_[d], d);
    }
    const float reach2 = float(reach * reach * (1 + 1e-4) + 1e-10 * side_ * side_);
    const double reach2_bucket = reach * reach * (1 + 1e-9);
    auto gap = [&](int i, int d) {  // distance along axis d from bucket slab i to [lo, hi]
      double b0 = origin_[d] + i * side_, b1 = b0 + side_;
      double t = b1 < lo[d] ? lo[d] - b1 : (b0 > hi[d] ? b0 - hi[d] : 0.0);
      return t * t;
    };
    for (int k = a[2]; k <= b[2]; ++k) {
      const double gz = gap(k, 2);
      for (int j = a[1]; j <= b[1]; ++j) {
        const double gyz = gz + gap(j, 1);
        if (gyz > reach2_bucket) continue;
        const size_t row = index(0, j, k);
        for (int i = a[0]; i <= b[0]; ++i) {
          const int32_t slot = slot_[row + i];
          if (slot < 0 || gyz + gap(i, 0) > reach2_bucket) continue;
          const Bucket& bk = buckets_[slot];
          const int count = std::min<int>(bk.count, kCapacity);
          if (bk.count > kCapacity) {
            auto it = std::lower_bound(overflow_.begin(), overflow_.end(), row + i,
                                       [](const Overflow& o, size_t a) { return o.bucket < a; });
            for (; it != overflow_.end() && it->bucket == row + i; ++it)
              if (visit(it->id)) return true;
          }
          const Vec3 c = corner(i, j, k);
          const float lx = float(lo.x - c.x), ly = float(lo.y - c.y), lz = float(lo.z - c.z);
          const float hx = float(hi.x - c.x), hy = float(hi.y - c.y), hz = float(hi.z - c.z);
          for (int s = 0; s < count; ++s) {
            float dx = std::max({lx - bk.x[s], bk.x[s] - hx, 0.f});
            float dy = std::max({ly - bk.y[s], bk.y[s] - hy, 0.f});
            float dz = std::max({lz - bk.z[s], bk.z[s] - hz, 0.f});
            if (dx * dx + dy * dy + dz * dz <= reach2 && visit(bk.id[s])) return true;
          }
        }
      }
    }
    return false;
  }


 private:
  struct Bucket {
    float x[kCapacity], y[kCapacity], z[kCapacity];
    int32_t id[kCapacity];
    uint8_t count = 0;  // kCapacity + 1: more in the overflow list
  };
  Vec3 corner(int i, int j, int k) const { return origin_ + Vec3{i * side_, j * side_, k * side_}; }
  int axis(double t, int d) const { return std::clamp(int(std::floor(t / side_)), 0, n_[d] - 1); }
  size_t index(int i, int j, int k) const { return (size_t(k) * n_[1] + j) * n_[0] + i; }

  Vec3 origin_;
  double side_ = 1;
  int n_[3] = {1, 1, 1};
  // Buckets are allocated as seeds arrive: a domain may fill a small part of its bounding box
  // (a slanted slab), and most buckets of the box then stay empty.
  std::vector<int32_t> slot_;  // per bucket of the box: its index in buckets_, or -1
  std::vector<Bucket> buckets_;
  struct Overflow {
    size_t bucket;
    int32_t id;
  };
  std::vector<Overflow> overflow_;
};

}  // namespace froth
