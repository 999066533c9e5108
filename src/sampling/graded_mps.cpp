#include "sampling/graded_mps.hpp"

#include <algorithm>
#include <cmath>

#include "common/random.hpp"
#include "common/surface_locator.hpp"
#include "sampling/protect.hpp"

namespace froth {
namespace {

constexpr int kRoundsPerLevel = 3;
constexpr int kMaxLevel = 30;

// A cube of the refinement: integer coordinates in units of the base side / 2^level.
struct Cube {
  int64_t i, j, k;
  bool boundary;  // meets the surface: its darts and children are tested one by one
};

struct Dart {
  double time;
  Vec3 p;
  bool boundary;
};

class GradedSampler {
 public:
  GradedSampler(const Domain& d, const SizingField& h, uint64_t seed)
      : d_(d), h_(h), r_(h.r()), seed_(seed), rng_(seed, RandomStream::Graded) {
    s_.grid = BackgroundGrid::covering(d.bounds, r_);
    s_.stats.base_cube_side = s_.grid.side;
    s_.stats.grid = {size_t(s_.grid.nx), size_t(s_.grid.ny), size_t(s_.grid.nz)};
    head_.assign(s_.grid.cube_count(), -1);
  }

  Sample run() {
    protect();
    std::vector<Cube> active = initial_cubes();
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
        for (const Dart& t : darts)
          if (!covered(t.p) && (!t.boundary || d_.contains(t.p))) add_seed(t.p, h_.at(t.p));
        if (q + 1 < kRoundsPerLevel)
          std::erase_if(active, [&](const Cube& c) { return cube_covered(c, level); });
      }
      stats.accepted = seeds_.size() - seeds0;
      s_.stats.darts += stats.darts;
      s_.stats.per_level.push_back(stats);
      if (level == kMaxLevel) break;
      active = refine(active, level);
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

  // Calls f(seed) for the seeds whose base cube lies within `reach` of p (h <= r: r + a cube
  // finds every disk that can hold p or a point of a cube around p).
  template <class F>
  void for_seeds_near(Vec3 p, double reach, F&& f) const {
    s_.grid.for_cubes_near(p, reach, [&](int64_t c) {
      for (int32_t q = head_[size_t(c)]; q >= 0; q = next_[size_t(q)]) f(q);
    });
  }
  bool covered(Vec3 p) const {
    bool in = false;
    for_seeds_near(p, r_, [&](int32_t q) { in |= norm2(p - seeds_[q]) < radius_[q] * radius_[q]; });
    return in;
  }
  // Inside one seed's disk entirely (all eight corners: the disk is convex).
  bool cube_covered(const Cube& c, int level) const {
    const double s = side(level);
    const Vec3 lo = corner(c, level), mid = lo + 0.5 * s * Vec3{1, 1, 1};
    bool in = false;
    for_seeds_near(mid, r_ + s, [&](int32_t q) {
      if (in) return;
      const double h2 = radius_[q] * radius_[q];
      bool all = true;
      for (int k = 0; k < 8 && all; ++k)
        all = norm2(lo + s * Vec3{double(k & 1), double(k >> 1 & 1), double(k >> 2 & 1)} - seeds_[q]) < h2;
      in = all;
    });
    return in;
  }

  // Outside the domain (-1), inside (1), or meeting its surface (0).
  int side_of(const Cube& c, int level) const {
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
    scratch_.clear();
    d_.locator->triangles_near(lo, hi, scratch_);
    if (!scratch_.empty()) return 0;
    return d_.contains(lo + 0.5 * s * Vec3{1, 1, 1}) ? 1 : -1;
  }

  std::vector<Cube> initial_cubes() const {
    std::vector<Cube> out;
    const auto& g = s_.grid;
    for (int k = 0; k < g.nz; ++k)
      for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
          Cube c{i, j, k, false};
          const Vec3 lo = corner(c, 0), hi = lo + Vec3{g.side, g.side, g.side};
          if (hi.x < d_.bounds.lo.x || hi.y < d_.bounds.lo.y || hi.z < d_.bounds.lo.z || lo.x > d_.bounds.hi.x ||
              lo.y > d_.bounds.hi.y || lo.z > d_.bounds.hi.z)
            continue;
          const int side = side_of(c, 0);
          if (side < 0 || cube_covered(c, 0)) continue;
          c.boundary = side == 0;
          out.push_back(c);
        }
    return out;
  }

  std::vector<Cube> refine(const std::vector<Cube>& active, int level) const {
    std::vector<Cube> out;
    for (const Cube& c : active)
      for (int q = 0; q < 8; ++q) {
        Cube child{2 * c.i + (q & 1), 2 * c.j + (q >> 1 & 1), 2 * c.k + (q >> 2 & 1), c.boundary};
        if (cube_covered(child, level + 1)) continue;
        if (c.boundary) {
          const int side = side_of(child, level + 1);
          if (side < 0) continue;
          child.boundary = side == 0;
        }
        out.push_back(child);
      }
    return out;
  }

  void add_seed(Vec3 p, double radius) {
    const int64_t c = base_of(p);
    next_.push_back(head_[size_t(c)]);
    head_[size_t(c)] = int32_t(seeds_.size());
    seeds_.push_back(p), radius_.push_back(radius);
  }

  // Reflex edges first (paper §2.2), at h_e = h/sqrt(2); the free seeds keep h from them.
  void protect() {
    if (d_.convex || d_.reflex_curves.empty()) return;
    const ProtectionSeeds p = protect_reflex_features(d_, r_, seed_, [&](Vec3 x) { return h_.at(x); });
    for (size_t k = 0; k < p.points.size(); ++k) {
      protection_.push_back({int32_t(seeds_.size()), p.kinds[k], p.inward[k]});
      add_seed(p.points[k], h_.at(p.points[k]));
    }
    s_.stats.vertex_seeds = size_t(std::count(p.kinds.begin(), p.kinds.end(), CellKind::Vertex));
    s_.stats.edge_seeds = p.points.size() - s_.stats.vertex_seeds;
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
  double r_;
  uint64_t seed_;
  CounterRng rng_;
  Sample s_;
  std::vector<Vec3> seeds_;
  std::vector<double> radius_;  // each seed's disk: h at the seed
  std::vector<Sample::Protected> protection_;
  // The seeds of each base cube as a list: its last seed, and each seed's previous one there.
  std::vector<int32_t> head_, next_;
  mutable std::vector<int32_t> scratch_;
};

}  // namespace

Sample sample_graded_poisson_disk(const Domain& domain, const SizingField& h, uint64_t seed) {
  return GradedSampler(domain, h, seed).run();
}

}  // namespace froth
