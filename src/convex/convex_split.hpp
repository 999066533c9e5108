// --convex (the paper's last planned step, issue 22 item 3): every non-convex cell split into
// convex pieces that still conform with their neighbours.
#pragma once
#include <vector>

#include "froth/mesh.hpp"

namespace froth {

// A cell is convex when every vertex lies on the inner side of every face plane within
// `tolerance`. Each non-convex cell is cut by the plane of a face some vertex lies beyond, the
// cut carried into the neighbours (a new vertex on every face through a cut edge, a neighbour's
// face across the cut split in two), until every piece is convex. Cut planes are planes of the
// cell's own faces, so each is used at most once down any line of pieces and the splitting ends.
// Pieces keep the parent's seed, kind, piece and radius; mesh.parent names the cell each came
// from. A cell no plane cuts cleanly (the cut would pinch a face, or leave a face with a hole) is
// left whole and counted.
// `domain_planes` are the domain's facet planes, which border faces name.
RunReport::ConvexSplit split_nonconvex_cells(PolyMesh& mesh, const std::vector<Plane>& domain_planes, double tolerance);

}  // namespace froth
