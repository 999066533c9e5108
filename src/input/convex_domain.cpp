// Convex domains: a box, or a closed surface validated to be convex with exact predicates
// (CGAL EPICK), whose distinct facet planes bound the domain.
#include <algorithm>
#include <map>
#include <numeric>
#include <sstream>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <fmt/format.h>

#include "froth/domain.hpp"
#include "common/union_find.hpp"
#include "features/features.hpp"
#include "froth/error.hpp"

namespace froth {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

Point to_cgal(Vec3 p) { return Point(p.x, p.y, p.z); }
std::string fmt_point(Vec3 p) { return fmt::format("({}, {}, {})", p.x, p.y, p.z); }

}  // namespace

ConvexDomain make_box_domain(Vec3 lo, Vec3 hi) {
  if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z))
    fail(ErrorKind::Usage, fmt::format("box: lower corner {} must be below upper corner {} on every axis",
                                       fmt_point(lo), fmt_point(hi)));
  ConvexDomain d;
  d.description = fmt::format("box:{},{},{},{},{},{}", lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
  d.planes = {{{-1, 0, 0}, -lo.x}, {{1, 0, 0}, hi.x}, {{0, -1, 0}, -lo.y},
              {{0, 1, 0}, hi.y},   {{0, 0, -1}, -lo.z}, {{0, 0, 1}, hi.z}};
  d.bounds = {lo, hi};
  Vec3 s = hi - lo;
  d.volume = s.x * s.y * s.z;
  d.surface_area = 2 * (s.x * s.y + s.y * s.z + s.z * s.x);
  return d;
}

ConvexDomain parse_box_spec(const std::string& spec) {
  std::string body = spec.substr(4);
  std::replace(body.begin(), body.end(), ',', ' ');
  std::istringstream in(body);
  double v[6];
  for (double& x : v)
    if (!(in >> x) || !std::isfinite(x))
      fail(ErrorKind::Usage, fmt::format("'{}': expected box:X0,Y0,Z0,X1,Y1,Z1 with six finite numbers", spec));
  std::string rest;
  if (in >> rest) fail(ErrorKind::Usage, fmt::format("'{}': trailing text '{}' after six numbers", spec, rest));
  return make_box_domain({v[0], v[1], v[2]}, {v[3], v[4], v[5]});
}

ConvexDomain convex_domain_from_surface(const TriangleSurface& s, const std::string& name) {
  const auto& V = s.vertices;
  const auto& T = s.triangles;
  if (T.size() < 4) fail(ErrorKind::InvalidInput, fmt::format("{}: {} triangles cannot close a solid", name, T.size()));

  for (size_t t = 0; t < T.size(); ++t) {
    auto [a, b, c] = T[t];
    if (a == b || b == c || a == c || CGAL::collinear(to_cgal(V[a]), to_cgal(V[b]), to_cgal(V[c])))
      fail(ErrorKind::InvalidInput, fmt::format("{}: triangle {} is degenerate (zero area): {} {} {}", name, t,
                                                fmt_point(V[a]), fmt_point(V[b]), fmt_point(V[c])));
  }

  // Each undirected edge must be used by exactly two triangles, once in each direction.
  struct Use { int32_t tri; bool forward; };
  std::map<std::pair<int32_t, int32_t>, std::vector<Use>> edges;
  for (size_t t = 0; t < T.size(); ++t)
    for (int e = 0; e < 3; ++e) {
      int32_t a = T[t][e], b = T[t][(e + 1) % 3];
      edges[{std::min(a, b), std::max(a, b)}].push_back({int32_t(t), a < b});
    }
  UnionFind component(T.size()), coplanar(T.size());
  for (const auto& [edge, uses] : edges) {
    auto where = fmt::format("edge {}-{} {} {}", edge.first, edge.second, fmt_point(V[edge.first]),
                             fmt_point(V[edge.second]));
    if (uses.size() == 1)
      fail(ErrorKind::InvalidInput, fmt::format("{}: surface is not closed: {} belongs to triangle {} only", name,
                                                where, uses[0].tri));
    if (uses.size() > 2)
      fail(ErrorKind::InvalidInput,
           fmt::format("{}: surface is not manifold: {} is shared by {} triangles", name, where, uses.size()));
    if (uses[0].forward == uses[1].forward)
      fail(ErrorKind::InvalidInput,
           fmt::format("{}: inconsistent orientation: triangles {} and {} run {} in the same direction", name,
                       uses[0].tri, uses[1].tri, where));
    component.unite(uses[0].tri, uses[1].tri);
  }
  for (size_t t = 1; t < T.size(); ++t)
    if (component.find(int32_t(t)) != 0)
      fail(ErrorKind::InvalidInput,
           fmt::format("{}: surface has more than one component (triangle {} is not connected to triangle 0); "
                       "this version meshes one convex solid",
                       name, t));

  double volume6 = 0, area2 = 0;
  for (auto [a, b, c] : T) {
    volume6 += dot(V[a], cross(V[b], V[c]));
    area2 += norm(cross(V[b] - V[a], V[c] - V[a]));
  }
  const bool inward = volume6 < 0;  // consistently wound but inside out: read it the other way

  // Local convexity at every edge (exact): the far vertex of the neighbouring triangle is never
  // strictly outside a triangle's plane. Coplanar neighbours join one facet plane.
  auto tri_points = [&](int32_t t) {
    auto [a, b, c] = T[t];
    return inward ? std::array<int32_t, 3>{a, c, b} : std::array<int32_t, 3>{a, b, c};
  };
  for (const auto& [edge, uses] : edges) {
    auto p = tri_points(uses[0].tri);
    const auto& q = T[uses[1].tri];
    int32_t far = q[0] + q[1] + q[2] - edge.first - edge.second;
    auto o = CGAL::orientation(to_cgal(V[p[0]]), to_cgal(V[p[1]]), to_cgal(V[p[2]]), to_cgal(V[far]));
    if (o == CGAL::POSITIVE)
      fail(ErrorKind::InvalidInput,
           fmt::format("{}: surface is not convex: reflex edge {}-{} {} {} between triangles {} and {}; "
                       "non-convex domains are not supported yet",
                       name, edge.first, edge.second, fmt_point(V[edge.first]), fmt_point(V[edge.second]),
                       uses[0].tri, uses[1].tri));
    if (o == CGAL::COPLANAR) coplanar.unite(uses[0].tri, uses[1].tri);
  }

  // One plane per coplanar group: Newell normal (area-weighted), offset averaged over corners.
  ConvexDomain d;
  d.description = name;
  std::map<int32_t, std::pair<Vec3, std::vector<int32_t>>> groups;
  for (size_t t = 0; t < T.size(); ++t) {
    auto p = tri_points(int32_t(t));
    auto& g = groups[coplanar.find(int32_t(t))];
    g.first = g.first + cross(V[p[1]] - V[p[0]], V[p[2]] - V[p[0]]);
    g.second.insert(g.second.end(), p.begin(), p.end());
  }
  for (auto& [root, g] : groups) {
    Vec3 n = (1.0 / norm(g.first)) * g.first;
    double off = 0;
    for (int32_t v : g.second) off += dot(n, V[v]);
    d.planes.push_back({n, off / double(g.second.size())});
  }

  Box b{V[0], V[0]};
  for (Vec3 p : V) {
    b.lo = {std::min(b.lo.x, p.x), std::min(b.lo.y, p.y), std::min(b.lo.z, p.z)};
    b.hi = {std::max(b.hi.x, p.x), std::max(b.hi.y, p.y), std::max(b.hi.z, p.z)};
  }
  d.bounds = b;
  d.volume = std::abs(volume6) / 6;
  d.surface_area = area2 / 2;

  // Local convexity does not exclude a surface that winds around twice; every vertex must lie
  // inside every facet plane. Quadratic, so only for surfaces of moderate size.
  if (double(V.size()) * double(d.planes.size()) <= 2e8) {
    double slack = 1e-9 * b.diagonal();
    for (size_t v = 0; v < V.size(); ++v)
      for (size_t p = 0; p < d.planes.size(); ++p)
        if (d.planes[p].signed_distance(V[v]) > slack)
          fail(ErrorKind::InvalidInput,
               fmt::format("{}: surface is not convex: vertex {} {} lies outside facet plane {}", name, v,
                           fmt_point(V[v]), p));
  }
  return d;
}

namespace {

// The box as a triangle surface (outward), for its features.
TriangleSurface box_surface(const Box& b) {
  TriangleSurface s;
  for (int c = 0; c < 8; ++c)
    s.vertices.push_back({(c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z});
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {1, 3, 7, 5}, {0, 4, 6, 2}};
  for (const auto& q : quads) {
    s.triangles.push_back({q[0], q[1], q[2]});
    s.triangles.push_back({q[0], q[2], q[3]});
  }
  return s;
}

}  // namespace

ConvexDomain load_domain(const std::string& input, double feature_angle) {
  if (!(feature_angle > 0 && feature_angle < 180))
    fail(ErrorKind::Usage, fmt::format("the feature angle must be between 0 and 180 degrees, got {}", feature_angle));
  if (input.rfind("box:", 0) == 0) {
    ConvexDomain d = parse_box_spec(input);
    d.features = classify_features(box_surface(d.bounds), feature_angle).summary();
    return d;
  }
  std::filesystem::path path(input);
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  TriangleSurface surface;
  if (ext == ".stl") surface = read_stl(path);
  else if (ext == ".off" || ext == ".obj" || ext == ".ply") surface = read_polygon_file(path);
  else
    fail(ErrorKind::Usage,
         fmt::format("{}: unsupported input format '{}' (froth reads STL, OFF, OBJ and PLY, or box:X0,Y0,Z0,X1,Y1,Z1)",
                     input, ext));
  ConvexDomain d = convex_domain_from_surface(surface, path.filename().string());
  d.features = classify_features(surface, feature_angle).summary();
  return d;
}

}  // namespace froth
