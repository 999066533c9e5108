// Multi-region solids (paper §2.2, "Non-manifold geometry"): the regions several closed surfaces
// bound, found from the triangles' sides. Every triangle has two sides; around each edge the
// triangles are ordered by angle, and the two sides facing one wedge between neighbours bound
// the same part of space. The parts (components of sides) are then material of a solid (the
// side its triangle's input orientation calls inside) or not: a part that no input calls inside
// is either outside everything or the outer side of an inclusion, which belongs to the innermost
// region around it.
#include <algorithm>
#include <cmath>
#include <map>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <fmt/format.h>

#include "common/union_find.hpp"
#include "input/conform.hpp"
#include "input/regions.hpp"
#include "froth/error.hpp"

namespace froth {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
K::Point_3 to_cgal(Vec3 p) { return {p.x, p.y, p.z}; }
std::string where(Vec3 p) { return fmt::format("({}, {}, {})", p.x, p.y, p.z); }

using Tri = std::array<int32_t, 3>;

// One input triangle: its vertices (shared ids) as the input winds them, the body whose inside
// is behind it (-1: not known, a single file's), and its patch.
struct Occurrence {
  Tri v;
  int32_t body;
  std::string patch;
};

// Does t run from a to b?
bool runs(const Tri& t, int32_t a, int32_t b) {
  for (int k = 0; k < 3; ++k)
    if (t[k] == a && t[(k + 1) % 3] == b) return true;
  return false;
}

Tri reversed(Tri t) { return {t[0], t[2], t[1]}; }

class RegionBuilder {
 public:
  // `file`: a single file's name (its bodies are found here), or empty for one body per input.
  RegionBuilder(std::vector<Vec3> vertices, std::vector<Occurrence> occ, std::vector<std::string> body_names,
                std::string file, const DomainOptions& options)
      : V_(std::move(vertices)), occ_(std::move(occ)), body_names_(std::move(body_names)), file_(std::move(file)),
        options_(options) {}

  Domain build() {
    unique_triangles();
    pair_sides();
    if (close_slivers()) {
      RegionBuilder again(std::move(V_), std::move(occ_), std::move(body_names_), std::move(file_), options_);
      again.closed_slivers_ = true;
      return again.build();
    }
    assign_parts();
    auto set = std::make_shared<RegionSet>();
    group_facets(*set);
    refuse_near_misses();
    make_solids(*set);
    Domain u = make_union(*set);
    u.regions = std::move(set);
    return u;
  }

 private:
  // Side 2u of unique triangle u is behind its (first occurrence's) winding, 2u + 1 in front.
  void unique_triangles() {
    std::map<Tri, int32_t> id;
    for (size_t k = 0; k < occ_.size(); ++k) {
      Tri key = occ_[k].v;
      std::sort(key.begin(), key.end());
      const auto [it, added] = id.try_emplace(key, int32_t(tri_.size()));
      const int32_t u = it->second;
      if (added) {
        tri_.push_back(occ_[k].v);
        first_occ_.push_back(int32_t(k));
        material_.push_back(-1), material_.push_back(-1);
      }
      const bool same = runs(tri_[u], occ_[k].v[0], occ_[k].v[1]);
      const int32_t side = 2 * u + (same ? 0 : 1);  // the input's inside is behind its winding
      if (!added && material_[size_t(side)] != -1) {
        const int32_t first = occ_[size_t(first_occ_[u])].body, again = occ_[k].body;
        const std::string which = first == again ? "two solids of this file"
                                                 : fmt::format("{} and {}", name_of_body(first), name_of_body(again));
        fail(ErrorKind::InvalidInput,
             fmt::format("{}: triangle {} {} {} is listed twice the same way: {} overlap there (solids that "
                         "touch must list a shared face opposite ways)",
                         name_of_body(again), where(V_[key[0]]), where(V_[key[1]]), where(V_[key[2]]), which));
      }
      material_[size_t(side)] = occ_[k].body >= 0 ? occ_[k].body : kUnknownBody;
      occ_of_side_.resize(material_.size(), -1);
      occ_of_side_[size_t(side)] = int32_t(k);
    }
  }

  // Around each edge, the wedges between angularly neighbouring triangles join their sides.
  void pair_sides() {
    for (size_t u = 0; u < tri_.size(); ++u)
      for (int k = 0; k < 3; ++k) {
        const int32_t a = tri_[u][k], b = tri_[u][(k + 1) % 3];
        around_[{std::min(a, b), std::max(a, b)}].push_back(int32_t(u));
      }
    parts_.reset(2 * tri_.size());
    for (const auto& [edge, tris] : around_) {
      edges_.push_back(edge);
      const auto [a, b] = edge;
      if (tris.size() < 2)
        fail(ErrorKind::InvalidInput, fmt::format("{}: surface is not closed: the edge {} - {} belongs to one triangle",
                                                  name_of_body(occ_[size_t(first_occ_[tris[0]])].body), where(V_[a]),
                                                  where(V_[b])));
      const Vec3 d = V_[b] - V_[a];
      const Vec3 e1 = std::abs(d.x) < 0.6 * norm(d) ? cross(d, Vec3{1, 0, 0}) : cross(d, Vec3{0, 1, 0});
      const Vec3 e2 = cross(d, e1);
      std::vector<std::pair<double, int32_t>> by_angle;
      for (int32_t u : tris) {
        const int32_t c = tri_[u][0] + tri_[u][1] + tri_[u][2] - a - b;
        const Vec3 w = V_[c] - V_[a];
        by_angle.push_back({std::atan2(dot(w, e2) / norm(e2), dot(w, e1) / norm(e1)), u});
      }
      std::sort(by_angle.begin(), by_angle.end());
      // Faces meant to coincide (two solids' sides of one face, rounded apart) are a rounding
      // error apart in angle: neighbours that close are put in order by the exact test.
      for (size_t k = 0; by_angle.size() > 2 && k < by_angle.size(); ++k) {
        auto &u = by_angle[k], &w = by_angle[(k + 1) % by_angle.size()];
        const double gap = w.first - u.first;  // negative from the last to the first
        if (gap + (gap < 0 ? 2 * M_PI : 0) > 1e-6) continue;
        const int32_t ends = a + b;  // clang 14 cannot capture structured bindings
        const auto far = [&](int32_t t) { return to_cgal(V_[tri_[t][0] + tri_[t][1] + tri_[t][2] - ends]); };
        if (CGAL::orientation(to_cgal(V_[a]), to_cgal(V_[b]), far(u.second), far(w.second)) == CGAL::NEGATIVE)
          std::swap(u.second, w.second);
      }
      // The front of a triangle running a -> b faces the way the angle grows about a -> b.
      for (size_t k = 0; k < by_angle.size(); ++k) {
        const int32_t u = by_angle[k].second, w = by_angle[(k + 1) % by_angle.size()].second;
        const int32_t u_side = 2 * u + (runs(tri_[u], a, b) ? 1 : 0);
        const int32_t w_side = 2 * w + (runs(tri_[w], a, b) ? 0 : 1);
        parts_.unite(u_side, w_side);
      }
    }
  }

  // Two solids meant to touch along a face that is not exactly planar (a tilted face's corners
  // rounded to doubles) and triangulated differently on each side: the two surfaces bulge apart
  // by rounding errors, leaving a sliver of space inside both or inside neither, bounded by the
  // two solids' triangles alone. Such a part, thinner than 1e-9 of the solids' size, is closed:
  // the later solid takes the earlier one's triangles there (listed the other way round), as if
  // it had been given them. Returns whether any was (the sides are then paired anew).
  bool close_slivers() {
    if (closed_slivers_) return false;
    std::map<int32_t, std::vector<int32_t>> sides_of_part;
    for (size_t s = 0; s < material_.size(); ++s) sides_of_part[parts_.find(int32_t(s))].push_back(int32_t(s));
    const double diag = norm(bounds().size());
    std::vector<uint8_t> drop(occ_.size(), 0);
    std::vector<Occurrence> taken;
    for (const auto& [root, sides] : sides_of_part) {
      double volume6 = 0, area = 0;
      bool one_solid_each = true;  // each triangle given by one input solid
      std::vector<std::pair<int32_t, int32_t>> by_body;  // (body, occurrence) of each triangle
      for (int32_t side : sides) {
        const Tri t = oriented_out_of(side);
        volume6 += dot(V_[t[0]], cross(V_[t[1]], V_[t[2]]));
        area += std::sqrt(area2(side)) / 2;
        const int32_t u = side / 2, behind = occ_of_side_[size_t(2 * u)], front = occ_of_side_[size_t(2 * u + 1)];
        const int32_t o = behind >= 0 ? behind : front;
        one_solid_each &= (behind >= 0) != (front >= 0) && occ_[size_t(o)].body >= 0;
        if (one_solid_each) by_body.push_back({occ_[size_t(o)].body, o});
      }
      if (!one_solid_each || volume6 <= 0 || volume6 / 6 > 1e-9 * diag * area) continue;
      std::vector<int32_t> bodies;
      for (const auto& [b, o] : by_body) bodies.push_back(b);
      std::sort(bodies.begin(), bodies.end());
      bodies.erase(std::unique(bodies.begin(), bodies.end()), bodies.end());
      if (bodies.size() != 2) continue;
      std::string patch;
      for (const auto& [b, o] : by_body)
        if (b == bodies[1]) drop[size_t(o)] = 1, patch = occ_[size_t(o)].patch;
      for (const auto& [b, o] : by_body)
        if (b == bodies[0]) taken.push_back({reversed(occ_[size_t(o)].v), bodies[1], patch});
    }
    if (taken.empty()) return false;
    std::vector<Occurrence> kept;
    for (size_t k = 0; k < occ_.size(); ++k)
      if (!drop[k]) kept.push_back(std::move(occ_[k]));
    kept.insert(kept.end(), taken.begin(), taken.end());
    occ_ = std::move(kept);
    return true;
  }

  // Each part of space (component of sides) to a region, or -1 (outside every region).
  void assign_parts() {
    const size_t sides = material_.size();
    std::map<int32_t, int32_t> part_of_root;
    part_.resize(sides);
    for (size_t s = 0; s < sides; ++s) {
      const auto [it, added] = part_of_root.try_emplace(parts_.find(int32_t(s)), int32_t(part_body_.size()));
      if (added) part_body_.push_back(-1), part_volume6_.push_back(0), part_probe_.push_back(int32_t(s));
      part_[s] = it->second;
    }
    for (size_t s = 0; s < sides; ++s) {
      const int32_t p = part_[s], m = material_[s];
      const Tri t = oriented_out_of(int32_t(s));
      part_volume6_[size_t(p)] += dot(V_[t[0]], cross(V_[t[1]], V_[t[2]]));
      if (area2(int32_t(s)) > area2(part_probe_[size_t(p)])) part_probe_[size_t(p)] = int32_t(s);
      if (m == -1) continue;
      int32_t& b = part_body_[size_t(p)];
      if (b >= 0 && b != m && m != kUnknownBody)
        fail(ErrorKind::InvalidInput, fmt::format("{} and {} overlap near {}: a part of space is inside both",
                                                  body_names_[size_t(b)], body_names_[size_t(m)], where(V_[tri_[s / 2][0]])));
      if (b < 0 || b == kUnknownBody) b = m;
    }
    // A single file's bodies: each material part of positive volume is a region of its own.
    for (size_t p = 0; p < part_body_.size(); ++p)
      if (part_body_[p] == kUnknownBody && part_volume6_[p] > 0) {
        part_body_[p] = int32_t(body_names_.size());
        body_names_.push_back(body_name_from_patches(int32_t(p)));
      }
    // Parts no input calls inside, and a single file's cavity walls: inside the innermost region
    // whose solid (as known so far) holds a point just off them, or outside.
    std::vector<int32_t> open;
    for (size_t p = 0; p < part_body_.size(); ++p)
      if (part_body_[p] < 0 || part_body_[p] == kUnknownBody) open.push_back(int32_t(p)), part_body_[p] = -1;
    if (open.empty()) return;
    // (Kept: a region that gains no part here is this domain in the end.)
    std::vector<Domain>& solid = provisional_;
    solid.resize(body_names_.size());
    for (size_t b = 0; b < body_names_.size(); ++b) solid[b] = region_domain(int32_t(b));
    std::vector<int32_t> decided(part_body_.size());
    for (int32_t p : open) {
      const int32_t s = part_probe_[size_t(p)];
      const Tri t = oriented_out_of(s);
      const Vec3 n = cross(V_[t[1]] - V_[t[0]], V_[t[2]] - V_[t[0]]);
      const Vec3 c = (1.0 / 3) * (V_[t[0]] + V_[t[1]] + V_[t[2]]);
      const double diag = norm(bounds().size());
      const Vec3 probe = c - (1e-9 * diag / norm(n)) * n;  // into the part
      int32_t host = -1;
      for (size_t b = 0; b < solid.size(); ++b)
        if (solid[b].contains(probe) && (host < 0 || solid[b].volume < solid[size_t(host)].volume)) host = int32_t(b);
      decided[size_t(p)] = host;
    }
    grown_.assign(body_names_.size(), 0);
    for (int32_t p : open) {
      part_body_[size_t(p)] = decided[size_t(p)];
      if (decided[size_t(p)] >= 0) grown_[size_t(decided[size_t(p)])] = 1;
    }
  }

  void group_facets(RegionSet& set) {
    const size_t U = tri_.size();
    side_region_.resize(2 * U);
    for (size_t s = 0; s < 2 * U; ++s) side_region_[s] = part_body_[size_t(part_[s])];
    for (size_t u = 0; u < U; ++u) {
      const int32_t behind = side_region_[2 * u], front = side_region_[2 * u + 1];
      const Tri& t = tri_[u];
      if (behind < 0 && front < 0)
        fail(ErrorKind::InvalidInput, fmt::format("triangle {} {} {} bounds no region (a loose sheet outside every solid)",
                                                  where(V_[t[0]]), where(V_[t[1]]), where(V_[t[2]])));
      if (behind == front)
        fail(ErrorKind::InvalidInput,
             fmt::format("triangle {} {} {} lies inside {} (a sheet with the same region on both sides)",
                         where(V_[t[0]]), where(V_[t[1]]), where(V_[t[2]]), body_names_[size_t(behind)]));
    }
    // Facets: coplanar triangles across an edge, with the same region on each side.
    UnionFind facets(U);
    for (const auto& [edge, tris] : around_)
      for (size_t i = 0; i < tris.size(); ++i)
        for (size_t j = i + 1; j < tris.size(); ++j) {
          const int32_t u = tris[i], w = tris[j];
          // Consistently wound across the edge: w runs it the other way; then its sides match u's.
          const bool consistent = runs(tri_[u], edge.first, edge.second) != runs(tri_[w], edge.first, edge.second);
          const int32_t wb = side_region_[2 * w + (consistent ? 0 : 1)], wf = side_region_[2 * w + (consistent ? 1 : 0)];
          if (wb != side_region_[2 * u] || wf != side_region_[2 * u + 1]) continue;
          const int32_t far = tri_[w][0] + tri_[w][1] + tri_[w][2] - edge.first - edge.second;
          if (CGAL::orientation(to_cgal(V_[tri_[u][0]]), to_cgal(V_[tri_[u][1]]), to_cgal(V_[tri_[u][2]]),
                                to_cgal(V_[far])) == CGAL::COPLANAR)
            facets.unite(u, w);
        }
    std::map<int32_t, int32_t> facet_of_root;
    facet_.resize(U);
    std::vector<Vec3> newell;
    std::vector<std::pair<double, int>> offset;
    for (size_t u = 0; u < U; ++u) {
      const int32_t root = facets.find(int32_t(u));
      const auto [it, added] = facet_of_root.try_emplace(root, int32_t(set.facet_sides.size()));
      if (added) {
        set.facet_sides.push_back({side_region_[2 * size_t(root)], side_region_[2 * size_t(root) + 1]});
        newell.push_back({}), offset.push_back({0, 0});
      }
      facet_[u] = it->second;
      // Wound as the facet's first triangle: flipped where its sides are the other way round.
      const bool flip = side_region_[2 * u] != set.facet_sides[size_t(it->second)][0];
      const Tri t = flip ? reversed(tri_[u]) : tri_[u];
      newell[size_t(it->second)] = newell[size_t(it->second)] + cross(V_[t[1]] - V_[t[0]], V_[t[2]] - V_[t[0]]);
    }
    for (size_t u = 0; u < U; ++u) {
      const int32_t f = facet_[u];
      const Vec3 n = (1 / norm(newell[size_t(f)])) * newell[size_t(f)];
      for (int k = 0; k < 3; ++k) offset[size_t(f)].first += dot(n, V_[tri_[u][k]]), ++offset[size_t(f)].second;
    }
    for (size_t f = 0; f < newell.size(); ++f) {
      const Vec3 n = (1 / norm(newell[f])) * newell[f];
      set.facet_planes.push_back({n, offset[f].first / offset[f].second});
    }
    // Interfaces: region pairs and their areas.
    std::map<std::pair<int32_t, int32_t>, double> area;
    for (size_t u = 0; u < U; ++u) {
      const int32_t a = side_region_[2 * u], b = side_region_[2 * u + 1];
      if (a < 0 || b < 0) continue;
      ++set.interface_triangles;
      area[{std::min(a, b), std::max(a, b)}] += std::sqrt(area2(int32_t(2 * u))) / 2;
    }
    for (const auto& [pair, a] : area) set.interfaces.push_back({pair.first, pair.second, a});
    set.edges = edges_;
  }

  // Faces meant to touch but a rounding error apart (an export in single precision, two solids
  // snapped to different grids) would mesh as two bodies with a sliver of gap between them: two
  // vertices of different regions closer than 1e-6 of the part's size, and not one vertex.
  void refuse_near_misses() const {
    std::vector<std::vector<int32_t>> regions_at(V_.size());
    for (size_t u = 0; u < tri_.size(); ++u)
      for (int32_t region : {side_region_[2 * u], side_region_[2 * u + 1]})
        if (region >= 0)
          for (int32_t v : tri_[u])
            if (std::find(regions_at[v].begin(), regions_at[v].end(), region) == regions_at[v].end())
              regions_at[v].push_back(region);
    const double tol = 1e-6 * norm(bounds().size());
    std::map<std::array<int64_t, 3>, std::vector<int32_t>> cells;
    auto cell_of = [&](Vec3 p) {
      return std::array<int64_t, 3>{int64_t(std::floor(p.x / tol)), int64_t(std::floor(p.y / tol)), int64_t(std::floor(p.z / tol))};
    };
    for (size_t v = 0; v < V_.size(); ++v)
      if (!regions_at[v].empty()) cells[cell_of(V_[v])].push_back(int32_t(v));
    for (size_t v = 0; v < V_.size(); ++v) {
      if (regions_at[v].empty()) continue;
      const auto c = cell_of(V_[v]);
      for (int64_t dz = -1; dz <= 1; ++dz)
        for (int64_t dy = -1; dy <= 1; ++dy)
          for (int64_t dx = -1; dx <= 1; ++dx) {
            const auto it = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
            if (it == cells.end()) continue;
            for (int32_t w : it->second) {
              if (w <= int32_t(v) || norm(V_[w] - V_[v]) >= tol) continue;
              for (int32_t a : regions_at[v])
                for (int32_t b : regions_at[size_t(w)])
                  if (a != b && std::find(regions_at[v].begin(), regions_at[v].end(), b) == regions_at[v].end())
                    fail(ErrorKind::InvalidInput,
                         fmt::format("{} and {} nearly touch: vertices {} and {} are {:.3g} apart (below 1e-6 of the "
                                     "part's size) but not one vertex; faces meant to touch must share their vertices "
                                     "exactly, and solids meant to be apart must be farther apart",
                                     body_names_[size_t(a)], body_names_[size_t(b)], where(V_[v]), where(V_[w]),
                                     norm(V_[w] - V_[v])));
            }
          }
    }
    // The same away from vertices: a vertex of one solid within tol of another's face.
    std::vector<std::array<int32_t, 2>> sides(tri_.size());
    for (size_t u = 0; u < tri_.size(); ++u) sides[u] = {side_region_[2 * u], side_region_[2 * u + 1]};
    if (const auto miss = vertex_near_other_face(V_, tri_, sides, regions_at, tol)) {
      const auto& t = tri_[size_t(miss->triangle)];
      const int32_t a = regions_at[size_t(miss->vertex)][0], b = std::max(sides[size_t(miss->triangle)][0], sides[size_t(miss->triangle)][1]);
      fail(ErrorKind::InvalidInput,
           fmt::format("{} and {} nearly touch: vertex {} of {} is {:.3g} from the triangle {} {} {} of {} (below 1e-6 of "
                       "the part's size) but not on it; faces meant to touch must meet exactly, and solids meant to be "
                       "apart must be farther apart",
                       body_names_[size_t(a)], body_names_[size_t(b)], where(V_[size_t(miss->vertex)]), body_names_[size_t(a)],
                       miss->distance, where(V_[t[0]]), where(V_[t[1]]), where(V_[t[2]]), body_names_[size_t(b)]));
    }
  }

  void make_solids(RegionSet& set) {
    set.names.assign(body_names_.begin(), body_names_.end());
    for (size_t k = 0; k < body_names_.size(); ++k) {
      const bool kept = k < provisional_.size() && !grown_[k];
      Domain d = kept ? std::move(provisional_[k]) : region_domain(int32_t(k));
      // The facets as planes, oriented out of this region.
      d.planes = set.facet_planes;
      for (size_t f = 0; f < d.planes.size(); ++f)
        if (set.facet_sides[f][1] == int32_t(k)) d.planes[f] = {-1.0 * d.planes[f].normal, -d.planes[f].offset};
      d.triangle_plane.clear();  // each triangle's facet, in region_domain's order
      for (size_t side = 0; side < material_.size(); ++side)
        if (part_body_[size_t(part_[side])] == int32_t(k)) d.triangle_plane.push_back(facet_[side / 2]);
      d.convex = false;
      d.reflex_curves.clear();
      set.solids.push_back(std::move(d));
    }
  }

  // The union: the triangles with a region on one side only, oriented out of it.
  Domain make_union(RegionSet& set) {
    TriangleSurface s;
    s.vertices = V_;
    std::vector<int32_t> facet;
    std::map<std::string, int32_t> patch_id;
    for (size_t u = 0; u < tri_.size(); ++u) {
      const int32_t b = side_region_[2 * u], f = side_region_[2 * u + 1];
      if (b >= 0 && f >= 0) continue;
      const int32_t side = int32_t(2 * u + (b >= 0 ? 0 : 1));
      s.triangles.push_back(oriented_out_of(side ^ 1));
      facet.push_back(facet_[u]);
      const int32_t region = b >= 0 ? b : f;
      const int32_t o = occ_of_side_[size_t(side)];
      const std::string patch = o >= 0 && !occ_[size_t(o)].patch.empty() ? occ_[size_t(o)].patch : body_names_[size_t(region)];
      const auto [it, added] = patch_id.try_emplace(patch, int32_t(s.patch_names.size()));
      if (added) s.patch_names.push_back(patch);
      s.triangle_patch.push_back(it->second);
    }
    std::string name;
    for (const std::string& n : body_names_) name += (name.empty() ? "" : " + ") + n;
    Domain u;
    try {
      u = domain_from_surface(s, "the union of " + name, options_);
    } catch (const Error& e) {
      fail(e.kind(), fmt::format("{} (where solids touch, both must have the same triangles there: froth does not yet "
                                 "make differently triangulated faces conform)",
                                 e.what()));
    }
    set.boundary = u;
    set.boundary.planes = set.facet_planes;
    for (size_t f = 0; f < set.facet_sides.size(); ++f)
      if (set.facet_sides[f][1] >= 0 && set.facet_sides[f][0] < 0)
        set.boundary.planes[f] = {-1.0 * set.facet_planes[f].normal, -set.facet_planes[f].offset};
    set.boundary.triangle_plane = facet;
    set.boundary.convex = false;
    u.description = name;
    return u;
  }

  // Region k's surface (the sides its parts hold, wound out of it) as a validated domain.
  Domain region_domain(int32_t k) {
    TriangleSurface s;
    s.vertices = V_;
    for (size_t side = 0; side < material_.size(); ++side)
      if (part_body_[size_t(part_[side])] == k) s.triangles.push_back(oriented_out_of(int32_t(side)));
    DomainOptions o = options_;
    o.repair = false;
    // Each input alone was valid (or a single file's solids are found here): a defect now is
    // where solids meet wrongly.
    try {
      return domain_from_surface(
          s, file_.empty() ? "region " + body_names_[size_t(k)] : fmt::format("{}, region {}", file_, body_names_[size_t(k)]), o);
    } catch (const Error& e) {
      fail(e.kind(), fmt::format("{} (the regions overlap, cross or touch other than along shared triangles)", e.what()));
    }
  }

  // Triangle of side s wound so that its normal points out of the part the side faces.
  Tri oriented_out_of(int32_t s) const { return s % 2 == 0 ? tri_[size_t(s / 2)] : reversed(tri_[size_t(s / 2)]); }
  double area2(int32_t s) const {
    const Tri& t = tri_[size_t(s / 2)];
    return norm2(cross(V_[t[1]] - V_[t[0]], V_[t[2]] - V_[t[0]]));
  }
  Box bounds() const {
    Box b{V_[0], V_[0]};
    for (Vec3 p : V_)
      for (int a = 0; a < 3; ++a) b.lo[a] = std::min(b.lo[a], p[a]), b.hi[a] = std::max(b.hi[a], p[a]);
    return b;
  }
  std::string name_of_body(int32_t b) const { return b >= 0 ? body_names_[size_t(b)] : file_; }
  // A single file's body: named by the patch most of its triangles are on, or by its number.
  std::string body_name_from_patches(int32_t part) const {
    std::map<std::string, size_t> count;
    for (size_t s = 0; s < material_.size(); ++s)
      if (part_[s] == part && occ_of_side_[s] >= 0) ++count[occ_[size_t(occ_of_side_[s])].patch];
    std::string best;
    size_t most = 0;
    for (const auto& [p, n] : count)
      if (n > most) best = p, most = n;
    for (const std::string& used : body_names_)
      if (used == best) best.clear();
    return best.empty() ? fmt::format("region_{}", body_names_.size()) : best;
  }

  static constexpr int32_t kUnknownBody = -2;
  bool closed_slivers_ = false;
  std::vector<Vec3> V_;
  std::vector<Occurrence> occ_;
  std::vector<std::string> body_names_;
  std::string file_;
  DomainOptions options_;
  std::vector<Tri> tri_;
  std::vector<int32_t> first_occ_, material_, occ_of_side_;
  std::vector<std::pair<int32_t, int32_t>> edges_;
  UnionFind parts_{0};
  std::map<std::pair<int32_t, int32_t>, std::vector<int32_t>> around_;  // each edge's triangles
  std::vector<int32_t> part_, part_body_, part_probe_, side_region_, facet_;
  std::vector<double> part_volume6_;
  std::vector<Domain> provisional_;  // the regions' solids before open parts joined them
  std::vector<uint8_t> grown_;       // per region: an open part joined it
};

std::string patch_of(const TriangleSurface& s, size_t t) {
  if (s.triangle_patch.size() != s.triangles.size()) return {};
  const int32_t p = s.triangle_patch[t];
  return p >= 0 && size_t(p) < s.patch_names.size() ? s.patch_names[size_t(p)] : std::string();
}

}  // namespace

bool has_shared_triangles(const TriangleSurface& s) {
  std::vector<Tri> keys(s.triangles);
  for (Tri& t : keys) std::sort(t.begin(), t.end());
  std::sort(keys.begin(), keys.end());
  return std::adjacent_find(keys.begin(), keys.end()) != keys.end();
}

Domain regions_from_shared_triangles(const TriangleSurface& s, const std::string& name, const DomainOptions& options) {
  std::vector<Occurrence> occ;
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    // What the regions' own validation would find later, found before the sides are paired
    // (which needs edges of positive length and finite coordinates).
    const Tri& v = s.triangles[t];
    bool finite = true;
    for (int32_t k : v) finite &= std::isfinite(s.vertices[k].x) && std::isfinite(s.vertices[k].y) && std::isfinite(s.vertices[k].z);
    if (!finite || v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
      fail(ErrorKind::InvalidInput, fmt::format("{}: triangle {} is degenerate or has a non-finite coordinate", name, t));
    occ.push_back({v, -1, patch_of(s, t)});
  }
  Domain d = RegionBuilder(s.vertices, std::move(occ), {}, name, options).build();
  d.description = name;
  return d;
}

Domain domain_from_regions(const std::vector<TriangleSurface>& surfaces, const std::vector<std::string>& names,
                           const DomainOptions& options) {
  // Each solid alone first: its own defects are named with its own triangles, and its shells
  // are oriented by nesting (a cavity's into the cavity).
  std::vector<TriangleSurface> solids;
  for (size_t k = 0; k < surfaces.size(); ++k) {
    solids.push_back(domain_from_surface(surfaces[k], names[k], options).surface);
    solids.back().patch_names = surfaces[k].patch_names;
    solids.back().triangle_patch.clear();
    for (size_t t = 0; t < solids.back().triangles.size(); ++t) {
      const std::string patch = patch_of(surfaces[k], t);
      solids.back().triangle_patch.push_back(patch.empty() ? -1 : surfaces[k].triangle_patch[t]);
    }
  }
  conform_touching_solids(solids);
  std::map<std::array<double, 3>, int32_t> vertex_id;
  std::vector<Vec3> V;
  std::vector<Occurrence> occ;
  for (size_t k = 0; k < solids.size(); ++k) {
    const TriangleSurface& s = solids[k];
    std::vector<int32_t> id(s.vertices.size());
    for (size_t v = 0; v < id.size(); ++v) {
      const Vec3 p = s.vertices[v];
      const auto [it, added] = vertex_id.try_emplace({p.x, p.y, p.z}, int32_t(V.size()));
      if (added) V.push_back(p);
      id[v] = it->second;
    }
    for (size_t t = 0; t < s.triangles.size(); ++t) {
      const Tri& tri = s.triangles[t];
      occ.push_back({{id[tri[0]], id[tri[1]], id[tri[2]]}, int32_t(k), patch_of(s, t)});
    }
  }
  return RegionBuilder(std::move(V), std::move(occ), names, "", options).build();
}

}  // namespace froth
