// Every tolerance froth uses, in one place, each relative to r or to the domain's size.
#pragma once
#include <algorithm>

namespace froth::tol {

// A vertex within this distance of a clipping plane lies on it (cell-local coordinates are
// relative to the seed, so round-off is ~1e-16 r; this leaves a wide margin).
inline double on_plane(double r) { return 1e-11 * r; }

// A seed vertex of a cell (three bisector planes) this close to another seed's bisector is cut
// or kept by exact predicates (voronoi/seed_ties.hpp), far above the float test's round-off.
inline double seed_tie_band(double r) { return 1e-8 * r; }

// A cell near a single facet plane is cut by it the quick way, as a convex domain's cells are,
// only if none of its vertices is this close to the plane: then the general clipper, which its
// neighbours may use, makes the same cut. The general clipper's round-off grows with the
// coordinates of long input triangles, hence the domain term. `size`: the cell's half-width.
inline double clear_of_facet(double size, double domain_diagonal) { return 1e-9 * size + 1e-12 * domain_diagonal; }

// A face loop of the clipper smaller than this (in area) is a sliver of near-coincident
// crossings, not a feature of the domain. `size`: the cell's half-width.
inline double negligible_loop_area(double size) { return (1e-6 * size) * (1e-6 * size); }

// Facet planes whose normals and offsets agree to this are one plane of the domain.
inline double coplanar(double domain_diagonal) { return 1e-9 * domain_diagonal; }

// --convex: a cell is convex when no vertex lies beyond a face plane by more than this (issue 22's
// figure); a cell whose vertices do is cut by that plane.
inline double convex(double r) { return 1e-12 * r; }

// Finest sub-cube level of the sampler: cubes of side base / 2^31 (~3e-10 r) are at the
// round-off of coordinates, so the sample is maximal up to round-off. (Sub-cube coordinates
// within a base cube are 31-bit.)
inline constexpr int kMaxSamplingLevel = 31;

}  // namespace froth::tol
