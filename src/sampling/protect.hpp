// Protection of reflex edges (paper §2.2): a seed at both ends of every run of reflex edges
// between true corners (turns over the feature angle), and each run maximally Poisson-disk
// sampled along its length with Euclidean disks of r_e = r/sqrt(2). On a straight run, a seed off
// it that keeps distance r from two consecutive seeds of the run (at most 2 r_e apart) is at
// least r_e from the run, so every point of a reflex edge is closest to a seed on it: the edge
// lies inside edge and vertex cells, and the other cells never wrap around it. A tessellated arc
// bends by less than the feature angle at each vertex: the argument holds up to its curvature.
#pragma once
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "froth/domain.hpp"
#include "froth/mesh.hpp"

namespace froth {

struct ProtectionSeeds {
  std::vector<Vec3> points;
  std::vector<CellKind> kinds;  // Vertex (a curve's end) or Edge
  // For each seed on the surface, a unit vector pointing into the domain from it; zero for a
  // seed already inside (vertex seeds sit 1e-7 r inside their vertex).
  std::vector<Vec3> inward;
};

class CounterRng;

// A straight piece of a protected curve and the parts of it no protection disk covers yet, as
// sorted, disjoint parameter intervals (arc length from a; dir has unit length).
struct LinePiece {
  Vec3 a, dir;
  double length;
  Vec3 inward;  // into the domain (or a region) from the piece
  std::vector<std::pair<double, double>> uncovered;
};

// Removes from the piece the points within `radius` of p.
void remove_disk(LinePiece& piece, Vec3 p, double radius);

// 1D random sequential addition to saturation: each dart is uniform on the still uncovered part
// of all pieces, so it is always accepted (the law of MPS); accept(piece, point) must remove its
// disk. Gaps of at most `crumb` are left: maximal up to round-off of the coordinates.
void saturate_pieces(std::vector<LinePiece>& pieces, const CounterRng& rng, double crumb,
                     const std::function<void(size_t, Vec3)>& accept);

// A pure function of (domain, r, seed). Seeds of one run keep r_e from each other; seeds of
// different runs may be closer where runs meet at a small angle (the paper's sharp edges).
// With a sizing field `h` (sampling/sizing.hpp), the disks are h_e = h(p)/sqrt(2) around each
// seed p instead (the "prior" rule: a later seed keeps the earlier one's radius).
ProtectionSeeds protect_reflex_features(const Domain& domain, double r, uint64_t seed,
                                        const std::function<double(Vec3)>& h = {});

}  // namespace froth
