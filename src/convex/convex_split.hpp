// --convex (the paper's last planned step, issue 22 item 3): every non-convex cell split into
// convex pieces that still conform with their neighbours.
#pragma once
#include <vector>

#include "froth/mesh.hpp"

namespace froth {

// A cell is convex when every vertex lies on the inner side of every face plane within
// tol::convex(r). Each non-convex cell is cut by the plane of a face some vertex lies beyond, the
// cut carried into the neighbours (a new vertex on every face through a cut edge, a neighbour's
// face across the cut split in two), until every piece is convex. Cut planes are planes of the
// cell's own faces, so each is used at most once down any line of pieces and the splitting ends.
// Pieces keep the parent's seed, kind, piece and radius; mesh.parent names the cell each came
// from. A cut that would pinch a face, leave a face with a hole or a sliver piece is refused; a
// cell every cut of which leaves a sliver is still cut if it is non-convex by more than the
// input's round-off, else left whole and counted (docs/design.md, "--convex").
// `domain_planes` are the domain's facet planes, which border faces name.
RunReport::ConvexSplit split_nonconvex_cells(PolyMesh& mesh, const std::vector<Plane>& domain_planes, double r);

}  // namespace froth
