// The surface's triangles bucketed in a uniform grid of cubes, for the clipper's question "which
// triangles meet this cell's box?", asked once per cell near the boundary. The cells' boxes are
// about the size of a grid cube, so a query reads at most eight buckets; the AABB tree it
// replaces there was slow on long, thin triangles (the tube, round.stl).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/surface_locator.hpp"
#include "froth/domain.hpp"

namespace froth {

class TriangleGrid {
 public:
  // Buckets of side about `side` (coarser if the surface's box would need too many).
  TriangleGrid(const TriangleSurface& surface, const SurfaceLocator& locator, double side);
  // For for_triangles_along() only: no locator, each entry's box kept beside it, and buckets the
  // median triangle's size (or coarser, as above), whatever the segments' length. Each triangle
  // is listed in every bucket its box meets, so smaller buckets would list the large facets of a
  // coarse CAD export millions of times, and larger ones would hand a short segment hundreds of
  // fine facets to reject.
  explicit TriangleGrid(const TriangleSurface& surface);

  // The triangles that meet the closed box [lo, hi] (exact), ascending: the same answer as
  // SurfaceLocator::triangles_near.
  void triangles_near(Vec3 lo, Vec3 hi, std::vector<int32_t>& out) const;

  // Calls f(t) for every triangle whose bounding box, widened by `margin`, meets the segment
  // [a, b], some more than once: the entries of the buckets along it (those met by its steps of
  // half a bucket, widened alike), each bucket once, tested by their boxes. Each entry's box sits
  // beside its id: a fine surface puts hundreds of triangles in the buckets a ray reads, and
  // reading each triangle's corners to reject it was most of the time.
  template <class F>
  void for_triangles_along(Vec3 a, Vec3 b, double margin, std::vector<size_t>& buckets, F&& f) const {
    buckets.clear();
    // The part of the segment inside the grid (widened by margin): a ray far longer than the
    // surface's box takes no more steps than the grid has buckets across.
    const Vec3 widen{margin, margin, margin}, end = origin_ + side_ * Vec3{double(n_[0]), double(n_[1]), double(n_[2])};
    double t0, t1;
    if (!clip_to_box(origin_ - widen, end + widen, a, b, t0, t1)) return;
    const Vec3 from = a + t0 * (b - a), to = a + t1 * (b - a);
    const int steps = std::max(1, int(std::ceil(2 * norm(to - from) / side_)));
    const Ray ray(a, b, margin);
    int first[3], last[3];
    size_t earlier = 0;  // from buckets[earlier]: the buckets the step before met
    for (int s = 0; s < steps; ++s) {
      const Vec3 p = from + (double(s) / steps) * (to - from), q = from + (double(s + 1) / steps) * (to - from);
      Vec3 lo, hi;
      for (int k = 0; k < 3; ++k) lo[k] = std::min(p[k], q[k]) - margin, hi[k] = std::max(p[k], q[k]) + margin;
      const size_t step_begin = buckets.size();
      if (!locate(lo, hi, first, last)) {
        earlier = step_begin;
        continue;
      }
      for (int k = first[2]; k <= last[2]; ++k)
        for (int j = first[1]; j <= last[1]; ++j)
          for (int i = first[0]; i <= last[0]; ++i) {
            // A bucket two steps meet, every step between meets too (the segment's coordinates
            // are monotone): the step before has it listed if it was read.
            const size_t bucket = (size_t(k) * n_[1] + j) * n_[0] + i;
            const auto before_end = buckets.begin() + std::ptrdiff_t(step_begin);
            const bool read = std::find(buckets.begin() + std::ptrdiff_t(earlier), before_end, bucket) != before_end;
            buckets.push_back(bucket);
            if (read) continue;
            for (uint32_t e = begin_[bucket]; e < begin_[bucket + 1]; ++e)
              if (ray.meets(boxes_[e])) f(ids_[e]);
          }
      earlier = step_begin;
    }
  }

 private:
  struct FloatBox {
    float lo[3], hi[3];  // rounded outward
  };
  // The slab test: the parameters [t0, t1] of the segment a + t (b - a), 0 <= t <= 1, inside
  // the box [lo, hi]; false if there are none.
  static bool clip_to_box(Vec3 lo, Vec3 hi, Vec3 a, Vec3 b, double& t0, double& t1) {
    t0 = 0, t1 = 1;
    for (int k = 0; k < 3; ++k) {
      const double d = b[k] - a[k];
      if (d == 0) {
        if (a[k] < lo[k] || a[k] > hi[k]) return false;
        continue;
      }
      double u = (lo[k] - a[k]) / d, v = (hi[k] - a[k]) / d;
      if (u > v) std::swap(u, v);
      t0 = std::max(t0, u), t1 = std::min(t1, v);
      if (t0 > t1) return false;
    }
    return true;
  }
  // The slab test of a segment against entries' boxes widened by margin, by products with the
  // direction's inverse, not divisions (the test of every entry along a ray was most of the
  // feature-size stage). Their rounding is far below the margin, which the callers keep for it.
  struct Ray {
    Vec3 a, inverse;
    bool along[3];  // the segment keeps this coordinate
    double margin;
    Ray(Vec3 from, Vec3 to, double m) : a(from), margin(m) {
      for (int k = 0; k < 3; ++k) along[k] = to[k] == from[k], inverse[k] = along[k] ? 0 : 1 / (to[k] - from[k]);
    }
    bool meets(const FloatBox& box) const {
      double t0 = 0, t1 = 1;
      for (int k = 0; k < 3; ++k) {
        const double lo = double(box.lo[k]) - margin, hi = double(box.hi[k]) + margin;
        if (along[k]) {
          if (a[k] < lo || a[k] > hi) return false;
          continue;
        }
        double u = (lo - a[k]) * inverse[k], v = (hi - a[k]) * inverse[k];
        if (u > v) std::swap(u, v);
        t0 = std::max(t0, u), t1 = std::min(t1, v);
        if (t0 > t1) return false;
      }
      return true;
    }
  };
  void fill(const TriangleSurface& surface, double side, bool for_segments);
  bool locate(Vec3 lo, Vec3 hi, int first[3], int last[3]) const;
  const SurfaceLocator* locator_ = nullptr;
  Vec3 origin_;
  double side_ = 1;
  int n_[3] = {1, 1, 1};
  std::vector<uint32_t> begin_;  // per bucket, into ids_
  std::vector<int32_t> ids_;
  std::vector<FloatBox> boxes_;  // per entry of ids_, where kept
};

}  // namespace froth
