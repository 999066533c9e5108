// Quality metrics on shapes with known answers, against exact oracles on random convex cells
// (CGAL's exact linear-program solver for the inradius, Min_sphere_d in exact arithmetic for the
// outradius), and the paper's bounds on whole meshes.
#include <gtest/gtest.h>

#include <numeric>

#include <CGAL/Cartesian_d.h>
#include <CGAL/Gmpq.h>
#include <CGAL/Gmpzf.h>
#include <CGAL/Min_sphere_annulus_d_traits_d.h>
#include <CGAL/Min_sphere_d.h>
#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>
#include <CGAL/Simple_cartesian.h>

#include <cmath>
#include <random>

#include "common/test_support.hpp"
#include "froth/quality.hpp"
#include "quality/inscribed_ball.hpp"
#include "voronoi/convex_cell.hpp"

namespace froth {
namespace {

constexpr double kEps = 1e-12;

// A one-cell mesh (seed at the origin) from a convex cell; faces of generators in `border` are
// border faces.
PolyMesh mesh_of(const ConvexCell& cell, const std::vector<int32_t>& border = {}) {
  PolyMesh m;
  for (size_t v = 0; v < cell.vertex_count(); ++v) m.points.push_back(cell.vertex(v));
  m.seeds = {{0, 0, 0}};
  m.kinds = {CellKind::Interior};
  for (size_t f = 0; f < cell.face_count(); ++f) {
    const int32_t g = cell.face_generator(f);
    m.face_generator.push_back(std::find(border.begin(), border.end(), g) != border.end() ? plane_generator(0) : 1);
    for (size_t k = 0; k < cell.face_size(f); ++k) m.face_vertices.push_back(cell.face_begin(f)[k]);
    m.face_vertex_begin.push_back(int64_t(m.face_vertices.size()));
  }
  m.cell_face_begin.push_back(int64_t(m.face_generator.size()));
  return m;
}

TEST(Quality, CubeHasAspectSqrt3AndRightAngles) {
  ConvexCell c;
  c.reset_cube(1);
  const CellQuality q = cell_quality(mesh_of(c), 0);
  EXPECT_NEAR(q.outradius, std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(q.inradius, 1, 1e-12);
  EXPECT_NEAR(q.aspect, std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(q.min_dihedral, 90, 1e-9);
  EXPECT_NEAR(q.max_dihedral, 90, 1e-9);
  EXPECT_NEAR(q.min_edge, 2, 1e-12);
  EXPECT_EQ(q.faces, 6u);
  EXPECT_EQ(q.vertices, 8u);
}

TEST(Quality, RegularTetrahedronHasAspectThree) {
  ConvexCell c;
  c.reset_cube(4);
  // Faces at distance 1 with normals toward alternate cube corners: a regular tetrahedron of
  // inradius 1, circumradius 3, dihedral angle acos(1/3).
  const double s = 1 / std::sqrt(3.0);
  for (Vec3 n : {Vec3{s, s, s}, Vec3{s, -s, -s}, Vec3{-s, s, -s}, Vec3{-s, -s, s}})
    ASSERT_EQ(c.clip(n, 1, 1, kEps), ConvexCell::Clip::Cut);
  const CellQuality q = cell_quality(mesh_of(c), 0);
  EXPECT_NEAR(q.inradius, 1, 1e-12);
  EXPECT_NEAR(q.outradius, 3, 1e-12);
  EXPECT_NEAR(q.aspect, 3, 1e-12);
  EXPECT_NEAR(q.min_dihedral, std::acos(1 / 3.0) * 180 / M_PI, 1e-9);
  EXPECT_NEAR(q.min_edge, std::sqrt(24.0), 1e-12);
}

TEST(Quality, TruncatedOctahedron) {
  // The cell of the body-centred cubic lattice: vertices are the permutations of (0, ±1, ±2);
  // squares at distance 2, hexagons at distance sqrt(3); outradius sqrt(5).
  ConvexCell c;
  c.reset_cube(3);
  const double s = 1 / std::sqrt(3.0);
  for (int k = 0; k < 8; ++k)
    c.clip({(k & 1) ? s : -s, (k & 2) ? s : -s, (k & 4) ? s : -s}, std::sqrt(3.0), 1, kEps);
  for (int a = 0; a < 3; ++a)
    for (double sign : {-1.0, 1.0}) {
      Vec3 n{};
      (a == 0 ? n.x : a == 1 ? n.y : n.z) = sign;
      c.clip(n, 2, 1, kEps);
    }
  const CellQuality q = cell_quality(mesh_of(c), 0);
  EXPECT_EQ(q.faces, 14u);
  EXPECT_EQ(q.vertices, 24u);
  EXPECT_NEAR(q.outradius, std::sqrt(5.0), 1e-12);
  EXPECT_NEAR(q.inradius, std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(q.min_edge, std::sqrt(2.0), 1e-12);
  // Hexagon-hexagon edges: acos(-1/3) = 109.47°; square-hexagon: 125.26°.
  EXPECT_NEAR(q.min_dihedral, std::acos(-1 / 3.0) * 180 / M_PI, 1e-9);
  EXPECT_NEAR(q.max_dihedral, std::acos(-1 / std::sqrt(3.0)) * 180 / M_PI, 1e-9);
}

TEST(Quality, ThinSlab) {
  ConvexCell c;
  c.reset_cube(5);
  c.clip({0, 0, 1}, 0.05, 1, kEps);
  c.clip({0, 0, -1}, 0.05, 1, kEps);
  const CellQuality q = cell_quality(mesh_of(c), 0);
  EXPECT_NEAR(q.inradius, 0.05, 1e-12);
  EXPECT_NEAR(q.outradius, std::sqrt(25 + 25 + 0.0025), 1e-12);
  EXPECT_NEAR(q.aspect, std::sqrt(50.0025) / 0.05, 1e-9);
  EXPECT_NEAR(q.min_edge, 0.1, 1e-12);
}

// The kernel of a non-convex cell need not hold its seed (the origin): a ball in the cube
// [1, 3]^3, and none in two half-spaces that do not meet (a negative radius).
TEST(Quality, InscribedBallAwayFromTheOrigin) {
  const std::vector<Vec3> axes = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  InscribedBall ball = largest_inscribed_ball(axes, {3, -1, 3, -1, 3, -1});
  ASSERT_TRUE(ball.ok);
  EXPECT_NEAR(ball.radius, 1, 1e-12);
  EXPECT_NEAR(norm(ball.center - Vec3{2, 2, 2}), 0, 1e-12);
  // x <= -1 and x >= 1, inside |y|, |z| <= 5: the best t is -1, at x = 0.
  ball = largest_inscribed_ball(axes, {-1, -1, 5, 5, 5, 5});
  ASSERT_TRUE(ball.ok);
  EXPECT_NEAR(ball.radius, -1, 1e-12);
  EXPECT_NEAR(ball.center.x, 0, 1e-12);
}

// A welded edge cell's 20 face planes (LCD-knob.stl, --cells 1415 --seed 74376258 --grade), two
// pairs of them 1e-15 apart: the simplex took a pivot of 2e-12 and answered a centre 0.156
// outside a plane, with a positive radius, where the kernel is empty. The answer must be the exact
// solver's, inside every plane by its radius.
TEST(Quality, InscribedBallOfNearlyParallelPlanes) {
  const std::vector<std::pair<Vec3, double>> planes = {
      {{0.2165872821739126, -0.97626325814327242, -3.1764570702699612e-16}, 0.018984842409771857},
      {{0.11866377169717822, 0.99293449395546729, -1.8234245529221178e-16}, 0.19308065586312562},
      {{-0.47004000684148611, -0.33523477612826119, 0.81650476841393294}, 0.25490292618602473},
      {{-0.47004000684148844, -0.33523477612826103, 0.81650476841393171}, 0.25490292618602428},
      {{0.90811473755436178, -0.34034172126994483, 0.2439162483304132}, 0.25734774333766669},
      {{0.42350214319225532, 0.57312207774611634, 0.70155329000122379}, 0.32185725153981831},
      {{0.4235021431922526, 0.57312207774611768, 0.70155329000122424}, 0.3218572515398187},
      {{-0.39098454036748614, -0.31284430951378855, -0.86559778604064519}, 0.33316218910359086},
      {{-0.044975378082894479, 0.54395689958666793, -0.83790697977661011}, 0.33404398963555387},
      {{-0.5793037732727282, 0.71214583529983844, 0.39655446982359782}, 0.35174919999530402},
      {{0.76820050776167459, 0.52803563816396537, -0.36200323852623095}, 0.35847691644634755},
      {{-0.97093491676333343, -0.22403811696547296, -0.084215850980347548}, 0.44899956304404215},
      {{-0.99232059371530446, 0.12369251912911203, 0}, 0.0023988497247997599},
      {{-0.99914575769972847, 0.041324990872781832, 7.4894693100495538e-16}, -0.0097485773952842251},
      {{-0.99914575769972858, 0.041324990872778349, -2.2059070543360112e-16}, -0.0097485773952848236},
      {{0.99224905218839354, -0.12264200920643671, 0.020018891304040505}, -0.011883801974429477},
      {{0.99251943287373467, -0.12051356590112614, 0.019536012945202727}, -0.0115735209029313},
      {{0.9989628522527183, -0.040973006320839708, 0.019860326587082675}, 1.8561541192951836e-16},
      {{0.99899516711890368, -0.040258045205003506, 0.019696341521860075}, -6.263641609036575e-05},
      {{0, 0, 1}, 0},
  };
  std::vector<Vec3> normals;
  std::vector<double> offsets;
  CGAL::Quadratic_program<double> lp(CGAL::SMALLER, false, 0, false, 0);
  for (const auto& [n, d] : planes) {
    const int row = int(normals.size());
    lp.set_a(0, row, n.x), lp.set_a(1, row, n.y), lp.set_a(2, row, n.z), lp.set_a(3, row, 1), lp.set_b(row, d);
    normals.push_back(n), offsets.push_back(d);
  }
  lp.set_c(3, -1);
  const auto exact = CGAL::solve_linear_program(lp, CGAL::Gmpzf());
  ASSERT_TRUE(exact.is_optimal());
  const InscribedBall ball = largest_inscribed_ball(normals, offsets);
  ASSERT_TRUE(ball.ok);
  EXPECT_NEAR(ball.radius, -CGAL::to_double(exact.objective_value()), 1e-12);
  EXPECT_LT(ball.radius, 0);  // the kernel is empty
  for (size_t f = 0; f < planes.size(); ++f) EXPECT_LE(dot(normals[f], ball.center) + ball.radius, offsets[f] + 1e-12) << f;
}

// Random convex cells against exact oracles.
TEST(Quality, RandomConvexCellsMatchExactOracles) {
  std::mt19937_64 gen(7);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> offset(0.3, 1.5);
  using QP = CGAL::Quadratic_program<double>;
  using Kd = CGAL::Cartesian_d<CGAL::Gmpq>;
  using Traits = CGAL::Min_sphere_annulus_d_traits_d<Kd>;
  for (int trial = 0; trial < 60; ++trial) {
    ConvexCell c;
    c.reset_cube(3);
    std::vector<Vec3> normals;
    std::vector<double> offsets;
    const int planes = 4 + trial % 30;
    for (int i = 0; i < planes; ++i) {
      Vec3 n{normal(gen), normal(gen), normal(gen)};
      n = (1 / norm(n)) * n;
      const double d = offset(gen);
      if (c.clip(n, d, 1, kEps) == ConvexCell::Clip::Cut) normals.push_back(n), offsets.push_back(d);
    }
    const CellQuality q = cell_quality(mesh_of(c), 0);
    // Inradius: maximise t subject to n.x + t <= d over the cell's faces (cube faces included).
    QP lp(CGAL::SMALLER, false, 0, false, 0);
    for (size_t f = 0; f < c.face_count(); ++f) {
      const uint16_t* fv = c.face_begin(f);
      Vec3 a = c.vertex(fv[0]), b = c.vertex(fv[1]), d3 = c.vertex(fv[2]);
      Vec3 n = cross(b - a, d3 - a);
      n = (1 / norm(n)) * n;
      lp.set_a(0, int(f), n.x), lp.set_a(1, int(f), n.y), lp.set_a(2, int(f), n.z), lp.set_a(3, int(f), 1);
      lp.set_b(int(f), dot(n, a));
    }
    lp.set_c(3, -1);
    const auto sol = CGAL::solve_linear_program(lp, CGAL::Gmpzf());
    ASSERT_TRUE(sol.is_optimal());
    EXPECT_NEAR(q.inradius, -CGAL::to_double(sol.objective_value()), 1e-9) << trial;
    // Outradius: Min_sphere_d in exact rational arithmetic.
    std::vector<Kd::Point_d> pts;
    for (size_t v = 0; v < c.vertex_count(); ++v) {
      const Vec3 p = c.vertex(v);
      const CGAL::Gmpq xyz[3] = {p.x, p.y, p.z};
      pts.emplace_back(3, xyz, xyz + 3);
    }
    CGAL::Min_sphere_d<Traits> ms(pts.begin(), pts.end());
    EXPECT_NEAR(q.outradius, std::sqrt(CGAL::to_double(ms.squared_radius())), 1e-9) << trial;
  }
}

// Whole meshes, welding off: no interior cell beyond the paper's bounds.
TEST(Quality, MeshesRespectTheoremOneAndLemmaSix) {
  for (const char* domain : {"box:0,0,0,1,1,1", "sphere"}) {
    Domain d = load_domain(std::string(domain) == "sphere" ? test::model("unit_sphere.STL") : domain);
    MeshOptions opt;
    opt.r = 0.1;
    opt.seed = 5;
    opt.weld = 0, opt.quality = false;  // measured below
    PolyMesh m = generate_mesh(d, opt, nullptr);
    std::vector<CellQuality> cells;
    QualityReport q = assess_quality(m, &cells);
    EXPECT_EQ(q.cells[0] + q.cells[1], m.cell_count());
    EXPECT_GT(q.cells[0], 100u);
    EXPECT_EQ(q.theorem1_violations, 0u) << domain;
    EXPECT_EQ(q.lemma6_interior_violations, 0u) << domain;
    EXPECT_EQ(q.lemma6_border_violations, 0u) << domain;
    EXPECT_LE(q.aspect[0].max, 2.0);
    EXPECT_GE(q.dihedral[0].min, 60 - 1e-7);
    EXPECT_LE(q.dihedral[0].max, 150 + 1e-7);
    // Lemmas 1 and 2 bound the radii themselves: R_o <= r, R_i >= r/2 for interior cells.
    for (size_t c = 0; c < m.cell_count(); ++c) {
      EXPECT_LE(cells[c].outradius, opt.r * (1 + 1e-9));
      if (m.kinds[c] == CellKind::Interior) EXPECT_GE(cells[c].inradius, opt.r / 2 * (1 - 1e-9));
    }
    // The histograms count every cell and every edge twice (once per cell around it) at most.
    uint64_t binned = 0;
    for (auto v : q.aspect_histogram[0].counts) binned += v;
    EXPECT_EQ(binned + q.aspect_histogram[0].below + q.aspect_histogram[0].above, q.cells[0]);
    EXPECT_EQ(q.aspect_histogram[0].below, 0u);  // aspect ratios are at least 1
  }
}

// A bad mesh is seen: flatten one cell and its aspect ratio and dihedrals leave the bounds.
TEST(Quality, DetectsAFlattenedCell) {
  ConvexCell c;
  c.reset_cube(1);
  c.clip({0, 0, 1}, 0.05, 1, kEps);
  PolyMesh m = mesh_of(c);
  QualityReport q = assess_quality(m);
  EXPECT_EQ(q.theorem1_violations, 1u);
  EXPECT_EQ(q.lemma6_interior_violations, 0u);  // right angles: within [60, 150]
  // A slab ten times wider than thick: its aspect ratio (over 4) is beyond the histogram's range,
  // so it is counted apart, not in an end bin.
  ConvexCell slab;
  slab.reset_cube(1);
  slab.clip({0, 0, 1}, -0.8, 1, kEps);
  const QualityReport flat = assess_quality(mesh_of(slab));
  ASSERT_GT(flat.aspect[0].max, flat.aspect_histogram[0].hi);
  EXPECT_EQ(flat.aspect_histogram[0].above, 1u);
  const auto& bins = flat.aspect_histogram[0].counts;
  EXPECT_EQ(std::accumulate(bins.begin(), bins.end(), uint64_t(0)), 0u);
  // A plane meeting the top face at a 30° edge.
  ASSERT_EQ(c.clip({0.5, 0, -std::sqrt(0.75)}, 0.257, 1, kEps), ConvexCell::Clip::Cut);
  q = assess_quality(mesh_of(c));
  EXPECT_EQ(q.lemma6_interior_violations, 1u);
  EXPECT_NEAR(q.dihedral[0].min, 30, 1e-9);
}

}  // namespace
}  // namespace froth
