// Helpers shared by the tests: independent re-computations of the paper's guarantees.
#pragma once
#include <string>
#include <vector>

#include "froth/froth.hpp"

namespace froth::test {

std::string model(const std::string& name);  // path of a file in shared/models

// Smallest distance between two seeds, by brute force over a hash grid (independent of froth's).
double min_seed_distance(const std::vector<Vec3>& seeds, double r);

// Newell normal (unit, outward for a counter-clockwise face) and centroid of face f.
Vec3 face_normal(const PolyMesh& m, int64_t f);
Vec3 face_centroid(const PolyMesh& m, int64_t f);
double face_area(const PolyMesh& m, int64_t f);  // Newell

// Interior dihedral angles (degrees) of cell c between faces sharing an edge.
std::vector<double> dihedral_angles(const PolyMesh& m, size_t c);

// A square sheet [x0, x1] x [y0, y1] at height z, split into n x n squares of two triangles
// each, wound counter-clockwise seen from +z (the crack tests' sheets).
TriangleSurface square_sheet(double x0, double x1, double y0, double y1, double z, int n);

// Runs the whole pipeline with `threads` threads.
PolyMesh mesh_of(const Domain& d, double r, uint64_t seed, int threads, RunReport* run = nullptr);

}  // namespace froth::test
