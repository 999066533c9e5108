#include "assembly/region_cells.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "froth/mesh.hpp"

namespace froth {

RegionSurfaces::RegionSurfaces(const RegionSet& regions, double r) : set(regions) {
  generators.reserve(regions.size());
  grids.reserve(regions.size());
  for (const Domain& d : regions.solids) {
    generators.emplace_back(d, regions.edges);
    grids.emplace_back(d.surface, *d.locator, 2.1 * r);  // a cell's box is at most 2.1 r wide
  }
}

RegionClipper::RegionClipper(const RegionSurfaces& surfaces) : s_(surfaces) {
  for (size_t k = 0; k < s_.set.size(); ++k)
    clippers_.push_back(std::make_unique<CellClipper>(s_.set.solids[k], s_.generators[k], s_.grids[k]));
}

namespace {

ConvexCell::Names sorted(ConvexCell::Names k) {
  std::sort(k.gen, k.gen + k.n);
  return k;
}

template <class Cell>
uint8_t loop_of(const Cell& c, size_t f) {
  if constexpr (requires { c.face_loop(f); }) return c.face_loop(f);
  return 0;
}

}  // namespace

// Vertices are one where their names are (an interface's vertices, in both parts).
template <class Cell>
void RegionClipper::add_part(const Cell& part, const std::vector<ConvexCell::Names>& names, int32_t region,
                             int pieces, RegionCell& out) {
  local_.resize(part.vertex_count());
  // A part's own vertices have distinct names: only a later part's are looked up (most cells
  // lie in one region and have one part).
  const bool first = out.regions_ == 0;
  for (size_t v = 0; v < part.vertex_count(); ++v) {
    const ConvexCell::Names key = sorted(names[v]);
    const uint64_t h = key.hash();
    int32_t found = -1;
    for (size_t j = 0; !first && j < index_.size(); ++j)
      if (index_[j].first == h && out.names_[size_t(index_[j].second)].same_as(key)) {
        found = index_[j].second;
        break;
      }
    if (found < 0) {
      found = int32_t(out.points_.size());
      out.points_.push_back(part.vertex(v));
      out.names_.push_back(key);
      index_.push_back({h, found});
    }
    local_[v] = found;
  }
  for (size_t f = 0; f < part.face_count(); ++f) {
    out.face_gen_.push_back(part.face_generator(f));
    out.face_region_.push_back(region);
    out.face_loop_.push_back(loop_of(part, f));
    const uint16_t* fv = part.face_begin(f);
    for (size_t k = 0; k < part.face_size(f); ++k) out.face_vert_.push_back(uint16_t(local_[fv[k]]));
    out.face_start_.push_back(uint32_t(out.face_vert_.size()));
  }
  ++out.regions_;
  out.pieces_ += pieces;
}

bool RegionClipper::clip(int32_t seed, Vec3 x, Vec3 anchor, int32_t own, const ConvexCell& cell, double half,
                         const std::vector<Vec3>& seeds, double eps, RegionCell& out, std::string& error) {
  out.points_.clear(), out.names_.clear(), out.face_gen_.clear(), out.face_region_.clear();
  out.face_start_.assign(1, 0), out.face_vert_.clear(), out.face_loop_.clear();
  out.regions_ = out.pieces_ = 0;
  index_.clear();
  reached_cube_ = false;
  auto fail_with = [&](const std::string& text) {
    error = fmt::format("cell {} at ({}, {}, {}): {}", seed, x.x, x.y, x.z, text);
    return false;
  };
  auto add_convex = [&](const ConvexCell& c, int32_t region) {
    for (size_t f = 0; f < c.face_count(); ++f)
      if (ConvexCell::is_cube_generator(c.face_generator(f))) {
        reached_cube_ = true;
        return false;
      }
    if (!c.vertex_names(names_))
      return fail_with(fmt::format("a vertex lies on more than {} faces", ConvexCell::kMaxGenerators));
    add_part(c, names_, region, 1, out);
    return true;
  };
  for (size_t k = 0; k < s_.set.size(); ++k) {
    const bool mine = int32_t(k) == own;
    int32_t facet = -1;
    const CellClipper::Result result =
        clippers_[k]->clip(seed, x, anchor, cell, half, seeds, clipped_, facet, error, mine);
    if (!error.empty()) return false;
    switch (result) {
      case CellClipper::Result::ReachesCube:
        reached_cube_ = true;
        return false;
      case CellClipper::Result::Outside:
        break;
      case CellClipper::Result::Inside:
        if (!mine) return fail_with(fmt::format("the cell lies whole in region {} but its seed is not in it", k));
        if (!add_convex(cell, int32_t(k))) return false;
        break;
      case CellClipper::Result::HalfSpace: {
        halfspace_ = cell;
        const Plane& pl = s_.set.solids[k].planes[size_t(facet)];
        const ConvexCell::Clip c = halfspace_.clip(pl.normal, pl.offset - dot(pl.normal, x), plane_generator(facet), eps);
        if (c == ConvexCell::Clip::Failed) return fail_with(fmt::format("clipping by facet plane {} failed", facet));
        if (c != ConvexCell::Clip::Empty && !add_convex(halfspace_, int32_t(k))) return false;
        break;
      }
      case CellClipper::Result::Clipped:
        add_part(clipped_, clipped_.names(), int32_t(k), clipped_.pieces(), out);
        break;
    }
  }
  if (out.regions_ == 0) return fail_with("the cell meets no region");
  return true;
}

}  // namespace froth
