// Domains: a box, or the solid a validated closed surface encloses. Every topological decision
// uses exact predicates (CGAL EPICK).
#include <algorithm>
#include <map>
#include <optional>
#include <numeric>
#include <span>
#include <sstream>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <fmt/format.h>

#include "froth/domain.hpp"
#include "input/regions.hpp"
#include "common/surface_locator.hpp"
#include "common/union_find.hpp"
#include "features/features.hpp"
#include "features/patches.hpp"
#include "froth/error.hpp"

namespace froth {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

Point to_cgal(Vec3 p) { return Point(p.x, p.y, p.z); }
std::string fmt_point(Vec3 p) { return fmt::format("({}, {}, {})", p.x, p.y, p.z); }

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

namespace {

// Per axis, the part's face nearer the origin where the part lies beyond 8 times its size from
// it, else 0: a coordinate minus it is then exact (Sterbenz: both within a factor 2 of each
// other), so the part moved by it is the same solid, exactly, in coordinates of its own size.
Vec3 far_origin(const Box& b) {
  const Vec3 size = b.size();
  const double extent = std::max({size.x, size.y, size.z});
  Vec3 o{};
  for (int a = 0; a < 3; ++a) {
    if (b.lo[a] > 0 && b.lo[a] >= 8 * extent) o[a] = b.lo[a];
    if (b.hi[a] < 0 && -b.hi[a] >= 8 * extent) o[a] = b.hi[a];
  }
  return o;
}

Box bounds_of(const std::vector<TriangleSurface>& surfaces) {
  Box b{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  for (const TriangleSurface& s : surfaces)
    for (Vec3 p : s.vertices)
      for (int a = 0; a < 3; ++a)
        if (std::isfinite(p[a])) b.lo[a] = std::min(b.lo[a], p[a]), b.hi[a] = std::max(b.hi[a], p[a]);
  return b;
}

// The domain `build` makes of `surfaces`, stored relative to far_origin of them. A far part is
// built as given first, so that its defects are named in the input's own coordinates (the exact
// predicates decide alike on the moved copy, which is then built).
template <class Build>
Domain relative_to_part(const std::vector<TriangleSurface>& surfaces, Build&& build) {
  const Box b = bounds_of(surfaces);
  const Vec3 o = b.lo.x <= b.hi.x ? far_origin(b) : Vec3{};
  if (o.x == 0 && o.y == 0 && o.z == 0) return build(surfaces);
  (void)build(surfaces);
  std::vector<TriangleSurface> moved = surfaces;
  for (TriangleSurface& s : moved)
    for (Vec3& p : s.vertices) p = p - o;
  Domain d = build(moved);
  d.origin = o;
  return d;
}

}  // namespace

Domain make_box_domain(Vec3 lo, Vec3 hi) {
  if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z))
    fail(ErrorKind::Usage, fmt::format("box: lower corner {} must be below upper corner {} on every axis",
                                       fmt_point(lo), fmt_point(hi)));
  Domain d;
  d.description = fmt::format("box:{},{},{},{},{},{}", lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
  d.planes = {{{-1, 0, 0}, -lo.x}, {{1, 0, 0}, hi.x}, {{0, -1, 0}, -lo.y},
              {{0, 1, 0}, hi.y},   {{0, 0, -1}, -lo.z}, {{0, 0, 1}, hi.z}};
  d.bounds = {lo, hi};
  Vec3 s = hi - lo;
  d.volume = s.x * s.y * s.z;
  d.surface_area = 2 * (s.x * s.y + s.y * s.z + s.z * s.x);
  d.surface = box_surface(d.bounds);
  d.triangle_plane = {4, 4, 5, 5, 2, 2, 3, 3, 1, 1, 0, 0};  // quads of box_surface -> planes above
  return d;
}

Domain parse_box_spec(const std::string& spec) {
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

namespace {

// Counts the crossings of the segment from p to `far` (beyond the surface) with the triangles
// outside component `skip`; nullopt when it grazes an edge or a vertex (the caller tries
// another direction).
std::optional<size_t> crossings(const TriangleSurface& s, const std::vector<int32_t>& component, int32_t skip, Vec3 p,
                                Vec3 far) {
  size_t n = 0;
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    if (component[t] == skip) continue;
    auto [i, j, k] = s.triangles[t];
    const int c = segment_crossing(p, far, s.vertices[i], s.vertices[j], s.vertices[k]);
    if (c < 0) return std::nullopt;
    n += size_t(c);
  }
  return n;
}

std::string where_edge(const std::vector<Vec3>& V, int32_t a, int32_t b) {
  return fmt::format("edge {}-{} {} {}", a, b, fmt_point(V[a]), fmt_point(V[b]));
}

// Finite coordinates, and triangles of positive area.
void check_points_and_triangles(const TriangleSurface& s, const std::string& name) {
  const auto& V = s.vertices;
  const auto& T = s.triangles;
  if (T.size() < 4) fail(ErrorKind::InvalidInput, fmt::format("{}: {} triangles cannot close a solid", name, T.size()));
  for (size_t v = 0; v < V.size(); ++v)
    if (!std::isfinite(V[v].x) || !std::isfinite(V[v].y) || !std::isfinite(V[v].z))
      fail(ErrorKind::InvalidInput, fmt::format("{}: vertex {} has a non-finite coordinate {}", name, v, fmt_point(V[v])));
  for (size_t t = 0; t < T.size(); ++t) {
    auto [a, b, c] = T[t];
    if (a == b || b == c || a == c || CGAL::collinear(to_cgal(V[a]), to_cgal(V[b]), to_cgal(V[c])))
      fail(ErrorKind::InvalidInput, fmt::format("{}: triangle {} is degenerate (zero area): {} {} {}", name, t,
                                                fmt_point(V[a]), fmt_point(V[b]), fmt_point(V[c])));
  }
}

// Each undirected edge with the triangles that use it, and whether they run it forward.
struct EdgeUse {
  int32_t tri;
  bool forward;
};
// In a flat list sorted by edge, each edge's uses in the order the triangles come: a map of
// vectors was a tenth of reading a 476,000-triangle part.
class EdgeUses {
 public:
  explicit EdgeUses(const TriangleSurface& s) {
    struct Key {
      int32_t a, b;
      EdgeUse use;
    };
    std::vector<Key> keys;
    keys.reserve(3 * s.triangles.size());
    for (size_t t = 0; t < s.triangles.size(); ++t)
      for (int e = 0; e < 3; ++e) {
        const int32_t a = s.triangles[t][e], b = s.triangles[t][(e + 1) % 3];
        keys.push_back({std::min(a, b), std::max(a, b), {int32_t(t), a < b}});
      }
    std::stable_sort(keys.begin(), keys.end(), [](const Key& x, const Key& y) { return std::pair(x.a, x.b) < std::pair(y.a, y.b); });
    uses_.reserve(keys.size());
    for (const Key& k : keys) uses_.push_back(k.use);
    for (size_t i = 0; i < keys.size();) {
      size_t j = i;
      while (j < keys.size() && keys[j].a == keys[i].a && keys[j].b == keys[i].b) ++j;
      groups_.push_back({{keys[i].a, keys[i].b}, std::span<const EdgeUse>(uses_.data() + i, j - i)});
      i = j;
    }
  }
  auto begin() const { return groups_.begin(); }
  auto end() const { return groups_.end(); }

 private:
  std::vector<EdgeUse> uses_;
  std::vector<std::pair<std::pair<int32_t, int32_t>, std::span<const EdgeUse>>> groups_;
};

// Each undirected edge must be used by exactly two triangles, in opposite directions unless
// `repair`. Returns each triangle's neighbours across its edges, with whether they run the
// shared edge the same way.
std::vector<std::vector<std::pair<int32_t, bool>>> check_edges(const TriangleSurface& s, const EdgeUses& edges,
                                                               const std::string& name, bool repair) {
  const auto& V = s.vertices;
  std::vector<std::vector<std::pair<int32_t, bool>>> across(s.triangles.size());  // neighbour, same direction?
  for (const auto& [edge, uses] : edges) {
    if (uses.size() == 1)
      fail(ErrorKind::InvalidInput, fmt::format("{}: surface is not closed: {} belongs to triangle {} only", name,
                                                where_edge(V, edge.first, edge.second), uses[0].tri));
    if (uses.size() > 2) {
      std::string tris;
      for (const EdgeUse& u : uses) tris += fmt::format("{}{}", tris.empty() ? "" : ", ", u.tri);
      fail(ErrorKind::InvalidInput, fmt::format("{}: surface is not manifold: {} is shared by {} triangles ({})", name,
                                                where_edge(V, edge.first, edge.second), uses.size(), tris));
    }
    const bool same = uses[0].forward == uses[1].forward;
    if (same && !repair)
      fail(ErrorKind::InvalidInput,
           fmt::format("{}: inconsistent orientation: triangles {} and {} run {} in the same direction "
                       "(the repair option reorients such shells)",
                       name, uses[0].tri, uses[1].tri, where_edge(V, edge.first, edge.second)));
    across[uses[0].tri].push_back({uses[1].tri, same});
    across[uses[1].tri].push_back({uses[0].tri, same});
  }
  return across;
}

// Each vertex's triangles must form one fan around it (joined across the edges at the vertex):
// two solids touching at a point are closed and edge-manifold but bound no solid there. The
// corners (triangle, vertex) of one fan are joined across its edges.
void check_vertex_fans(const TriangleSurface& s, const EdgeUses& edges, const std::string& name) {
  const auto& V = s.vertices;
  const auto& T = s.triangles;
  UnionFind fans(3 * T.size());
  auto corner = [&](int32_t t, int32_t v) { return 3 * t + int32_t(T[t][0] == v ? 0 : T[t][1] == v ? 1 : 2); };
  for (const auto& [edge, uses] : edges)
    for (int32_t v : {edge.first, edge.second}) fans.unite(corner(uses[0].tri, v), corner(uses[1].tri, v));
  std::vector<int32_t> first_fan(V.size(), -1);
  for (size_t c = 0; c < 3 * T.size(); ++c) {
    const int32_t v = T[c / 3][c % 3], fan = fans.find(int32_t(c));
    if (first_fan[v] < 0) first_fan[v] = fan;
    else if (first_fan[v] != fan)
      fail(ErrorKind::InvalidInput,
           fmt::format("{}: surface is not manifold at vertex {} {}: its triangles form separate fans (parts that "
                       "touch at a single point); move them apart or join them along a face",
                       name, v, fmt_point(V[v])));
  }
}

// Shells: edge-connected components (each triangle's in `component`), each wound consistently
// (flipping triangles if repair was asked, counted in d.reoriented_triangles). Returns how many.
int32_t orient_shells(TriangleSurface& s, const std::vector<std::vector<std::pair<int32_t, bool>>>& across,
                      std::vector<int32_t>& component, Domain& d, const std::string& name) {
  auto& T = s.triangles;
  component.assign(T.size(), -1);
  std::vector<char> flip(T.size(), 0);
  int32_t shells = 0;
  for (size_t seed = 0; seed < T.size(); ++seed) {
    if (component[seed] >= 0) continue;
    std::vector<int32_t> stack{int32_t(seed)};
    component[seed] = shells;
    while (!stack.empty()) {
      int32_t t = stack.back();
      stack.pop_back();
      for (auto [u, same] : across[t]) {
        const char want = char(flip[t] ^ same);
        if (component[u] < 0) {
          component[u] = shells, flip[u] = want;
          stack.push_back(u);
        } else if (flip[u] != want) {
          fail(ErrorKind::InvalidInput, fmt::format("{}: the shell of triangle {} cannot be oriented (it is one-sided "
                                                    "like a Moebius strip; see triangles {} and {})",
                                                    name, seed, t, u));
        }
      }
    }
    ++shells;
  }
  for (size_t t = 0; t < T.size(); ++t)
    if (flip[t]) std::swap(T[t][1], T[t][2]), ++d.reoriented_triangles;
  return shells;
}

// Nesting: a shell inside an odd number of others bounds a cavity. Orientation is taken from
// nesting, never trusted to the file: outer shells face out, cavity shells into the cavity.
void nest_shells(TriangleSurface& s, const std::vector<int32_t>& component, int32_t shells, const Box& bounds,
                 Domain& d, const std::string& name) {
  const auto& V = s.vertices;
  auto& T = s.triangles;
  std::vector<double> volume6(shells, 0);
  std::vector<std::vector<int32_t>> triangles_of(shells);
  for (size_t t = 0; t < T.size(); ++t) {
    auto [a, b, c] = T[t];
    volume6[component[t]] += dot(V[a], cross(V[b], V[c]));
    if (triangles_of[component[t]].size() < 8) triangles_of[component[t]].push_back(int32_t(t));
  }
  std::vector<char> reverse(shells, 0);
  for (int32_t c = 0; c < shells; ++c) {
    size_t depth = 0;
    if (shells > 1) {
      // Rays from a point inside one of the shell's triangles: a vertex may be shared with
      // another shell that touches it there (trimesh's box.STL), and every ray from it grazes.
      std::optional<size_t> n;
      for (size_t k = 0; !n && k < triangles_of[c].size(); ++k) {
        const auto [ta, tb, tc] = T[size_t(triangles_of[c][k])];
        const Vec3 p = (1.0 / 3) * (V[ta] + V[tb] + V[tc]);
        for (int attempt = 0; !n && attempt < 16; ++attempt) {
          // Fixed, irrational-looking directions: deterministic and unlikely to graze anything.
          const double u = 0.6180339887 * (attempt + 1), w = 0.4142135623 * (attempt + 1);
          const Vec3 dir{std::cos(2 * M_PI * u) * std::sin(M_PI * w), std::sin(2 * M_PI * u) * std::sin(M_PI * w),
                         std::cos(M_PI * w)};
          n = crossings(s, component, c, p, p + 2 * (bounds.diagonal() + 1) * dir);
        }
      }
      if (!n) fail(ErrorKind::Internal, fmt::format("{}: could not decide which shells enclose shell {}", name, c));
      depth = *n;
    }
    const bool cavity = depth % 2 == 1;
    d.cavities += cavity;
    reverse[c] = (volume6[c] < 0) != cavity;
  }
  for (size_t t = 0; t < T.size(); ++t)
    if (reverse[component[t]]) std::swap(T[t][1], T[t][2]);
  d.shells = size_t(shells);
}

// Facet planes: one per edge-connected group of coplanar triangles (exact), Newell normal
// (area-weighted), offset averaged over the corners. Returns whether no edge is reflex.
bool group_facet_planes(const TriangleSurface& s, const EdgeUses& edges, Domain& d) {
  const auto& V = s.vertices;
  const auto& T = s.triangles;
  bool locally_convex = true;
  UnionFind coplanar(T.size());
  for (const auto& [edge, uses] : edges) {
    const auto& p = T[uses[0].tri];
    const auto& q = T[uses[1].tri];
    int32_t far = q[0] + q[1] + q[2] - edge.first - edge.second;
    auto o = CGAL::orientation(to_cgal(V[p[0]]), to_cgal(V[p[1]]), to_cgal(V[p[2]]), to_cgal(V[far]));
    if (o == CGAL::POSITIVE) locally_convex = false;
    if (o == CGAL::COPLANAR) coplanar.unite(uses[0].tri, uses[1].tri);
  }
  std::map<int32_t, int32_t> plane_of_root;
  std::vector<std::pair<Vec3, std::vector<int32_t>>> groups;
  d.triangle_plane.resize(T.size());
  for (size_t t = 0; t < T.size(); ++t) {
    auto [it, added] = plane_of_root.try_emplace(coplanar.find(int32_t(t)), int32_t(groups.size()));
    if (added) groups.emplace_back();
    d.triangle_plane[t] = it->second;
    auto& g = groups[it->second];
    auto [p0, p1, p2] = T[t];
    g.first = g.first + cross(V[p1] - V[p0], V[p2] - V[p0]);
    g.second.insert(g.second.end(), {p0, p1, p2});
  }
  for (auto& [normal, corners] : groups) {
    Vec3 n = (1.0 / norm(normal)) * normal;
    double off = 0;
    for (int32_t v : corners) off += dot(n, V[v]);
    d.planes.push_back({n, off / double(corners.size())});
  }
  return locally_convex;
}

// The enclosed volume and the area, which must be finite and positive.
void measure_solid(const TriangleSurface& s, const Box& b, Domain& d, const std::string& name) {
  const auto& V = s.vertices;
  double total6 = 0, area2 = 0;
  for (auto [p0, p1, p2] : s.triangles) {
    total6 += dot(V[p0], cross(V[p1], V[p2]));
    area2 += norm(cross(V[p1] - V[p0], V[p2] - V[p0]));
  }
  d.volume = total6 / 6;
  d.surface_area = area2 / 2;
  if (!std::isfinite(d.volume) || !std::isfinite(d.surface_area))
    fail(ErrorKind::InvalidInput,
         fmt::format("{}: the part's volume or area overflows double precision (coordinates up to {:.3g}); scale it "
                     "down (froth takes sizes from 1e-100 to 1e100)",
                     name, std::max({std::abs(b.lo.x), std::abs(b.lo.y), std::abs(b.lo.z), std::abs(b.hi.x),
                                     std::abs(b.hi.y), std::abs(b.hi.z)})));
  if (!(d.volume > 0))
    fail(ErrorKind::InvalidInput, fmt::format("{}: the surface encloses no volume ({})", name, d.volume));
}

}  // namespace

// The surface validated, its shells nested and oriented, its facet planes grouped; no features yet.
static Domain validated_domain(const TriangleSurface& input, const std::string& name, bool repair) {
  TriangleSurface s = input;
  const auto& V = s.vertices;
  auto& T = s.triangles;
  check_points_and_triangles(s, name);
  const EdgeUses edges(s);
  const auto across = check_edges(s, edges, name, repair);
  check_vertex_fans(s, edges, name);
  Domain d;
  std::vector<int32_t> component;
  const int32_t shells = orient_shells(s, across, component, d, name);
  Box b{V[0], V[0]};
  for (Vec3 p : V) {
    b.lo = {std::min(b.lo.x, p.x), std::min(b.lo.y, p.y), std::min(b.lo.z, p.z)};
    b.hi = {std::max(b.hi.x, p.x), std::max(b.hi.y, p.y), std::max(b.hi.z, p.z)};
  }
  nest_shells(s, component, shells, b, d, name);

  // Self-intersections (exact), on the oriented surface.
  d.locator = std::make_shared<SurfaceLocator>(s);
  if (auto pair = d.locator->first_self_intersection())
    fail(ErrorKind::InvalidInput,
         fmt::format("{}: surface intersects itself: triangles {} and {} meet away from a shared edge or vertex, near {}",
                     name, pair->first, pair->second, fmt_point(V[T[pair->first][0]])));

  d.description = name;
  const bool locally_convex = group_facet_planes(s, edges, d) && shells == 1;
  d.bounds = b;
  measure_solid(s, b, d, name);
  // Local convexity does not exclude a surface that winds around twice; every vertex must lie
  // inside every facet plane (self-intersection is already excluded, so this is a safeguard).
  d.convex = locally_convex;
  if (d.convex && double(V.size()) * double(d.planes.size()) <= 2e8) {
    const double slack = 1e-9 * b.diagonal();
    for (size_t v = 0; v < V.size() && d.convex; ++v)
      for (const Plane& pl : d.planes)
        if (pl.signed_distance(V[v]) > slack) { d.convex = false; break; }
  }
  d.surface = std::move(s);
  return d;
}

bool Domain::contains(Vec3 p) const {
  if (convex) {
    for (const Plane& pl : planes)
      if (pl.signed_distance(p) > 0) return false;
    return true;
  }
  return locator->inside(p);
}


namespace {

void check_feature_angle(double degrees) {
  if (!(degrees > 0 && degrees < 180))
    fail(ErrorKind::Usage, fmt::format("the feature angle must be strictly between 0 and 180 degrees, got {}", degrees));
}

// The features of the domain's surface, and the reflex curves protection seeds (paper §2.2).
void find_features(Domain& d, double feature_angle) {
  const SurfaceFeatures features = classify_features(d.surface, feature_angle);
  d.features = features.summary();
  // A surface whose file names no patches gets one per smooth region between feature curves.
  if (d.surface.patch_names.empty() || d.surface.triangle_patch.size() != d.surface.triangles.size()) {
    size_t count = 0;
    d.surface.triangle_patch = smooth_regions(d.surface, features, count);
    d.surface.patch_names.clear();
    for (size_t k = 0; k < count; ++k) d.surface.patch_names.push_back(fmt::format("surface_{}", k));
  }
  if (!d.convex)
    for (const FeatureCurve& c : features.curves)
      if (c.cls == EdgeClass::Reflex) d.reflex_curves.push_back(c.vertices);
}

}  // namespace

Domain domain_from_surface(const TriangleSurface& surface, const std::string& name, const DomainOptions& options) {
  check_feature_angle(options.feature_angle);
  Domain d = validated_domain(surface, name, options.repair);
  find_features(d, options.feature_angle);
  return d;
}

namespace {

TriangleSurface read_surface(const std::string& input, const DomainOptions& options) {
  std::filesystem::path path(input);
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    fail(ErrorKind::Io, fmt::format("{}: is a directory, not a surface file (STL, OFF, OBJ or PLY)", input));
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".stl") return read_stl(path, options.max_memory_bytes);
  if (ext == ".off" || ext == ".obj" || ext == ".ply") return read_polygon_file(path, options.max_memory_bytes);
  fail(ErrorKind::Usage,
       fmt::format("{}: unsupported input format '{}' (froth reads STL, OFF, OBJ and PLY, or box:X0,Y0,Z0,X1,Y1,Z1)",
                   input, ext));
}

}  // namespace

Domain load_domain(const std::string& input, const DomainOptions& options) {
  check_feature_angle(options.feature_angle);
  if (input.rfind("box:", 0) == 0) {
    Domain d = parse_box_spec(input);
    const Vec3 o = far_origin(d.bounds);
    if (o.x != 0 || o.y != 0 || o.z != 0) {
      const std::string description = d.description;
      d = make_box_domain(d.bounds.lo - o, d.bounds.hi - o);
      d.description = description, d.origin = o;
    }
    find_features(d, options.feature_angle);
    return d;
  }
  const TriangleSurface surface = read_surface(input, options);
  const std::string name = std::filesystem::path(input).filename().string();
  return relative_to_part({surface}, [&](const std::vector<TriangleSurface>& s) {
    if (has_shared_triangles(s[0])) return regions_from_shared_triangles(s[0], name, options);
    return domain_from_surface(s[0], name, options);
  });
}

Domain load_regions(const std::vector<std::string>& inputs, const DomainOptions& options) {
  if (inputs.empty()) fail(ErrorKind::Usage, "no input given: name a surface file or a box spec for each region");
  if (inputs.size() == 1) return load_domain(inputs[0], options);
  check_feature_angle(options.feature_angle);
  std::vector<TriangleSurface> surfaces;
  std::vector<std::string> names;
  for (const std::string& input : inputs) {
    if (input.rfind("box:", 0) == 0) {
      const Domain box = parse_box_spec(input);
      surfaces.push_back(box.surface);
      names.push_back(fmt::format("box_{}", names.size()));
    } else {
      surfaces.push_back(read_surface(input, options));
      names.push_back(std::filesystem::path(input).stem().string());
    }
    for (size_t k = 0; k + 1 < names.size(); ++k)
      if (names[k] == names.back()) names.back() += fmt::format("_{}", names.size() - 1);
  }
  return relative_to_part(surfaces,
                          [&](const std::vector<TriangleSurface>& s) { return domain_from_regions(s, names, options); });
}

Domain domain_anywhere(const TriangleSurface& surface, const std::string& name, const DomainOptions& options) {
  return relative_to_part({surface},
                          [&](const std::vector<TriangleSurface>& s) { return domain_from_surface(s[0], name, options); });
}

}  // namespace froth
