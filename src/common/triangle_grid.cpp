#include "common/triangle_grid.hpp"

#include <algorithm>
#include <cmath>

namespace froth {

TriangleGrid::TriangleGrid(const TriangleSurface& surface, const SurfaceLocator& locator, double side)
    : locator_(&locator) {
  fill(surface, side, false);
}

TriangleGrid::TriangleGrid(const TriangleSurface& surface) { fill(surface, 0, true); }

void TriangleGrid::fill(const TriangleSurface& surface, double side, bool for_segments) {
  const auto& V = surface.vertices;
  Box all{V.empty() ? Vec3{} : V[0], V.empty() ? Vec3{} : V[0]};
  std::vector<Box> boxes;  // per triangle
  boxes.reserve(surface.triangles.size());
  for (const auto& t : surface.triangles) {
    Box b{V[t[0]], V[t[0]]};
    for (int k = 1; k < 3; ++k)
      for (int a = 0; a < 3; ++a) b.lo[a] = std::min(b.lo[a], V[t[k]][a]), b.hi[a] = std::max(b.hi[a], V[t[k]][a]);
    for (int a = 0; a < 3; ++a) all.lo[a] = std::min(all.lo[a], b.lo[a]), all.hi[a] = std::max(all.hi[a], b.hi[a]);
    boxes.push_back(b);
  }
  if (for_segments && !boxes.empty()) {  // the median triangle's longest side
    std::vector<double> extent;
    extent.reserve(boxes.size());
    for (const Box& b : boxes) extent.push_back(std::max({b.size().x, b.size().y, b.size().z}));
    std::nth_element(extent.begin(), extent.begin() + int64_t(extent.size() / 2), extent.end());
    side = extent[extent.size() / 2];
  }
  // At most 256 buckets along an axis: a fine grid over a large, thin or hollow surface would
  // cost more memory than the queries gain.
  side_ = std::max({side, all.size().x / 256, all.size().y / 256, all.size().z / 256, 1e-300});
  origin_ = all.lo;
  for (int a = 0; a < 3; ++a) n_[a] = std::max(1, int(std::ceil(all.size()[a] / side_)));
  begin_.assign(size_t(n_[0]) * n_[1] * n_[2] + 1, 0);
  // Counting sort of (bucket, triangle) by bucket, triangles ascending within a bucket.
  int first[3], last[3];
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<uint32_t> next;
    if (pass == 1) {
      for (size_t b = 1; b < begin_.size(); ++b) begin_[b] += begin_[b - 1];
      ids_.resize(begin_.back());
      if (for_segments) boxes_.resize(begin_.back());
      next.assign(begin_.begin(), begin_.end() - 1);
    }
    for (size_t t = 0; t < boxes.size(); ++t) {
      locate(boxes[t].lo, boxes[t].hi, first, last);
      for (int k = first[2]; k <= last[2]; ++k)
        for (int j = first[1]; j <= last[1]; ++j)
          for (int i = first[0]; i <= last[0]; ++i) {
            const size_t b = (size_t(k) * n_[1] + j) * n_[0] + i;
            if (pass == 0) ++begin_[b + 1];
            else {
              if (for_segments) {
                FloatBox& f = boxes_[next[b]];
                for (int a = 0; a < 3; ++a)
                  f.lo[a] = std::nextafter(float(boxes[t].lo[a]), -INFINITY),
                  f.hi[a] = std::nextafter(float(boxes[t].hi[a]), INFINITY);
              }
              ids_[next[b]++] = int32_t(t);
            }
          }
    }
  }
}

// The range of buckets the box meets, clamped to the grid; false if it misses the grid.
bool TriangleGrid::locate(Vec3 lo, Vec3 hi, int first[3], int last[3]) const {
  for (int a = 0; a < 3; ++a) {
    const double u = (lo[a] - origin_[a]) / side_, v = (hi[a] - origin_[a]) / side_;
    if (v < 0 || u > n_[a]) return false;
    first[a] = std::clamp(int(std::floor(u)), 0, n_[a] - 1);
    last[a] = std::clamp(int(std::floor(v)), 0, n_[a] - 1);
  }
  return true;
}

void TriangleGrid::triangles_near(Vec3 lo, Vec3 hi, std::vector<int32_t>& out) const {
  out.clear();
  int first[3], last[3];
  if (!locate(lo, hi, first, last)) return;
  for (int k = first[2]; k <= last[2]; ++k)
    for (int j = first[1]; j <= last[1]; ++j)
      for (int i = first[0]; i <= last[0]; ++i) {
        const size_t b = (size_t(k) * n_[1] + j) * n_[0] + i;
        out.insert(out.end(), ids_.begin() + begin_[b], ids_.begin() + begin_[b + 1]);
      }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  // The exact test rejects by bounding box first.
  std::erase_if(out, [&](int32_t t) { return !locator_->triangle_meets_box(t, lo, hi); });
}

}  // namespace froth
