// The uniform sampler's marks for its first two refinements (sampling/mps_sampler.hpp), kept
// per block of cubes. Internal to the sampler.
#pragma once
#include <cstdint>
#include <vector>

#include "common/background_grid.hpp"

namespace froth::mps {

// Per cube of a sampler's window, its 64 grandchildren (bit x + 4y + 16z) in one seed's ball,
// kept only for the blocks of 4^3 cubes that hold an active cube: a thin or hollow solid fills
// a fifth of its grid or less (round.stl: 18%), and a dense array over the window cost it the
// marks, and the first two refinements twice the time.
class GrandchildMarks {
 public:
  // The blocks holding one of `active`'s cubes; the cubes they hold (64 per block).
  template <class Active>
  size_t allocate(const BackgroundGrid& g, int64_t cube_offset, size_t window_cubes, const Active& active) {
    k0_ = int(cube_offset / (int64_t(g.nx) * g.ny));
    const int layers = int(window_cubes / (size_t(g.nx) * g.ny));
    bx_ = (g.nx + 3) / 4, by_ = (g.ny + 3) / 4;
    block_.assign(size_t(bx_) * by_ * size_t((layers + 3) / 4), -1);
    int32_t blocks = 0;
    for (const auto& part : active.parts)
      for (const auto& c : part) {
        int i, j, k;
        g.coords(c.base, i, j, k);
        int32_t& slot = block_[block_of(i, j, k - k0_)];
        if (slot < 0) slot = blocks++;
      }
    blocks_ = size_t(blocks);
    return blocks_ * 64;
  }
  void fill() { marks_.assign(blocks_ * 64, 0); }
  void release() { std::vector<uint64_t>().swap(marks_), std::vector<int32_t>().swap(block_); }
  // Cube (i, j, k) of the grid (k a layer of the window): its marks, or null outside the blocks.
  uint64_t* at(int i, int j, int k) {
    const int32_t slot = block_[block_of(i, j, k - k0_)];
    return slot < 0 ? nullptr : &marks_[size_t(slot) * 64 + size_t((k - k0_) & 3) * 16 + size_t(j & 3) * 4 + size_t(i & 3)];
  }
  uint64_t get(int i, int j, int k) const {
    const int32_t slot = block_[block_of(i, j, k - k0_)];
    return slot < 0 ? 0 : marks_[size_t(slot) * 64 + size_t((k - k0_) & 3) * 16 + size_t(j & 3) * 4 + size_t(i & 3)];
  }

 private:
  size_t block_of(int i, int j, int window_k) const {
    return (size_t(window_k >> 2) * size_t(by_) + size_t(j >> 2)) * size_t(bx_) + size_t(i >> 2);
  }
  int k0_ = 0, bx_ = 0, by_ = 0;
  size_t blocks_ = 0;
  std::vector<int32_t> block_;   // per block of the window: its slot, or -1
  std::vector<uint64_t> marks_;  // 64 cubes per slot, x fastest
};

}  // namespace froth::mps
