// Cubes cut by the domain's boundary: the initial base cubes by blocks and octants, sub-cube
// classification and reference points for inside tests (sampling/mps_sampler.hpp).
#include "sampling/mps_sampler.hpp"

#include "common/facet_planes.hpp"

namespace froth::mps {

int Sampler::classify_sub_box(Vec3 lo, double h, size_t slot, int32_t& plane) const {
  plane = -1;
  if (domain_.convex) {
    const int cls = classify_box(lo, h, cutting_planes(slot), nullptr, &plane);
    if (cls != 0) plane = -1;
    return cls;
  }
  if (const int32_t facet = boundary_facet_[slot]; facet >= 0) {
    // The plane alone classifies a sub-cube that lies beyond its round-off band on one side, or
    // reaches past the band on both. One within the band on a side is left to the facet's
    // triangles (they are coplanar only to the band): called cut there, a sub-cube outside the
    // domain but in the band was never dropped, and below a side of the band's width such cubes
    // multiplied eightfold per level (step.off, --cells 9895 --seed 3512652964).
    const Plane& pl = domain_.planes[facet];
    const double band = round_off_band(pl, lo, h);
    const int cls = classify_box(lo, h, std::array{facet}, nullptr, &plane, band);
    if (cls != 0) return cls;
    double dmin = pl.signed_distance(lo), dmax = dmin;
    for (int a = 0; a < 3; ++a) (pl.normal[a] > 0 ? dmax : dmin) += h * pl.normal[a];
    if (dmin < -band && dmax > band) return 0;
    plane = -1;
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

int Sampler::classify_box_by_surface(Vec3 lo, double h, std::span<const int32_t> candidates, std::vector<int32_t>* cut,
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

Sampler::Reference Sampler::reference_near(Vec3 p, double h) const {
  int side = domain_.locator->side(p);
  for (int n = 1; side == 0; ++n) {
    p = p + Vec3{h * 0.037, -h * 0.029, h * 0.011};
    side = domain_.locator->side(p);
  }
  return {p, side > 0};
}

void Sampler::classify_cut_octants(int i0, int j0, int k0, int n, const std::vector<int32_t>& cut, const Reference& ref,
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

ActiveCubes Sampler::initial_cubes() {
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
    for (size_t slot = 0; slot < boundary_base_.size(); ++slot) boundary_facet_[slot] = facet_plane_of(domain_, cutting_planes(slot));
  }
  std::erase_if(cubes, [](const std::vector<ActiveCube>& part) { return part.empty(); });
  return {std::move(cubes)};
}

}  // namespace froth::mps
