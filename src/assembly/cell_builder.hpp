// One seed's cell (paper §2.3): cut from a cube around the seed by a convex domain's facet planes
// and by the bisectors of its neighbours within 2r (Lemma 1), nearest first, until the security
// radius shows no farther seed can cut; in any other domain then clipped to the surface
// (src/clip), or to every region it meets (assembly/region_cells.hpp). The cells are assembled
// into one mesh by assembly/tessellation.cpp.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "assembly/region_cells.hpp"
#include "clip/clip_cell.hpp"
#include "voronoi/seed_ties.hpp"
#include "froth/domain.hpp"
#include "froth/error.hpp"
#include "sampling/mps.hpp"
#include "voronoi/convex_cell.hpp"

namespace froth {

struct Neighbour {
  double d2;
  int32_t seed;
};

// Sorts a short range by insertion: for the few elements of a cell's neighbour list or a vertex
// name, std::sort's partitioning and calls cost more than the sort itself.
template <class T, class Less>
void insertion_sort(T* first, T* last, Less less) {
  for (T* k = first + (first != last); k < last; ++k) {
    const T x = *k;
    T* j = k;
    for (; j > first && less(x, j[-1]); --j) *j = j[-1];
    *j = x;
  }
}

class CellBuilder {
 public:
  // `clip_convex`: clip a convex domain's cells to its surface too, instead of cutting them by
  // its planes (when a cell meets more planes than a ConvexCell holds: a cone's apex).
  CellBuilder(const Domain& domain, const Sample& sample, double r, bool clip_convex);

  // A clipper for one thread, or none for a convex domain.
  // One thread's cell and scratch, reused from seed to seed; build() leaves its result here:
  // `cell`, or `clipped` where it met a non-convex domain's surface, or `in_regions` (a
  // multi-region solid's).
  struct Workspace {
    ConvexCell cell;
    ClippedCell clipped;
    bool is_clipped = false;
    RegionCell in_regions;
    std::vector<Neighbour> nb;
    std::vector<ConvexCell::Names> names;  // of `cell`'s vertices
    std::unique_ptr<CellClipper> clipper;  // a non-convex domain's
    std::unique_ptr<RegionClipper> region_clipper;  // a multi-region solid's
  };
  Workspace workspace() const {
    Workspace w;
    if (!cut_by_planes_) w.clipper = std::make_unique<CellClipper>(domain_, *generators_, *triangles_);
    if (regions_) w.region_clipper = std::make_unique<RegionClipper>(*regions_);
    return w;
  }

  // A multi-region solid's clipper for one thread, or none.

  // How many cells were cut again by seeds beyond 2r (build()).
  size_t recut_cells() const { return recut_.load(); }

  // The region each seed's anchor lies in (a multi-region solid's; empty otherwise).
  std::vector<int32_t> seed_regions() const;

  // What went wrong with a cell (froth's fault on valid input: Internal).
  struct CellError {
    CellError() = default;
    CellError(std::string t, ErrorKind k = ErrorKind::Internal) : text(std::move(t)), kind(k) {}
    std::string text;
    ErrorKind kind = ErrorKind::Internal;
    bool cut_failed = false;  // a cut of a convex domain's cell failed (its planes overflow the cell)
    bool failed() const { return !text.empty(); }
  };

  // Builds cell i in the thread's workspace `w` (a multi-region solid's seed in region
  // `own_region`); returns no error or what went wrong.
  CellError build(int32_t i, Workspace& w, int32_t own_region = -1) const;

 private:
  // A protection seed lies on the surface: inside tests start from a point just off it.
  Vec3 anchor_of(int32_t i) const {
    const Sample::Protected* p = sample_.protection_of(i);
    return p ? 1e-6 * r_ * p->inward : Vec3{};
  }

  // The seeds other than i within `reach` (reach_, 2r, Lemma 1; or more) of its seed x, nearest
  // first.
  void gather_neighbours(int32_t i, Vec3 x, double reach, std::vector<Neighbour>& nb) const;

  // Cell i cut by the neighbours `nb` (nearest first) up to its security radius, then clipped;
  // `extent2` the squared radius of the cut cell, `beyond` set where a part of it in the domain
  // reaches beyond r of the seed (build() then cuts it by farther seeds).
  CellError cut_and_clip(int32_t i, Workspace& w, int32_t own_region, double& extent2, bool& beyond) const;

  CellError cut_failure(std::string text) const {
    CellError e(std::move(text));
    e.cut_failed = cut_by_planes_;
    return e;
  }
  static bool usable(ConvexCell::Clip c) { return c == ConvexCell::Clip::Cut || c == ConvexCell::Clip::Unchanged; }
  const Domain& domain_;
  const Sample& sample_;
  double r_, eps_;
  // Voronoi neighbours are at most 2r apart (Lemma 1); the cubes that may hold one of a seed in
  // a given cube, as index offsets, and how far they reach along an axis and in the index.
  static constexpr int kMaxStencil = 729;
  double reach_ = 0;
  std::vector<int64_t> stencil_offsets_;
  int stencil_span_ = 0;
  int64_t stencil_reach_ = 0;
  bool cut_by_planes_ = true;  // a convex domain's cells are cut by its planes, others clipped
  std::optional<SurfaceGenerators> generators_;
  std::optional<TriangleGrid> triangles_;
  std::optional<RegionSurfaces> regions_;
  SeedTies ties_;  // near-cospherical seeds decided alike in every cell
  mutable std::atomic<size_t> recut_{0};
};

}  // namespace froth
