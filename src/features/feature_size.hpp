// Local feature size of the input surface (paper §3.1's lfs, §2.2's close features): at each
// triangle's centroid, how thick the solid is (along the inward normal) and how wide the gap to
// another part of the surface is (along the outward normal).
//
// Smooth patches are the triangles joined across edges that are not features. A hit q of the
// ray from p at distance t counts if q lies on p's own patch (the far side of a thin rod), or if
// q cannot be reached from p over the surface without leaving the ball of radius kLocality * t
// around p. So the other face of a wedge of more than atan(1 / kLocality) = 27 degrees (or of
// such a V-groove, for gaps), which meets p's face at a feature edge nearby, is a sharp feature
// (paper §2.2), not a thin wall; the two faces of a plate count, but within 2 t of its rim. Ray
// hits use CGAL's AABB tree with exact predicates (EPICK).
#pragma once
#include <cstdint>
#include <vector>

#include "froth/domain.hpp"
#include "froth/mesh.hpp"

namespace froth {

struct FeatureSize {
  static constexpr double kLocality = 2;
  double cap = 0;  // distances at or beyond the cap are not measured (stored as INFINITY)
  std::vector<double> thickness, gap;  // per triangle of the surface

  FeatureSizeReport report;  // the summary over the surface, by area
};

// Measures every triangle of the domain's (outward) surface, up to `cap`.
FeatureSize measure_feature_size(const Domain& domain, double cap);

}  // namespace froth
