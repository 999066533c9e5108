// Cracks (issue 38): open sheets inside a solid, read and validated as the first step of cutting
// them into the mesh (the paper's §2.2, non-manifold facets). A sheet is any triangle surface:
// open (its free edges inside the solid are the crack front) or closed (a lens, no front). The
// part that pokes out of the solid is clipped away (and reported); the rest is what the mesh
// will be cut along.
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "froth/domain.hpp"

namespace froth {

struct ExactSurface;  // an exact CGAL mesh (input/cgal_meshes.hpp)

struct CrackSheet {
  std::string name;         // the file's stem
  TriangleSurface given;    // the sheet as given, validated and wound (cut_along_cracks corefines the solid with it)
  TriangleSurface surface;  // inside the solid; each edge-connected piece wound one way (side a)
  double input_area = 0;    // of the sheet as given
  double area = 0;          // of the part inside the solid
  // Edges used by one triangle: on the solid's boundary (where an edge or through crack meets it,
  // clipped there) or inside it (the crack front), as vertex pairs of `surface`.
  std::vector<std::array<int32_t, 2>> front, on_boundary;
  // Edges along which another sheet crosses this one (after conform_crack_sheets): curves of
  // both, protected as a front is.
  std::vector<std::array<int32_t, 2>> on_sheets;
  double front_length = 0;
  Vec3 clipped_at{NAN, NAN, NAN};  // a point of the part clipped away, if any
  // The sheet as given corefined exactly with those it crosses (conform_crack_sheets; null if
  // none): the solid's surface is corefined with it, so that its lines on the surface have the
  // clipped sheet's points.
  std::shared_ptr<const ExactSurface> conformed;
};

// Each edge of a sheet, as (smaller vertex, larger), with the triangles that use it.
using EdgeTriangles = std::map<std::pair<int32_t, int32_t>, std::vector<int32_t>>;
EdgeTriangles edge_triangles(const TriangleSurface& s);

// Reads a sheet (STL, OBJ, OFF or PLY) and keeps its part inside `solid` (a validated domain's
// closed surface, outward). Refused (Error InvalidInput, naming the defect and a point): a
// triangle of zero area or a coordinate that is not finite, an edge of three or more triangles,
// a vertex whose triangles make separate fans, a piece that cannot be wound one way, a sheet
// that intersects itself, that lies on the solid's boundary, or that misses the solid.
// `origin`: the solid's Domain::origin, subtracted from the sheet's points (the solid's stored
// coordinates are the input's minus it).
CrackSheet load_crack(const std::string& path, const TriangleSurface& solid, const DomainOptions& options = {},
                      Vec3 origin = {});

// The same for a sheet given as triangles (`name` for messages).
CrackSheet crack_from_surface(const TriangleSurface& sheet, const std::string& name, const TriangleSurface& solid);

// `crack` clipped again from its sheet (as conformed), to `surface`: the solid's surface after
// other sheets were cut into it, whose edges cross this sheet's line on it at more points (the
// cut needs the sheet's edges along the line to be the surface's). `solid` is the same surface
// as given, to find the lines. With `may_miss`, a sheet with nothing inside `surface` is left as
// it was and false returned (otherwise refused, as load_crack refuses it).
bool clip_crack_again(CrackSheet& crack, const ExactSurface& surface, const TriangleSurface& solid, bool may_miss = false);

// Sheets that cross (a branching crack) made to share the curve where they cross: the sheets as
// given are corefined with every other they meet (CGAL, exact constructions) and clipped to
// `solid` again, the new points rounded to doubles alike in both, and the curve's edges listed
// in both sheets' `on_sheets`. Their areas do not change. Sheets that overlap in a plane are
// refused (InvalidInput, naming both).
void conform_crack_sheets(std::vector<CrackSheet>& sheets, const TriangleSurface& solid);

}  // namespace froth
