// Meshes cut open along cracks (input/cracked_domain.hpp, issue 38): the crack's faces on each
// side sum to the sheet's area, no face shared by two cells lies on a sheet, the two sides share
// no vertex away from the front, and the mesh passes the structural checks with its volume.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <map>
#include <set>

#include "common/test_support.hpp"
#include "froth/domain.hpp"
#include "froth/error.hpp"
#include "froth/validate.hpp"
#include "input/cracked_domain.hpp"
#include "input/cracks.hpp"

namespace froth {
namespace {

Domain cracked_box(const std::vector<std::pair<TriangleSurface, std::string>>& given) {
  const Domain box = load_domain("box:0,0,0,1,1,1");
  std::vector<CrackSheet> sheets;
  for (const auto& [sheet, name] : given) sheets.push_back(crack_from_surface(sheet, name, box.surface));
  conform_crack_sheets(sheets, box.surface);
  return cut_along_cracks(box, std::move(sheets));
}
Domain cracked_box(const TriangleSurface& sheet, const std::string& name) { return cracked_box({{sheet, name}}); }

struct CrackFaces {
  double area[2] = {0, 0};
  size_t matched_on_sheet = 0;   // interior faces lying on the sheet
  size_t shared_vertices = 0;    // vertices used by faces of both sides
  size_t shared_off_front = 0;   // of those, vertices off the front (`on_front`)
};

// The faces on the patches crack_NAME_a and _b of a sheet in the plane z = z0, within `inside`
// (a rectangle's (x0, x1, y0, y1), its edges the front; none: the whole plane, no front).
CrackFaces crack_faces(const PolyMesh& m, const std::string& name, double z0,
                       std::array<double, 4> inside = {-1e300, 1e300, -1e300, 1e300}) {
  CrackFaces out;
  int32_t patch[2] = {-1, -1};
  for (size_t p = 0; p < m.patch_names.size(); ++p) {
    if (m.patch_names[p] == "crack_" + name + "_a") patch[0] = int32_t(p);
    if (m.patch_names[p] == "crack_" + name + "_b") patch[1] = int32_t(p);
  }
  EXPECT_GE(patch[0], 0);
  EXPECT_GE(patch[1], 0);
  std::set<int32_t> used[2];
  for (size_t f = 0; f < m.face_count(); ++f) {
    const int32_t p = m.patch_of(f);
    bool on_plane = true;
    for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k)
      on_plane &= std::abs(m.points[m.face_vertices[k]].z - z0) < 1e-9;
    if (!is_border_generator(m.face_generator[f])) {
      const Vec3 c = test::face_centroid(m, int64_t(f));
      out.matched_on_sheet += on_plane && c.x > inside[0] && c.x < inside[1] && c.y > inside[2] && c.y < inside[3];
      continue;
    }
    for (int s = 0; s < 2; ++s) {
      if (p != patch[s]) continue;
      EXPECT_TRUE(on_plane) << "face " << f;
      out.area[s] += face_area(m, f);
      for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k) used[s].insert(m.face_vertices[k]);
    }
  }
  const double tol = 1e-12;
  for (int32_t v : used[0]) {
    if (!used[1].count(v)) continue;
    ++out.shared_vertices;
    const Vec3 p = m.points[v];
    const bool on_front = std::abs(p.x - inside[0]) < tol || std::abs(p.x - inside[1]) < tol ||
                          std::abs(p.y - inside[2]) < tol || std::abs(p.y - inside[3]) < tol;
    out.shared_off_front += !on_front;
  }
  return out;
}

double volume_sum(const PolyMesh& m) {
  double sum = 0;
  for (size_t c = 0; c < m.cell_count(); ++c) sum += cell_volume(m, c);
  return sum;
}

// The cracked box (or solid of `volume`) meshed at r = 1/12 and 1/20 with seeds 1 and 2, each mesh
// checked (closed, matched, its volume the solid's) and handed to `check`.
template <class Check>
void for_each_mesh(const Domain& d, Check&& check, double volume = 1.0) {
  for (double r : {1.0 / 12, 1.0 / 20})
    for (uint64_t seed : {1, 2}) {
      SCOPED_TRACE(testing::Message() << "r " << r << " seed " << seed);
      RunReport run;
      const PolyMesh m = test::mesh_of(d, r, seed, 2, &run);
      const MeshCheck structure = check_mesh(m);
      EXPECT_TRUE(structure.ok()) << structure.first_problem;
      EXPECT_NEAR(volume_sum(m), volume, 1e-9);
      check(m, run);
    }
}

TEST(CrackMesh, ThroughCrackCutsTheBoxInTwo) {
  const Domain d = cracked_box(test::square_sheet(-0.2, 1.3, -0.1, 1.2, 0.5, 5), "through");
  for_each_mesh(d, [](const PolyMesh& m, const RunReport&) {
    const CrackFaces c = crack_faces(m, "through", 0.5);
    EXPECT_NEAR(c.area[0], 1.0, 1e-9);
    EXPECT_NEAR(c.area[1], 1.0, 1e-9);
    EXPECT_EQ(c.matched_on_sheet, 0u);
    EXPECT_EQ(c.shared_vertices, 0u);
    // No cell reaches across the crack.
    for (size_t cell = 0; cell < m.cell_count(); ++cell) {
      double lo = 1, hi = 0;
      for (int64_t f = m.cell_face_begin[cell]; f < m.cell_face_begin[cell + 1]; ++f)
        for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k)
          lo = std::min(lo, m.points[m.face_vertices[k]].z), hi = std::max(hi, m.points[m.face_vertices[k]].z);
      EXPECT_FALSE(lo < 0.5 - 1e-9 && hi > 0.5 + 1e-9) << "cell " << cell;
    }
  });
}

// Two through cracks crossing along a line from face to face (z = 0.5 and x = 0.37): the cut
// surface has four copies of each point of the crossing, one per quarter, and the box falls
// into four pieces that no cell reaches across.
TEST(CrackMesh, CrossingThroughCracksCutTheBoxInFour) {
  TriangleSurface upright = test::square_sheet(-0.13, 1.07, -0.11, 1.09, 0, 4);
  for (Vec3& p : upright.vertices) p = {0.37, p.x, p.y};
  const Domain d = cracked_box({{test::square_sheet(-0.2, 1.3, -0.1, 1.2, 0.5, 5), "flat"}, {upright, "upright"}});
  std::map<std::array<double, 3>, int> copies;
  for (const Vec3& p : d.surface.vertices)
    if (std::abs(p.x - 0.37) < 1e-12 && std::abs(p.z - 0.5) < 1e-12) ++copies[{p.x, p.y, p.z}];
  ASSERT_GE(copies.size(), 3u);
  for (const auto& [p, n] : copies) EXPECT_EQ(n, 4) << "at y = " << p[1];
  for_each_mesh(d, [](const PolyMesh& m, const RunReport& run) {
    ASSERT_EQ(run.cracks.size(), 2u);
    for (const RunReport::Crack& c : run.cracks) {
      EXPECT_NEAR(c.from_a, 1.0, 1e-9) << c.name;
      EXPECT_NEAR(c.from_b, 1.0, 1e-9) << c.name;
    }
    EXPECT_EQ(crack_faces(m, "flat", 0.5).matched_on_sheet, 0u);
    for (size_t cell = 0; cell < m.cell_count(); ++cell) {
      Vec3 lo{1, 1, 1}, hi{0, 0, 0};
      for (int64_t f = m.cell_face_begin[cell]; f < m.cell_face_begin[cell + 1]; ++f)
        for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k)
          for (int a = 0; a < 3; ++a)
            lo[a] = std::min(lo[a], m.points[m.face_vertices[k]][a]), hi[a] = std::max(hi[a], m.points[m.face_vertices[k]][a]);
      EXPECT_FALSE(lo.z < 0.5 - 1e-9 && hi.z > 0.5 + 1e-9) << "cell " << cell;
      EXPECT_FALSE(lo.x < 0.37 - 1e-9 && hi.x > 0.37 + 1e-9) << "cell " << cell;
    }
  });
}

// A closed sheet: an octahedron flattened in z (half-widths 0.3, 0.3, 0.08) around the box's
// centre, its points on |x - 0.5| / 0.3 + |y - 0.5| / 0.3 + |z - 0.5| / 0.08 = 1.
TriangleSurface lens() {
  TriangleSurface s;
  s.vertices = {{0.8, 0.5, 0.5}, {0.2, 0.5, 0.5}, {0.5, 0.8, 0.5}, {0.5, 0.2, 0.5}, {0.5, 0.5, 0.58}, {0.5, 0.5, 0.42}};
  s.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return s;
}

double lens_level(Vec3 p) { return std::abs(p.x - 0.5) / 0.3 + std::abs(p.y - 0.5) / 0.3 + std::abs(p.z - 0.5) / 0.08; }

TEST(CrackMesh, ClosedSheetCutsOutItsInside) {
  const TriangleSurface sheet = lens();
  double area = 0;
  for (const auto& t : sheet.triangles)
    area += 0.5 * norm(cross(sheet.vertices[size_t(t[1])] - sheet.vertices[size_t(t[0])],
                             sheet.vertices[size_t(t[2])] - sheet.vertices[size_t(t[0])]));
  const Domain d = cracked_box(sheet, "lens");
  for (uint64_t seed : {1, 2}) {
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    const PolyMesh m = test::mesh_of(d, 1.0 / 12, seed, 2);
    const MeshCheck check = check_mesh(m);
    EXPECT_TRUE(check.ok()) << check.first_problem;
    EXPECT_NEAR(volume_sum(m), 1.0, 1e-9);
    double side[2] = {0, 0};
    size_t matched_on_lens = 0;
    std::set<int32_t> used[2];
    for (size_t f = 0; f < m.face_count(); ++f) {
      // On the lens: its points and its centroid (a face across the thin lens has its points on
      // it but not its centroid).
      bool on = std::abs(lens_level(test::face_centroid(m, int64_t(f))) - 1) < 1e-9;
      for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k)
        on &= std::abs(lens_level(m.points[m.face_vertices[k]]) - 1) < 1e-9;
      const int32_t p = m.patch_of(f);
      if (!is_border_generator(m.face_generator[f])) matched_on_lens += on;
      for (int s = 0; s < 2; ++s)
        if (p >= 0 && m.patch_names[size_t(p)] == std::string("crack_lens_") + "ab"[s]) {
          EXPECT_TRUE(on) << "face " << f;
          side[s] += face_area(m, f);
          for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k) used[s].insert(m.face_vertices[k]);
        }
    }
    EXPECT_NEAR(side[0], area, 1e-9);
    EXPECT_NEAR(side[1], area, 1e-9);
    EXPECT_EQ(matched_on_lens, 0u);
    for (int32_t v : used[0]) EXPECT_EQ(used[1].count(v), 0u);
  }
}

TEST(CrackMesh, ThreadCountsGiveTheSameMesh) {
  const Domain d = cracked_box(test::square_sheet(-0.2, 1.3, -0.1, 1.2, 0.5, 5), "through");
  const PolyMesh one = test::mesh_of(d, 1.0 / 20, 3, 1), two = test::mesh_of(d, 1.0 / 20, 3, 2);
  ASSERT_EQ(one.cell_count(), two.cell_count());
  EXPECT_TRUE(std::equal(one.points.begin(), one.points.end(), two.points.begin(), two.points.end(),
                         [](Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }));
  EXPECT_TRUE(std::equal(one.face_vertices.begin(), one.face_vertices.end(), two.face_vertices.begin(),
                         two.face_vertices.end()));
  EXPECT_EQ(one.face_patch, two.face_patch);
}

TEST(CrackMesh, PennyOpensInsideItsFront) {
  // A rectangle inside the box: its front all round, inside the solid. Each side's faces sum to
  // its area; the sides share only points on the front; every cell is closed and has a kernel.
  const Domain d = cracked_box(test::square_sheet(0.25, 0.75, 0.3, 0.7, 0.5, 3), "penny");
  for_each_mesh(d, [](const PolyMesh& m, const RunReport& run) {
    const CrackFaces c = crack_faces(m, "penny", 0.5, {0.25, 0.75, 0.3, 0.7});
    EXPECT_NEAR(c.area[0], 0.2, 1e-9);
    EXPECT_NEAR(c.area[1], 0.2, 1e-9);
    EXPECT_EQ(c.matched_on_sheet, 0u);
    EXPECT_GT(c.shared_vertices, 0u);  // the crack closes at its front,
    EXPECT_EQ(c.shared_off_front, 0u);  // and only there
    // No slit cell (its two crack faces meeting inside it would leave it no kernel).
    EXPECT_EQ(run.without_center, 0u);
  });
}

// Two unit cubes side by side (regions box_0 and box_1, sharing the face x = 1), cut along
// `sheet` (input/cracked_regions.cpp).
Domain cracked_regions(const TriangleSurface& sheet, const std::string& name) {
  const Domain two = load_regions({"box:0,0,0,1,1,1", "box:1,0,0,2,1,1"});
  std::vector<CrackSheet> sheets{crack_from_surface(sheet, name, two.surface)};
  conform_crack_sheets(sheets, two.surface);
  return cut_along_cracks(two, std::move(sheets));
}

// A penny in the first of two regions: the regions keep one numbering (every solid has every
// facet, the crack's copies are facets of the first region with nothing in front), and the mesh
// opens inside the front as in one region, each region's cells summing to its cube.
TEST(CrackMesh, PennyInOneOfTwoRegions) {
  const Domain d = cracked_regions(test::square_sheet(0.25, 0.75, 0.3, 0.7, 0.5, 3), "penny");
  ASSERT_TRUE(d.regions && d.cracks);
  const RegionSet& set = *d.regions;
  const size_t facets = set.facet_planes.size();
  EXPECT_EQ(facets, size_t(d.cracks->plane_begin.back()));
  EXPECT_LT(size_t(d.cracks->plane_begin[0]), facets);
  for (size_t f = size_t(d.cracks->plane_begin[0]); f < facets; ++f)
    EXPECT_EQ(set.facet_sides[f], (std::array<int32_t, 2>{0, -1})) << "facet " << f;
  for (size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(set.solids[k].planes.size(), facets);
    EXPECT_EQ(set.solids[k].surface.vertices.size(), set.boundary.surface.vertices.size());
    const bool cut = std::any_of(set.solids[k].triangle_plane.begin(), set.solids[k].triangle_plane.end(),
                                 [&](int32_t p) { return p >= d.cracks->plane_begin[0]; });
    EXPECT_EQ(cut, k == 0) << "region " << k;
  }
  EXPECT_TRUE(std::is_sorted(set.edges.begin(), set.edges.end()));
  for_each_mesh(
      d,
      [](const PolyMesh& m, const RunReport& run) {
        double in[2] = {0, 0};
        for (size_t c = 0; c < m.cell_count(); ++c) in[m.region_of(c)] += cell_volume(m, c);
        EXPECT_NEAR(in[0], 1.0, 1e-9);
        EXPECT_NEAR(in[1], 1.0, 1e-9);
        const CrackFaces c = crack_faces(m, "penny", 0.5, {0.25, 0.75, 0.3, 0.7});
        EXPECT_NEAR(c.area[0], 0.2, 1e-9);
        EXPECT_NEAR(c.area[1], 0.2, 1e-9);
        EXPECT_EQ(c.matched_on_sheet, 0u);
        EXPECT_GT(c.shared_vertices, 0u);
        EXPECT_EQ(c.shared_off_front, 0u);
        EXPECT_EQ(run.without_center, 0u);
      },
      2.0);
}

// A sheet lying on the interface is an input defect (exit 3); one that ends at the interface
// without crossing it is not supported yet (exit 2).
TEST(CrackMesh, SheetOnAnInterfaceIsRefused) {
  TriangleSurface on = test::square_sheet(0.3, 0.7, 0.2, 0.6, 0, 2);
  for (Vec3& p : on.vertices) p = {1, p.x, p.y};
  const std::pair<TriangleSurface, std::pair<ErrorKind, std::string>> cases[] = {
      {on, {ErrorKind::InvalidInput, "lies on the interface between regions box_0 and box_1"}},
      {test::square_sheet(-0.5, 1.0, 0.3, 0.7, 0.5, 3), {ErrorKind::Usage, "ends at the interface between regions box_0 and box_1"}}};
  for (const auto& [sheet, expected] : cases) {
    try {
      cracked_regions(sheet, "sheet");
      ADD_FAILURE() << "cut: " << expected.second;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), expected.first) << e.what();
      EXPECT_NE(std::string(e.what()).find(expected.second), std::string::npos) << e.what();
    }
  }
}

// A sheet in two parts, one in each region, off the interface: both regions are cut (the part in
// the second was left uncut before).
TEST(CrackMesh, SheetInPartsInTwoRegions) {
  TriangleSurface sheet = test::square_sheet(0.2, 0.7, 0.3, 0.7, 0.5, 2);
  const TriangleSurface other = test::square_sheet(1.3, 1.8, 0.3, 0.7, 0.5, 2);
  const int32_t n = int32_t(sheet.vertices.size());
  sheet.vertices.insert(sheet.vertices.end(), other.vertices.begin(), other.vertices.end());
  for (auto t : other.triangles) sheet.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
  const Domain d = cracked_regions(sheet, "two");
  const PolyMesh m = test::mesh_of(d, 1.0 / 12, 1, 2);
  EXPECT_TRUE(check_mesh(m).ok());
  const CrackFaces c = crack_faces(m, "two", 0.5);
  EXPECT_NEAR(c.area[0], 0.4, 1e-9);
  EXPECT_NEAR(c.area[1], 0.4, 1e-9);
}

// A through crack of both regions (z = 0.41, across the interface): each region is cut along
// its part, the sheet's points on the interface have one copy per side, shared by both regions.
TEST(CrackMesh, ThroughCrackAcrossTheInterface) {
  const Domain d = cracked_regions(test::square_sheet(-0.2, 2.3, -0.1, 1.2, 0.41, 5), "across");
  std::map<std::array<double, 3>, int> copies;
  for (const Vec3& p : d.regions->boundary.surface.vertices)
    if (std::abs(p.x - 1) < 1e-12 && std::abs(p.z - 0.41) < 1e-12) ++copies[{p.x, p.y, p.z}];
  ASSERT_GE(copies.size(), 2u);
  for (const auto& [p, n] : copies) EXPECT_EQ(n, 2) << "at y = " << p[1];
  for (uint64_t seed : {1, 2}) {
    RunReport run;
    const PolyMesh m = test::mesh_of(d, 1.0 / 12, seed, 2, &run);
    const MeshCheck structure = check_mesh(m);
    EXPECT_TRUE(structure.ok()) << structure.first_problem;
    const CrackFaces c = crack_faces(m, "across", 0.41);
    EXPECT_NEAR(c.area[0], 2.0, 1e-9);
    EXPECT_NEAR(c.area[1], 2.0, 1e-9);
    EXPECT_EQ(c.matched_on_sheet, 0u);
    EXPECT_EQ(c.shared_vertices, 0u);
  }
}

}  // namespace
}  // namespace froth

