// Every seed's Voronoi cell, clipped to the convex domain, assembled into one conforming mesh.
#pragma once
#include "froth/domain.hpp"
#include "froth/mesh.hpp"
#include "sampling/mps.hpp"

namespace froth {

struct TessellationTimes {
  double cells = 0;     // seconds computing cells
  double assembly = 0;  // seconds giving shared vertices one id
};

// Throws Error(Internal) if a cell cannot be closed by its neighbours (the sample is not maximal)
// or two cells disagree on a shared vertex.
PolyMesh build_voronoi_mesh(const ConvexDomain& domain, const Sample& sample, double r, TessellationTimes* times);

}  // namespace froth
