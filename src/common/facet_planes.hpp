// Which facet plane a set of the domain's triangles lies in.
#pragma once
#include <cstdint>
#include <span>

#include "froth/domain.hpp"

namespace froth {

// The facet plane of all of `triangles`, or -1 if they lie in several (or there are none).
// When they are all the triangles that meet a box, the surface within the box is that plane's
// whole section of it: the surface is closed and does not cross itself, and a triangle across
// the edge of the plane's region would meet the box too. So the plane's sign alone tells the
// side of a point of the box.
inline int32_t facet_plane_of(const Domain& domain, std::span<const int32_t> triangles) {
  if (triangles.empty()) return -1;
  const int32_t plane = domain.triangle_plane[size_t(triangles[0])];
  for (int32_t t : triangles)
    if (domain.triangle_plane[size_t(t)] != plane) return -1;
  return plane;
}

}  // namespace froth
