// Every tolerance froth uses, in one place, each relative to r or to the domain's size.
#pragma once
#include <algorithm>

namespace froth::tol {

// A vertex within this distance of a clipping plane lies on it (cell-local coordinates are
// relative to the seed, so round-off is ~1e-16 r; this leaves a wide margin).
inline double on_plane(double r) { return 1e-11 * r; }

// Facet planes whose normals and offsets agree to this are one plane of the domain.
inline double coplanar(double domain_diagonal) { return 1e-9 * domain_diagonal; }

// Finest sub-cube level of the sampler: cubes of side base / 2^31 (~3e-10 r) are at the
// round-off of coordinates, so the sample is maximal up to round-off. (Sub-cube coordinates
// within a base cube are 31-bit.)
inline constexpr int kMaxSamplingLevel = 31;

}  // namespace froth::tol
