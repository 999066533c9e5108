// The largest ball inside a convex polyhedron given by its face planes (the Chebyshev centre):
// maximise t subject to dot(n_f, c) + t <= d_f for unit normals n_f. A linear program in four
// free variables (c, t); c = 0 with t at most every d_f is feasible, and the simplex method
// starts from it with the slacks as basis. Free variables enter first and never
// leave (they have no bound); Bland's rule prevents cycling. The dictionary has one row per
// face and four columns, so a pivot costs O(faces). An answer outside a plane by more than
// round-off, or none, is recomputed by CGAL's exact linear-program solver.
#pragma once
#include <vector>

#include "froth/geometry.hpp"

namespace froth {

struct InscribedBall {
  Vec3 center;
  double radius = 0;  // negative when the half-spaces have no common interior (empty kernel)
  bool ok = false;  // false if the program is unbounded (the planes do not enclose a cell)
};

InscribedBall largest_inscribed_ball(const std::vector<Vec3>& normals, const std::vector<double>& offsets);

}  // namespace froth
