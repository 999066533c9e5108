// A crack front's skirt glued back (input/cracked_domain.hpp): the solid was cut along each
// sheet extended beyond its front, so that every cell the front passes through falls into a
// piece on each side; the skirt is no crack, so after assembly its two copies become one again.
// Their points coincide (each copy's point of a cell's edge or face is the same point, computed
// from the skirt's triangle wound either way) and are made one vertex; then a face on copy a and
// the face on copy b with the same vertices are a matched pair between the two cells they
// belong to, or, in one cell (the skirt's rim passes through it), a fin of no volume, dropped with
// the spikes it leaves in the cell's other faces. The crack then closes at its front, where the
// sheet's two copies meet the skirt.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/face_scratch.hpp"
#include "froth/mesh.hpp"

namespace froth {

// `planes`: the skirts' facet planes as (copy a's, copy b's); `sheet_planes`: per sheet, its
// copies' facet planes as [begin, middle) for copy a and [middle, end) for copy b (CrackSet,
// skirts included); `tolerance`: how far apart two copies' points may lie (a rounding error of
// the cells' size). Where a skirt crosses another sheet, its copies are glued on each side of
// that sheet apart. Returns an error text, or "".
std::string glue_extensions(PolyMesh& mesh, const std::vector<std::array<int32_t, 2>>& planes,
                            const std::vector<std::array<int32_t, 3>>& sheet_planes, double tolerance);

// The copies of each crack point, for welding to move alike (FaceScratch::point_twins): per
// point of a face on one side of a sheet, the point at its place (within `tolerance`) on the
// sheet's other side and on the same side of every other sheet through it (where two sheets
// cross, a point's four copies are each other's twins across one sheet or the other); none for
// the front's points, which both sides share. `sheet_planes` as above.
PointTwins crack_point_twins(const PolyMesh& mesh, const std::vector<std::array<int32_t, 3>>& sheet_planes,
                             double tolerance);

}  // namespace froth
