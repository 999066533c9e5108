#include "common/surface_locator.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <fmt/format.h>

#include "froth/error.hpp"

namespace froth {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Side = CGAL::Side_of_triangle_mesh<Mesh, Kernel>;
using Tree = Side::AABB_tree;

Point to_cgal(Vec3 p) { return Point(p.x, p.y, p.z); }

}  // namespace

struct SurfaceLocator::Impl {
  Mesh mesh;
  std::unique_ptr<Tree> tree;
  std::unique_ptr<Side> side;
  std::vector<Point> points;
  std::vector<CGAL::Bbox_3> boxes;  // per triangle
};

SurfaceLocator::SurfaceLocator(const TriangleSurface& surface, bool soup)
    : triangles_(surface.triangles), impl_(std::make_unique<Impl>()) {
  Mesh& m = impl_->mesh;
  for (Vec3 p : surface.vertices) {
    impl_->points.push_back(to_cgal(p));
    if (!soup) m.add_vertex(impl_->points.back());
  }
  for (size_t t = 0; t < surface.triangles.size(); ++t) {
    auto [a, b, c] = surface.triangles[t];
    if (soup) {
      const auto& P = impl_->points;
      a = int32_t(m.add_vertex(P[size_t(a)])), b = int32_t(m.add_vertex(P[size_t(b)])), c = int32_t(m.add_vertex(P[size_t(c)]));
    }
    auto f = m.add_face(Mesh::Vertex_index(a), Mesh::Vertex_index(b), Mesh::Vertex_index(c));
    if (f == Mesh::null_face() || size_t(f) != t) {
      Vec3 p = surface.vertices[a];
      fail(ErrorKind::InvalidInput,
           fmt::format("triangle {} cannot join its neighbours into a 2-manifold surface: one of its vertices {}, {}, {} "
                       "(first at ({}, {}, {})) is shared by two sheets that only touch there",
                       t, a, b, c, p.x, p.y, p.z));
    }
  }
  for (auto [a, b, c] : surface.triangles) {
    const auto& P = impl_->points;
    impl_->boxes.push_back(P[a].bbox() + P[b].bbox() + P[c].bbox());
  }
  impl_->tree = std::make_unique<Tree>(faces(m).first, faces(m).second, m);
  impl_->tree->build();
  impl_->side = std::make_unique<Side>(*impl_->tree);
}

SurfaceLocator::~SurfaceLocator() = default;

int SurfaceLocator::side(Vec3 p) const {
  switch ((*impl_->side)(to_cgal(p))) {
    case CGAL::ON_BOUNDED_SIDE: return 1;
    case CGAL::ON_BOUNDARY: return 0;
    default: return -1;
  }
}

bool SurfaceLocator::inside(Vec3 p) const { return side(p) > 0; }

void SurfaceLocator::triangles_near(Vec3 lo, Vec3 hi, std::vector<int32_t>& out) const {
  out.clear();
  std::vector<Mesh::Face_index> hits;
  impl_->tree->all_intersected_primitives(CGAL::Bbox_3(lo.x, lo.y, lo.z, hi.x, hi.y, hi.z), std::back_inserter(hits));
  for (auto f : hits) out.push_back(int32_t(f));
  std::sort(out.begin(), out.end());
}

bool SurfaceLocator::triangle_meets_box(int32_t t, Vec3 lo, Vec3 hi) const {
  const CGAL::Bbox_3& tb = impl_->boxes[t];
  if (tb.xmax() < lo.x || tb.xmin() > hi.x || tb.ymax() < lo.y || tb.ymin() > hi.y || tb.zmax() < lo.z ||
      tb.zmin() > hi.z)
    return false;
  const auto& P = impl_->points;
  auto [a, b, c] = triangles_[t];
  // Separating axes (the box's three, checked above; the triangle's normal; the nine products of
  // a box edge and a triangle edge), in floating point with a margin far above the rounding of
  // these products (about 1e-15 of their scale): an axis that separates by more than the margin
  // proves a miss, overlaps by more than it on every axis prove a hit, and anything closer is
  // left to the exact predicate.
  {
    const Vec3 p{P[a].x(), P[a].y(), P[a].z()};
    const Vec3 u = Vec3{P[b].x(), P[b].y(), P[b].z()} - p, v = Vec3{P[c].x(), P[c].y(), P[c].z()} - p;
    const Vec3 n = cross(u, v);
    const Vec3 l = lo - p, h = hi - p;
    double dmin = 0, dmax = 0, scale = 0;
    for (int k = 0; k < 3; ++k) {
      dmin += n[k] * (n[k] > 0 ? l[k] : h[k]);
      dmax += n[k] * (n[k] > 0 ? h[k] : l[k]);
      scale = std::max({scale, std::abs(u[k]), std::abs(v[k])});
    }
    const double reach = std::max({std::abs(l.x), std::abs(l.y), std::abs(l.z), std::abs(h.x), std::abs(h.y), std::abs(h.z)});
    const double margin = 1e-10 * scale * scale * reach;
    if (dmin > margin || dmax < -margin) return false;
    bool clear = dmin < -margin && dmax > margin;
    // Box edge e_k x triangle edge f: the triangle projects to [min, max] of its corners (relative
    // to p: 0, u, v), the box to [min, max] of its corners' projections.
    const double edge_margin = 1e-10 * scale * std::max(scale, reach);
    const Vec3 edges[3] = {u, v - u, v};
    for (const Vec3& f : edges)
      for (int k = 0; k < 3; ++k) {
        Vec3 axis{};  // e_k x f
        axis[(k + 1) % 3] = -f[(k + 2) % 3];
        axis[(k + 2) % 3] = f[(k + 1) % 3];
        if (axis.x == 0 && axis.y == 0 && axis.z == 0) continue;  // f along the box edge: no axis
        const double tu = dot(axis, u), tv = dot(axis, v);
        const double tmin = std::min({0.0, tu, tv}), tmax = std::max({0.0, tu, tv});
        double bmin = 0, bmax = 0;
        for (int q = 0; q < 3; ++q) {
          bmin += axis[q] * (axis[q] > 0 ? l[q] : h[q]);
          bmax += axis[q] * (axis[q] > 0 ? h[q] : l[q]);
        }
        if (tmin > bmax + edge_margin || tmax < bmin - edge_margin) return false;
        clear &= tmin < bmax - edge_margin && tmax > bmin + edge_margin;
      }
    if (clear) return true;
  }
  return CGAL::do_intersect(Kernel::Triangle_3(P[a], P[b], P[c]),
                            Kernel::Iso_cuboid_3(to_cgal(lo), to_cgal(hi)));
}

namespace {

int crossing(const Point& pa, const Point& pb, const Point& P, const Point& Q, const Point& R) {
  const auto oa = CGAL::orientation(P, Q, R, pa), ob = CGAL::orientation(P, Q, R, pb);
  if (oa == CGAL::COPLANAR || ob == CGAL::COPLANAR) {
    // An end on the plane: degenerate only if it lies in the (closed) triangle.
    return Kernel::Triangle_3(P, Q, R).has_on(oa == CGAL::COPLANAR ? pa : pb) ? -1 : 0;
  }
  if (oa == ob) return 0;
  // The segment crosses the plane; it crosses the triangle if it passes each edge on the same side.
  const auto s0 = CGAL::orientation(pa, pb, P, Q), s1 = CGAL::orientation(pa, pb, Q, R),
             s2 = CGAL::orientation(pa, pb, R, P);
  const bool has_pos = s0 == CGAL::POSITIVE || s1 == CGAL::POSITIVE || s2 == CGAL::POSITIVE;
  const bool has_neg = s0 == CGAL::NEGATIVE || s1 == CGAL::NEGATIVE || s2 == CGAL::NEGATIVE;
  if (has_pos && has_neg) return 0;
  if (s0 == CGAL::ZERO || s1 == CGAL::ZERO || s2 == CGAL::ZERO) return -1;
  return 1;
}

}  // namespace

int segment_crossing(Vec3 a, Vec3 b, Vec3 p, Vec3 q, Vec3 r) {
  return crossing(to_cgal(a), to_cgal(b), to_cgal(p), to_cgal(q), to_cgal(r));
}

int SurfaceLocator::segment_crossing(Vec3 a, Vec3 b, int32_t t) const {
  const auto& P = impl_->points;
  auto [i, j, k] = triangles_[t];
  return crossing(to_cgal(a), to_cgal(b), P[i], P[j], P[k]);
}

std::optional<std::pair<int32_t, int32_t>> SurfaceLocator::first_self_intersection() const {
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(impl_->mesh, std::back_inserter(pairs));
  if (pairs.empty()) return std::nullopt;
  auto first = *std::min_element(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) {
    return std::minmax(int32_t(a.first), int32_t(a.second)) < std::minmax(int32_t(b.first), int32_t(b.second));
  });
  return std::minmax(int32_t(first.first), int32_t(first.second));
}

bool SurfaceLocator::side_from(Vec3 a, bool a_inside, Vec3 b, std::span<const int32_t> triangles,
                               bool& b_inside) const {
  bool in = a_inside;
  // A triangle whose bounding box misses the segment's neither crosses it nor holds an end.
  const Vec3 lo{std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
  const Vec3 hi{std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
  for (int32_t t : triangles) {
    const CGAL::Bbox_3& tb = impl_->boxes[t];
    if (tb.xmax() < lo.x || tb.xmin() > hi.x || tb.ymax() < lo.y || tb.ymin() > hi.y || tb.zmax() < lo.z ||
        tb.zmin() > hi.z)
      continue;
    int c = segment_crossing(a, b, t);
    if (c < 0) return false;
    if (c > 0) in = !in;
  }
  b_inside = in;
  return true;
}

}  // namespace froth
