// Where a point lies with respect to the domain's closed surface, and which triangles are near
// a box: the queries that sampling and clipping ask of a non-convex domain. Built once per
// domain; every query is const and thread-safe.
#pragma once
#include <array>
#include <memory>
#include <optional>
#include <utility>
#include <span>
#include <vector>

#include "froth/domain.hpp"

namespace froth {

// Does the segment [a, b] cross triangle (p, q, r)? 1 yes, 0 no, -1 degenerate (it touches an
// edge or a vertex of the triangle, or an end lies in it). Exact.
int segment_crossing(Vec3 a, Vec3 b, Vec3 p, Vec3 q, Vec3 r);

class SurfaceLocator {
 public:
  // `surface` must be closed and free of self-intersections (validated); shells may nest.
  // `soup`: each triangle gets vertices of its own in the CGAL mesh, for a surface that touches
  // itself (a solid cut along cracks, input/cracked_domain.hpp), which a halfedge mesh cannot
  // hold; every query but first_self_intersection is geometric and answers alike.
  explicit SurfaceLocator(const TriangleSurface& surface, bool soup = false);
  ~SurfaceLocator();

  // Inside the solid by ray parity (CGAL Side_of_triangle_mesh: exact predicates, a random ray
  // when the first one is degenerate). Points on the surface count as outside.
  bool inside(Vec3 p) const;
  // +1 inside, 0 on the surface, -1 outside.
  int side(Vec3 p) const;

  // Triangles whose bounding boxes meet the box [lo, hi].
  void triangles_near(Vec3 lo, Vec3 hi, std::vector<int32_t>& out) const;

  // Does triangle t meet the closed box [lo, hi] (exact)?
  bool triangle_meets_box(int32_t t, Vec3 lo, Vec3 hi) const;

  // Does the segment [a, b] cross triangle t? 1 yes, 0 no, -1 degenerate (it touches an edge or
  // a vertex of t, or an end lies on t's plane). Exact.
  int segment_crossing(Vec3 a, Vec3 b, int32_t t) const;

  // The side of b, knowing a's and that only `triangles` can meet [a, b]: parity of crossings.
  // False when a crossing is degenerate; then `b_inside` is not set.
  bool side_from(Vec3 a, bool a_inside, Vec3 b, std::span<const int32_t> triangles, bool& b_inside) const;

  // A pair of triangles that intersect other than along a shared edge or vertex (exact), if any.
  std::optional<std::pair<int32_t, int32_t>> first_self_intersection() const;

 private:
  struct Impl;  // the surface as a CGAL mesh, its vertices and triangle boxes, the AABB tree
  std::vector<std::array<int32_t, 3>> triangles_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace froth
