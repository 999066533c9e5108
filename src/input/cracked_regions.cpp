// A multi-region solid cut open along its crack sheets: each region's solid is cut along the
// sheets' pieces in it as a one-region solid is (input/cracked_domain.cpp); a sheet that crosses
// an interface has a piece in each region, which ends on the interface along the same line from
// both sides. The regions are then one RegionSet again, numbered alike: the shared vertices keep
// their ids, a new point gets one id per place and crack sides it bounds (so a line on an
// interface has one copy per side of the sheet, the same in both regions), the facets keep their
// numbers, and each crack copy becomes a facet of its own with its region behind it and nothing
// in front, as a piece of the outer boundary is. Cells are cut to each region by its cut solid
// (assembly/region_cells.hpp), so a cell the sheet crosses falls into a piece on each side.
//
// Not yet (refused, exit 2): a sheet that ends at an interface without crossing it (the crack
// closes there: the line would be a front lying on the interface, split in the other region's
// faces too), one that crosses an interface and another sheet, and a front whose 2r skirt reaches
// an interface (the two regions' skirts would meet it along different lines).
#include <algorithm>
#include <map>
#include <optional>
#include <set>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <fmt/format.h>

#include "common/surface_locator.hpp"
#include "froth/error.hpp"
#include "input/cgal_meshes.hpp"
#include "input/cracked_domain.hpp"
#include "input/cracks.hpp"

namespace froth {
namespace {

using Triangle = InexactKernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<InexactKernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<InexactKernel, Primitive>>;

std::string at(Vec3 p) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", p.x, p.y, p.z); }
Triangle triangle_of(const std::vector<Vec3>& V, const std::array<int32_t, 3>& t) {
  auto p = [&](int q) { return InexactKernel::Point_3(V[size_t(t[q])].x, V[size_t(t[q])].y, V[size_t(t[q])].z); };
  return {p(0), p(1), p(2)};
}
Vec3 centroid(const std::vector<Vec3>& V, const std::array<int32_t, 3>& t) {
  return (1.0 / 3) * (V[size_t(t[0])] + V[size_t(t[1])] + V[size_t(t[2])]);
}

// The interfaces' triangles (once each, from the region behind them), to find a sheet that
// touches one (exact predicates).
class Interfaces {
 public:
  explicit Interfaces(const RegionSet& set) {
    for (size_t k = 0; k < set.size(); ++k) {
      const Domain& d = set.solids[k];
      for (size_t t = 0; t < d.surface.triangles.size(); ++t) {
        const auto& sides = set.facet_sides[size_t(d.triangle_plane[t])];
        if (sides[0] != int32_t(k) || sides[1] < 0) continue;
        triangles_.push_back(triangle_of(d.surface.vertices, d.surface.triangles[t]));
        between_.push_back(sides);
      }
    }
    if (!triangles_.empty()) tree_.emplace(triangles_.begin(), triangles_.end());
  }
  // The interface (its two regions) that triangle t of `s` touches, and a point near where.
  std::optional<std::pair<std::array<int32_t, 2>, Vec3>> touched_by(const std::vector<Vec3>& V,
                                                                    const std::array<int32_t, 3>& t) const {
    if (!tree_) return std::nullopt;
    const auto hit = tree_->any_intersected_primitive(triangle_of(V, t));
    if (!hit) return std::nullopt;
    const Vec3 c = centroid(V, t);
    const auto q = tree_->closest_point({c.x, c.y, c.z});
    return std::pair{between_[size_t(*hit - triangles_.begin())], Vec3{q.x(), q.y(), q.z()}};
  }
  // Whether p lies on an interface (within `tol`).
  bool on(Vec3 p, double tol) const {
    return tree_ && tree_->squared_distance(InexactKernel::Point_3(p.x, p.y, p.z)) <= tol * tol;
  }

 private:
  std::vector<Triangle> triangles_;
  std::vector<std::array<int32_t, 2>> between_;
  std::optional<Tree> tree_;
};

// A sheet's part in one region (the sheet itself where it lies in one).
struct Piece {
  CrackSheet sheet;
  size_t of;       // the sheet's index
  int32_t region;
};

// The pieces of the sheets, region by region. A sheet that lies on an interface is refused
// (InvalidInput); one that reaches an interface without crossing it, or that crosses an
// interface and another sheet, is not supported yet (Usage). A sheet that crosses interfaces is
// clipped to each region it enters, and each of its lines on an interface must be a line of the
// pieces on both sides.
std::vector<Piece> pieces_of_sheets(const RegionSet& set, const Interfaces& interfaces,
                                    const std::vector<CrackSheet>& sheets) {
  std::vector<Piece> pieces;
  const double tol = 1e-12 * set.boundary.bounds.diagonal();
  for (size_t i = 0; i < sheets.size(); ++i) {
    const CrackSheet& c = sheets[i];
    const TriangleSurface& S = c.surface;
    std::optional<std::pair<std::array<int32_t, 2>, Vec3>> touch;
    std::set<int32_t> in;
    for (const auto& t : S.triangles) {
      const Vec3 m = centroid(S.vertices, t);
      if (const auto here = interfaces.touched_by(S.vertices, t)) {
        const bool on = interfaces.on(m, tol) && interfaces.on(S.vertices[size_t(t[0])], tol) &&
                        interfaces.on(S.vertices[size_t(t[1])], tol) && interfaces.on(S.vertices[size_t(t[2])], tol);
        if (on)  // (the input's defect, as a sheet on the boundary)
          fail(ErrorKind::InvalidInput,
               fmt::format("crack {} lies on the interface between regions {} and {} near {}: a crack must cross "
                           "the material, not lie between two regions (a delamination there is the interface itself)",
                           c.name, set.names[size_t(here->first[0])], set.names[size_t(here->first[1])], at(m)));
        touch = here;
      }
      for (const Vec3 p : {m, S.vertices[size_t(t[0])], S.vertices[size_t(t[1])], S.vertices[size_t(t[2])]})
        for (size_t k = 0; k < set.size(); ++k)
          if (set.solids[k].contains(p)) in.insert(int32_t(k));
    }
    if (in.empty()) fail(ErrorKind::Internal, fmt::format("crack {} lies in no region", c.name));
    if (!touch && in.size() == 1) {
      pieces.push_back({c, i, *in.begin()});
      continue;
    }
    // Across an interface, or in separate parts in several regions: a piece per region.
    const std::string between =
        touch ? fmt::format("the interface between regions {} and {} near {}", set.names[size_t(touch->first[0])],
                            set.names[size_t(touch->first[1])], at(touch->second))
              : fmt::format("regions {} and {}", set.names[size_t(*in.begin())], set.names[size_t(*in.rbegin())]);
    if (!c.on_sheets.empty() || c.conformed)
      fail(ErrorKind::Usage, fmt::format("crack {} crosses another crack and lies in {}: a crack in several regions "
                                         "that crosses another is not supported yet",
                                         c.name, between));
    const std::string ends = fmt::format("crack {} ends at {}: a crack that reaches an interface without crossing "
                                         "it is not supported yet (extend it across, or keep it inside one region)",
                                         c.name, between);
    // The regions it enters: a large triangle of it can cross a thin region with no point in it,
    // so every region near it is clipped to, and those it misses are left out.
    Box near{S.vertices[0], S.vertices[0]};
    for (Vec3 p : S.vertices)
      for (int a = 0; a < 3; ++a) near.lo[a] = std::min(near.lo[a], p[a]), near.hi[a] = std::max(near.hi[a], p[a]);
    for (size_t k = 0; k < set.size(); ++k) {
      const Box& b = set.solids[k].bounds;
      bool apart = false;
      for (int a = 0; a < 3; ++a) apart |= b.hi[a] < near.lo[a] || near.hi[a] < b.lo[a];
      if (!apart) in.insert(int32_t(k));
    }
    // Each line on an interface, by its rounded ends, in how many pieces.
    std::map<std::array<double, 6>, int> lines;
    for (int32_t k : in) {
      Piece p{c, i, k};
      if (!clip_crack_again(p.sheet, ExactSurface{to_cgal_mesh<ExactMesh>(set.solids[size_t(k)].surface)},
                            set.solids[size_t(k)].surface, true))
        continue;
      const auto& V = p.sheet.surface.vertices;
      for (const auto& e : p.sheet.on_boundary) {
        const Vec3 a = V[size_t(e[0])], b = V[size_t(e[1])];
        if (!interfaces.on(a, tol) || !interfaces.on(b, tol) || !interfaces.on(0.5 * (a + b), tol)) continue;
        std::array<double, 6> key{a.x, a.y, a.z, b.x, b.y, b.z};
        if (std::tie(b.x, b.y, b.z) < std::tie(a.x, a.y, a.z)) key = {b.x, b.y, b.z, a.x, a.y, a.z};
        ++lines[key];
      }
      pieces.push_back(std::move(p));
    }
    if (std::count_if(pieces.begin(), pieces.end(), [&](const Piece& p) { return p.of == i; }) < 2)
      fail(ErrorKind::Usage, ends);
    for (const auto& [line, count] : lines)
      if (count != 2) fail(ErrorKind::Usage, ends);
  }
  return pieces;
}

// Plane f of a region's solid, oriented out of it (as RegionSet::solids hold them).
std::vector<Plane> planes_out_of(const RegionSet& set, int32_t k) {
  std::vector<Plane> planes = set.facet_planes;
  for (size_t f = 0; f < planes.size(); ++f)
    if (set.facet_sides[f][1] == k) planes[f] = {-1.0 * planes[f].normal, -planes[f].offset};
  return planes;
}

}  // namespace

Domain cut_regions_along_cracks(const Domain& whole, std::vector<CrackSheet> sheets, double r) {
  const RegionSet& R = *whole.regions;
  const Interfaces interfaces(R);
  std::vector<Piece> pieces = pieces_of_sheets(R, interfaces, sheets);
  const std::vector<Vec3>& V0 = R.boundary.surface.vertices;
  const size_t n0 = V0.size();
  const int32_t facets = int32_t(R.facet_planes.size());
  for (const Domain& d : R.solids)
    if (d.surface.vertices.size() != n0) fail(ErrorKind::Internal, "regions that do not share their vertices");

  // Each region with pieces cut as a solid of its own: its facets are the region set's, its new
  // vertices and crack planes numbered after them.
  struct Cut {
    Domain d;
    std::vector<size_t> pieces;  // indices in `pieces`, in the cut's order
  };
  std::vector<std::optional<Cut>> cuts(R.size());
  std::vector<std::array<int32_t, 2>> where(pieces.size());  // (region, index in its cut)
  for (size_t k = 0; k < R.size(); ++k) {
    Cut c;
    std::vector<CrackSheet> mine;
    for (size_t q = 0; q < pieces.size(); ++q)
      if (pieces[q].region == int32_t(k))
        where[q] = {int32_t(k), int32_t(c.pieces.size())}, c.pieces.push_back(q), mine.push_back(pieces[q].sheet);
    if (mine.empty()) continue;
    c.d = cut_along_cracks(R.solids[k], std::move(mine), r);
    cuts[k] = std::move(c);
  }
  auto local_of = [&](size_t q) -> const CrackSet& { return *cuts[size_t(where[q][0])]->d.cracks; };

  // Crack planes sheet by sheet in the input's order: its pieces' copies facing side a, then
  // those facing side b, each piece's in its cut's order.
  auto set = std::make_shared<CrackSet>();
  auto out = std::make_shared<RegionSet>(R);
  std::vector<int32_t> a_first(pieces.size()), b_first(pieces.size());
  set->plane_begin = {facets};
  for (size_t i = 0; i < sheets.size(); ++i) {
    const int32_t base = set->plane_begin.back();
    int32_t n = 0;
    for (size_t q = 0; q < pieces.size(); ++q)
      if (pieces[q].of == i) {
        const CrackSet& local = local_of(q);
        const size_t j = size_t(where[q][1]);
        a_first[q] = base + n;
        n += local.plane_middle[j] - local.plane_begin[j];
      }
    for (size_t q = 0; q < pieces.size(); ++q)
      if (pieces[q].of == i) b_first[q] = a_first[q] + n;
    set->plane_middle.push_back(base + n);
    set->plane_begin.push_back(base + 2 * n);
  }
  out->facet_planes.resize(size_t(set->plane_begin.back()));
  out->facet_sides.resize(size_t(set->plane_begin.back()));
  std::vector<std::vector<int32_t>> plane_of(R.size());
  for (size_t k = 0; k < R.size(); ++k) {
    if (!cuts[k]) continue;
    const Domain& d = cuts[k]->d;
    const CrackSet& local = *d.cracks;
    plane_of[k].resize(d.planes.size());
    for (int32_t p = 0; p < facets; ++p) plane_of[k][size_t(p)] = p;
    for (size_t j = 0; j < cuts[k]->pieces.size(); ++j) {
      const size_t q = cuts[k]->pieces[j];
      for (int32_t p = local.plane_begin[j]; p < local.plane_begin[j + 1]; ++p) {
        const int32_t g = p < local.plane_middle[j] ? a_first[q] + (p - local.plane_begin[j])
                                                    : b_first[q] + (p - local.plane_middle[j]);
        plane_of[k][size_t(p)] = g;
        out->facet_planes[size_t(g)] = d.planes[size_t(p)];  // (out of region k: k behind, nothing in front)
        out->facet_sides[size_t(g)] = {int32_t(k), -1};
      }
    }
    for (const auto& [a, b] : local.extension_planes)
      set->extension_planes.push_back({plane_of[k][size_t(a)], plane_of[k][size_t(b)]});
  }
  std::sort(set->extension_planes.begin(), set->extension_planes.end());
  auto sheet_of_plane = [&](int32_t g) {
    return size_t(std::upper_bound(set->plane_begin.begin(), set->plane_begin.end(), g) - set->plane_begin.begin()) - 1;
  };
  std::vector<uint8_t> is_extension(size_t(set->plane_begin.back()), 0);
  for (const auto& [a, b] : set->extension_planes) is_extension[size_t(a)] = is_extension[size_t(b)] = 1;

  // Vertices: the shared ones keep their ids; the cuts' new ones follow, one id per point and
  // crack sides it bounds (a point of a sheet's line on an interface is cut in both regions, its
  // copy on each side of the sheet the same in both).
  std::vector<Vec3> V = V0;
  std::vector<std::vector<int32_t>> vertex_of(R.size());
  std::map<std::pair<std::array<double, 3>, std::vector<int32_t>>, int32_t> new_id;
  for (size_t k = 0; k < R.size(); ++k) {
    if (!cuts[k]) continue;
    const Domain& d = cuts[k]->d;
    std::vector<std::vector<int32_t>> sides(d.surface.vertices.size());  // 2 sheet + side
    for (size_t t = 0; t < d.surface.triangles.size(); ++t)
      if (const int32_t p = d.triangle_plane[t]; p >= facets) {
        const int32_t g = plane_of[k][size_t(p)];
        const size_t i = sheet_of_plane(g);
        for (int32_t v : d.surface.triangles[t]) sides[size_t(v)].push_back(int32_t(2 * i) + (g >= set->plane_middle[i]));
      }
    vertex_of[k].resize(d.surface.vertices.size());
    for (size_t v = 0; v < vertex_of[k].size(); ++v) {
      if (v < n0) {
        vertex_of[k][v] = int32_t(v);
        continue;
      }
      std::sort(sides[v].begin(), sides[v].end());
      sides[v].erase(std::unique(sides[v].begin(), sides[v].end()), sides[v].end());
      const Vec3 x = d.surface.vertices[v];
      const auto [it, added] = new_id.try_emplace({{x.x, x.y, x.z}, std::move(sides[v])}, int32_t(V.size()));
      if (added) V.push_back(x);
      vertex_of[k][v] = it->second;
    }
  }

  // The boundary's patches: the union's, then each crack's sides (and its skirt's, glued: on no face).
  Domain boundary = R.boundary;
  TriangleSurface& B = boundary.surface;
  if (B.triangle_patch.size() != B.triangles.size()) B.patch_names = {"surface"}, B.triangle_patch.assign(B.triangles.size(), 0);
  std::vector<std::array<int32_t, 3>> crack_patch(sheets.size());
  for (size_t i = 0; i < sheets.size(); ++i) {
    const int32_t a = int32_t(B.patch_names.size());
    B.patch_names.push_back(fmt::format("crack_{}_a", sheets[i].name));
    B.patch_names.push_back(fmt::format("crack_{}_b", sheets[i].name));
    crack_patch[i] = {a, a + 1, -1};
    set->patches.push_back({a, a + 1});
    const bool skirted = std::any_of(set->extension_planes.begin(), set->extension_planes.end(), [&](const auto& e) {
      return e[0] >= set->plane_begin[i] && e[0] < set->plane_begin[i + 1];
    });
    if (skirted) crack_patch[i][2] = int32_t(B.patch_names.size()), B.patch_names.push_back(fmt::format("crack_{}_extension", sheets[i].name));
  }

  // The boundary: the uncut regions' triangles as they were, then each cut region's that are not
  // on an interface, crack copies included.
  TriangleSurface kept;
  kept.vertices = V;
  std::vector<int32_t> kept_plane, kept_patch;
  for (size_t t = 0; t < B.triangles.size(); ++t) {
    const auto& sides = R.facet_sides[size_t(boundary.triangle_plane[t])];
    if (cuts[size_t(std::max(sides[0], sides[1]))]) continue;
    kept.triangles.push_back(B.triangles[t]);
    kept_plane.push_back(boundary.triangle_plane[t]);
    kept_patch.push_back(B.triangle_patch[t]);
  }
  for (size_t k = 0; k < R.size(); ++k) {
    if (!cuts[k]) continue;
    Domain& d = cuts[k]->d;
    TriangleSurface outer;  // the region's triangles on the union's boundary, for their patches
    outer.vertices = d.surface.vertices;
    std::vector<size_t> outer_of;
    for (size_t t = 0; t < d.surface.triangles.size(); ++t) {
      auto& tri = d.surface.triangles[t];
      int32_t& plane = d.triangle_plane[t];
      const bool crack = plane >= facets;
      if (!crack && R.is_interface(plane)) {
        for (int32_t& v : tri) v = vertex_of[k][size_t(v)];
        continue;
      }
      if (!crack) outer.triangles.push_back(tri), outer_of.push_back(kept.triangles.size());
      for (int32_t& v : tri) v = vertex_of[k][size_t(v)];
      plane = plane_of[k][size_t(plane)];
      kept.triangles.push_back(tri);
      kept_plane.push_back(plane);
      if (crack) {
        const size_t i = sheet_of_plane(plane);
        const int side = plane < set->plane_middle[i] ? 0 : 1;
        if (const auto touch = is_extension[size_t(plane)] ? interfaces.touched_by(V, tri) : std::nullopt)
          fail(ErrorKind::Usage,
               fmt::format("crack {}: its front comes within 2r = {:.6g} of the interface between regions {} and {} "
                           "near {}; the cells at a front are split by the sheet extended 2r beyond it, and that "
                           "extension must stay off interfaces (use a smaller r, or move the crack's front away "
                           "from the interface)",
                           sheets[i].name, 2 * r, R.names[size_t(touch->first[0])], R.names[size_t(touch->first[1])],
                           at(touch->second)));
        kept_patch.push_back(is_extension[size_t(plane)] ? crack_patch[i][2] : crack_patch[i][size_t(side)]);
      } else {
        kept_patch.push_back(0);  // (set below from the triangle of the uncut boundary it lies in)
      }
    }
    if (!outer.triangles.empty()) {
      const std::vector<int32_t> parent = parent_triangles(B, outer);
      for (size_t t = 0; t < parent.size(); ++t) kept_patch[outer_of[t]] = B.triangle_patch[size_t(parent[t])];
    }
    // The cut region as RegionSet's solids hold it: the shared numbering, planes out of it.
    d.surface.vertices = V;
    d.planes = planes_out_of(*out, int32_t(k));
    d.locator = std::make_shared<SurfaceLocator>(d.surface, true);
    d.cracks = set;
    out->solids[k] = std::move(d);
  }
  for (size_t k = 0; k < R.size(); ++k)
    if (!cuts[k]) out->solids[k].planes = planes_out_of(*out, int32_t(k)), out->solids[k].surface.vertices = V;
  B.vertices = std::move(kept.vertices);
  B.triangles = std::move(kept.triangles);
  B.triangle_patch = std::move(kept_patch);
  boundary.triangle_plane = std::move(kept_plane);
  boundary.planes = out->facet_planes;  // (oriented out of the union, as make_union orients them)
  for (size_t f = 0; f < size_t(facets); ++f)
    if (R.facet_sides[f][1] >= 0 && R.facet_sides[f][0] < 0)
      boundary.planes[f] = {-1.0 * R.facet_planes[f].normal, -R.facet_planes[f].offset};
  boundary.locator = std::make_shared<SurfaceLocator>(B, true);
  boundary.convex = false;

  // Every region's edges, numbered alike (SurfaceGenerators).
  out->edges.clear();
  for (const Domain& d : out->solids)
    for (const auto& t : d.surface.triangles)
      for (int q = 0; q < 3; ++q) out->edges.push_back(std::minmax(t[size_t(q)], t[size_t((q + 1) % 3)]));
  std::sort(out->edges.begin(), out->edges.end());
  out->edges.erase(std::unique(out->edges.begin(), out->edges.end()), out->edges.end());
  out->boundary = boundary;

  set->fronts = std::any_of(sheets.begin(), sheets.end(), [](const CrackSheet& c) { return !c.front.empty(); });
  set->skirt_r = set->fronts ? r : 0;
  for (Piece& p : pieces) set->pieces.push_back(std::move(p.sheet));
  set->sheets = std::move(sheets);
  set->solid = whole;
  Domain d = whole;
  d.surface = boundary.surface;
  d.triangle_plane = boundary.triangle_plane;
  d.planes = boundary.planes;
  d.locator = boundary.locator;
  d.convex = false;
  d.regions = std::move(out);
  d.cracks = std::move(set);
  return d;
}

}  // namespace froth
