// Structural checks of a finished mesh. generate_mesh runs them before returning, so froth
// never hands back a mesh that fails them; the tests call them too.
#pragma once
#include <cstdint>
#include <string>

#include "froth/mesh.hpp"

namespace froth {

struct MeshCheck {
  size_t unmatched_faces = 0;     // interior faces without an identical twin in the neighbour
  size_t open_cells = 0;          // cells whose faces do not close (an edge not used twice)
  size_t nonpositive_cells = 0;   // cells with volume <= 0
  std::string first_problem;      // description of the first defect found
  bool ok() const { return unmatched_faces == 0 && open_cells == 0 && nonpositive_cells == 0; }
};

// Uses mesh.volumes when they are filled in (one per cell), else computes the volumes.
MeshCheck check_mesh(const PolyMesh& mesh);

// Signed volume of cell c from the mesh's points (divergence theorem, faces fanned from their
// centroids).
double cell_volume(const PolyMesh& mesh, size_t c);

// Total area of the border faces (Newell), which must equal the domain's surface area.
double border_area(const PolyMesh& mesh);
// The area of face f (a fan from its first vertex).
double face_area(const PolyMesh& mesh, size_t f);

// Star-shapedness from the seeds: a cell is star-shaped from its seed when the seed is on the
// inner side of every face's plane (it is then in the cell's kernel, the intersection of those
// half-spaces). A cell that is not may still be star-shaped from other points, if its kernel
// holds a ball: what a solver that needs star-shaped cells (virtual elements) asks.
struct StarShape {
  size_t cells_not = 0;   // cells with a face plane beyond their seed by more than the tolerance
  double worst = 0;       // the largest distance of a face plane beyond its seed
  size_t cells_without_kernel = 0;  // of those, cells whose kernel holds no ball of radius tolerance
};
// Cells [begin, end) only, if given.
StarShape star_shape(const PolyMesh& mesh, double tolerance, size_t begin = 0, size_t end = SIZE_MAX);

// A point of each cell to fan it into tetrahedra from (mesh.centers): its seed where every face
// plane has the seed on its inner side by more than `tolerance` (1e-6 r), else the centre of the
// largest ball in its kernel; NaN for a cell whose kernel holds no ball of radius `tolerance`
// (empty, counted by star_shape before welding, or too thin to fan from).
std::vector<Vec3> fan_centers(const PolyMesh& mesh, double tolerance);

}  // namespace froth
