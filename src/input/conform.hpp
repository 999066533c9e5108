// Solids meant to touch whose shared faces were triangulated independently on each side (two
// parts meshed apart, a block on a larger plate): made to share their triangles there exactly,
// as the regions need (input/regions.cpp pairs the two sides of each shared triangle).
#pragma once
#include <array>
#include <optional>
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

// A vertex closer than `tol` to a triangle that does not have it, where no region of the vertex
// (`regions_at`) is on either side of the triangle (`triangle_sides`, -1 for none): two
// solids' faces meant to touch but apart by less than tol, away from their vertices (after
// conform_touching_solids, touching faces share their vertices). Found with CGAL's AABB tree.
struct NearMiss {
  int32_t vertex = -1, triangle = -1;
  double distance = 0;
};
std::optional<NearMiss> vertex_near_other_face(const std::vector<Vec3>& vertices,
                                               const std::vector<std::array<int32_t, 3>>& triangles,
                                               const std::vector<std::array<int32_t, 2>>& triangle_sides,
                                               const std::vector<std::vector<int32_t>>& regions_at, double tol);

}  // namespace froth
