// A seed's cell in a multi-region solid (froth/domain.hpp's RegionSet): its Voronoi cell V cut
// to each region it meets, V ∩ R for every region R, as one cell whose faces know their region.
// Each part is clipped as a non-convex domain's cell is (src/clip), with every region naming the
// facets, input edges and vertices alike, so the two parts of a cell that an interface crosses
// share the interface's vertices, and so do the neighbours' parts. Assembly then splits the cell
// into one cell per region and piece (assembly/split_pieces.hpp).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "clip/clip_cell.hpp"
#include "common/triangle_grid.hpp"
#include "froth/domain.hpp"
#include "voronoi/convex_cell.hpp"

namespace froth {

// The parts of one cell: ClippedCell's faces and vertices (for assembly), each face's region, and
// pieces() counted over all regions (a cell of one region in one piece needs no split).
class RegionCell : public ClippedCell {
 public:
  int32_t face_region(size_t f) const { return face_region_[f]; }
  int regions() const { return regions_; }

 private:
  friend class RegionClipper;
  std::vector<int32_t> face_region_;
  int regions_ = 0;
};

// The regions' generators and triangle grids, shared by all threads.
struct RegionSurfaces {
  RegionSurfaces(const RegionSet& regions, double r);
  const RegionSet& set;
  std::vector<SurfaceGenerators> generators;
  std::vector<TriangleGrid> grids;
};

class RegionClipper {
 public:
  // One per thread.
  explicit RegionClipper(const RegionSurfaces& surfaces);
  // Cuts `cell` (relative to seed x, bisector faces only) to every region it meets. `own`: the
  // region holding the anchor (x + anchor, strictly inside it). False with `error` set on failure,
  // or with reached_cube() (a part reaches the cube around x: CellClipper::Result::ReachesCube).
  bool clip(int32_t seed, Vec3 x, Vec3 anchor, int32_t own, const ConvexCell& cell, double half,
            const std::vector<Vec3>& seeds, double eps, RegionCell& out, std::string& error);
  bool reached_cube() const { return reached_cube_; }

 private:
  template <class Cell>
  void add_part(const Cell& part, const std::vector<ConvexCell::Names>& names, int32_t region, int pieces,
                RegionCell& out);
  const RegionSurfaces& s_;
  std::vector<std::unique_ptr<CellClipper>> clippers_;
  ClippedCell clipped_;
  ConvexCell halfspace_;
  std::vector<ConvexCell::Names> names_;
  std::vector<std::pair<uint64_t, int32_t>> index_;  // (hash of a name, local vertex)
  std::vector<int32_t> local_;
  bool reached_cube_ = false;
};

}  // namespace froth
