// A solid cut open along its crack sheets (issue 38; the paper's §2.2 non-manifold facets): the
// domain D \ S whose surface is the solid's plus each sheet twice, once facing each side. The
// copy facing side a (the sheet's normal side) is wound against the sheet and the copy facing
// side b with it, so each bounds its own side as an outer surface bounds the solid; the copies
// share only the front's vertices, where the crack closes. Where a sheet meets the solid's
// surface (an edge or through crack) the surface is corefined with it (CGAL, exact, rounded
// alike) and cut along the line, its vertices there doubled for side b.
//
// Cells are then clipped to this surface as to any other (src/clip): a cell the sheet crosses
// falls into a piece on each side, which assembly makes separate cells; the points of the two
// copies have different names, so the crack's two faces share no vertex but the front's, and a
// face on a sheet is a border face (patches crack_NAME_a and crack_NAME_b), never matched.
#pragma once
#include <cstdint>
#include <vector>

#include "froth/domain.hpp"
#include "input/cracks.hpp"

namespace froth {

struct CrackSet {
  std::vector<CrackSheet> sheets;
  // A multi-region solid's: each sheet's part in each region it crosses (the sheet itself where it
  // lies in one), whose lines on the interfaces are curves the sheet's seeds protect. Empty: the
  // sheets.
  std::vector<CrackSheet> pieces;
  // The solid as it was before the cut (its feature size and reports are of it).
  Domain solid;
  // Per sheet, the facet planes of its copy facing side a, then those facing side b:
  // [plane_begin[k], plane_middle[k]) and [plane_middle[k], plane_begin[k + 1]).
  std::vector<int32_t> plane_begin{0}, plane_middle;
  // Per sheet, its patches (crack_NAME_a, crack_NAME_b) in the cut surface's patch_names.
  std::vector<std::array<int32_t, 2>> patches;
  // A front inside the solid: each cell it passes through must be split there, so the sheet is
  // cut extended beyond its front by a skirt 2 `skirt_r` wide (0: not yet, the cut is a slit
  // until the mesh's r is known; run_pipeline cuts again), whose two copies are glued back into
  // matched faces after assembly (assembly/glue_extensions.hpp). The skirts' facet planes as
  // (copy a's, copy b's).
  bool fronts = false;
  double skirt_r = 0;
  std::vector<std::array<int32_t, 2>> extension_planes;
};

// `solid` (a validated one-region domain, as load_domain makes) cut open along `sheets` (as
// load_crack and conform_crack_sheets make them, in the solid's stored coordinates); where a
// sheet has a front inside the solid and `r` > 0, along the sheet extended by its skirt (above).
// Throws Error(InvalidInput) where a sheet's cut cannot be made (two sheets meeting the solid's
// surface at one point), naming the point.
// A multi-region solid (`solid.regions` set) is cut region by region (cut_regions_along_cracks).
Domain cut_along_cracks(const Domain& solid, std::vector<CrackSheet> sheets, double r = 0);

// A multi-region solid cut along its sheets region by region (input/cracked_regions.cpp): the
// domain's regions are the cut regions, numbered alike, and its surface is their union's boundary
// with the crack copies. Throws Error(InvalidInput) for a sheet lying on an interface, Usage for
// one that ends at an interface, crosses one and another sheet, or whose front's skirt meets one.
Domain cut_regions_along_cracks(const Domain& solid, std::vector<CrackSheet> sheets, double r);

// For each triangle of `cut` (a surface split from `whole`, as a corefinement or a clip splits
// it), the triangle of `whole` it lies in: the nearest to its centroid, which lies inside it.
std::vector<int32_t> parent_triangles(const TriangleSurface& whole, const TriangleSurface& cut);

}  // namespace froth
