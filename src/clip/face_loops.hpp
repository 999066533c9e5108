// The loops a clipped cell's faces are made of: directed edges between named points chained
// into closed loops (pinches included), and a plane's loops made faces, a hole kept after the
// outer loop around it.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "froth/geometry.hpp"

namespace froth {

struct DirectedEdge {
  int32_t from, to;
  bool operator<(const DirectedEdge& o) const { return from != o.from ? from < o.from : to < o.to; }
};

// Closed loops of point ids, flat: loop k is ids[begin[k] .. begin[k + 1]).
struct Loops {
  std::vector<int32_t> ids;
  std::vector<uint32_t> begin{0};
  size_t size() const { return begin.size() - 1; }
  std::span<const int32_t> operator[](size_t k) const { return {ids.data() + begin[k], begin[k + 1] - begin[k]}; }
  void clear() { ids.clear(), begin.assign(1, 0); }
};

// Newell vector area of a loop.
Vec3 loop_area(const std::vector<Vec3>& pts, std::span<const int32_t> loop);

// Chains directed edges between points 0 .. points-1 into closed loops (each starting at the
// first of its edges in `edges`); false if a chain does not close. `leaving` (the edge leaving
// each point, -1 if none: all -1 between calls) and `used` are scratch. A point with several
// edges leaving it (a pinch) is chained in the plane of normal n.
bool chain_loops(const std::vector<DirectedEdge>& edges, size_t points, Loops& loops, std::vector<int32_t>& leaving,
                 std::vector<uint8_t>& used, const std::vector<Vec3>& pts, Vec3 n);

// A cell's faces as they are built: loops of point ids, each with its generator and its kind
// (0: a face; 1: an outer loop followed by its holes; 2: a hole of the last outer loop).
struct FaceLoops {
  Loops& faces;
  std::vector<int32_t>& generator;
  std::vector<uint8_t>& kind;
};

// Adds the loops of one plane (unit normal n) as faces on generator g. A loop turning clockwise
// about n is a hole in another: a polygon with a hole is no VTK face, so it is kept as its outer
// loop followed by its holes, which the assembly triangulates from the global points
// (assembly/holed_faces), the same way in both cells. False if a hole lies inside none of the
// loops and is not a sliver of area below `negligible_area`.
bool add_faces_with_holes(const Loops& plane_loops, Vec3 n, int32_t g, const std::vector<Vec3>& pts,
                          double negligible_area, FaceLoops out);

}  // namespace froth
