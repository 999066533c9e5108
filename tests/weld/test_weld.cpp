// Welding: the mesh stays valid and conforming, the total volume moves by no more than the
// stated bound, no edge shorter than w is left unless a merge was refused, and the result is
// one global decision (the same for any thread count).
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>

#include "common/test_support.hpp"
#include "froth/validate.hpp"
#include "froth/quality.hpp"
#include "froth/weld.hpp"

namespace froth {
namespace {

PolyMesh unwelded(const std::string& domain, double r, uint64_t seed) {
  Domain d = load_domain(domain == "sphere" ? test::model("unit_sphere.STL") : domain);
  MeshOptions opt;
  opt.r = r;
  opt.seed = seed;
  opt.weld = 0, opt.quality = false;  // unwelded: the tests weld it
  return generate_mesh(d, opt, nullptr);
}

double total_volume(const PolyMesh& m) {
  double v = 0;
  for (size_t c = 0; c < m.cell_count(); ++c) v += cell_volume(m, c);
  return v;
}

class Weld : public testing::TestWithParam<std::tuple<std::string, double>> {};

TEST_P(Weld, KeepsTheMeshValidAndTheVolumeWithinTheBound) {
  const auto& [domain, w_over_r] = GetParam();
  const double r = 0.1;
  for (uint64_t seed : {1u, 2u}) {
    PolyMesh m = unwelded(domain, r, seed);
    const double before = total_volume(m);
    const size_t points = m.points.size(), cells = m.cell_count();
    const WeldStats st = weld_mesh(m, w_over_r * r, r);
    EXPECT_GT(st.edges_collapsed, 0u);
    EXPECT_EQ(m.points.size(), points - st.edges_collapsed);
    EXPECT_EQ(m.cell_count(), cells);
    const MeshCheck check = check_mesh(m);
    EXPECT_TRUE(check.ok()) << check.first_problem;
    EXPECT_LE(std::abs(total_volume(m) - before), st.volume_change_bound() + 1e-12);
    if (st.clusters_refused == 0) EXPECT_GE(st.shortest_edge_after, w_over_r * r);
    EXPECT_LE(st.max_displacement, 8 * w_over_r * r);  // clusters are chains of short edges
    for (size_t c = 0; c < m.cell_count(); ++c) EXPECT_GT(cell_volume(m, c), 0);
  }
}

INSTANTIATE_TEST_SUITE_P(BoxAndSphere, Weld,
                         testing::Values(std::make_tuple("box:0,0,0,1,1,1", 0.02), std::make_tuple("sphere", 0.02),
                                         std::make_tuple("sphere", 0.1)),
                         [](const auto& i) {
                           return (std::get<0>(i.param) == "sphere" ? std::string("sphere") : std::string("box")) +
                                  "_w" + std::to_string(int(std::get<1>(i.param) * 100));
                         });

TEST(Weld, BelowTheShortestEdgeChangesNothing) {
  PolyMesh m = unwelded("box:0,0,0,1,1,1", 0.1, 3);
  const PolyMesh copy = m;
  const WeldStats probe = weld_mesh(m, 0, 0.1);  // w = 0: only measures
  EXPECT_EQ(probe.edges_collapsed, 0u);
  const WeldStats st = weld_mesh(m, probe.shortest_edge_before * 0.999, 0.1);
  EXPECT_EQ(st.edges_collapsed, 0u);
  EXPECT_EQ(m.points, copy.points);
  EXPECT_EQ(m.face_vertices, copy.face_vertices);
}

TEST(Weld, SameResultForAnyThreadCount) {
  // Over 16384 faces, so the border area is summed over several chunks; and welding heavily
  // enough (w = r / 10) that faces vanish and the face arrays are compacted in place.
  const double r = 0.05;
  PolyMesh a = unwelded("sphere", r, 4), b = a;
  ASSERT_GT(a.face_count(), 4u * 16384);
  omp_set_num_threads(1);
  const WeldStats sa = weld_mesh(a, r / 10, r);
  omp_set_num_threads(2);
  const WeldStats sb = weld_mesh(b, r / 10, r);
  EXPECT_GT(sa.faces_removed, 0u);
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.face_vertices, b.face_vertices);
  EXPECT_EQ(a.face_vertex_begin, b.face_vertex_begin);
  EXPECT_EQ(a.face_generator, b.face_generator);
  EXPECT_EQ(a.cell_face_begin, b.cell_face_begin);
  EXPECT_EQ(sa.border_area, sb.border_area);  // bit for bit: the report is a pure function too
  EXPECT_EQ(sa.edges_collapsed, sb.edges_collapsed);
  EXPECT_EQ(sa.max_displacement, sb.max_displacement);
  EXPECT_EQ(sa.shortest_edge_after, sb.shortest_edge_after);
  const MeshCheck check = check_mesh(a);
  EXPECT_TRUE(check.ok()) << check.first_problem;
}

// Border vertices keep their planes: welding a box keeps every border vertex on the box.
TEST(Weld, BorderVerticesStayOnTheDomain) {
  PolyMesh m = unwelded("box:0,0,0,1,1,1", 0.1, 5);
  weld_mesh(m, 0.003, 0.1);
  for (size_t f = 0; f < m.face_count(); ++f) {
    if (!is_border_generator(m.face_generator[f])) continue;
    for (int64_t k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k) {
      const Vec3 p = m.points[m.face_vertices[k]];
      const double d = std::min({p.x, p.y, p.z, 1 - p.x, 1 - p.y, 1 - p.z});
      EXPECT_LT(std::abs(d), 1e-12);
    }
  }
}

// A multi-region solid's interface binds its vertices as the border does: welding the five
// heater solids heavily (w = r / 20) keeps each region's volume and each interface's area, seen
// from either side, to round-off (a vertex off its facet would change both), and the mesh valid.
TEST(Weld, InterfaceVerticesStayOnTheirFacets) {
  std::vector<std::string> files;
  for (const char* name : {"bottomAir", "heater", "leftSolid", "rightSolid", "topAir"})
    files.push_back(test::model(std::string("multi_region_heater/") + name + ".stl"));
  const Domain d = load_regions(files);
  ASSERT_TRUE(d.regions);
  MeshOptions opt;
  opt.r = 0.012;
  opt.weld = 0.05 * opt.r;
  RunReport run;
  const PolyMesh m = generate_mesh(d, opt, &run);
  ASSERT_TRUE(run.welding);
  EXPECT_GT(run.welding->edges_collapsed, 500u);
  EXPECT_TRUE(check_mesh(m).ok());
  ASSERT_EQ(run.regions.size(), 5u);
  for (const RunReport::Region& r : run.regions) EXPECT_NEAR(r.volume, r.enclosed, 1e-12 * r.enclosed) << r.name;
  ASSERT_FALSE(run.interfaces.empty());
  for (const RunReport::Interface& i : run.interfaces) {
    EXPECT_NEAR(i.from_a, i.area, 1e-12 * i.area) << i.a << " | " << i.b;
    EXPECT_NEAR(i.from_b, i.area, 1e-12 * i.area) << i.a << " | " << i.b;
  }
}

}  // namespace
}  // namespace froth

namespace froth {
namespace {

// The bound counts before welding come from the welded mesh's counts with the welded cells'
// verdicts swapped back: they must equal a full count on the unwelded mesh, and per-cell
// verdicts must add up to the report's counts.
TEST(Weld, BoundsBeforeWeldingMatchTheUnweldedMesh) {
  Domain d = load_domain(test::model("unit_sphere.STL"));
  MeshOptions opt;
  opt.r = 0.1;
  opt.seed = 8;
  opt.weld = 0;
  RunReport plain, welded;
  generate_mesh(d, opt, &plain);
  opt.weld = 0.2 * opt.r;  // large: welding visibly distorts cells
  PolyMesh m = generate_mesh(d, opt, &welded);
  ASSERT_TRUE(welded.bounds_before_weld && welded.quality && plain.quality);
  EXPECT_EQ(welded.bounds_before_weld->theorem1_violations, plain.quality->theorem1_violations);
  EXPECT_EQ(welded.bounds_before_weld->lemma6_interior_violations, plain.quality->lemma6_interior_violations);
  EXPECT_EQ(welded.bounds_before_weld->lemma6_border_violations, plain.quality->lemma6_border_violations);
  uint64_t t1 = 0, l6i = 0, l6b = 0;
  for (size_t c = 0; c < m.cell_count(); ++c) {
    const CellVerdict v = cell_verdict(m, c);
    t1 += v.theorem1, l6i += v.lemma6_interior, l6b += v.lemma6_border;
    EXPECT_EQ(v.q.aspect, m.quality[c].aspect);
  }
  EXPECT_EQ(t1, welded.quality->theorem1_violations);
  EXPECT_EQ(l6i, welded.quality->lemma6_interior_violations);
  EXPECT_EQ(l6b, welded.quality->lemma6_border_violations);
  EXPECT_GT(welded.weld_aspect_shift, 0);
  std::printf("after welding at 0.2 r: %llu, %llu, %llu cells beyond the bounds\n", (unsigned long long)t1,
              (unsigned long long)l6i, (unsigned long long)l6b);
}

}  // namespace
}  // namespace froth
