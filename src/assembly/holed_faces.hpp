// A cell face with holes (a hole or pillar of the domain narrower than the cell passes through
// it, or a wall pierces a bisector) is no VTK face: it is replaced by triangles. Both cells that
// share the face must cut it the same way, so the triangulation is made from the global points
// after assembly, from a canonical form of its loops that does not depend on which cell asks.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "froth/mesh.hpp"

namespace froth {

struct HoledFace {
  int64_t face;    // the outer loop: mesh face `face`; its holes are the next `loops - 1` faces
  uint32_t loops;
};

// Replaces each listed group of loops (sorted by face) by the constrained Delaunay triangles of
// the region they bound, with the group's generator, wound as the outer loop. Returns an error
// text, empty on success.
std::string triangulate_holed_faces(PolyMesh& mesh, const std::vector<HoledFace>& holed);

}  // namespace froth
