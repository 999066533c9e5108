// Maximal Poisson-disk sampling on a background grid of cubes with diagonal r.
//
// Unbiasedness: the darts are a space-time Poisson process of constant intensity over the domain
// (each round gives every active cube a Poisson number of darts with uniform positions and
// uniform arrival times within the round), and a dart is accepted iff no earlier-accepted seed
// lies within r. That is random sequential addition exactly, run to saturation; Ebeida et al.'s
// refinement only drops sub-cubes that are already covered (where every dart would be rejected)
// or outside the domain, which does not change the law of the accepted set. Within a round the
// candidates are accepted greedily in arrival order, so the result does not depend on how the
// work is split. Cubes cut by the boundary are sampled too (darts outside are rejected), so the
// density does not sag next to the boundary.
#include "sampling/mps.hpp"

#include <omp.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <map>
#include <optional>
#include <cstring>
#include <span>

#include "common/random.hpp"
#include "common/surface_locator.hpp"
#include "sampling/protect.hpp"
#include "common/tolerances.hpp"

namespace froth {
namespace {

// 16 bytes: the active lists are the sampler's largest memory.
struct ActiveCube {
  static constexpr uint32_t kInside = 0x80000000u;  // in sz_flags: entirely inside the domain
  uint32_t base;              // base cube index (the pipeline keeps grids under 2^31 cubes)
  uint32_t sx, sy;            // sub-cube coordinates inside the base cube at the current level
  uint32_t sz_flags;          // sub-cube z coordinate, and kInside
  uint32_t sz() const { return sz_flags & ~kInside; }
  bool inside() const { return sz_flags & kInside; }
};

// The active cubes of a level, in parts that are units of work: a part's children are a part
// of the next level, so the lists are never copied into one (that copy was 5% of the sampling
// time). Results depend on neither the parts nor their order: darts are keyed by cube, and
// seeds are numbered in Morton order.
struct ActiveCubes {
  std::vector<std::vector<ActiveCube>> parts;
  size_t size() const {
    size_t n = 0;
    for (const auto& p : parts) n += p.size();
    return n;
  }
  bool empty() const { return size() == 0; }
};

// Concatenates per-chunk results in chunk order, freeing each chunk as it goes.
template <class T>
std::vector<T> concatenate(std::vector<std::vector<T>>& parts) {
  size_t total = 0;
  for (const auto& p : parts) total += p.size();
  std::vector<T> all;
  all.reserve(total);
  for (auto& p : parts) {
    all.insert(all.end(), p.begin(), p.end());
    std::vector<T>().swap(p);
  }
  return all;
}

struct Candidate {
  uint64_t time;
  int64_t base;
  Vec3 p;
};

// Expected darts per active cube per round, and rounds per refinement level. They tune speed
// only: the law of the sample is the same for any choice (each round is a slice of the darts'
// arrival times, and its intensity may differ from the next one's). The first level throws its
// darts in rounds that double: the first round's candidates conflict only with each other, and
// the cost of deciding them in arrival order grows with the square of their density, while a
// later round's darts mostly meet a seed and stop there, so the acceptance falls as the rounds
// grow. Each round walks every base cube, so fewer, doubling rounds beat six equal ones
// (commit 2ffdb9f has the figures).
constexpr std::array<double, 4> kDartsPerCubeLevel0Rounds = {0.0625, 0.125, 0.25, 0.5};
constexpr double kDartsPerCubePerRound = 0.5;
constexpr int kRoundsPerLevel = 1;
// The first refinement level at which a child in no single ball gets the exact two- and
// three-ball test (covered()). Above it, most such children hold a gap or need more balls, and
// the test (half of a level's refinement time) costs more than refining the few it clears: their
// children mostly fit in one ball. Below it, cubes straddling the seam of two balls would double
// at every level; level 7 measured best (commit 7d3a47c). Levels are relative to r, so the
// choice does not depend on scale. Nor does the
// sample: a child's darts depend only on its place and level, and those thrown into covered
// space are all rejected, so keeping a covered child changes the work, not the seeds.
constexpr int kFirstExactCoverageLevel = 7;
// The first refinement level that throws the next level's darts itself, into the children it
// keeps, testing them against the seeds it gathered for them (refine()). Where the marks stand in
// for those seeds (levels 0 and 1 of most domains) it has none; where it has them at those levels
// (a domain that fills little of its grid), throwing there gained nothing measurable (commit
// 4e3c950).
constexpr int kFirstFusedDartLevel = 2;

// Inverse CDF of the Poisson law with mean `mean`: the CDF tabulated once (it is summed term by
// term, p0 = exp(-mean) first), then read per draw, where a division per term cost 5% of the
// dart throwing.
class Poisson {
 public:
  explicit Poisson(double mean) {
    double p = std::exp(-mean), cdf = p;
    cdf_[0] = cdf;
    for (int k = 1; k < kMax; ++k) {
      p *= mean / k;
      cdf += p;
      cdf_[k] = cdf;
    }
  }
  // The count whose CDF interval holds u (at most kMax - 1).
  int operator()(double u) const {
    int k = 0;
    while (k < kMax - 1 && u > cdf_[k]) ++k;
    return k;
  }

 private:
  static constexpr int kMax = 65;
  double cdf_[kMax];
};

class Sampler {
 public:
  Sampler(const Domain& domain, double r, uint64_t seed, SamplingPartition* partition)
      : domain_(domain), r_(r), r2_(r * r), seed_(seed), rng_(seed, RandomStream::Sampling),
        partition_(partition) {
    s_.grid = BackgroundGrid::covering(domain.bounds, r);
    const int64_t layer = int64_t(s_.grid.nx) * s_.grid.ny;
    if (partition_) {
      const Slab& sl = partition_->slab;
      owned_begin_ = sl.owned_begin, owned_end_ = sl.owned_end;
      s_.cube_offset = layer * sl.window_begin;
      s_.cube_seed.assign(size_t(layer) * (sl.window_end - sl.window_begin), -1);
    } else {
      owned_begin_ = 0, owned_end_ = s_.grid.nz;
      s_.cube_seed.assign(s_.grid.cube_count(), -1);
    }
    for (const auto& [di, dj, dk] : stencil())
      stencil_offsets_.push_back((int64_t(dk) * s_.grid.ny + dj) * s_.grid.nx + di);
    s_.stats.base_cube_side = s_.grid.side;
    s_.stats.grid = {size_t(s_.grid.nx), size_t(s_.grid.ny), size_t(s_.grid.nz)};
  }

  Sample run() {
    protect();
    ActiveCubes active = initial_cubes();
    initial_active_ = active.size();
    int level = 0;
    // The first round's candidates of this level when the refinement before threw its darts.
    std::optional<Darts> thrown;
    while (anywhere(!active.empty())) {
      const int rounds = level == 0 ? int(kDartsPerCubeLevel0Rounds.size()) : kRoundsPerLevel;
      const size_t darts0 = s_.stats.darts, seeds0 = s_.seeds.size();
      s_.stats.per_level.push_back({active.size(), 0, 0});
      for (int q = 0; q < rounds && anywhere(!active.empty()); ++q) {
        if (q > 0 || !thrown) thrown = throw_round(active, level, q);
        accept_round(*thrown);
        thrown.reset();
      }
      s_.stats.per_level.back().darts = s_.stats.darts - darts0;
      s_.stats.per_level.back().accepted = s_.seeds.size() - seeds0;
      if (level == tol::kMaxSamplingLevel) break;
      active = refine(active, level, thrown);
      ++level;
    }
    s_.stats.levels = size_t(level) + 1;
    s_.stats.uncovered_cubes = active.size();
    order_seeds_by_cube();
    s_.stats.seeds = s_.seeds.size();
    return std::move(s_);
  }

 private:
  int layer_of(int64_t b) const { return int(b / (int64_t(s_.grid.nx) * s_.grid.ny)); }
  int32_t& cube_entry(int64_t b) { return s_.cube_seed[b - s_.cube_offset]; }
  int32_t cube_entry(int64_t b) const { return s_.cube_seed[b - s_.cube_offset]; }

  // Is `mine` true on any rank? (Every rank calls it at the same point.)
  bool anywhere(bool mine) const { return partition_ ? partition_->comm->any(mine) : mine; }

  Vec3 base_origin(int64_t b) const {
    const auto& g = s_.grid;
    int i, j, k;
    g.coords(b, i, j, k);
    return g.origin + Vec3{i * g.side, j * g.side, k * g.side};
  }

  // The entries (cube_seed) of base cube b's stencil cubes [first, last) that hold seeds, in
  // stencil order, into `found` (room for kStencilSize); -1 when the stencil leaves the grid or
  // the window, and the caller walks it cube by cube. Most cubes are two or more cubes from the
  // sides: their stencil is read through index offsets without a branch per cube (nine in ten
  // are empty, which a branch mispredicts: 15% of the sampling time at 3e5 seeds). The first
  // kNearestCubes entries of the stencil are the cubes that share a face, edge or corner with b.
  static constexpr int kStencilSize = 116, kNearestCubes = 26;
  int occupied_stencil(int64_t b, int i0, int j0, int32_t* found, int first = 0, int last = kStencilSize) const {
    const auto& g = s_.grid;
    const int64_t slot = b - s_.cube_offset, span = 2 * (int64_t(g.nx) * g.ny + g.nx + 1);
    if (!(i0 >= 2 && i0 + 2 < g.nx && j0 >= 2 && j0 + 2 < g.ny && slot >= span &&
          slot + span < int64_t(s_.cube_seed.size())))
      return -1;
    return s_.occupied_entries(slot, std::span(stencil_offsets_).subspan(first, last - first), found);
  }
  // Calls f(position) for the seeds of the entries occupied_stencil() found.
  template <class F>
  void for_found_seeds(const int32_t* found, int n, F&& f) const {
    for (int k = 0; k < n; ++k) s_.for_seeds_of_entry(found[k], [&](int32_t id) { f(s_.seeds[id]); });
  }

  // Seeds within r of base cube b (which holds no seed), read from the grid itself through the
  // stencil below.
  void seeds_near_base_cube(int64_t b, std::vector<Vec3>& near) const {
    near.clear();
    const auto& g = s_.grid;
    int i0, j0, k0;
    g.coords(b, i0, j0, k0);
    const Vec3 lo = base_origin(b), hi = lo + Vec3{g.side, g.side, g.side};
    auto add_if_near = [&](Vec3 p) {
      double d2 = 0;
      for (int a = 0; a < 3; ++a) {
        const double t = std::max({lo[a] - p[a], p[a] - hi[a], 0.0});
        d2 += t * t;
      }
      if (d2 < r2_) near.push_back(p);
    };
    int32_t found[kStencilSize];
    const int n = occupied_stencil(b, i0, j0, found);
    if (n >= 0) return for_found_seeds(found, n, add_if_near);
    for (const auto& [di, dj, dk] : stencil()) {
      if (!g.inside(i0 + di, j0 + dj, k0 + dk)) continue;
      s_.for_seeds_in_cube(g.index(i0 + di, j0 + dj, k0 + dk), [&](int32_t id) { add_if_near(s_.seeds[id]); });
    }
  }

  // The base cubes within r of a base cube, as offsets, nearest first: all within two steps along
  // each axis but the cube itself and the eight two steps away along all three (their distance
  // is exactly r).
  static const std::vector<std::array<int, 3>>& stencil() {
    static const std::vector<std::array<int, 3>> offsets = [] {
      std::vector<std::array<int, 3>> o;
      for (int k = -2; k <= 2; ++k)
        for (int j = -2; j <= 2; ++j)
          for (int i = -2; i <= 2; ++i)
            if ((i || j || k) && !(std::abs(i) == 2 && std::abs(j) == 2 && std::abs(k) == 2)) o.push_back({i, j, k});
      auto steps = [](const std::array<int, 3>& d) {
        int s = 0;
        for (int a : d) s += std::max(std::abs(a) - 1, 0) * 4 + std::abs(a);
        return s;
      };
      std::stable_sort(o.begin(), o.end(), [&](const auto& a, const auto& b) { return steps(a) < steps(b); });
      return o;
    }();
    return offsets;
  }

  // Is one of `seeds` closer than r to p? Without a branch per seed: there are few, and one of
  // them mostly is.
  bool any_within_r(std::span<const Vec3> seeds, Vec3 p) const {
    bool hit = false;
    for (const Vec3& s : seeds) hit |= norm2(s - p) < r2_;
    return hit;
  }

  // Is a seed closer than r to p, a point of base cube b (which holds no seed), when b's stencil
  // leaves the grid or the window (occupied_stencil() gives -1): its cubes one by one, nearest
  // first, skipping those beyond r and outside the grid.
  bool seed_within_r_near_edge(Vec3 p, int64_t b) const {
    const auto& g = s_.grid;
    int i0, j0, k0;
    g.coords(b, i0, j0, k0);
    const Vec3 q = p - g.origin;
    double gap[3][5];  // squared distance from p to the slab of cube c0 + d along each axis
    for (int d = -2; d <= 2; ++d) {
      gap[0][d + 2] = BackgroundGrid::axis_gap(q.x, i0 + d, g.side);
      gap[1][d + 2] = BackgroundGrid::axis_gap(q.y, j0 + d, g.side);
      gap[2][d + 2] = BackgroundGrid::axis_gap(q.z, k0 + d, g.side);
    }
    for (const auto& [di, dj, dk] : stencil()) {
      if (gap[0][di + 2] + gap[1][dj + 2] + gap[2][dk + 2] >= r2_) continue;
      if (!g.inside(i0 + di, j0 + dj, k0 + dk)) continue;
      bool hit = false;
      s_.for_seeds_in_cube(g.index(i0 + di, j0 + dj, k0 + dk), [&](int32_t id) { hit |= norm2(s_.seeds[id] - p) < r2_; });
      if (hit) return true;
    }
    return false;
  }

  // The seeds of a base cube's stencil, gathered by the first dart into one of its sub-cubes
  // and read by the next ones (a base cube's sub-cubes are adjacent in the active lists): the
  // nearest kNearestCubes cubes' at once, the rest at the first dart they do not reject.
  struct StencilSeeds {
    int64_t base = -1;
    int i0 = 0, j0 = 0;
    bool interior = false;  // the stencil lies inside the grid and the window
    bool outer_known = false;
    std::vector<Vec3> nearest, outer;
  };
  // Is a seed closer than r to p, a point of base cube b (which holds no seed)? For darts into
  // b's sub-cubes, through `cache`.
  bool seed_within_r(Vec3 p, int64_t b, StencilSeeds& cache) const {
    int32_t found[kStencilSize];
    if (cache.base != b) {
      int k0;
      s_.grid.coords(b, cache.i0, cache.j0, k0);
      const int n = occupied_stencil(b, cache.i0, cache.j0, found, 0, kNearestCubes);
      cache.base = b, cache.interior = n >= 0, cache.outer_known = false;
      cache.nearest.clear();
      if (cache.interior) for_found_seeds(found, n, [&](Vec3 s) { cache.nearest.push_back(s); });
    }
    if (!cache.interior) return seed_within_r_near_edge(p, b);
    // Most darts after the first level meet a seed, most often in a cube next to theirs: those
    // cubes first.
    if (any_within_r(cache.nearest, p)) return true;
    if (!cache.outer_known) {
      cache.outer.clear();
      for_found_seeds(found, occupied_stencil(b, cache.i0, cache.j0, found, kNearestCubes),
                      [&](Vec3 s) { cache.outer.push_back(s); });
      cache.outer_known = true;
    }
    return any_within_r(cache.outer, p);
  }

  // The children of the parent [lo, lo + 2h]^3 inside one seed's ball, as bits (child dx + 2 dy +
  // 4 dz). A child is in seed q's ball iff its farthest corner is: iff the squared distances from
  // q to the child's farther face along each axis sum to at most r^2. Eight children in ten are
  // covered so; testing all eight per seed at once avoids a mispredicted branch per child and seed.
  uint32_t children_in_one_ball(Vec3 lo, double h, const std::vector<Vec3>& near) const {
    uint32_t inside = 0;
    for (const Vec3& q : near) {
      double far2[3][2];  // per axis, per half of the parent
      for (int a = 0; a < 3; ++a) {
        const double x = q[a], l = lo[a];
        const double f0 = std::max(x - l, l + h - x), f1 = std::max(x - l - h, l + 2 * h - x);
        far2[a][0] = f0 * f0;
        far2[a][1] = f1 * f1;
      }
#ifdef __SSE2__
      // Two children (x = 0, 1) per vector compare, the sums grouped as below.
      const __m128d x = _mm_loadu_pd(far2[0]), limit = _mm_set1_pd(r2_);
      for (int yz = 0; yz < 4; ++yz) {
        const __m128d sum = _mm_add_pd(_mm_add_pd(x, _mm_set1_pd(far2[1][yz & 1])), _mm_set1_pd(far2[2][yz >> 1]));
        inside |= uint32_t(_mm_movemask_pd(_mm_cmple_pd(sum, limit))) << (2 * yz);
      }
#else
      for (int c = 0; c < 8; ++c) inside |= uint32_t(far2[0][c & 1] + far2[1][c >> 1 & 1] + far2[2][c >> 2] <= r2_) << c;
#endif
    }
    return inside;
  }

  // Which of the 64 grandchildren of every cube of the window (bit x + 4y + 16z, in steps of a
  // quarter side) lie in one seed's ball, for the seeds from `first` on: the one-ball tests of
  // the first two refinements, done from the seeds' side. A tenth of the cubes hold a seed, so
  // marking the cubes around each seed reads far less than gathering the seeds around each cube,
  // and the marks of a level's seeds serve the next level too.
  void mark_grandchildren_in_one_ball(size_t first) {
    const auto& g = s_.grid;
    grandchild_marks_.resize(s_.cube_seed.size(), 0);
    const int64_t layer = int64_t(g.nx) * g.ny;
    const int k_begin = int(s_.cube_offset / layer), k_end = k_begin + int(s_.cube_seed.size() / layer);
    // A seed marks cubes up to two layers from its own. The seeds are split by slabs of
    // kMarkSlab layers, and the slabs of one parity are marked in parallel: their seeds' cubes
    // are apart, so no two threads write one cube and the marks need no atomic OR (that was a
    // fifth of the marking time). Marks are ORed, so the order does not matter. (A mark lost
    // would only keep a covered cube: work, not a different sample.)
    constexpr int kMarkSlab = 4;
    const int slabs = std::max(1, (k_end - k_begin + kMarkSlab - 1) / kMarkSlab);
    auto slab_of = [&](Vec3 q) {
      int i, j, k;
      g.locate(q, i, j, k);
      return size_t(std::clamp((k - k_begin) / kMarkSlab, 0, slabs - 1));
    };
    std::vector<uint32_t> slab_begin(size_t(slabs) + 1, 0), by_slab(s_.seeds.size() - first), slab(by_slab.size());
    for (size_t id = first; id < s_.seeds.size(); ++id) ++slab_begin[(slab[id - first] = uint32_t(slab_of(s_.seeds[id]))) + 1];
    for (int sl = 0; sl < slabs; ++sl) slab_begin[sl + 1] += slab_begin[sl];
    std::vector<uint32_t> fill(slab_begin.begin(), slab_begin.end() - 1);
    for (size_t id = first; id < s_.seeds.size(); ++id) by_slab[fill[slab[id - first]]++] = uint32_t(id);
    for (int parity = 0; parity < 2; ++parity) {
#pragma omp parallel for schedule(dynamic, 1)
      for (int sl = parity; sl < slabs; sl += 2)
        for (uint32_t at = slab_begin[sl]; at < slab_begin[sl + 1]; ++at) mark_around(s_.seeds[by_slab[at]], k_begin, k_end);
    }
  }

  // The marks of seed q on the cubes of layers [k_begin, k_end) around it.
  void mark_around(Vec3 q, int k_begin, int k_end) {
    const auto& g = s_.grid;
    const double h = g.side / 4;
    int c[3];
    g.locate(q, c[0], c[1], c[2]);
    // Per axis, for the cubes d = -2..2 steps from q's and each of their quarters: the squared
    // distance from q to the quarter's farther face (as in children_in_one_ball), and its
    // smallest value over the cube's four quarters.
    double far2[3][5][4], nearest2[3][5];
    for (int a = 0; a < 3; ++a)
      for (int d = 0; d < 5; ++d) {
        const double x = q[a], l = g.origin[a] + (c[a] + d - 2) * g.side;
        for (int u = 0; u < 4; ++u) {
          const double f = std::max(x - (l + u * h), l + (u + 1) * h - x);
          far2[a][d][u] = f * f;
        }
        nearest2[a][d] = std::min({far2[a][d][0], far2[a][d][1], far2[a][d][2], far2[a][d][3]});
      }
    // Only cubes with a grandchild in the ball (the smallest terms along each axis fit), other
    // than q's own, which holds a seed and is never refined.
    for (int dk = 0; dk < 5; ++dk) {
      const int k = c[2] + dk - 2;
      if (k < k_begin || k >= k_end) continue;
      for (int dj = 0; dj < 5; ++dj) {
        const int j = c[1] + dj - 2;
        if (j < 0 || j >= g.ny || nearest2[2][dk] + nearest2[1][dj] > r2_) continue;
        for (int di = 0; di < 5; ++di) {
          const int i = c[0] + di - 2;
          if (i < 0 || i >= g.nx || nearest2[2][dk] + nearest2[1][dj] + nearest2[0][di] > r2_) continue;
          if (di == 2 && dj == 2 && dk == 2) continue;
          uint64_t in = 0;
#ifdef __SSE2__
          // A row's four tests as two vector compares (the compiler kept them scalar, a
          // compare and a flag per grandchild: most of the marking time); the same tests.
          const __m128d x01 = _mm_loadu_pd(&far2[0][di][0]), x23 = _mm_loadu_pd(&far2[0][di][2]);
#endif
          for (int z = 0; z < 4; ++z)
            for (int y = 0; y < 4; ++y) {
              const double room = r2_ - far2[2][dk][z] - far2[1][dj][y];
#ifdef __SSE2__
              const __m128d limit = _mm_set1_pd(room);
              const uint64_t row = uint64_t(_mm_movemask_pd(_mm_cmple_pd(x01, limit)) |
                                            _mm_movemask_pd(_mm_cmple_pd(x23, limit)) << 2);
#else
              uint64_t row = 0;
              for (int x = 0; x < 4; ++x) row |= uint64_t(far2[0][di][x] <= room) << x;
#endif
              in |= row << (4 * y + 16 * z);
            }
          if (in) grandchild_marks_[g.index(i, j, k) - s_.cube_offset] |= in;
        }
      }
    }
  }

  // The children of sub-cube (sx, sy, sz) of base cube b at level 0 or 1 that the marks show to be
  // covered (bits as children_in_one_ball): at level 1, those in one ball; at level 0, those
  // whose eight children each are.
  uint32_t marked_children(int64_t b, int level, uint32_t sx, uint32_t sy, uint32_t sz) const {
    const uint64_t m = grandchild_marks_[b - s_.cube_offset];
    uint32_t covered = 0;
    for (uint32_t ch = 0; ch < 8; ++ch) {
      const uint32_t x = ch & 1, y = ch >> 1 & 1, z = ch >> 2;
      if (level == 1) {
        covered |= uint32_t(m >> ((2 * sx + x) + 4 * (2 * sy + y) + 16 * (2 * sz + z)) & 1) << ch;
      } else {
        const uint64_t quad = uint64_t(0x33) << (2 * x + 8 * y + 32 * z);  // its 2x2x2 quarters
        const uint64_t all = quad | quad << 16;
        covered |= uint32_t((m & all) == all) << ch;
      }
    }
    return covered;
  }

  // The nearest near seed of each point of the parent's 3x3x3 lattice (its children's corners),
  // found when a child first needs it: neighbouring children share corners.
  struct CornerCache {
    Vec3 lo;
    double h;
    uint32_t known = 0;  // bit p: point p's entry is filled in
    int nearest[27];
    double dist2[27];
    void reset(Vec3 parent_lo, double child_side) { lo = parent_lo, h = child_side, known = 0; }
    Vec3 point(int p) const { return lo + Vec3{(p % 3) * h, (p / 3 % 3) * h, (p / 9) * h}; }
    // The lattice point of corner k of child (dx, dy, dz); corner k is at the child's low corner
    // plus (k & 1, k >> 1 & 1, k >> 2) sides.
    static int child_corner(int dx, int dy, int dz, int k) {
      return ((dz + (k >> 2)) * 3 + dy + ((k >> 1) & 1)) * 3 + dx + (k & 1);
    }
  };

  // The distinct nearest seeds of a piece's vertices (indices into the near seeds), up to three.
  struct Sites {
    int id[3];
    int n = 0;
    // False if `s` would be a fourth: the exact tests give up there.
    bool add(int s) {
      if (std::find(id, id + n, s) != id + n) return true;
      if (n == 3) return false;
      id[n++] = s;
      return true;
    }
  };
  // The index in `near` of the seed nearest x (the first of ties; -1 if none), and its squared
  // distance.
  static int nearest_seed(Vec3 x, const std::vector<Vec3>& near, double& dist2) {
    dist2 = INFINITY;
    int arg = -1;
    for (size_t i = 0; i < near.size(); ++i) {
      const double d = norm2(near[i] - x);
      if (d < dist2) dist2 = d, arg = int(i);
    }
    return arg;
  }
  int nearest_to_corner(int p, const std::vector<Vec3>& near, CornerCache& cc) const {
    if (!(cc.known >> p & 1)) {
      cc.nearest[p] = nearest_seed(cc.point(p), near, cc.dist2[p]);
      cc.known |= 1u << p;
    }
    return cc.nearest[p];
  }

  // A cube's edges as pairs of corners; corner k is lo + h * (k & 1, k >> 1 & 1, k >> 2).
  static constexpr int kCubeEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                            {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

  // The last steps of the exact coverage tests below, on a convex piece P of a cube whose
  // vertices are each within r of their nearest seed in `near`, these being the two or three
  // `s`: P is covered by their balls iff every crossing of one of P's edges with the bisector
  // of two sites, not nearer the third, is within r, and, for three sites, so are the ends of the
  // equidistant line's part in P. P is the box [lo, hi], cut by `cut` if given.
  bool sites_cover(const std::vector<Vec3>& near, const Sites& s, const Vec3 (*edges)[2], int count, Vec3 lo, Vec3 hi,
                   const Plane* cut) const {
    const int* site = s.id;
    const int sites = s.n;
    const double limit = r2_ * (1 - 1e-12);
    for (int i = 0; i < sites; ++i)
      for (int j = i + 1; j < sites; ++j) {
        const Vec3 qa = near[site[i]], qb = near[site[j]];
        const Vec3 n = qb - qa;
        const double mid = (norm2(qb) - norm2(qa)) / 2;  // bisector: dot(n, p) = mid
        for (int e = 0; e < count; ++e) {
          const double su = dot(n, edges[e][0]) - mid, sv = dot(n, edges[e][1]) - mid;
          if ((su < 0) == (sv < 0)) continue;
          const Vec3 x = edges[e][0] + (su / (su - sv)) * (edges[e][1] - edges[e][0]);
          const double d2 = norm2(x - qa);
          if (sites == 3 && norm2(x - near[site[3 - i - j]]) < d2) continue;  // inside the third's piece
          if (d2 >= limit) return false;
        }
      }
    if (sites < 3) return true;
    // The line equidistant from the three, through their circumcentre normal to their plane, as
    // centre + t * axis: its part in P is an interval of t, whose ends are its crossings with P's
    // faces.
    const Vec3 a = near[site[0]], b = near[site[1]] - a, c = near[site[2]] - a;
    const Vec3 axis = cross(b, c);
    const double w = norm2(axis);
    if (!(w > 1e-24 * r2_ * r2_)) return false;  // (nearly) collinear: give up
    const Vec3 centre = a + (1 / (2 * w)) * cross(norm2(b) * c - norm2(c) * b, axis);
    double t0 = -INFINITY, t1 = INFINITY;
    auto keep_below = [&](Vec3 n, double offset) {  // t with dot(n, centre + t axis) <= offset
      const double s0 = dot(n, centre) - offset, ds = dot(n, axis);
      if (ds == 0) {
        if (s0 > 0) t0 = INFINITY;
      } else if (ds > 0) {
        t1 = std::min(t1, -s0 / ds);
      } else {
        t0 = std::max(t0, -s0 / ds);
      }
    };
    for (int ax = 0; ax < 3; ++ax) {
      Vec3 e{};
      e[ax] = 1;
      keep_below(e, hi[ax]);
      keep_below(-1.0 * e, -lo[ax]);
    }
    if (cut) keep_below(cut->normal, cut->offset);
    if (t0 <= t1)
      for (double t : {t0, t1})
        if (norm2(centre + t * axis - a) >= limit) return false;
    return true;
  }

  // Is child (dx, dy, dz) of the parent described by `cc`, in no single ball (see
  // children_in_one_ball), inside the union of the r-balls around `near`? When the corners'
  // nearest seeds are two or three seeds S, exact for the balls of S: the cube is cut into
  // convex pieces by S's Voronoi diagram, and a piece is inside its seed's ball iff its
  // vertices are. They are the cube's corners (each within r of its nearest seed, checked
  // first), the crossings of the cube's edges with a bisector of two seeds of S that are not
  // nearer the third, and, for three seeds, the crossings of the cube's faces with the line
  // equidistant from all three. Nearly half the cubes a two-ball test keeps are covered by three.
  bool covered(const std::vector<Vec3>& near, CornerCache& cc, int dx, int dy, int dz) const {
    Vec3 corner[8];
    Sites sites;
    for (int k = 0; k < 8; ++k) {
      const int p = CornerCache::child_corner(dx, dy, dz, k);
      const int n = nearest_to_corner(p, near, cc);
      if (cc.dist2[p] > r2_) return false;  // a corner is uncovered
      corner[k] = cc.point(p);
      if (!sites.add(n)) return false;  // four or more nearest seeds: give up (keep the cube)
    }
    if (sites.n < 2) return false;
    Vec3 edges[12][2];
    for (int e = 0; e < 12; ++e) edges[e][0] = corner[kCubeEdges[e][0]], edges[e][1] = corner[kCubeEdges[e][1]];
    // Corners are classified by nearest seed but the bisector tests by sign; they agree up to
    // round-off, and a tie point is within r of both seeds by the checks above.
    return sites_cover(near, sites, edges, 12, corner[0], corner[7], nullptr);
  }

  // A band around facet plane `pl` wider than the round-off of its signed distances at points
  // of the box [lo, lo + h]^3 (the plane is fitted to its triangles' corners, which lie on it
  // exactly).
  static double round_off_band(const Plane& pl, Vec3 lo, double h) {
    return 1e-9 * (std::abs(pl.offset) + h + std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z)}));
  }

  // Is the part of child (dx, dy, dz) on the inner side of `pl` inside the union of the r-balls
  // around `near`? The same exact test as covered() on the convex piece P = child ∩ {pl <= 0}
  // (made a round-off margin larger, so that it holds the domain's part): P's vertices are the
  // child's corners inside and the crossings of its edges with the plane; its edges, the inside
  // parts of the child's edges and the plane's section of each face; the three-seed line is
  // clipped to P. A cube cut by the boundary is often covered where it is inside the domain while
  // its part outside is not, and covered() alone keeps refining it (half of the cut sub-cubes
  // of the tube: measured with 256 random points each).
  bool covered_below_plane(const std::vector<Vec3>& near, CornerCache& cc, int dx, int dy, int dz,
                           const Plane& pl) const {
    const Vec3 lo = cc.point(((dz * 3) + dy) * 3 + dx);
    const double h = cc.h;
    const Plane below{pl.normal, pl.offset + round_off_band(pl, lo, h)};  // P's cutting plane
    Vec3 corner[8];
    double sd[8];
    int lattice[8];  // the corners' points in the parent's lattice
    for (int k = 0; k < 8; ++k) {
      lattice[k] = CornerCache::child_corner(dx, dy, dz, k);
      corner[k] = cc.point(lattice[k]);
      sd[k] = below.signed_distance(corner[k]);
    }
    Vec3 vert[20], seg[24][2];
    int nv = 0, ns = 0, cross_at[12];
    Sites sites;
    for (int k = 0; k < 8; ++k) {
      if (sd[k] > 0) continue;
      const int n = nearest_to_corner(lattice[k], near, cc);
      if (cc.dist2[lattice[k]] > r2_ || !sites.add(n)) return false;
      vert[nv++] = corner[k];
    }
    const int corners_inside = nv;
    if (nv == 0) return false;  // the plane only grazes the child: keep it
    for (int e = 0; e < 12; ++e) {
      const int a = kCubeEdges[e][0], b = kCubeEdges[e][1];
      cross_at[e] = -1;
      if ((sd[a] <= 0) && (sd[b] <= 0)) {
        seg[ns][0] = corner[a], seg[ns++][1] = corner[b];
      } else if ((sd[a] <= 0) != (sd[b] <= 0)) {
        const Vec3 x = corner[a] + (sd[a] / (sd[a] - sd[b])) * (corner[b] - corner[a]);
        cross_at[e] = nv;
        vert[nv++] = x;
        seg[ns][0] = sd[a] <= 0 ? corner[a] : corner[b], seg[ns++][1] = x;
      }
    }
    // The plane's section of each face joins its two crossings (other counts: degenerate, keep).
    for (int axis = 0; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side) {
        int on[4], m = 0;
        for (int e = 0; e < 12; ++e) {
          const int a = kCubeEdges[e][0], b = kCubeEdges[e][1];
          if ((a >> axis & 1) == side && (b >> axis & 1) == side && cross_at[e] >= 0) on[m++] = cross_at[e];
        }
        if (m == 2) seg[ns][0] = vert[on[0]], seg[ns++][1] = vert[on[1]];
        else if (m != 0) return false;
      }
    // The crossings' nearest seeds (the corners' are cached).
    for (int v = corners_inside; v < nv; ++v) {
      double d2;
      const int n = nearest_seed(vert[v], near, d2);
      if (d2 > r2_ || !sites.add(n)) return false;
    }
    return sites.n < 2 || sites_cover(near, sites, seg, ns, corner[0], corner[7], &below);
  }

  // -1 outside, 0 cut by the boundary, 1 inside, with respect to the given planes; `cut`
  // (optional) receives the planes that cut the box, `first_cut` (optional) the first of them.
  // A box within `band` of a plane counts as cut by it.
  template <class PlaneIds>
  int classify_box(Vec3 lo, double h, const PlaneIds& ids, std::vector<int32_t>* cut = nullptr,
                   int32_t* first_cut = nullptr, double band = 0) const {
    bool inside = true;
    for (int32_t id : ids) {
      const Plane& pl = domain_.planes[id];
      // Extreme corners of the box along the plane normal.
      double dmin = pl.signed_distance(lo), dmax = dmin;
      for (int a = 0; a < 3; ++a) (pl.normal[a] > 0 ? dmax : dmin) += h * pl.normal[a];
      if (dmin > band) return -1;
      if (dmax > -band) {
        if (inside && first_cut) *first_cut = id;
        inside = false;
        if (cut) cut->push_back(id);
      }
    }
    return inside ? 1 : 0;
  }

  // A boundary base cube's place in the boundary lists (a bisection: callers look it up once
  // per cube, not per dart or per child).
  size_t boundary_slot(uint32_t b) const {
    return size_t(std::lower_bound(boundary_base_.begin(), boundary_base_.end(), b) - boundary_base_.begin());
  }

  // What cuts the boundary cube in `slot`: facet planes of a convex domain, triangles of any
  // other.
  std::span<const int32_t> cutting_planes(size_t slot) const {
    return {boundary_planes_.data() + boundary_begin_[slot], boundary_begin_[slot + 1] - boundary_begin_[slot]};
  }

  // Is p, a point of the boundary cube in `slot`, inside the domain?
  bool inside_domain(Vec3 p, size_t slot) const {
    if (!domain_.convex) {
      if (const int32_t facet = boundary_facet_[slot]; facet >= 0) {  // the plane decides, away from it
        const Plane& P = domain_.planes[facet];
        const double s = P.signed_distance(p);
        if (std::abs(s) > round_off_band(P, p, s_.grid.side)) return s < 0;
      }
      // Parity of crossings from the cube's reference point; only the cube's triangles can
      // cross the segment, which stays in the cube.
      const Reference& ref = boundary_ref_[slot];
      bool in;
      if (domain_.locator->side_from(ref.p, ref.inside, p, cutting_planes(slot), in)) return in;
      return domain_.locator->inside(p);  // a degenerate crossing: ask the whole surface
    }
    for (int32_t id : cutting_planes(slot))
      if (domain_.planes[id].signed_distance(p) > 0) return false;
    return true;
  }

  // classify_box for a sub-cube of the boundary cube in `slot`. When it is cut (0), `plane`
  // receives a facet plane whose inner side holds the domain's part of the sub-cube, or -1: for
  // a convex domain any plane that cuts it; otherwise the plane of the triangles that meet it, if
  // they all lie in one (then they span the plane's section of the sub-cube:
  // Domain::facet_plane_of).
  int classify_sub_box(Vec3 lo, double h, size_t slot, int32_t& plane) const {
    plane = -1;
    if (domain_.convex) {
      const int cls = classify_box(lo, h, cutting_planes(slot), nullptr, &plane);
      if (cls != 0) plane = -1;
      return cls;
    }
    if (const int32_t facet = boundary_facet_[slot]; facet >= 0) {
      // The plane alone classifies the sub-cube (`plane` is set only when it cuts); within a
      // round-off band of it, it is cut.
      return classify_box(lo, h, std::array{facet}, nullptr, &plane, round_off_band(domain_.planes[facet], lo, h));
    }
    const Vec3 hi = lo + Vec3{h, h, h};
    int32_t first = -1;
    for (int32_t t : cutting_planes(slot)) {
      if (first >= 0 && domain_.triangle_plane[t] == domain_.triangle_plane[first]) continue;
      if (!domain_.locator->triangle_meets_box(t, lo, hi)) continue;
      if (first >= 0) return 0;  // triangles of two planes
      first = t;
    }
    if (first >= 0) {
      plane = domain_.triangle_plane[first];
      return 0;
    }
    return inside_domain(lo + Vec3{h / 2, h / 2, h / 2}, slot) ? 1 : -1;
  }

  // Non-convex domains: -1, 0 or 1 as classify_box, by which of `candidates` meet the box
  // (`cut` receives them). None means the box is on one side of the surface: that of its centre,
  // by parity from `ref` (a point of known side whose segment to the centre only candidates can
  // cross), or by the whole surface.
  struct Reference { Vec3 p; bool inside; };
  int classify_box_by_surface(Vec3 lo, double h, std::span<const int32_t> candidates, std::vector<int32_t>* cut,
                              const Reference* ref) const {
    const Vec3 hi = lo + Vec3{h, h, h};
    bool any = false;
    for (int32_t t : candidates)
      if (domain_.locator->triangle_meets_box(t, lo, hi)) {
        any = true;
        if (!cut) break;
        cut->push_back(t);
      }
    if (any) return 0;
    const Vec3 c = lo + Vec3{h / 2, h / 2, h / 2};
    bool in;
    if (!ref || !domain_.locator->side_from(ref->p, ref->inside, c, candidates, in)) in = domain_.locator->inside(c);
    return in ? 1 : -1;
  }

  // A point near `p` off the surface, and its side.
  Reference reference_near(Vec3 p, double h) const {
    int side = domain_.locator->side(p);
    for (int n = 1; side == 0; ++n) {
      p = p + Vec3{h * 0.037, -h * 0.029, h * 0.011};
      side = domain_.locator->side(p);
    }
    return {p, side > 0};
  }

  // The base cubes of the box of n^3 cubes from (i0, j0, k0) (n a power of two), which `cut`
  // meets and of which `ref` is a point of known side, for a non-convex domain: each octant is
  // tested against the triangles that meet the box, then either taken whole (inside), dropped
  // (outside) or split again, down to single cubes, which get their triangles and a reference
  // point for inside tests (their centre).
  void classify_cut_octants(int i0, int j0, int k0, int n, const std::vector<int32_t>& cut, const Reference& ref,
                            std::vector<ActiveCube>& cubes, std::vector<std::pair<uint32_t, int32_t>>& cuts,
                            std::vector<std::pair<uint32_t, Reference>>& refs) const {
    const auto& g = s_.grid;
    const int m = n / 2;
    std::vector<int32_t> sub;
    for (int o = 0; o < 8; ++o) {
      const int i = i0 + (o & 1) * m, j = j0 + (o >> 1 & 1) * m, k = k0 + (o >> 2) * m;
      if (i >= g.nx || j >= g.ny || k >= std::min(g.nz, owned_end_) || k + m <= owned_begin_) continue;
      const Vec3 lo = g.origin + Vec3{i * g.side, j * g.side, k * g.side};
      const double h = m * g.side;
      sub.clear();
      const int cls = classify_box_by_surface(lo, h, cut, &sub, &ref);
      if (cls < 0) continue;
      if (cls > 0) {
        for (int kk = std::max(k, owned_begin_); kk < std::min({k + m, g.nz, owned_end_}); ++kk)
          for (int jj = j; jj < std::min(j + m, g.ny); ++jj)
            for (int ii = i; ii < std::min(i + m, g.nx); ++ii)
              cubes.push_back({uint32_t(g.index(ii, jj, kk)), 0, 0, ActiveCube::kInside});
        continue;
      }
      // Cut: its centre is its reference point, by parity from `ref` (only `cut` can cross the
      // segment, which stays in the box) or nudged off the surface.
      const Vec3 centre = lo + Vec3{h / 2, h / 2, h / 2};
      Reference own{centre, false};
      if (!domain_.locator->side_from(ref.p, ref.inside, centre, cut, own.inside)) own = reference_near(centre, g.side);
      if (m > 1) {
        classify_cut_octants(i, j, k, m, sub, own, cubes, cuts, refs);
        continue;
      }
      if (k < owned_begin_) continue;
      const uint32_t b = uint32_t(g.index(i, j, k));
      cubes.push_back({b, 0, 0, 0});
      for (int32_t t : sub) cuts.push_back({b, t});
      refs.push_back({b, own});
    }
  }

  // Base cubes not outside the domain, and for those cut by the boundary the planes (convex
  // domain) or triangles that cut them. Blocks of 8^3 cubes are classified first (and a cut
  // block's octants in turn, for triangles), so a cube is tested only against the few that cut
  // its block.
  ActiveCubes initial_cubes() {
    const auto& g = s_.grid;
    constexpr int B = 8;
    const int bx = (g.nx + B - 1) / B, by = (g.ny + B - 1) / B, bz = (g.nz + B - 1) / B;
    // Only the layers of blocks that meet this sampler's slab.
    const int bz0 = owned_begin_ / B, bz1 = std::min(bz, (owned_end_ + B - 1) / B);
    const size_t blocks = size_t(bx) * by * (bz1 - bz0);
    std::vector<std::vector<ActiveCube>> cubes(blocks);
    std::vector<std::vector<std::pair<uint32_t, int32_t>>> cuts(blocks);
    std::vector<std::vector<std::pair<uint32_t, Reference>>> refs(blocks);
    std::vector<int32_t> all(domain_.planes.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = int32_t(i);
    const bool convex = domain_.convex;
#pragma omp parallel for schedule(dynamic, 1)
    for (size_t blk = 0; blk < blocks; ++blk) {
      const int i0 = int(blk % bx) * B, j0 = int((blk / bx) % by) * B, k0 = (bz0 + int(blk / (size_t(bx) * by))) * B;
      std::vector<int32_t> block_cut, cube_cut;
      // The block as a cube of side B * side (it may stick out of the grid: harmless).
      const Vec3 block_lo = g.origin + Vec3{i0 * g.side, j0 * g.side, k0 * g.side};
      const double bh = B * g.side;
      int cls;
      if (convex) {
        cls = classify_box(block_lo, bh, all, &block_cut);
      } else {
        // The triangles that meet the block (exactly, as classify_box_by_surface would test them).
        domain_.locator->triangles_near(block_lo, block_lo + Vec3{bh, bh, bh}, block_cut);
        cls = block_cut.empty() ? classify_box_by_surface(block_lo, bh, block_cut, nullptr, nullptr) : 0;
      }
      if (cls < 0) continue;
      if (!convex && cls == 0) {
        // Halves of halves, from a reference point near the block's centre: a cube is tested
        // only against the triangles that meet its octant.
        const Reference block_ref = reference_near(block_lo + Vec3{bh / 2, bh / 2, bh / 2}, g.side);
        classify_cut_octants(i0, j0, k0, B, block_cut, block_ref, cubes[blk], cuts[blk], refs[blk]);
        std::sort(cubes[blk].begin(), cubes[blk].end(),
                  [](const ActiveCube& a, const ActiveCube& b) { return a.base < b.base; });
        continue;
      }
      // Inside, or cut by planes of a convex domain.
      for (int k = std::max(k0, owned_begin_); k < std::min({k0 + B, g.nz, owned_end_}); ++k)
        for (int j = j0; j < std::min(j0 + B, g.ny); ++j)
          for (int i = i0; i < std::min(i0 + B, g.nx); ++i) {
            const uint32_t b = uint32_t(g.index(i, j, k));
            cube_cut.clear();
            const int c = cls > 0 ? 1 : classify_box(base_origin(b), g.side, block_cut, &cube_cut);
            if (c < 0) continue;
            cubes[blk].push_back({b, 0, 0, c > 0 ? ActiveCube::kInside : 0});
            for (int32_t id : cube_cut) cuts[blk].push_back({b, id});
          }
    }
    std::vector<std::pair<uint32_t, int32_t>> pairs = concatenate(cuts);
    std::sort(pairs.begin(), pairs.end());
    boundary_begin_.assign(1, 0);
    for (size_t k = 0; k < pairs.size(); ++k) {
      if (k == 0 || pairs[k].first != pairs[k - 1].first) {
        if (k > 0) boundary_begin_.push_back(uint32_t(k));
        boundary_base_.push_back(pairs[k].first);
      }
      boundary_planes_.push_back(pairs[k].second);
    }
    boundary_begin_.push_back(uint32_t(pairs.size()));
    if (!convex) {
      std::vector<std::pair<uint32_t, Reference>> all_refs = concatenate(refs);
      std::sort(all_refs.begin(), all_refs.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
      boundary_ref_.resize(all_refs.size());
      for (size_t k = 0; k < all_refs.size(); ++k) boundary_ref_[k] = all_refs[k].second;  // in boundary_base_ order
      boundary_facet_.resize(boundary_base_.size());
      for (size_t slot = 0; slot < boundary_base_.size(); ++slot) boundary_facet_[slot] = domain_.facet_plane_of(cutting_planes(slot));
    }
    std::erase_if(cubes, [](const std::vector<ActiveCube>& part) { return part.empty(); });
    return {std::move(cubes)};
  }

  // A round's candidates, per part of the active cubes: the darts no seed rejects.
  struct Darts {
    std::vector<std::vector<Candidate>> parts;
    size_t thrown = 0;
  };

  // Throws round `round`'s darts into active cube c of `level` (low corner lo, side h; slot_of()
  // gives its boundary slot) and appends to `out` those inside the domain that `near_seed(p)`
  // does not reject; returns how many it threw. A cube's darts depend only on its place, level
  // and round, so whoever throws them throws the same ones.
  template <class Slot, class NearSeed>
  int throw_darts(const ActiveCube& c, int level, int round, Vec3 lo, double h, Slot slot_of, const Poisson& poisson,
                  NearSeed near_seed, std::vector<Candidate>& out) const {
    const uint64_t c1 = (uint64_t(c.sx) << 32) | c.sy;
    const uint64_t tag = (uint64_t(c.sz()) << 32) | (uint64_t(level) << 24) | (uint64_t(round) << 12);
    const int n = poisson(CounterRng::unit(rng_.words(uint64_t(c.base), c1, tag, 0)[0]));
    if (n == 0) return 0;
    const size_t slot = c.inside() ? 0 : slot_of();
    for (int k = 0; k < n; ++k) {
      auto w = rng_.words(uint64_t(c.base), c1, tag | uint64_t(k + 1), 0);
      Vec3 p = lo + Vec3{CounterRng::unit(w[0]) * h, CounterRng::unit(w[1]) * h, CounterRng::unit(w[2]) * h};
      if (!c.inside() && !inside_domain(p, slot)) continue;
      if (near_seed(p)) continue;
      out.push_back({w[3], c.base, p});
    }
    return n;
  }

  static Poisson darts_per_cube(int level, int round) {
    return Poisson(level == 0 ? kDartsPerCubeLevel0Rounds[size_t(round)] : kDartsPerCubePerRound);
  }

  Darts throw_round(const ActiveCubes& active, int level, int round) const {
    const double h = std::ldexp(s_.grid.side, -level);
    const Poisson poisson = darts_per_cube(level, round);
    const size_t chunks = active.parts.size();
    Darts out;
    out.parts.resize(chunks);
    size_t darts = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : darts)
    for (size_t ch = 0; ch < chunks; ++ch) {
      StencilSeeds stencil_seeds;
      for (const ActiveCube& c : active.parts[ch]) {
        if (cube_entry(c.base) != -1) continue;  // a seed covers the whole base cube
        const Vec3 lo = base_origin(c.base) + Vec3{c.sx * h, c.sy * h, c.sz() * h};
        darts += size_t(throw_darts(c, level, round, lo, h, [&] { return boundary_slot(c.base); }, poisson,
                                    [&](Vec3 p) { return seed_within_r(p, c.base, stencil_seeds); }, out.parts[ch]));
      }
    }
    out.thrown = darts;
    return out;
  }

  // Accepts a round's candidates that no earlier one of the round rules out, as new seeds.
  void accept_round(Darts& round) {
    s_.stats.darts += round.thrown;
    Round round_set;
    round_set.all = concatenate(round.parts);
    if (partition_) add_neighbours_candidates(round_set);
    const std::vector<Candidate>& all = round_set.all;
    s_.stats.candidates += all.size();
    const std::vector<uint8_t> accepted = accept_in_arrival_order(round_set);
    // New seeds are numbered in Morton order of their cubes, so the seeds that neighbour
    // queries read together lie together in memory (the arrival order scatters them). A
    // neighbour's accepted candidates are this rank's halo seeds.
    std::vector<std::pair<uint64_t, uint32_t>> order;
    for (size_t c = 0; c < all.size(); ++c)
      if (accepted[c]) order.push_back({morton(all[c].base), uint32_t(c)});
    std::sort(order.begin(), order.end());
    for (const auto& [key, c] : order) {
      cube_entry(all[c].base) = int32_t(s_.seeds.size());
      s_.seeds.push_back(all[c].p);
    }
  }

  static bool by_arrival(const Candidate& a, const Candidate& b) {
    return a.time != b.time ? a.time < b.time : a.base < b.base;
  }

  // One round's candidates. In a partitioned run they are in arrival order and include the
  // neighbours' candidates within r of this slab (`source`: 0 own, 1 from the rank below, 2 from
  // above), with the positions of the candidates whose decisions the ranks trade.
  struct Round {
    std::vector<Candidate> all;
    std::vector<uint8_t> source;
    std::vector<uint32_t> send_lower, send_upper, from_lower, from_upper;
  };

  // Candidates within r of the slab's faces go to the neighbour on that side: a candidate
  // conflicts only with others within r, and r spans fewer than kSamplingHaloLayers layers.
  void add_neighbours_candidates(Round& rs) {
    auto pack = [&](bool lower) {
      Communicator::Bytes out;
      for (const Candidate& c : rs.all) {
        const int k = layer_of(c.base);
        if (lower ? k < owned_begin_ + kSamplingHaloLayers : k >= owned_end_ - kSamplingHaloLayers) {
          const auto* b = reinterpret_cast<const uint8_t*>(&c);
          out.insert(out.end(), b, b + sizeof(Candidate));
        }
      }
      return out;
    };
    Communicator::Bytes below, above;
    partition_->comm->exchange_with_neighbours(pack(true), pack(false), below, above);
    ++partition_->exchanges;
    rs.source.assign(rs.all.size(), 0);
    for (const auto* bytes : {&below, &above}) {
      const size_t n = bytes->size() / sizeof(Candidate);
      const size_t at = rs.all.size();
      rs.all.resize(at + n);
      if (n > 0) std::memcpy(static_cast<void*>(rs.all.data() + at), bytes->data(), n * sizeof(Candidate));
      rs.source.resize(at + n, bytes == &below ? 1 : 2);
    }
    std::vector<uint32_t> perm(rs.all.size());
    for (size_t i = 0; i < perm.size(); ++i) perm[i] = uint32_t(i);
    std::sort(perm.begin(), perm.end(), [&](uint32_t a, uint32_t b) { return by_arrival(rs.all[a], rs.all[b]); });
    std::vector<Candidate> sorted(perm.size());
    std::vector<uint8_t> source(perm.size());
    for (size_t i = 0; i < perm.size(); ++i) sorted[i] = rs.all[perm[i]], source[i] = rs.source[perm[i]];
    rs.all = std::move(sorted);
    rs.source = std::move(source);
    // Each side's candidates keep their relative (arrival) order, so both ranks list the traded
    // ones in the same order.
    for (size_t c = 0; c < rs.all.size(); ++c) {
      const int k = layer_of(rs.all[c].base);
      if (rs.source[c] == 1) rs.from_lower.push_back(uint32_t(c));
      else if (rs.source[c] == 2) rs.from_upper.push_back(uint32_t(c));
      else {
        if (k < owned_begin_ + kSamplingHaloLayers) rs.send_lower.push_back(uint32_t(c));
        if (k >= owned_end_ - kSamplingHaloLayers) rs.send_upper.push_back(uint32_t(c));
      }
    }
  }

  // Interleaved bits of a base cube's coordinates (i in bits 0, 3, 6, ..., j in 1, 4, ..., k in
  // 2, 5, ...; 21 bits each), spread by masks instead of a loop over the bits (the loop was half
  // of the serial numbering of a round's new seeds).
  static uint64_t spread_bits(uint64_t x) {
    x &= 0x1FFFFF;
    x = (x | x << 32) & 0x1F00000000FFFFull;
    x = (x | x << 16) & 0x1F0000FF0000FFull;
    x = (x | x << 8) & 0x100F00F00F00F00Full;
    x = (x | x << 4) & 0x10C30C30C30C30C3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
    return x;
  }
  uint64_t morton(int64_t b) const {
    int i, j, k;
    s_.grid.coords(b, i, j, k);
    return spread_bits(uint64_t(i)) | spread_bits(uint64_t(j)) << 1 | spread_bits(uint64_t(k)) << 2;
  }

  // Greedy in arrival order, computed in parallel: a candidate is accepted iff no earlier
  // candidate of the round that conflicts with it (within r, or in the same base cube) is
  // accepted. Each pass decides every candidate whose earlier conflicting candidates are all
  // decided; decisions are final, so the result is the sequential greedy one whatever the
  // threads or their timing, and whatever the order of `all`. In a partitioned run a rank
  // decides its own candidates only; after it can go no further the ranks trade the decisions
  // near their shared faces, until no rank has an undecided candidate. The earliest undecided
  // candidate anywhere is always decidable, so this ends, with the serial decisions.
  std::vector<uint8_t> accept_in_arrival_order(const Round& rs) {
    enum : uint8_t { Undecided, Accepted, Rejected };
    const std::vector<Candidate>& all = rs.all;
    const size_t n = all.size();
    // Candidates bucketed in cubes of side r over their bounding box (counting sort). When the
    // box has many more cubes than candidates (late rounds, or a domain that fills little of its
    // box) the cubes are hashed into 2n slots, so a round costs O(n); cubes that share a slot
    // only add candidates the exact test then skips.
    Box box{all.empty() ? Vec3{} : all[0].p, all.empty() ? Vec3{} : all[0].p};
    for (const Candidate& c : all)
      for (int a = 0; a < 3; ++a) box.lo[a] = std::min(box.lo[a], c.p[a]), box.hi[a] = std::max(box.hi[a], c.p[a]);
    const int nx = std::max(1, int(std::ceil(box.size().x / r_))), ny = std::max(1, int(std::ceil(box.size().y / r_))),
              nz = std::max(1, int(std::ceil(box.size().z / r_)));
    auto cell = [&](Vec3 p, int& i, int& j, int& k) {
      i = std::clamp(int((p.x - box.lo.x) / r_), 0, nx - 1);
      j = std::clamp(int((p.y - box.lo.y) / r_), 0, ny - 1);
      k = std::clamp(int((p.z - box.lo.z) / r_), 0, nz - 1);
    };
    const size_t cubes = size_t(nx) * ny * nz;
    const bool hashed = cubes > 4 * n;
    const size_t slots = hashed ? std::bit_ceil(2 * n) : cubes;
    auto slot = [&](int i, int j, int k) {
      if (!hashed) return (size_t(k) * ny + j) * nx + i;
      return size_t((uint64_t(i) * 73856093u) ^ (uint64_t(j) * 19349663u) ^ (uint64_t(k) * 83492791u)) & (slots - 1);
    };
    std::vector<uint32_t> begin(slots + 1, 0), key(n);
    for (size_t c = 0; c < n; ++c) {
      int i, j, k;
      cell(all[c].p, i, j, k);
      key[c] = uint32_t(slot(i, j, k));
      ++begin[key[c] + 1];
    }
    for (size_t b = 1; b < begin.size(); ++b) begin[b] += begin[b - 1];
    // The candidates again in slot order, each slot's in arrival order, and everything the
    // passes read kept in that order: a candidate's neighbours are then read from nearby memory
    // (in arrival order they are scattered in space, and their reads missed the cache: half of
    // a round's time).
    struct Entry {
      Candidate c;
      uint32_t index;  // in `all`
    };
    std::vector<Entry> entry(n);
    std::vector<uint32_t> at(n);  // entry of each candidate of `all`
    {
      std::vector<uint32_t> fill(begin.begin(), begin.end() - 1);
      for (size_t c = 0; c < n; ++c) entry[fill[key[c]]++] = {all[c], uint32_t(c)};
    }
#pragma omp parallel for schedule(dynamic, 4096)
    for (size_t b = 0; b < slots; ++b) {
      std::sort(entry.begin() + begin[b], entry.begin() + begin[b + 1],
                [](const Entry& x, const Entry& y) { return by_arrival(x.c, y.c); });
      for (uint32_t e = begin[b]; e < begin[b + 1]; ++e) at[entry[e].index] = e;
    }
    std::vector<std::atomic<uint8_t>> state(n);  // by entry
    for (auto& s : state) s.store(Undecided, std::memory_order_relaxed);
    // The pass in which an entry was last found blocked (0: none). A blocked entry reached again
    // in that pass through another's recursion answers at once: otherwise a cluster of k
    // mutually conflicting candidates whose earliest waits for a neighbour rank's decision is
    // walked along every descending chain, some 2^k times, up to the depth bound (commit
    // 811beed). The answer is only postponed to a later
    // pass, and the outcome, greedy in arrival order, does not depend on when it is decided.
    std::vector<std::atomic<uint32_t>> blocked_in_pass(n);
    for (auto& b : blocked_in_pass) b.store(0, std::memory_order_relaxed);
    uint32_t pass = 0;
    constexpr int kDecideDepth = 16;
    for (;;) {
      bool undecided = n > 0, progress = true;
      while (undecided && progress) {
        undecided = progress = false;
        ++pass;
        size_t lookups = 0;
#pragma omp parallel for schedule(dynamic, 4096) reduction(|| : undecided, progress) reduction(+ : lookups)
        for (size_t e = 0; e < n; ++e) {
          if (state[e].load(std::memory_order_relaxed) != Undecided) continue;
          if (!rs.source.empty() && rs.source[entry[e].index] != 0) continue;  // a neighbour decides it
          // Decides entry f if it can, deciding its undecided earlier conflicting candidates
          // first, to a bounded depth: in bucket order those are often not visited yet, and
          // leaving them to the next pass took 4 to 6 passes.
          auto decide = [&](auto& self, uint32_t f, int depth) -> uint8_t {
            ++lookups;
            const uint8_t known = state[f].load(std::memory_order_acquire);
            if (known != Undecided) return known;
            if (!rs.source.empty() && rs.source[entry[f].index] != 0) return Undecided;  // until traded
            // (A pass's own visit to an entry always looks again: its blockers may be decided by now.)
            if (depth < kDecideDepth && blocked_in_pass[f].load(std::memory_order_relaxed) == pass) return Undecided;
            const Candidate& me = entry[f].c;
            int ci, cj, ck;
            cell(me.p, ci, cj, ck);
            bool blocked = false;
            for (int k = std::max(0, ck - 1); k <= std::min(nz - 1, ck + 1); ++k)
              for (int j = std::max(0, cj - 1); j <= std::min(ny - 1, cj + 1); ++j)
                for (int i = std::max(0, ci - 1); i <= std::min(nx - 1, ci + 1); ++i) {
                  const size_t b = slot(i, j, k);
                  for (uint32_t o = begin[b]; o < begin[b + 1]; ++o) {
                    const Candidate& other = entry[o].c;
                    if (!by_arrival(other, me)) break;  // only earlier arrivals matter (in order in a slot)
                    if (other.base != me.base && norm2(other.p - me.p) >= r2_) continue;
                    const uint8_t so = depth > 0 ? self(self, o, depth - 1) : state[o].load(std::memory_order_acquire);
                    if (so == Accepted) {
                      state[f].store(Rejected, std::memory_order_release);
                      progress = true;
                      return Rejected;
                    }
                    blocked |= so == Undecided;
                  }
                }
            if (blocked) {
              blocked_in_pass[f].store(pass, std::memory_order_relaxed);
              return Undecided;
            }
            state[f].store(Accepted, std::memory_order_release);
            progress = true;
            return Accepted;
          };
          if (decide(decide, uint32_t(e), kDecideDepth) == Undecided) undecided = true;
        }
        s_.stats.decision_lookups += lookups;
      }
      if (!partition_) break;
      // Trade decisions with the neighbours, then stop when no rank has an undecided candidate
      // (the trade before that last check delivered the final ones).
      auto states = [&](const std::vector<uint32_t>& candidates) {
        Communicator::Bytes out(candidates.size());
        for (size_t k = 0; k < candidates.size(); ++k) out[k] = state[at[candidates[k]]].load(std::memory_order_relaxed);
        return out;
      };
      Communicator::Bytes below, above;
      partition_->comm->exchange_with_neighbours(states(rs.send_lower), states(rs.send_upper), below, above);
      ++partition_->exchanges;
      for (size_t k = 0; k < rs.from_lower.size(); ++k) state[at[rs.from_lower[k]]].store(below.at(k));
      for (size_t k = 0; k < rs.from_upper.size(); ++k) state[at[rs.from_upper[k]]].store(above.at(k));
      if (!anywhere(undecided)) break;
    }
    std::vector<uint8_t> accepted(n);
    for (size_t c = 0; c < n; ++c) accepted[c] = state[at[c]].load(std::memory_order_relaxed) == Accepted;
    return accepted;
  }

  // Splits every active cube into 8 and keeps the children that are neither covered (by one
  // ball, or from kFirstExactCoverageLevel on provably by two or three) nor outside the domain.
  // From kFirstFusedDartLevel on it also throws the next level's first round into them, into
  // `next_darts`.
  ActiveCubes refine(const ActiveCubes& active, int level, std::optional<Darts>& next_darts) {
    const double h = std::ldexp(s_.grid.side, -(level + 1));
    const size_t chunks = active.parts.size();
    std::vector<std::vector<ActiveCube>> kept(chunks);
    const bool exact = level >= kFirstExactCoverageLevel;
    // The first two refinements' one-ball tests from the seeds' side (the seeds near a cube are
    // then needed only for the exact test). Marks take 8 bytes per cube of the window: only where
    // the domain fills a fifth of it or more, so they cost at most 40 bytes per cube of the
    // domain, under 300 per seed, while the sampler's memory is still far below the peak of the
    // stages after it. A thin or hollow solid's grid can be mostly empty cubes: step.off fills
    // 1.5% of its grid, and its 10^5 cells would have taken 380 MB of marks.
    const bool marked = level <= 1 && 5 * initial_active_ >= s_.cube_seed.size();
    if (marked) {
      mark_grandchildren_in_one_ball(marked_seeds_);
      marked_seeds_ = s_.seeds.size();
    }
    const bool need_near = exact || !marked;
    // The next level's first darts thrown here, into each child kept, and tested against the
    // parent's near seeds, which include every seed within r of it: a dart then reads a few seeds
    // already in cache instead of the grid around it, and the active cubes are walked once, not
    // twice. The darts, and which of them are candidates, are throw_round's.
    const bool throw_next = need_near && level >= kFirstFusedDartLevel;
    const int next_level = level + 1;
    const Poisson poisson = darts_per_cube(next_level, 0);
    Darts darts;
    if (throw_next) darts.parts.resize(chunks);
    size_t thrown = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : thrown)
    for (size_t ch = 0; ch < chunks; ++ch) {
      std::vector<Vec3> near_base, near;
      CornerCache corners;
      int64_t cached_base = -1;
      for (const ActiveCube& c : active.parts[ch]) {
        if (cube_entry(c.base) != -1) continue;  // a seed covers the whole base cube
        const Vec3 base_lo = base_origin(c.base);
        const Vec3 lo = base_lo + Vec3{c.sx * 2 * h, c.sy * 2 * h, c.sz() * 2 * h};
        if (need_near) {
          if (c.base != cached_base) {  // a base cube's sub-cubes are adjacent in the list
            cached_base = c.base;
            seeds_near_base_cube(c.base, near_base);
          }
          // Of the base cube's neighbours, those that may reach this cube.
          const Vec3 center = lo + Vec3{h, h, h};
          const double reach = r_ + h * std::sqrt(3.0);
          near.resize(near_base.size());  // filled without a branch per seed
          size_t in_reach = 0;
          for (Vec3 q : near_base) {
            near[in_reach] = q;
            in_reach += norm2(q - center) < reach * reach;
          }
          near.resize(in_reach);
        }
        const uint32_t in_one_ball =
            marked ? marked_children(c.base, level, c.sx, c.sy, c.sz()) : children_in_one_ball(lo, h, near);
        corners.reset(lo, h);
        const size_t slot = c.inside() ? 0 : boundary_slot(c.base);
        // The children in no single ball, in order (a loop over them, not a branch per child).
        for (uint32_t rest = ~in_one_ball & 0xFF; rest != 0; rest &= rest - 1) {
          const uint32_t child = uint32_t(std::countr_zero(rest));
          uint32_t dx = child & 1, dy = (child >> 1) & 1, dz = child >> 2;
          Vec3 clo = lo + Vec3{dx * h, dy * h, dz * h};
          if (exact && covered(near, corners, int(dx), int(dy), int(dz))) continue;
          uint32_t inside = c.sz_flags & ActiveCube::kInside;
          if (!inside) {
            int32_t plane;
            int cls = classify_sub_box(clo, h, slot, plane);
            if (cls < 0) continue;
            if (cls == 0 && plane >= 0 && exact &&
                covered_below_plane(near, corners, int(dx), int(dy), int(dz), domain_.planes[plane]))
              continue;
            inside = cls > 0 ? ActiveCube::kInside : 0;
          }
          kept[ch].push_back({c.base, 2 * c.sx + dx, 2 * c.sy + dy, (2 * c.sz() + dz) | inside});
          if (throw_next) {
            const ActiveCube& k = kept[ch].back();  // its corner as throw_round rounds it
            const Vec3 k_lo = base_lo + Vec3{k.sx * h, k.sy * h, k.sz() * h};
            thrown += size_t(throw_darts(k, next_level, 0, k_lo, h, [slot] { return slot; }, poisson,
                                         [&](Vec3 p) { return any_within_r(near, p); }, darts.parts[ch]));
          }
        }
      }
    }
    if (throw_next) {
      darts.thrown = thrown;
      next_darts = std::move(darts);
    }
    if (level == 1) std::vector<uint64_t>().swap(grandchild_marks_);
    std::erase_if(kept, [](const std::vector<ActiveCube>& part) { return part.empty(); });
    return {std::move(kept)};
  }

  // Protection seeds first (paper §2.2); the free seeds then keep r from them like from each other.
  void protect() {
    if (domain_.convex || domain_.reflex_curves.empty()) return;
    ProtectionSeeds p = protect_reflex_features(domain_, r_, seed_);
    std::map<int64_t, std::vector<int32_t>> in_cube;  // by index into cube_seed
    for (size_t k = 0; k < p.points.size(); ++k) {
      int i, j, l;
      s_.grid.locate(p.points[k], i, j, l);
      const int64_t slot = s_.grid.index(i, j, l) - s_.cube_offset;
      if (slot < 0 || slot >= int64_t(s_.cube_seed.size())) continue;  // outside this rank's window
      const int32_t id = int32_t(s_.seeds.size());
      s_.seeds.push_back(p.points[k]);
      s_.protected_seeds.push_back({id, p.kinds[k], p.inward[k]});
      in_cube[slot].push_back(id);
    }
    s_.cube_extra_begin.assign(1, 0);
    for (const auto& [c, ids] : in_cube) {
      if (ids.size() == 1) {
        s_.cube_seed[c] = ids[0];
        continue;
      }
      s_.cube_seed[c] = -2 - int32_t(s_.cube_extra_begin.size() - 1);
      s_.cube_extra.insert(s_.cube_extra.end(), ids.begin(), ids.end());
      s_.cube_extra_begin.push_back(int32_t(s_.cube_extra.size()));
    }
    s_.stats.vertex_seeds = size_t(std::count(p.kinds.begin(), p.kinds.end(), CellKind::Vertex));
    s_.stats.edge_seeds = p.points.size() - s_.stats.vertex_seeds;
  }

  void order_seeds_by_cube() {
    std::vector<Vec3> ordered;
    ordered.reserve(s_.seeds.size());
    std::vector<int32_t> new_id(s_.seeds.size(), -1);
    auto place = [&](int32_t& q) {
      new_id[q] = int32_t(ordered.size());
      ordered.push_back(s_.seeds[q]);
      q = new_id[q];
    };
    for (int32_t& q : s_.cube_seed) {
      if (q >= 0) place(q);
      else if (q <= -2)
        for (int32_t k = s_.cube_extra_begin[-2 - q]; k < s_.cube_extra_begin[-1 - q]; ++k) place(s_.cube_extra[k]);
    }
    for (auto& p : s_.protected_seeds) p.seed = new_id[p.seed];
    std::sort(s_.protected_seeds.begin(), s_.protected_seeds.end(),
              [](const auto& a, const auto& b) { return a.seed < b.seed; });
    s_.seeds = std::move(ordered);
  }

  const Domain& domain_;
  // Boundary base cubes (sorted) and, for each, the domain planes that cut it.
  std::vector<uint32_t> boundary_base_, boundary_begin_;
  std::vector<int32_t> boundary_planes_;
  std::vector<Reference> boundary_ref_;  // non-convex domains: per boundary cube
  // Non-convex domains, per boundary cube: the facet plane of all the triangles that meet it,
  // or -1; the plane alone then tells a sub-cube's or a dart's side (Domain::facet_plane_of).
  std::vector<int32_t> boundary_facet_;
  // Per window cube, its grandchildren in one seed's ball, from the first marked_seeds_ seeds
  // (levels 0 and 1; mark_grandchildren_in_one_ball).
  std::vector<uint64_t> grandchild_marks_;
  size_t marked_seeds_ = 0;
  size_t initial_active_ = 0;  // base cubes not outside the domain (in this sampler's slab)
  double r_, r2_;
  uint64_t seed_;
  CounterRng rng_;
  Sample s_;
  std::vector<int64_t> stencil_offsets_;  // stencil() as offsets of base cube indices
  SamplingPartition* partition_;    // null: the whole grid on this process
  int owned_begin_, owned_end_;     // the z layers whose cubes this sampler throws darts into
};

}  // namespace

Sample sample_maximal_poisson_disk(const Domain& domain, double r, uint64_t seed, SamplingPartition* partition) {
  return Sampler(domain, r, seed, partition).run();
}

}  // namespace froth
