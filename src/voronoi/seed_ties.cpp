#include "voronoi/seed_ties.hpp"

#include <algorithm>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace froth {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

int SeedTies::conflict(int32_t a, int32_t b, int32_t c, int32_t d, int32_t e) const {
  auto point = [&](int32_t s) {
    const Vec3 p = seeds_[size_t(s)];
    return Kernel::Point_3(p.x, p.y, p.z);
  };
  Kernel::Point_3 v[4] = {point(a), point(b), point(c), point(d)};
  const Kernel::Point_3 q = point(e);
  const int orient = int(CGAL::orientation(v[0], v[1], v[2], v[3]));
  if (orient == 0) return 0;
  const CGAL::Bounded_side side = CGAL::side_of_bounded_sphere(v[0], v[1], v[2], v[3], q);
  if (side != CGAL::ON_BOUNDARY) return side == CGAL::ON_BOUNDED_SIDE ? 1 : -1;
  // On the sphere. With weights w_s, e's power against the vertex's orthosphere is
  // sum_i lambda_i w_i - w_e (lambda: e's barycentric coordinates in the tetrahedron), and the
  // largest weight, the smallest index, decides its sign: e itself (conflict), or vertex seed i
  // by the sign of lambda_i (conflict where it is negative).
  const int32_t ids[4] = {a, b, c, d};
  int32_t order[5] = {a, b, c, d, e};
  std::sort(order, order + 5);
  for (int32_t s : order) {
    if (s == e) return 1;
    const int i = int(std::find(ids, ids + 4, s) - ids);
    Kernel::Point_3 w[4] = {v[0], v[1], v[2], v[3]};
    w[i] = q;
    const int lambda = int(CGAL::orientation(w[0], w[1], w[2], w[3])) * orient;
    if (lambda != 0) return lambda < 0 ? 1 : -1;
  }
  return 1;  // not reached: e lies on no more than three of the tetrahedron's face planes
}

}  // namespace froth
