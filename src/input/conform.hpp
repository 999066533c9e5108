// Solids meant to touch whose shared faces were triangulated independently on each side (two
// parts meshed apart, a block on a larger plate): made to share their triangles there exactly,
// as the regions need (input/regions.cpp pairs the two sides of each shared triangle).
#pragma once
#include <vector>

#include "froth/domain.hpp"

namespace froth {

// Each pair of solids whose surfaces meet is corefined (CGAL's Polygon Mesh Processing, exact
// constructions): each surface gains the other's vertices and edges where they meet, so
// touching faces end up with the same triangles, and crossing surfaces with an exact curve
// where they cross (which the regions then refuse as an overlap). Points made here are rounded
// to the nearest double; both solids round a shared point alike. A split triangle keeps its
// patch. Returns how many solids changed; the solids must each be valid (closed, not
// self-intersecting, outward).
int conform_touching_solids(std::vector<TriangleSurface>& solids);

}  // namespace froth
