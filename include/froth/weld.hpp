// Welding (paper §2.4): cell vertices joined by an edge shorter than w become one vertex, by one
// global decision, so every cell sees the same merge and the mesh stays conforming.
#pragma once
#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include "froth/mesh.hpp"

namespace froth {

struct WeldStats {
  double tolerance = 0;
  uint64_t edges_collapsed = 0;   // vertices merged away
  uint64_t faces_removed = 0;     // faces that collapsed to an edge or a point
  uint64_t clusters_refused = 0;  // merges refused: they would pinch a face or move a vertex off a border plane
  double shortest_edge_before = 0, shortest_edge_after = 0;
  double max_displacement = 0;    // largest distance a vertex moved
  double max_nonplanarity = 0;    // largest distance of a face's vertex from the face's best-fit plane, / r
  double border_area = 0;         // of the mesh before welding
  // Interior faces are shared by two cells with the same vertices, so their contributions to
  // the total volume cancel (volumes use a fan from each face's centroid, the same for both
  // twins); only border faces change it, and moving their vertices by at most d changes the
  // volume they enclose by at most d * border area to first order.
  double volume_change_bound() const { return max_displacement * border_area; }
};

// The default tolerance: 1e-4 of the cells' size, which is r, or the domain's diagonal where r
// is larger (one cell, or a few, over the whole part: a tolerance from r would then weld away
// the part's own details). 0 (`unwelded`) for a run that splits cells convex
// (MeshOptions::convex), whose faces must stay planar.
inline double default_weld_tolerance(double r, double domain_diagonal, bool unwelded = false) {
  return unwelded ? 0 : 1e-4 * std::min(r, domain_diagonal);
}

// Welds the mesh in place with tolerance w > 0 (r scales the non-planarity figure). Vertices on
// the domain's boundary keep their position when merged with others (the one on the most
// domain planes wins), so border faces stay on their planes wherever they can; other clusters
// move to their centroid. A multi-region mesh's interface facets (FaceScratch::face_interface_facet, src/common/face_scratch.hpp)
// bind their vertices as border planes do: an interface vertex stays on its facets, and a
// cluster holding one goes to it, so no cell reaches past the interface into another region.
// `before_change`, if given, is told the cells welding will change (sorted), before any changes.
WeldStats weld_mesh(PolyMesh& mesh, double w, double r,
                    const std::function<void(const std::vector<size_t>& cells)>& before_change = {});

}  // namespace froth
