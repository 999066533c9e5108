// Surface patches where the file names none: the smooth regions between the feature curves, on
// which a user puts boundary conditions (a box's six sides, a hole's wall, a fillet's flank).
#pragma once
#include <cstdint>
#include <vector>

#include "features/features.hpp"
#include "froth/domain.hpp"

namespace froth {

// Each triangle's smooth region: triangles joined across every edge that is not on a feature
// curve, numbered by their first triangle. `count` is the number of regions.
std::vector<int32_t> smooth_regions(const TriangleSurface& surface, const SurfaceFeatures& features, size_t& count);

}  // namespace froth
