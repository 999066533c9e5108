#include "sampling/graded_mps.hpp"

#include <algorithm>
#include <cmath>

#include "common/random.hpp"
#include "common/surface_locator.hpp"
#include "sampling/protect_interfaces.hpp"

namespace froth {
namespace {

constexpr int kRoundsPerLevel = 3;
constexpr int kMaxLevel = 30;

// A cube of the refinement: integer coordinates in units of the base side / 2^level.
struct Cube {
  int64_t i, j, k;
  bool boundary;  // meets the surface: its darts and children are tested one by one
  uint32_t tris_begin = 0, tris_end = 0;  // a boundary cube's triangles, in its level's pool
};

// Is the box [lo, lo + s]^3 inside the union of the balls (c1, h1) and (c2, h2)? Each point of the
// box must lie in the ball of smaller power; power is convex, so it suffices to check the box's
// corners and the points where its edges cross the power plane (the vertices of the box's two
// parts), exactly as the uniform sampler's two-ball test does for equal radii.
bool box_in_two_balls(Vec3 lo, double s, Vec3 c1, double h1, Vec3 c2, double h2) {
  auto power = [](Vec3 x, Vec3 c, double h) { return norm2(x - c) - h * h; };
  Vec3 corner[8];
  bool first[8];
  for (int k = 0; k < 8; ++k) {
    corner[k] = lo + s * Vec3{double(k & 1), double(k >> 1 & 1), double(k >> 2 & 1)};
    const double p1 = power(corner[k], c1, h1), p2 = power(corner[k], c2, h2);
    if (std::min(p1, p2) >= 0) return false;
    first[k] = p1 <= p2;
  }
  for (int k = 0; k < 8; ++k)
    for (int bit = 1; bit < 8; bit <<= 1) {
      const int m = k | bit;
      if (m == k || first[k] == first[m]) continue;
      // p1 - p2 is linear along the edge: where it vanishes, both powers must be negative.
      const double fa = power(corner[k], c1, h1) - power(corner[k], c2, h2);
      const double fb = power(corner[m], c1, h1) - power(corner[m], c2, h2);
      const Vec3 x = corner[k] + (fa / (fa - fb)) * (corner[m] - corner[k]);
      if (power(x, c1, h1) >= 0) return false;
    }
  return true;
}

struct Dart {
  double time;
  Vec3 p;
  bool boundary;
};

class GradedSampler {
 public:
  std::function<void(double)> progress_;  // told after each level the fraction of the domain covered

  GradedSampler(const Domain& d, const SizingField& h, uint64_t seed)
      : d_(d), h_(h), r_(h.r()), reach_factor_((1 + 1e-6) / (1 - h.lipschitz())), seed_(seed),
        rng_(seed, RandomStream::Graded) {
    s_.grid = BackgroundGrid::covering(d.bounds, r_);
    s_.stats.base_cube_side = s_.grid.side;
    s_.stats.grid = {size_t(s_.grid.nx), size_t(s_.grid.ny), size_t(s_.grid.nz)};
    head_.assign(s_.grid.cube_count(), -1);
  }

  Sample run() {
    protect();
    std::vector<Cube> active = initial_cubes();
    const size_t initial_active = std::max<size_t>(1, active.size());
    int level = 0;
    for (; !active.empty(); ++level) {
      SamplingLevel stats{active.size(), 0, 0};
      const size_t seeds0 = seeds_.size();
      for (int q = 0; q < kRoundsPerLevel && !active.empty(); ++q) {
        std::vector<Dart> darts;
        darts.reserve(active.size());
        for (const Cube& c : active) darts.push_back(dart(c, level, q));
        std::sort(darts.begin(), darts.end(), [](const Dart& a, const Dart& b) { return a.time < b.time; });
        stats.darts += darts.size();
        // Against the seeds before the round in parallel (most darts fall in a disk), then the
        // survivors in arrival order against the round's new seeds too: the same decisions.
        std::vector<uint8_t> open(darts.size());
#pragma omp parallel for schedule(dynamic, 512)
        for (size_t k = 0; k < darts.size(); ++k)
          open[k] = !covered(darts[k].p) && (!darts[k].boundary || d_.contains(darts[k].p));
        for (size_t k = 0; k < darts.size(); ++k)
          if (open[k] && !covered(darts[k].p)) add_seed(darts[k].p, h_.at(darts[k].p));
        // Told after each round too (the same fraction): the caller may stop the run there.
        if (progress_) progress_(1.0 - double(active.size()) / (double(initial_active) * std::pow(8.0, level)));
        if (q + 1 < kRoundsPerLevel) {
          std::vector<uint8_t> done(active.size());
#pragma omp parallel for schedule(dynamic, 1024)
          for (size_t a = 0; a < active.size(); ++a) done[a] = cube_covered(active[a], level);
          size_t kept = 0;
          for (size_t a = 0; a < active.size(); ++a)
            if (!done[a]) active[kept++] = active[a];
          active.resize(kept);
        }
      }
      stats.accepted = seeds_.size() - seeds0;
      s_.stats.darts += stats.darts;
      s_.stats.per_level.push_back(stats);
      if (level == kMaxLevel) break;
      active = refine(active, level);
      if (progress_) progress_(1.0 - double(active.size()) / (double(initial_active) * std::pow(8.0, level + 1)));
    }
    s_.stats.levels = size_t(level) + 1;
    s_.stats.uncovered_cubes = active.size();
    return finish();
  }

 private:
  double side(int level) const { return s_.grid.side / double(int64_t(1) << level); }
  Vec3 corner(const Cube& c, int level) const {
    return s_.grid.origin + side(level) * Vec3{double(c.i), double(c.j), double(c.k)};
  }
  int64_t base_of(Vec3 p) const {
    int i, j, k;
    s_.grid.locate(p, i, j, k);
    return s_.grid.index(i, j, k);
  }

  // Uniform in the cube, with an arrival time within the round: the space-time process.
  Dart dart(const Cube& c, int level, int round) const {
    const auto w = rng_.words(uint64_t(c.i), uint64_t(c.j), uint64_t(c.k), uint64_t(level) << 8 | uint64_t(round));
    const double s = side(level);
    const Vec3 p = corner(c, level) + s * Vec3{CounterRng::unit(w[0]), CounterRng::unit(w[1]), CounterRng::unit(w[2])};
    return {double(level * kRoundsPerLevel + round) + CounterRng::unit(w[3]), p, c.boundary};
  }

  // Calls f(seed) for the seeds whose base cube lies within `reach` of p, until f returns true.
  template <class F>
  void for_seeds_near(Vec3 p, double reach, F&& f) const {
    s_.grid.for_cubes_near(p, reach, [&](int64_t c) {
      for (int32_t q = head_[size_t(c)]; q >= 0; q = next_[size_t(q)])
        if (f(q)) return true;
      return false;
    });
  }
  // How far from p a seed can be whose disk reaches within `extra` of p: |p - q| < h(q) + extra
  // and h(q) <= h(p) + lambda |p - q| give (h(p) + extra) / (1 - lambda), and never more than
  // r + extra. Where h is small this reads a few base cubes instead of all within r (the scans
  // were most of the graded sampler's time). The slack covers the nodes' float rounding.
  double reach(Vec3 p, double extra) const {
    return std::min(r_ + extra, (h_.at(p) + extra) * reach_factor_ + 1e-9 * r_);
  }
  bool covered(Vec3 p) const {
    bool in = false;
    for_seeds_near(p, reach(p, 0), [&](int32_t q) { return in = norm2(p - seeds_[q]) < radius_[q] * radius_[q]; });
    return in;
  }
  // Inside one seed's disk entirely (all eight corners: the disk is convex), or, from level 3
  // on, inside the union of two (box_in_two_balls): without it the cubes along the curves where
  // disks meet are refined to the last level. The first disk found to hold the cube ends the
  // search: with a margin for round-off, by its distance to the centre alone.
  struct CubeTest {
    Vec3 lo, mid;
    double s, half_diagonal;
    int32_t near[16];  // the first disks that reach into the cube, for the two-disk test
    int n = 0;
  };
  CubeTest cube_test(const Cube& c, int level) const {
    CubeTest t;
    t.s = side(level), t.lo = corner(c, level), t.mid = t.lo + 0.5 * t.s * Vec3{1, 1, 1};
    t.half_diagonal = 0.5 * std::sqrt(3.0) * t.s;
    return t;
  }
  // Seed q against the cube: true if its disk holds the whole cube.
  bool holds(CubeTest& t, int32_t q) const {
    const double h = radius_[q], dist = norm(t.mid - seeds_[q]);
    if (dist >= h + t.half_diagonal) return false;
    if (t.n < 16) t.near[t.n++] = q;
    if (dist + t.half_diagonal < h * (1 - 1e-12)) return true;
    bool all = true;
    for (int k = 0; k < 8 && all; ++k)
      all = norm2(t.lo + t.s * Vec3{double(k & 1), double(k >> 1 & 1), double(k >> 2 & 1)} - seeds_[q]) < h * h;
    return all;
  }
  bool in_two_disks(const CubeTest& t, int level) const {
    if (level < 3) return false;
    for (int a = 0; a < t.n; ++a)
      for (int b = a + 1; b < t.n; ++b)
        if (box_in_two_balls(t.lo, t.s, seeds_[t.near[a]], radius_[t.near[a]], seeds_[t.near[b]], radius_[t.near[b]]))
          return true;
    return false;
  }
  bool cube_covered(const Cube& c, int level) const {
    CubeTest t = cube_test(c, level);
    bool in = false;
    for_seeds_near(t.mid, reach(t.mid, t.half_diagonal), [&](int32_t q) { return in = holds(t, q); });
    return in || in_two_disks(t, level);
  }
  // The same test from `candidates`, the seeds whose disks reach into the cube's parent in the
  // order the grid gives them (seeds_reaching): a disk that reaches into a child reaches into
  // its parent, and the order is the grid's, so the answer is cube_covered's with one grid
  // walk per parent instead of one per child.
  bool cube_covered(const Cube& c, int level, const std::vector<int32_t>& candidates) const {
    CubeTest t = cube_test(c, level);
    for (int32_t q : candidates)
      if (holds(t, q)) return true;
    return in_two_disks(t, level);
  }
  void seeds_reaching(const Cube& c, int level, std::vector<int32_t>& out) const {
    const CubeTest t = cube_test(c, level);
    out.clear();
    for_seeds_near(t.mid, reach(t.mid, t.half_diagonal), [&](int32_t q) {
      if (norm(t.mid - seeds_[q]) < radius_[q] + t.half_diagonal) out.push_back(q);
      return false;
    });
  }

  // Outside the domain (-1), inside (1), or meeting its surface (0). A non-convex domain's cube
  // that meets the surface gets its triangles in `pool` (from `candidates`, its parent's, if given).
  int side_of(Cube& c, int level, std::vector<int32_t>& pool, const int32_t* candidates = nullptr,
              size_t candidate_count = 0) const {
    const double s = side(level);
    const Vec3 lo = corner(c, level), hi = lo + Vec3{s, s, s};
    if (d_.convex) {
      bool all_in = true;
      for (const Plane& pl : d_.planes) {
        int out = 0;
        for (int k = 0; k < 8; ++k)
          out += pl.signed_distance(lo + s * Vec3{double(k & 1), double(k >> 1 & 1), double(k >> 2 & 1)}) > 0;
        if (out == 8) return -1;
        all_in &= out == 0;
      }
      return all_in ? 1 : 0;
    }
    c.tris_begin = uint32_t(pool.size());
    if (candidates) {
      for (size_t k = 0; k < candidate_count; ++k)
        if (d_.locator->triangle_meets_box(candidates[k], lo, hi)) pool.push_back(candidates[k]);
    } else {
      scratch_.clear();
      d_.locator->triangles_near(lo, hi, scratch_);
      pool.insert(pool.end(), scratch_.begin(), scratch_.end());
    }
    c.tris_end = uint32_t(pool.size());
    if (c.tris_end > c.tris_begin) return 0;
    return d_.contains(lo + 0.5 * s * Vec3{1, 1, 1}) ? 1 : -1;
  }

  // The base cubes in the domain or on its surface, by blocks of 8^3 (in parallel, joined in
  // block order): a block that meets no triangle is all inside or all outside, by one test.
  std::vector<Cube> initial_cubes() {
    constexpr int kBlock = 8;
    const auto& g = s_.grid;
    const int bx = (g.nx + kBlock - 1) / kBlock, by = (g.ny + kBlock - 1) / kBlock, bz = (g.nz + kBlock - 1) / kBlock;
    const size_t blocks = size_t(bx) * by * bz;
    std::vector<std::vector<Cube>> out(blocks);
    std::vector<std::vector<int32_t>> pools(blocks);
#pragma omp parallel
    {
      std::vector<int32_t> near;
#pragma omp for schedule(dynamic, 1)
      for (size_t b = 0; b < blocks; ++b) {
        const int i0 = int(b % bx) * kBlock, j0 = int(b / bx % by) * kBlock, k0 = int(b / (size_t(bx) * by)) * kBlock;
        const int i1 = std::min(g.nx, i0 + kBlock), j1 = std::min(g.ny, j0 + kBlock), k1 = std::min(g.nz, k0 + kBlock);
        const Vec3 lo = corner(Cube{i0, j0, k0, false}, 0), hi = corner(Cube{i1, j1, k1, false}, 0);
        if (hi.x < d_.bounds.lo.x || hi.y < d_.bounds.lo.y || hi.z < d_.bounds.lo.z || lo.x > d_.bounds.hi.x ||
            lo.y > d_.bounds.hi.y || lo.z > d_.bounds.hi.z)
          continue;
        near.clear();
        if (!d_.convex) d_.locator->triangles_near(lo, hi, near);
        // No triangle in the block: every cube on the side of the block's centre.
        const int block_side = !d_.convex && near.empty() ? (d_.contains(0.5 * (lo + hi)) ? 1 : -1) : 0;
        if (block_side < 0) continue;
        for (int k = k0; k < k1; ++k)
          for (int j = j0; j < j1; ++j)
            for (int i = i0; i < i1; ++i) {
              Cube c{i, j, k, false};
              std::vector<int32_t>& pool = pools[b];
              const size_t pool_size = pool.size();
              const int side = block_side > 0 ? 1 : side_of(c, 0, pool, near.data(), near.size());
              if (side < 0 || cube_covered(c, 0)) {
                pool.resize(pool_size);
                continue;
              }
              c.boundary = side == 0;
              out[b].push_back(c);
            }
      }
    }
    pool_.clear();
    return join(out, pools, pool_);
  }

  // The children not covered and not outside, in the parents' order (chunks in parallel, each
  // with its own triangle pool, joined in order).
  std::vector<Cube> refine(const std::vector<Cube>& active, int level) {
    constexpr size_t kChunk = 4096;
    const size_t chunks = (active.size() + kChunk - 1) / kChunk;
    std::vector<std::vector<Cube>> out(chunks);
    std::vector<std::vector<int32_t>> pools(chunks);
#pragma omp parallel for schedule(dynamic, 1)
    for (size_t ch = 0; ch < chunks; ++ch) {
      std::vector<int32_t> candidates;
      for (size_t a = ch * kChunk; a < std::min(active.size(), (ch + 1) * kChunk); ++a) {
        const Cube& c = active[a];
        seeds_reaching(c, level, candidates);
        for (int q = 0; q < 8; ++q) {
          Cube child{2 * c.i + (q & 1), 2 * c.j + (q >> 1 & 1), 2 * c.k + (q >> 2 & 1), c.boundary};
          if (cube_covered(child, level + 1, candidates)) continue;
          if (c.boundary) {
            std::vector<int32_t>& pool = pools[ch];
            const size_t pool_size = pool.size();
            const int side = side_of(child, level + 1, pool, pool_.data() + c.tris_begin, c.tris_end - c.tris_begin);
            if (side < 0) {
              pool.resize(pool_size);
              continue;
            }
            child.boundary = side == 0;
          }
          out[ch].push_back(child);
        }
      }
    }
    std::vector<int32_t> pool;
    std::vector<Cube> all = join(out, pools, pool);
    pool_.swap(pool);
    return all;
  }

  // The cubes and triangle pools of parallel chunks as one list and one pool, in chunk order.
  static std::vector<Cube> join(const std::vector<std::vector<Cube>>& out, const std::vector<std::vector<int32_t>>& pools,
                                std::vector<int32_t>& pool) {
    std::vector<Cube> all;
    for (size_t ch = 0; ch < out.size(); ++ch) {
      const uint32_t shift = uint32_t(pool.size());
      for (Cube c : out[ch]) {
        if (c.boundary) c.tris_begin += shift, c.tris_end += shift;
        all.push_back(c);
      }
      pool.insert(pool.end(), pools[ch].begin(), pools[ch].end());
    }
    return all;
  }

  void add_seed(Vec3 p, double radius) {
    const int64_t c = base_of(p);
    next_.push_back(head_[size_t(c)]);
    head_[size_t(c)] = int32_t(seeds_.size());
    seeds_.push_back(p), radius_.push_back(radius);
  }

  // Reflex edges first (paper §2.2), at h_e = h/sqrt(2), then a multi-region solid's interfaces
  // (protect_interfaces.hpp); the free seeds keep h from them.
  void protect() {
    if (!d_.regions && (d_.convex || d_.reflex_curves.empty())) return;
    const ProtectionSeeds p = protect_boundary_and_interfaces(
        d_, r_, seed_, s_.stats, [&](Vec3 x) { return h_.at(x); }, h_.lipschitz());
    for (size_t k = 0; k < p.points.size(); ++k) {
      protection_.push_back({int32_t(seeds_.size()), p.kinds[k], p.inward[k]});
      add_seed(p.points[k], h_.at(p.points[k]));
    }
  }

  // Seeds numbered by base cube, each cube's in the order they came.
  Sample finish() {
    std::vector<int32_t> new_id(seeds_.size(), -1), ids;
    s_.cube_seed.assign(s_.grid.cube_count(), -1);
    s_.cube_extra_begin.assign(1, 0);
    for (size_t c = 0; c < head_.size(); ++c) {
      if (head_[c] < 0) continue;
      ids.clear();
      for (int32_t q = head_[c]; q >= 0; q = next_[size_t(q)]) ids.push_back(q);
      std::reverse(ids.begin(), ids.end());  // in the order they came
      for (int32_t q : ids) new_id[q] = int32_t(s_.seeds.size()), s_.seeds.push_back(seeds_[q]);
      if (ids.size() == 1) {
        s_.cube_seed[c] = new_id[ids[0]];
        continue;
      }
      s_.cube_seed[c] = -2 - int32_t(s_.cube_extra_begin.size() - 1);
      for (int32_t q : ids) s_.cube_extra.push_back(new_id[q]);
      s_.cube_extra_begin.push_back(int32_t(s_.cube_extra.size()));
    }
    for (Sample::Protected p : protection_) s_.protected_seeds.push_back({new_id[p.seed], p.kind, p.inward});
    std::sort(s_.protected_seeds.begin(), s_.protected_seeds.end(),
              [](const auto& a, const auto& b) { return a.seed < b.seed; });
    s_.stats.seeds = s_.seeds.size();
    return std::move(s_);
  }

  const Domain& d_;
  const SizingField& h_;
  double r_, reach_factor_;
  uint64_t seed_;
  CounterRng rng_;
  Sample s_;
  std::vector<Vec3> seeds_;
  std::vector<double> radius_;  // each seed's disk: h at the seed
  std::vector<Sample::Protected> protection_;
  // The seeds of each base cube as a list: its last seed, and each seed's previous one there.
  std::vector<int32_t> head_, next_;
  mutable std::vector<int32_t> scratch_;
  std::vector<int32_t> pool_;  // the active boundary cubes' triangles
};

}  // namespace

Sample sample_graded_poisson_disk(const Domain& domain, const SizingField& h, uint64_t seed,
                                  const std::function<void(double)>& progress) {
  GradedSampler sampler(domain, h, seed);
  sampler.progress_ = progress;
  return sampler.run();
}

}  // namespace froth
