// Maximal Poisson-disk sampling (sampling/mps_sampler.hpp): the levels, their dart rounds and
// the refinement between them, protection seeds first and the seeds numbered by cube last.
#include "sampling/mps_sampler.hpp"
#include "sampling/protect_interfaces.hpp"

#include <cmath>

namespace froth::mps {

Sample Sampler::run() {
  protect();
  ActiveCubes active = initial_cubes();
  initial_active_ = active.size();
  // Marks cost 8 bytes per cube of their blocks: at most 40 per active cube, under 300 per seed,
  // while the sampler's memory is still far below the peak of the stages after it.
  use_marks_ = 5 * initial_active_ >= grandchild_marks_.allocate(s_.grid, s_.cube_offset, s_.cube_seed.size(), active);
  if (use_marks_) grandchild_marks_.fill();
  else grandchild_marks_.release();
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
      // Told after each round too (the same fraction): the caller may stop the run there.
      if (progress_) progress_(1.0 - double(active.size()) / (double(initial_active_) * std::pow(8.0, level)));
    }
    s_.stats.per_level.back().darts = s_.stats.darts - darts0;
    s_.stats.per_level.back().accepted = s_.seeds.size() - seeds0;
    if (level == tol::kMaxSamplingLevel) break;
    active = refine(active, level, thrown);
    ++level;
    if (progress_) progress_(1.0 - double(active.size()) / (double(initial_active_) * std::pow(8.0, level)));
  }
  s_.stats.levels = size_t(level) + 1;
  s_.stats.uncovered_cubes = active.size();
  order_seeds_by_cube();
  s_.stats.seeds = s_.seeds.size();
  return std::move(s_);
}

Sampler::Darts Sampler::throw_round(const ActiveCubes& active, int level, int round) const {
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

ActiveCubes Sampler::refine(const ActiveCubes& active, int level, std::optional<Darts>& next_darts) {
  const double h = std::ldexp(s_.grid.side, -(level + 1));
  const size_t chunks = active.parts.size();
  std::vector<std::vector<ActiveCube>> kept(chunks);
  const bool exact = level >= kFirstExactCoverageLevel;
  // The first two refinements' one-ball tests from the seeds' side (the seeds near a cube are
  // then needed only for the exact test), where the marks' blocks are not mostly empty (run()).
  const bool marked = level <= 1 && use_marks_;
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
  if (level == 1) grandchild_marks_.release();
  std::erase_if(kept, [](const std::vector<ActiveCube>& part) { return part.empty(); });
  return {std::move(kept)};
}

void Sampler::protect() {
  if (!domain_.regions && !domain_.cracks && (domain_.convex || domain_.reflex_curves.empty())) return;
  const ProtectionSeeds p = protect_boundary_and_interfaces(domain_, r_, seed_, s_.stats);
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
}

void Sampler::order_seeds_by_cube() {
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

}  // namespace froth::mps

namespace froth {

Sample sample_maximal_poisson_disk(const Domain& domain, double r, uint64_t seed, SamplingPartition* partition,
                                   const std::function<void(double)>& progress) {
  mps::Sampler sampler(domain, r, seed, partition);
  sampler.on_level(progress);
  return sampler.run();
}

}  // namespace froth
