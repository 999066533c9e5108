#include "assembly/cell_builder.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "common/tolerances.hpp"

namespace froth {

CellBuilder::CellBuilder(const Domain& domain, const Sample& sample, double r, bool clip_convex)
    : domain_(domain), sample_(sample), r_(r), eps_(tol::on_plane(r)), reach_(2 * r * (1 + 1e-9)),
      ties_(sample.seeds, tol::seed_tie_band(r)) {
  const BackgroundGrid& g = sample.grid;
  // Cubes (di, dj, dk) away whose distance from the seed's cube is below the reach.
  const int span = int(std::ceil(reach_ / g.side));
  for (int dk = -span; dk <= span; ++dk)
    for (int dj = -span; dj <= span; ++dj)
      for (int di = -span; di <= span; ++di) {
        auto gap = [&](int d) { return std::max(std::abs(d) - 1, 0) * g.side; };
        if (gap(di) * gap(di) + gap(dj) * gap(dj) + gap(dk) * gap(dk) >= reach_ * reach_) continue;
        stencil_offsets_.push_back((int64_t(dk) * g.ny + dj) * g.nx + di);
      }
  // Cubes of side r / sqrt(3) and a reach of 2r: four cubes each way, at most 9^3 of them.
  if (stencil_offsets_.size() > size_t(kMaxStencil))
    fail(ErrorKind::Internal, fmt::format("the cells' grid stencil has {} cubes", stencil_offsets_.size()));
  stencil_span_ = span, stencil_reach_ = span * (int64_t(g.nx) * g.ny + g.nx + 1);
  cut_by_planes_ = domain.convex && !clip_convex && !domain.regions;
  if (domain.regions) {
    regions_.emplace(*domain.regions, r);
  } else if (!cut_by_planes_) {
    generators_.emplace(domain);
    triangles_.emplace(domain.surface, *domain.locator, 2.1 * r);  // a cell's box is at most 2.1 r wide
  }
}

std::vector<int32_t> CellBuilder::seed_regions() const {
  std::vector<int32_t> out;
  if (!regions_) return out;
  out.resize(sample_.seeds.size(), -1);
  const RegionSet& set = regions_->set;
#pragma omp parallel for schedule(dynamic, 1024)
  for (size_t i = 0; i < out.size(); ++i) {
    const Vec3 p = sample_.seeds[i] + anchor_of(int32_t(i));
    for (size_t k = 0; k < set.size() && out[i] < 0; ++k) {
      const Box& b = set.solids[k].bounds;
      if (p.x < b.lo.x || p.y < b.lo.y || p.z < b.lo.z || p.x > b.hi.x || p.y > b.hi.y || p.z > b.hi.z) continue;
      if (set.solids[k].contains(p)) out[i] = int32_t(k);
    }
  }
  return out;
}

CellBuilder::CellError CellBuilder::build(int32_t i, Workspace& w, int32_t own_region) const {
  const Vec3 x = sample_.seeds[i];
  gather_neighbours(i, x, reach_, w.nb);
  double extent2 = 0;
  bool beyond = false;
  CellError e = cut_and_clip(i, w, own_region, extent2, beyond);
  if (!beyond) return e;
  recut_.fetch_add(1, std::memory_order_relaxed);
  // The seeds within 2r cut V to the Voronoi cell within r of x (Lemma 1), which holds all of
  // the cell in D if the sample is maximal; but a part of V ∩ D beyond r of x (behind a wall
  // or across a gap) may belong to a seed farther than 2r. So V is cut again by every seed
  // within its security radius, twice its extent: then V ∩ D is the cell, all within r.
  gather_neighbours(i, x, 2 * std::sqrt(extent2) * (1 + 1e-9) + 4 * eps_, w.nb);
  e = cut_and_clip(i, w, own_region, extent2, beyond);
  if (beyond)
    return fmt::format("cell {} at ({}, {}, {}) is not closed within r of its seed in the domain: the sample is not maximal",
                       i, x.x, x.y, x.z);
  return e;
}

CellBuilder::CellError CellBuilder::cut_and_clip(int32_t i, Workspace& w, int32_t own_region, double& extent2,
                                                 bool& beyond) const {
  const Vec3 x = sample_.seeds[i];
  ConvexCell& cell = w.cell;
  ClippedCell& clipped = w.clipped;
  bool& is_clipped = w.is_clipped;
  const double half = 1.05 * r_;  // the cell lies in the ball of radius r (Lemma 1)
  cell.reset_cube(half);
  is_clipped = false;
  beyond = false;
  // Keeps the part of the cell on the inner side of facet plane p.
  auto cut_by_plane = [&](int32_t p) {
    const Plane& pl = domain_.planes[size_t(p)];
    return usable(cell.clip(pl.normal, pl.offset - dot(pl.normal, x), plane_generator(p), eps_));
  };
  // A convex domain cuts the cell by its facet planes; any other clips it afterwards.
  for (size_t p = 0; p < (cut_by_planes_ ? domain_.planes.size() : 0); ++p) {
    const Plane& pl = domain_.planes[p];
    if (pl.offset - dot(pl.normal, x) >= half * std::sqrt(3.0)) continue;
    if (!cut_by_plane(int32_t(p))) return cut_failure(fmt::format("cell {}: clipping by domain plane {} failed", i, p));
  }
  // Security radius: a seed farther than twice the cell's radius cannot cut it. The cell's
  // radius is a pass over its vertices; after a cut the farthest vertex of the new face gives
  // a lower bound on it, and a neighbour within that is cut without the pass. The stop is the
  // same: only a neighbour beyond the lower bound asks for the radius itself.
  auto security_bound = [&](double rmax2) { return 4 * rmax2 + 4 * eps_ * std::sqrt(rmax2); };
  double bound = security_bound(cell.max_radius2());
  bool exact = true;  // else `bound` is the lower one
  for (const Neighbour& n : w.nb) {
    if (n.d2 > bound) {
      if (exact) break;
      bound = security_bound(cell.max_radius2()), exact = true;
      if (n.d2 > bound) break;
    }
    double d = std::sqrt(n.d2);
    Vec3 dir = (1 / d) * (sample_.seeds[n.seed] - x);
    ConvexCell::Clip c = cell.clip(dir, d / 2, n.seed, eps_, &ties_, i);
    if (!usable(c)) return cut_failure(fmt::format("cell {}: clipping by the bisector with seed {} failed", i, n.seed));
    if (c == ConvexCell::Clip::Cut) bound = security_bound(cell.new_face_radius2()), exact = false;
  }
  extent2 = cell.max_radius2();
  // A part of V ∩ D with a point beyond r of x: cut by too few seeds (build()). Within r of x
  // the cell is exact, and a part beyond it lies wholly beyond r(1 + 2e-9) (reach_'s margin).
  const double limit2 = r_ * r_ * (1 + 2e-9);
  auto reaches_beyond = [&](const ClippedCell& c) {
    for (size_t v = 0; v < c.vertex_count(); ++v)
      if (norm2(c.vertex(v)) > limit2) return true;
    return false;
  };
  if (w.region_clipper) {
    if (own_region < 0) return fmt::format("cell {} at ({}, {}, {}): its seed lies in no region", i, x.x, x.y, x.z);
    std::string error;
    if (!w.region_clipper->clip(i, x, anchor_of(i), own_region, cell, half, sample_.seeds, eps_, w.in_regions, error)) {
      beyond = w.region_clipper->reached_cube();
      return error;
    }
    beyond = reaches_beyond(w.in_regions);
    return {};
  }
  if (!cut_by_planes_) {
    std::string error;
    const Vec3 anchor = anchor_of(i);
    int32_t facet = -1;
    const CellClipper::Result result =
        w.clipper->clip(i, x, anchor, cell, half, sample_.seeds, clipped, facet, error);
    if (result == CellClipper::Result::ReachesCube) {
      beyond = true;
      return {};
    }
    if (result == CellClipper::Result::HalfSpace && !cut_by_plane(facet))
      return fmt::format("cell {}: clipping by facet plane {} failed", i, facet);
    if (result == CellClipper::Result::Clipped) {
      if (!error.empty()) return error;
      is_clipped = true;
      beyond = reaches_beyond(clipped);
      return {};
    }
  }
  // A convex V ∩ D holds the seed: it lies within r of it if the sample is maximal.
  for (size_t f = 0; f < cell.face_count(); ++f)
    if (ConvexCell::is_cube_generator(cell.face_generator(f)))
      return fmt::format("cell {} at ({}, {}, {}) is not closed within r of its seed: the sample is not maximal",
                         i, x.x, x.y, x.z);
  if (!cell.vertex_names(w.names))
    return fmt::format("cell {}: a vertex lies on more than {} faces", i, ConvexCell::kMaxGenerators);
  return {};
}

void CellBuilder::gather_neighbours(int32_t i, Vec3 x, double reach, std::vector<Neighbour>& nb) const {
  const double reach2 = reach * reach;
  auto keep_if_in_reach = [&](int32_t j) {
    const double d2 = norm2(sample_.seeds[j] - x);
    if (j != i && d2 <= reach2) nb.push_back({d2, j});
  };
  const BackgroundGrid& g = sample_.grid;
  int ci, cj, ck;
  g.locate(x, ci, cj, ck);
  const int64_t slot = g.index(ci, cj, ck) - sample_.cube_offset;
  const int s = stencil_span_;
  if (reach == reach_ && ci >= s && ci + s < g.nx && cj >= s && cj + s < g.ny && slot >= stencil_reach_ &&
      slot + stencil_reach_ < int64_t(sample_.cube_seed.size())) {
    // Most seeds: every cube within reach of the seed's cube, read through index offsets
    // without a branch per cube (six in seven are empty, which a branch mispredicts), then the
    // seeds within reach kept without a branch per seed.
    int32_t found[kMaxStencil];
    const int n = sample_.occupied_entries(slot, stencil_offsets_, found);
    nb.resize(size_t(n));
    size_t kept = 0;
    for (int k = 0; k < n; ++k) {
      const int32_t j = found[k];
      if (j < 0) continue;  // several protection seeds: below
      const double d2 = norm2(sample_.seeds[j] - x);
      nb[kept] = {d2, j};
      kept += (d2 <= reach2) & (j != i);
    }
    nb.resize(kept);
    for (int k = 0; k < n; ++k)
      if (found[k] < -1) sample_.for_seeds_of_entry(found[k], keep_if_in_reach);
  } else {
    nb.clear();
    g.for_cubes_near(x, reach, [&](int64_t c) { sample_.for_seeds_in_cube(c, keep_if_in_reach); });
  }
  // Nearest first, ties by seed. Some 25 neighbours: by insertion (std::sort's partition step
  // and calls were a tenth of the cells' neighbour search); a long list, as protection seeds
  // can make, by std::sort.
  auto nearer = [](const Neighbour& a, const Neighbour& b) { return a.d2 != b.d2 ? a.d2 < b.d2 : a.seed < b.seed; };
  if (nb.size() > 64) std::sort(nb.begin(), nb.end(), nearer);
  else insertion_sort(nb.data(), nb.data() + nb.size(), nearer);
}

}  // namespace froth
