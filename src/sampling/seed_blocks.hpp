// The graded sampler's seeds (graded_mps.cpp) with their disks' radii, listed by base cube of the
// sampling grid. The lists are kept only for the blocks of 8^3 base cubes that hold the domain,
// each block's cubes together in memory, as a walk around a point reads them: the grid spans the
// domain's bounding box, which a thin or slanted part fills little of (step.off's grid has 48
// million cubes for 720,000 in the part).
#pragma once
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/background_grid.hpp"

namespace froth {

class SeedBlocks {
 public:
  static constexpr int kBlock = 8, kBlockCubes = kBlock * kBlock * kBlock;

  // Read-only outside add() and order_by_place(): seed q's centre and radius.
  std::vector<Vec3> point;
  std::vector<double> radius;

  explicit SeedBlocks(const BackgroundGrid& grid)
      : grid_(grid), blocks_x_((grid.nx + kBlock - 1) / kBlock), blocks_y_((grid.ny + kBlock - 1) / kBlock) {}

  const BackgroundGrid& grid() const { return grid_; }
  int blocks_x() const { return blocks_x_; }
  int blocks_y() const { return blocks_y_; }
  size_t block_count() const { return size_t(blocks_x_) * blocks_y_ * size_t((grid_.nz + kBlock - 1) / kBlock); }
  size_t size() const { return point.size(); }
  // Places for the base cubes of every block with used[b] (blocks numbered x fastest).
  void place_blocks(const std::vector<char>& used) {
    block_slot_.assign(used.size(), -1);
    int32_t slots = 0;
    for (size_t b = 0; b < used.size(); ++b)
      if (used[b]) block_slot_[b] = slots++;
    head_.assign(size_t(slots) * kBlockCubes, -1);
    occupied_.assign(head_.size() / kBlock, 0);
  }
  // The number of places: arrays indexed by cube_slot() take this size.
  size_t places() const { return head_.size(); }

  // Base cube (i, j, k)'s place, or -1 in a block without places.
  int64_t cube_slot(int i, int j, int k) const {
    const int64_t slot = block_slot_[block_of(i, j, k)];
    return slot < 0 ? -1 : slot * kBlockCubes + (k % kBlock * kBlock + j % kBlock) * kBlock + i % kBlock;
  }

  // Adds a seed (numbered size() before the call) to its base cube's list.
  void add(Vec3 p, double r) {
    int i, j, k;
    grid_.locate(p, i, j, k);
    int64_t c = cube_slot(i, j, k);
    if (c < 0) {  // a protection seed on a face of a block that keeps no cube: give it a place
      block_slot_[block_of(i, j, k)] = int32_t(head_.size() / kBlockCubes);
      head_.resize(head_.size() + kBlockCubes, -1);
      occupied_.resize(head_.size() / kBlock, 0);
      c = cube_slot(i, j, k);
    }
    next_.push_back(head_[size_t(c)]);
    head_[size_t(c)] = int32_t(point.size());
    occupied_[size_t(c / kBlock)] |= uint8_t(1u << (c % kBlock));
    point.push_back(p), radius.push_back(r);
  }

  // Renumbers the seeds by their base cube's place, keeping each cube's in the order they came,
  // and returns each old number's new one: they came in arrival order, scattered in memory, and
  // every walk around a cube reads the seeds of its neighbours. Seeds added later still get the
  // numbers after all earlier ones.
  std::vector<int32_t> order_by_place() {
    std::vector<int32_t> order;
    order.reserve(point.size());
    for (int32_t head : head_) {
      const size_t first = order.size();
      for (int32_t q = head; q >= 0; q = next_[size_t(q)]) order.push_back(q);
      std::reverse(order.begin() + int64_t(first), order.end());
    }
    std::vector<int32_t> new_id(point.size());
    std::vector<Vec3> points(point.size());
    std::vector<double> radii(point.size());
    for (size_t k = 0; k < order.size(); ++k) {
      new_id[size_t(order[k])] = int32_t(k);
      points[k] = point[size_t(order[k])], radii[k] = radius[size_t(order[k])];
    }
    point.swap(points), radius.swap(radii);
    // Each list again from its newest (highest-numbered) seed.
    for (int32_t& head : head_)
      if (head >= 0) head = new_id[size_t(head)];
    std::vector<int32_t> next(next_.size());
    for (size_t q = 0; q < next_.size(); ++q) next[size_t(new_id[q])] = next_[q] >= 0 ? new_id[size_t(next_[q])] : -1;
    next_.swap(next);
    return new_id;
  }

  // Calls row(k, j, i0, i1) for the rows of base cubes (i0 to i1 along x) that hold every cube
  // whose distance to p is below `reach` (and a few more at the ends: callers measure); true from
  // row stops the walk.
  template <class Row>
  void for_rows_near(Vec3 p, double reach, Row&& row) const {
    const auto& g = grid_;
    int ci, cj, ck;
    g.locate(p, ci, cj, ck);
    const int span = int(std::ceil(reach / g.side));
    const double r2 = reach * reach, inverse_side = 1 / g.side;
    const Vec3 q = p - g.origin;
    for (int k = std::max(0, ck - span); k <= std::min(g.nz - 1, ck + span); ++k) {
      const double dz = BackgroundGrid::axis_gap(q.z, k, g.side);
      if (dz >= r2) continue;
      for (int j = std::max(0, cj - span); j <= std::min(g.ny - 1, cj + span); ++j) {
        const double dyz = dz + BackgroundGrid::axis_gap(q.y, j, g.side);
        if (dyz >= r2) continue;
        // The row's cubes within reach, by a product (a division per row was a quarter of the
        // walk), widened by 1e-9 of a cube against its rounding.
        const double w = std::sqrt(r2 - dyz);
        const int i0 = std::max(0, int(std::floor((q.x - w) * inverse_side - 1e-9))),
                  i1 = std::min(g.nx - 1, int(std::floor((q.x + w) * inverse_side + 1e-9)));
        if (i0 <= i1 && row(k, j, i0, i1)) return;
      }
    }
  }
  // Calls f(slot, i, j, k) for each base cube with a place near p (for_rows_near); true from f
  // stops the walk.
  template <class F>
  void for_slots_near(Vec3 p, double reach, F&& f) const {
    for_rows_near(p, reach, [&](int k, int j, int i0, int i1) {
      for (int i = i0; i <= i1; ++i) {
        const int64_t slot = cube_slot(i, j, k);
        if (slot >= 0 && f(slot, i, j, k)) return true;
      }
      return false;
    });
  }
  // Calls f(q) for the seeds numbered `first` or later in the base cubes near p, until f returns
  // true: a cube's list runs from its newest seed. Only the cubes that hold a seed are read,
  // through each block row's bits: most hold none, and a branch per cube on it would be
  // mispredicted.
  template <class F>
  void for_seeds_near(Vec3 p, double reach, F&& f, int32_t first = 0) const {
    for_rows_near(p, reach, [&](int k, int j, int i0, int i1) {
      for (int b = i0 / kBlock; b <= i1 / kBlock; ++b) {
        const int32_t block = block_slot_[block_of(b * kBlock, j, k)];
        if (block < 0) continue;
        const int64_t row = (int64_t(block) * kBlock + k % kBlock) * kBlock + j % kBlock;
        const int lo = std::max(i0 - b * kBlock, 0), hi = std::min(i1 - b * kBlock, kBlock - 1);
        for (uint32_t bits = occupied_[size_t(row)] & ((2u << hi) - (1u << lo)); bits; bits &= bits - 1)
          for (int32_t q = head_[size_t(row * kBlock + std::countr_zero(bits))]; q >= first; q = next_[size_t(q)])
            if (f(q)) return true;
      }
      return false;
    });
  }

  // Calls f(cube index, its seeds in the order they came) for every base cube with seeds among
  // cubes [begin, end), in the order of the cubes' indices.
  template <class F>
  void for_each_cube(int64_t begin, int64_t end, F&& f) const {
    std::vector<int32_t> ids;
    for (size_t c = size_t(begin); c < size_t(end); ++c) {
      int i, j, k;
      grid_.coords(int64_t(c), i, j, k);
      const int64_t slot = cube_slot(i, j, k);
      if (slot < 0) {  // the rest of the block's row
        c += size_t(std::min(kBlock - i % kBlock, grid_.nx - i) - 1);
        continue;
      }
      if (head_[size_t(slot)] < 0) continue;
      ids.clear();
      for (int32_t q = head_[size_t(slot)]; q >= 0; q = next_[size_t(q)]) ids.push_back(q);
      std::reverse(ids.begin(), ids.end());
      f(int64_t(c), ids);
    }
  }

 private:
  size_t block_of(int i, int j, int k) const {
    return size_t((k / kBlock * blocks_y_ + j / kBlock) * blocks_x_ + i / kBlock);
  }

  BackgroundGrid grid_;
  int blocks_x_, blocks_y_;
  // Per block, its place (cube_slot) or -1.
  std::vector<int32_t> block_slot_;
  // Each base cube's seeds as a list: its last seed, and each seed's previous one there.
  std::vector<int32_t> head_, next_;
  std::vector<uint8_t> occupied_;  // per row of 8 cubes in a block: which hold a seed
};

}  // namespace froth
