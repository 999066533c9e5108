#include "sampling/graded_mps.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iterator>
#include <span>
#include <tuple>

#include "common/random.hpp"
#include "common/surface_locator.hpp"
#include "froth/error.hpp"
#include "sampling/graded_rounds.hpp"
#include "sampling/poisson_count.hpp"
#include "sampling/protect_interfaces.hpp"
#include "sampling/seed_blocks.hpp"

namespace froth {
namespace {

double sqr(double x) { return x * x; }

// Darts per active cube per round (a Poisson mean) and the rounds of each level. They tune speed
// only: each round is a slice of the darts' arrival times, so the law of the sample is the same
// for any choice (test_graded's packing fraction). The first level's rounds double, as the
// uniform sampler's do (mps_sampler.hpp): a round's darts are decided in arrival order one by one,
// and a small first round has few that conflict with each other. A round walks the grid only
// around the cubes that get a dart, so rounds of under one dart per cube cost under one walk per
// cube; later levels throw one round, and refinement drops the covered cubes.
constexpr double kLevel0DartsPerCube[] = {0.0625, 0.125, 0.25, 0.5};
constexpr double kDartsPerCube = 1.0;
constexpr int kMaxLevel = 40;
// The first level whose cubes in no single disk get the two-disk test: above it most such cubes
// hold a gap or need more disks, and the pairs cost more than refining the few they clear.
constexpr int kFirstTwoDiskLevel = 5;

// A cube of the refinement: integer coordinates in units of the base side / 2^level.
struct Cube {
  int64_t i, j, k;
  bool boundary;  // meets the surface: its darts and children are tested one by one
  // A non-convex domain's boundary cube: is its centre inside? The side of a point of the cube
  // follows by the parity of crossings with the cube's triangles, the only ones that can cross
  // the segment from the centre (inside_cube), without a ray through the whole surface.
  bool centre_inside = false;
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

class GradedSampler {
 public:
  std::function<void(double)> progress_;  // told after each level the fraction of the domain covered

  GradedSampler(const Domain& d, const SizingField& h, uint64_t seed, SamplingPartition* partition)
      : d_(d), h_(h), r_(h.r()), reach_factor_((1 + 1e-6) / (1 - h.lipschitz())), seed_(seed),
        rng_(seed, RandomStream::Graded), seeds_(BackgroundGrid::covering(d.bounds, h.r())), partition_(partition) {
    s_.grid = seeds_.grid();
    const Slab whole{0, s_.grid.nz, 0, s_.grid.nz};
    slab_ = partition_ ? partition_->slab : whole;
    s_.stats.base_cube_side = s_.grid.side;
    s_.stats.grid = {size_t(s_.grid.nx), size_t(s_.grid.ny), size_t(s_.grid.nz)};
  }

  Sample run() {
    std::vector<Cube> active = initial_cubes();
    protect();
    // Protection seeds are few: each marks the base cubes in its disk.
    const std::vector<uint64_t> in_disk = subcubes_in_one_disk(0);
    std::erase_if(active, [&](const Cube& c) {
      return in_disk[size_t(seeds_.cube_slot(int(c.i), int(c.j), int(c.k)))] != 0;
    });
    const size_t initial_active = std::max<size_t>(1, active.size());
    int level = 0, epoch = 0;
    for (; anywhere(!active.empty()); ++level) {
      SamplingLevel stats{active.size(), 0, 0};
      const size_t seeds0 = seeds_.size();
      const int rounds = level == 0 ? int(std::size(kLevel0DartsPerCube)) : 1;
      for (int q = 0; q < rounds; ++q, ++epoch) {
        const Poisson poisson(level == 0 ? kLevel0DartsPerCube[q] : kDartsPerCube);
        std::vector<GradedDart> darts = open_darts(active, level, q, epoch, poisson, stats.darts);
        std::sort(darts.begin(), darts.end(), arrives_before);
        // The darts no earlier seed covers, in arrival order against the round's new seeds:
        // the decisions of random sequential addition.
        if (partition_) {
          const AcceptedDarts accepted = accept_across_ranks(darts, seeds_, h_, reach_factor_, *partition_, exchanges_);
          for (size_t k = 0; k < accepted.point.size(); ++k) seeds_.add(accepted.point[k], accepted.radius[k]);
        } else {
          const int32_t round_first = int32_t(seeds_.size());
          for (const GradedDart& t : darts)
            if (!covered(t.p, round_first)) seeds_.add(t.p, h_.at(t.p));
        }
        // Told after each round too (the same fraction): the caller may stop the run there.
        if (progress_) progress_(1.0 - double(active.size()) / (double(initial_active) * std::pow(8.0, level)));
      }
      stats.accepted = seeds_.size() - seeds0;
      s_.stats.darts += stats.darts;
      s_.stats.per_level.push_back(stats);
      if (level == kMaxLevel) break;
      const std::vector<int32_t> new_id = seeds_.order_by_place();
      for (Sample::Protected& p : protection_) p.seed = new_id[size_t(p.seed)];
      active = refine(active, level);
      if (progress_) progress_(1.0 - double(active.size()) / (double(initial_active) * std::pow(8.0, level + 1)));
    }
    s_.stats.levels = size_t(level) + 1;
    s_.stats.uncovered_cubes = active.size();
    if (partition_) partition_->exchanges += exchanges_;
    return finish();
  }

 private:
  // Is `mine` true on any rank? (Every rank calls it at the same point.)
  bool anywhere(bool mine) const { return partition_ ? partition_->comm->any(mine) : mine; }
  double side(int level) const { return s_.grid.side / double(int64_t(1) << level); }
  Vec3 corner(const Cube& c, int level) const {
    return s_.grid.origin + side(level) * Vec3{double(c.i), double(c.j), double(c.k)};
  }

  // A round's darts into the active cubes that no seed before the round covers and that lie in
  // the domain, with their arrival times; `thrown` counts all. Each cube gets a Poisson number of
  // darts, uniform in it and in the round's time slice (epoch, epoch + 1): the space-time Poisson
  // process. A cube's darts depend only on its place, level and round, and the cubes are taken in
  // chunks of the active list, which is in space order, so the seeds near a run of darts are read
  // once per base cube (near_disks) while they are in cache.
  std::vector<GradedDart> open_darts(const std::vector<Cube>& active, int level, int round, int epoch,
                               const Poisson& poisson, size_t& thrown) const {
    constexpr size_t kChunk = 4096;
    const size_t chunks = (active.size() + kChunk - 1) / kChunk;
    std::vector<std::vector<GradedDart>> out(chunks);
    const double s = side(level);
    const uint64_t tag = uint64_t(level) << 24 | uint64_t(round) << 16;
    size_t count = 0;
#pragma omp parallel reduction(+ : count)
    {
      NearCache near;
#pragma omp for schedule(dynamic, 1)
      for (size_t ch = 0; ch < chunks; ++ch)
        for (size_t a = ch * kChunk; a < std::min(active.size(), (ch + 1) * kChunk); ++a) {
          const Cube& c = active[a];
          const auto key = [&](uint64_t k) { return rng_.words(uint64_t(c.i), uint64_t(c.j), uint64_t(c.k), tag | k); };
          const int n = poisson(CounterRng::unit(key(0)[0]));
          count += size_t(n);
          for (int k = 1; k <= n; ++k) {
            const auto w = key(uint64_t(k));
            const Vec3 p =
                corner(c, level) + s * Vec3{CounterRng::unit(w[0]), CounterRng::unit(w[1]), CounterRng::unit(w[2])};
            // A lone dart in a cube of the first level reads only the disks within its reach.
            if (level == 0 && n == 1 ? covered(p, 0) : near_disks(c, level, near).covers(p)) continue;
            if (c.boundary && !inside_cube(c, level, p)) continue;
            out[ch].push_back({double(epoch) + CounterRng::unit(w[3]), p});
          }
        }
    }
    thrown += count;
    size_t total = 0;
    for (const auto& o : out) total += o.size();
    std::vector<GradedDart> all;
    all.reserve(total);
    for (const auto& o : out) all.insert(all.end(), o.begin(), o.end());
    return all;
  }

  // The disks that may reach into a cube's ancestor, as positions and radii, read once for a run
  // of darts or children below it (the active lists are in space order).
  struct NearDisks {
    int level = -1;
    int64_t i = 0, j = 0, k = 0;
    std::vector<int32_t> ids;
    std::vector<Vec3> centre;
    std::vector<double> radius, radius2;
    bool holds_key(const Cube& a, int at) const { return level == at && i == a.i && j == a.j && k == a.k; }
    // Without a branch per disk: there are few, and one of them mostly holds the point.
    bool covers(Vec3 p) const {
      bool in = false;
      for (size_t q = 0; q < centre.size(); ++q) in |= norm2(p - centre[q]) < radius2[q];
      return in;
    }
  };
  // A base cube's disks are read with one grid walk for all the cubes below it; where they are
  // many (h well below r), each parent's are picked from them, so that a cube is not tested
  // against disks far from it.
  struct NearCache {
    NearDisks base, parent;
  };
  static constexpr size_t kSharedDisks = 64;
  const NearDisks& near_disks(const Cube& c, int level, NearCache& cache) const {
    const Cube base{c.i >> level, c.j >> level, c.k >> level, false};
    if (!cache.base.holds_key(base, 0)) read_disks(base, cache.base);
    if (level <= 1 || cache.base.ids.size() <= kSharedDisks) return cache.base;
    const Cube parent{c.i >> 1, c.j >> 1, c.k >> 1, false};
    if (!cache.parent.holds_key(parent, level - 1)) pick_disks(cache.base, parent, level - 1, cache.parent);
    return cache.parent;
  }
  void read_disks(const Cube& base, NearDisks& near) const {
    near.level = 0, near.i = base.i, near.j = base.j, near.k = base.k;
    seeds_reaching(base, 0, near.ids);
    near.centre.clear(), near.radius.clear(), near.radius2.clear();
    for (int32_t q : near.ids) {
      near.centre.push_back(seeds_.point[q]);
      near.radius.push_back(seeds_.radius[q]), near.radius2.push_back(seeds_.radius[q] * seeds_.radius[q]);
    }
  }
  // The disks of `from` (those of an ancestor) that reach into cube c of `level`, in their order.
  void pick_disks(const NearDisks& from, const Cube& c, int level, NearDisks& near) const {
    near.level = level, near.i = c.i, near.j = c.j, near.k = c.k;
    near.ids.clear(), near.centre.clear(), near.radius.clear(), near.radius2.clear();
    const CubeTest t = cube_test(c, level);
    for (size_t q = 0; q < from.ids.size(); ++q)
      if (norm2(t.mid - from.centre[q]) < sqr(from.radius[q] + t.half_diagonal)) {
        near.ids.push_back(from.ids[q]), near.centre.push_back(from.centre[q]);
        near.radius.push_back(from.radius[q]), near.radius2.push_back(from.radius2[q]);
      }
  }

  // Which of the n^3 cubes of side s from `lo` (n <= 4; bit x + n (y + n z)) lie in the disk of
  // centre c and squared radius h2, every corner strictly inside (as in holds()): a cube's
  // farthest corner from c is, along each axis, its farther face.
  static uint64_t cubes_in_disk(Vec3 lo, double s, int n, Vec3 c, double h2) {
    double far[3][4];
    for (int a = 0; a < 3; ++a)
      for (int t = 0; t < n; ++t) {
        const double near_face = lo[a] + s * t - c[a], far_face = near_face + s;
        far[a][t] = std::max(near_face * near_face, far_face * far_face);
      }
    uint64_t bits = 0;
    for (int z = 0; z < n; ++z) {
      if (far[2][z] >= h2) continue;
      for (int y = 0; y < n; ++y) {
        const double yz = far[1][y] + far[2][z];
        if (yz >= h2) continue;
        for (int x = 0; x < n; ++x) bits |= uint64_t(yz + far[0][x] < h2) << (x + n * (y + n * z));
      }
    }
    return bits;
  }

  // Per base cube, which of its cubes of `level` (0, 1 or 2: 1, 8 or 64, bit x + n (y + n z)
  // with n = 2^level) lie in one seed's disk, every corner strictly inside as in holds(). Each seed
  // marks the cubes around it: there are several base cubes per seed, so this reads far less
  // than a walk around every cube, and at these levels the single-disk test is the whole test.
  std::vector<uint64_t> subcubes_in_one_disk(int level) const {
    const int n = 1 << level;
    const double s = side(level);
    std::vector<uint64_t> marks(seeds_.places(), 0);
#pragma omp parallel for schedule(dynamic, 1024)
    for (size_t q = 0; q < seeds_.size(); ++q) {
      const Vec3 c = seeds_.point[q];
      const double h2 = seeds_.radius[q] * seeds_.radius[q];
      seeds_.for_slots_near(c, seeds_.radius[q], [&](int64_t slot, int bi, int bj, int bk) {
        const Vec3 lo =
            s_.grid.origin + s * Vec3{double(int64_t(bi) * n), double(int64_t(bj) * n), double(int64_t(bk) * n)};
        const uint64_t bits = cubes_in_disk(lo, s, n, c, h2);
        if (bits) std::atomic_ref<uint64_t>(marks[size_t(slot)]).fetch_or(bits, std::memory_order_relaxed);
        return false;
      });
    }
    return marks;
  }

  // How far from p a seed can be whose disk reaches within `extra` of p (graded_reach). Where h
  // is small this reads a few base cubes instead of all within r (the scans were most of the
  // graded sampler's time).
  double reach(Vec3 p, double extra) const { return graded_reach(h_, reach_factor_, p, extra); }
  // Is p in the disk of a seed numbered `first` or later?
  bool covered(Vec3 p, int32_t first) const {
    bool in = false;
    seeds_.for_seeds_near(
        p, reach(p, 0), [&](int32_t q) { return in = norm2(p - seeds_.point[q]) < sqr(seeds_.radius[q]); }, first);
    return in;
  }
  // Inside one seed's disk entirely (all eight corners: the disk is convex), or, from
  // kFirstTwoDiskLevel on, inside the union of two (box_in_two_balls): without it the cubes
  // along the curves where disks meet are refined to the last level. The first disk found to
  // hold the cube ends the search: with a margin for round-off, by its distance to the centre.
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
    const double h = seeds_.radius[q], dist = norm(t.mid - seeds_.point[q]);
    if (dist >= h + t.half_diagonal) return false;
    if (t.n < 16) t.near[t.n++] = q;
    if (dist + t.half_diagonal < h * (1 - 1e-12)) return true;
    bool all = true;
    for (int k = 0; k < 8 && all; ++k)
      all = norm2(t.lo + t.s * Vec3{double(k & 1), double(k >> 1 & 1), double(k >> 2 & 1)} - seeds_.point[q]) < h * h;
    return all;
  }
  bool in_two_disks(const CubeTest& t, int level) const {
    if (level < kFirstTwoDiskLevel) return false;
    for (int a = 0; a < t.n; ++a)
      for (int b = a + 1; b < t.n; ++b)
        if (box_in_two_balls(t.lo, t.s, seeds_.point[t.near[a]], seeds_.radius[t.near[a]], seeds_.point[t.near[b]],
                             seeds_.radius[t.near[b]]))
          return true;
    return false;
  }
  // Is the cube covered, by one disk or two? From `candidates`, the seeds whose disks reach into
  // it (a superset: those that reach into an ancestor, read once for the cubes below it).
  bool cube_covered(const Cube& c, int level, const std::vector<int32_t>& candidates) const {
    CubeTest t = cube_test(c, level);
    for (int32_t q : candidates)
      if (holds(t, q)) return true;
    return in_two_disks(t, level);
  }
  void seeds_reaching(const Cube& c, int level, std::vector<int32_t>& out) const {
    const CubeTest t = cube_test(c, level);
    out.clear();
    seeds_.for_seeds_near(t.mid, reach(t.mid, t.half_diagonal), [&](int32_t q) {
      if (norm(t.mid - seeds_.point[q]) < seeds_.radius[q] + t.half_diagonal) out.push_back(q);
      return false;
    });
  }

  // Outside the domain (-1), inside (1), or meeting its surface (0). A non-convex domain's cube
  // gets its triangles in `pool` (those of `candidates` that meet it) and its centre's side, by
  // parity from `ref`, a point of known side in a box holding the cube that only `candidates`
  // meet (the parent's centre, or the block's).
  struct Reference {
    Vec3 p;
    bool inside;
  };
  int side_of(Cube& c, int level, std::vector<int32_t>& pool, std::span<const int32_t> candidates,
              const Reference& ref) const {
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
    for (int32_t t : candidates)
      if (d_.locator->triangle_meets_box(t, lo, hi)) pool.push_back(t);
    c.tris_end = uint32_t(pool.size());
    const Vec3 centre = lo + 0.5 * s * Vec3{1, 1, 1};
    bool in = ref.inside;
    if (!(ref.p == centre) && !d_.locator->side_from(ref.p, ref.inside, centre, candidates, in))
      in = d_.contains(centre);
    c.centre_inside = in;
    if (c.tris_end > c.tris_begin) return 0;
    return in ? 1 : -1;
  }
  // Is p, a point of boundary cube c of `level`, inside the domain?
  bool inside_cube(const Cube& c, int level, Vec3 p) const {
    if (d_.convex) return d_.contains(p);
    const Vec3 centre = corner(c, level) + 0.5 * side(level) * Vec3{1, 1, 1};
    bool in;
    if (d_.locator->side_from(centre, c.centre_inside, p, {pool_.data() + c.tris_begin, c.tris_end - c.tris_begin}, in))
      return in;
    return d_.contains(p);  // a degenerate crossing: ask the whole surface
  }

  // The base cubes in the domain or on its surface, by blocks of 8^3 (in parallel, joined in
  // block order): a block that meets no triangle is all inside or all outside, by one test. The
  // blocks that keep a cube get a place in the seed lists (SeedBlocks).
  std::vector<Cube> initial_cubes() {
    const auto& g = s_.grid;
    const int kBlock = SeedBlocks::kBlock, blocks_x = seeds_.blocks_x(), blocks_y = seeds_.blocks_y();
    const size_t blocks = seeds_.block_count();
    std::vector<std::vector<Cube>> out(blocks);
    std::vector<std::vector<int32_t>> pools(blocks);
#pragma omp parallel
    {
      std::vector<int32_t> near, row;
#pragma omp for schedule(dynamic, 1)
      for (size_t b = 0; b < blocks; ++b) {
        const int i0 = int(b % blocks_x) * kBlock, j0 = int(b / blocks_x % blocks_y) * kBlock,
                  k0 = int(b / (size_t(blocks_x) * blocks_y)) * kBlock;
        // A partitioned run's rank throws darts only into its own layers.
        const int i1 = std::min(g.nx, i0 + kBlock), j1 = std::min(g.ny, j0 + kBlock),
                  k1 = std::min({g.nz, k0 + kBlock, slab_.owned_end});
        if (k1 <= slab_.owned_begin) continue;
        const Vec3 lo = corner(Cube{i0, j0, k0, false}, 0), hi = corner(Cube{i1, j1, k1, false}, 0);
        if (hi.x < d_.bounds.lo.x || hi.y < d_.bounds.lo.y || hi.z < d_.bounds.lo.z || lo.x > d_.bounds.hi.x ||
            lo.y > d_.bounds.hi.y || lo.z > d_.bounds.hi.z)
          continue;
        near.clear();
        if (!d_.convex) d_.locator->triangles_near(lo, hi, near);
        // No triangle in the block: every cube on the side of the block's centre.
        const int block_side = !d_.convex && near.empty() ? (d_.contains(0.5 * (lo + hi)) ? 1 : -1) : 0;
        if (block_side < 0) continue;
        for (int k = std::max(k0, slab_.owned_begin); k < k1; ++k)
          for (int j = j0; j < j1; ++j) {
            // Along a row, each cube's centre takes its side from the previous one's, by parity
            // with the row's triangles; the first asks the whole surface.
            if (block_side == 0 && !d_.convex) {
              const Vec3 row_lo = corner(Cube{i0, j, k, false}, 0), row_hi = corner(Cube{i1, j + 1, k + 1, false}, 0);
              row.clear();
              for (int32_t t : near)
                if (d_.locator->triangle_meets_box(t, row_lo, row_hi)) row.push_back(t);
            }
            Reference previous{};
            for (int i = i0; i < i1; ++i) {
              Cube c{i, j, k, false};
              std::vector<int32_t>& pool = pools[b];
              const size_t pool_size = pool.size();
              const Vec3 centre = corner(c, 0) + 0.5 * g.side * Vec3{1, 1, 1};
              if (i == i0) previous = {centre, !d_.convex && block_side == 0 && d_.contains(centre)};
              const int side = block_side > 0 ? 1 : side_of(c, 0, pool, row, previous);
              previous = {centre, c.centre_inside};
              if (side < 0) {
                pool.resize(pool_size);
                continue;
              }
              c.boundary = side == 0;
              out[b].push_back(c);
            }
          }
      }
    }
    std::vector<char> used(blocks);
    for (size_t b = 0; b < blocks; ++b) used[b] = !out[b].empty();
    seeds_.place_blocks(used);
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
    // Children of the second and third levels are tested against single disks only (in_two_disks).
    static_assert(kFirstTwoDiskLevel > 2);
    const std::vector<uint64_t> marks = level + 1 <= 2 ? subcubes_in_one_disk(level + 1) : std::vector<uint64_t>();
    auto marked = [&](const Cube& child) {
      const int n = 1 << (level + 1);
      const int up = level + 1;
      const int64_t b = seeds_.cube_slot(int(child.i >> up), int(child.j >> up), int(child.k >> up));
      return (marks[size_t(b)] >> ((child.i & (n - 1)) + n * ((child.j & (n - 1)) + n * (child.k & (n - 1))))) & 1;
    };
#pragma omp parallel
    {
      NearCache near;
      std::vector<int32_t> candidates;
#pragma omp for schedule(dynamic, 1)
      for (size_t ch = 0; ch < chunks; ++ch) {
        for (size_t a = ch * kChunk; a < std::min(active.size(), (ch + 1) * kChunk); ++a) {
          const Cube& c = active[a];
          // The disks that reach c, from those read once for the cubes around it; the children
          // in one of them, or in two from kFirstTwoDiskLevel on.
          candidates.clear();
          uint64_t in_one = 0;
          if (marks.empty()) {
            const NearDisks& around = near_disks(c, level, near);
            const CubeTest t = cube_test(c, level);
            for (size_t q = 0; q < around.ids.size(); ++q)
              if (norm2(t.mid - around.centre[q]) < sqr(around.radius[q] + t.half_diagonal)) {
                candidates.push_back(around.ids[q]);
                in_one |= cubes_in_disk(t.lo, 0.5 * t.s, 2, around.centre[q], around.radius2[q]);
              }
          }
          const bool two_disks = level + 1 >= kFirstTwoDiskLevel;
          for (int q = 0; q < 8; ++q) {
            Cube child{2 * c.i + (q & 1), 2 * c.j + (q >> 1 & 1), 2 * c.k + (q >> 2 & 1), c.boundary};
            const bool in_disks = !marks.empty() ? marked(child) != 0
                                  : (in_one >> q & 1) || (two_disks && cube_covered(child, level + 1, candidates));
            if (in_disks) continue;
            if (c.boundary) {
              std::vector<int32_t>& pool = pools[ch];
              const size_t pool_size = pool.size();
              const Reference parent_centre{corner(c, level) + 0.5 * side(level) * Vec3{1, 1, 1}, c.centre_inside};
              const std::span<const int32_t> parent_tris{pool_.data() + c.tris_begin, c.tris_end - c.tris_begin};
              const int where = side_of(child, level + 1, pool, parent_tris, parent_centre);
              if (where < 0) {
                pool.resize(pool_size);
                continue;
              }
              child.boundary = where == 0;
            }
            out[ch].push_back(child);
          }
        }
      }
    }
    std::vector<int32_t> pool;
    std::vector<Cube> all = join(out, pools, pool);
    pool_.swap(pool);
    return all;
  }

  // The cubes and triangle pools of parallel chunks as one list and one pool, in chunk order.
  // Each chunk is freed once copied: the active lists are the sampler's largest memory.
  static std::vector<Cube> join(std::vector<std::vector<Cube>>& out, std::vector<std::vector<int32_t>>& pools,
                                std::vector<int32_t>& pool) {
    size_t total = 0;
    for (const auto& o : out) total += o.size();
    std::vector<Cube> all;
    all.reserve(total);
    for (size_t ch = 0; ch < out.size(); ++ch) {
      const uint32_t shift = uint32_t(pool.size());
      for (Cube c : out[ch]) {
        if (c.boundary) c.tris_begin += shift, c.tris_end += shift;
        all.push_back(c);
      }
      pool.insert(pool.end(), pools[ch].begin(), pools[ch].end());
      std::vector<Cube>().swap(out[ch]);
      std::vector<int32_t>().swap(pools[ch]);
    }
    return all;
  }

  // Reflex edges first (paper §2.2), at h_e = h/sqrt(2), then a multi-region solid's interfaces
  // or a cut solid's crack sheets (protect_interfaces.hpp); the free seeds keep h from them.
  void protect() {
    if (!d_.regions && !d_.cracks && (d_.convex || d_.reflex_curves.empty())) return;
    const ProtectionSeeds p = protect_boundary_and_interfaces(
        d_, r_, seed_, s_.stats, [&](Vec3 x) { return h_.at(x); }, h_.lipschitz());
    for (size_t k = 0; k < p.points.size(); ++k) {
      int i, j, l;
      s_.grid.locate(p.points[k], i, j, l);
      if (l < slab_.window_begin || l >= slab_.window_end) continue;  // outside this rank's window
      protection_.push_back({int32_t(seeds_.size()), p.kinds[k], p.inward[k]});
      seeds_.add(p.points[k], h_.at(p.points[k]));
    }
  }

  // Seeds numbered by base cube, each cube's in the order they came; a partitioned run's rank
  // holds its window's (mps.hpp's Sample).
  Sample finish() {
    std::vector<int32_t> new_id(seeds_.size(), -1);
    const int64_t layer = int64_t(s_.grid.nx) * s_.grid.ny;
    s_.cube_offset = layer * slab_.window_begin;
    s_.cube_seed.assign(size_t(layer * (slab_.window_end - slab_.window_begin)), -1);
    s_.cube_extra_begin.assign(1, 0);
    seeds_.for_each_cube(s_.cube_offset, layer * slab_.window_end, [&](int64_t c, const std::vector<int32_t>& ids) {
      c -= s_.cube_offset;
      for (int32_t q : ids) new_id[q] = int32_t(s_.seeds.size()), s_.seeds.push_back(seeds_.point[q]);
      if (ids.size() == 1) {
        s_.cube_seed[c] = new_id[ids[0]];
        return;
      }
      s_.cube_seed[c] = -2 - int32_t(s_.cube_extra_begin.size() - 1);
      for (int32_t q : ids) s_.cube_extra.push_back(new_id[q]);
      s_.cube_extra_begin.push_back(int32_t(s_.cube_extra.size()));
    });
    if (std::count(new_id.begin(), new_id.end(), -1) != 0)
      fail(ErrorKind::Internal, "the graded sampler holds a seed outside its slab's window");
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
  SeedBlocks seeds_;  // each seed with its disk's radius, h at the seed
  std::vector<Sample::Protected> protection_;
  std::vector<int32_t> pool_;  // the active boundary cubes' triangles
  SamplingPartition* partition_;  // null: the whole grid on this process
  Slab slab_;                     // the layers this sampler throws darts into, and its window
  size_t exchanges_ = 0;
};

}  // namespace

Sample sample_graded_poisson_disk(const Domain& domain, const SizingField& h, uint64_t seed,
                                  SamplingPartition* partition, const std::function<void(double)>& progress) {
  GradedSampler sampler(domain, h, seed, partition);
  sampler.progress_ = progress;
  return sampler.run();
}

}  // namespace froth
