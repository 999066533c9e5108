// The best-fit plane of a polygon that may be slightly non-planar (after welding): Newell's
// normal through the vertices' centroid.
#pragma once
#include <cstddef>

#include "froth/geometry.hpp"

namespace froth {

struct FacePlane {
  Vec3 normal;  // unit, or zero for a degenerate polygon
  Vec3 centroid;
  double area = 0;
};

// `vertex(k)` gives vertex k of the n, in order.
template <class Vertex>
FacePlane best_fit_plane(size_t n, Vertex&& vertex) {
  Vec3 normal{}, centroid{};
  for (size_t k = 0; k < n; ++k) {
    const Vec3 u = vertex(k);
    normal = normal + cross(u, vertex(k + 1 < n ? k + 1 : 0));
    centroid = centroid + u;
  }
  const double len = norm(normal);
  return {len > 0 ? (1 / len) * normal : normal, (1.0 / double(n)) * centroid, len / 2};
}

}  // namespace froth
