// The surface's triangles bucketed in a uniform grid of cubes, for the clipper's question "which
// triangles meet this cell's box?", asked once per cell near the boundary. The cells' boxes are
// about the size of a grid cube, so a query reads at most eight buckets; the AABB tree it
// replaces there was slow on long, thin triangles (the tube, round.stl).
#pragma once
#include <cstdint>
#include <vector>

#include "common/surface_locator.hpp"
#include "froth/domain.hpp"

namespace froth {

class TriangleGrid {
 public:
  // Buckets of side about `side` (coarser if the surface's box would need too many).
  TriangleGrid(const TriangleSurface& surface, const SurfaceLocator& locator, double side);

  // The triangles that meet the closed box [lo, hi] (exact), ascending: the same answer as
  // SurfaceLocator::triangles_near.
  void triangles_near(Vec3 lo, Vec3 hi, std::vector<int32_t>& out) const;

 private:
  bool locate(Vec3 lo, Vec3 hi, int first[3], int last[3]) const;
  const SurfaceLocator& locator_;
  Vec3 origin_;
  double side_ = 1;
  int n_[3] = {1, 1, 1};
  std::vector<uint32_t> begin_;  // per bucket, into ids_
  std::vector<int32_t> ids_;
};

}  // namespace froth
