// The convex cell on its own: volumes, generator names and degenerate cuts.
#include <gtest/gtest.h>

#include <cmath>

#include "voronoi/convex_cell.hpp"

namespace froth {
namespace {

constexpr double kEps = 1e-12;

TEST(ConvexCell, CubeHasVolumeEightHalfCubed) {
  ConvexCell c;
  c.reset_cube(0.5);
  EXPECT_EQ(c.vertex_count(), 8u);
  EXPECT_EQ(c.face_count(), 6u);
  EXPECT_NEAR(c.volume(), 1.0, 1e-15);
  EXPECT_NEAR(c.max_radius2(), 0.75, 1e-15);
}

TEST(ConvexCell, HalvingCutKeepsHalfTheVolume) {
  ConvexCell c;
  c.reset_cube(1);
  ASSERT_EQ(c.clip({1, 0, 0}, 0, 7, kEps), ConvexCell::Clip::Cut);
  EXPECT_NEAR(c.volume(), 4.0, 1e-14);
  EXPECT_EQ(c.face_count(), 6u);
  EXPECT_EQ(c.vertex_count(), 8u);
  // The new vertices lie on generator 7 and on two cube faces.
  std::vector<ConvexCell::Names> names;
  ASSERT_TRUE(c.vertex_names(names));
  int on7 = 0;
  for (size_t v = 0; v < c.vertex_count(); ++v)
    if (names[v].has(7)) {
      ++on7;
      EXPECT_EQ(names[v].n, 3);
      EXPECT_NEAR(c.vertex(v).x, 0, 1e-15);
    }
  EXPECT_EQ(on7, 4);
}

TEST(ConvexCell, CornerCutMakesTriangleAndTetrahedronVolume) {
  ConvexCell c;
  c.reset_cube(1);
  // Plane x+y+z = 2 cuts off the corner (1,1,1): a tetrahedron of legs 1, volume 1/6.
  Vec3 n = (1 / std::sqrt(3.0)) * Vec3{1, 1, 1};
  ASSERT_EQ(c.clip(n, 2 / std::sqrt(3.0), 9, kEps), ConvexCell::Clip::Cut);
  EXPECT_NEAR(c.volume(), 8.0 - 1.0 / 6.0, 1e-13);
  EXPECT_EQ(c.face_count(), 7u);
  EXPECT_EQ(c.vertex_count(), 10u);
}

TEST(ConvexCell, PlaneThroughVerticesAddsGeneratorWithoutNewVertices) {
  ConvexCell c;
  c.reset_cube(1);
  // x + y = 0 passes through the vertical edges at (1,-1) and (-1,1): a diagonal cut.
  Vec3 n = (1 / std::sqrt(2.0)) * Vec3{1, 1, 0};
  ASSERT_EQ(c.clip(n, 0, 5, kEps), ConvexCell::Clip::Cut);
  EXPECT_NEAR(c.volume(), 4.0, 1e-14);
  EXPECT_EQ(c.vertex_count(), 6u);  // a triangular prism
  EXPECT_EQ(c.face_count(), 5u);
  std::vector<ConvexCell::Names> names;
  ASSERT_TRUE(c.vertex_names(names));
  int on5 = 0;
  for (size_t v = 0; v < c.vertex_count(); ++v)
    if (std::abs(c.vertex(v).x + c.vertex(v).y) < 1e-15) {
      EXPECT_TRUE(names[v].has(5));
      ++on5;
    }
  EXPECT_EQ(on5, 4);  // the snapped vertices joined the new face
}

TEST(ConvexCell, TouchingPlaneLeavesCellUnchanged) {
  ConvexCell c;
  c.reset_cube(1);
  Vec3 n = (1 / std::sqrt(3.0)) * Vec3{1, 1, 1};
  EXPECT_EQ(c.clip(n, std::sqrt(3.0), 4, kEps), ConvexCell::Clip::Unchanged);
  EXPECT_NEAR(c.volume(), 8, 1e-14);
  EXPECT_EQ(c.face_count(), 6u);
}

TEST(ConvexCell, PlaneMissingCellIsUnchangedAndAllOutsideIsEmpty) {
  ConvexCell c;
  c.reset_cube(1);
  EXPECT_EQ(c.clip({0, 0, 1}, 5, 1, kEps), ConvexCell::Clip::Unchanged);
  EXPECT_EQ(c.clip({0, 0, 1}, -5, 1, kEps), ConvexCell::Clip::Empty);
}

TEST(ConvexCell, ManyRandomCutsKeepAClosedConvexCellAndMatchAnalyticBall) {
  // Cut by tangent planes of the unit sphere in many directions: the cell converges to the
  // ball from outside; its volume is above 4/3 pi and decreasing.
  ConvexCell c;
  c.reset_cube(2);
  double last = c.volume();
  const int n = 240;  // below kMaxPlanes: every tangent plane stays a face
  for (int i = 0; i < n; ++i) {
    double z = 1 - 2 * (i + 0.5) / n, phi = i * M_PI * (3 - std::sqrt(5.0));
    double s = std::sqrt(1 - z * z);
    Vec3 dir{s * std::cos(phi), s * std::sin(phi), z};
    auto res = c.clip(dir, 1, i, kEps);
    ASSERT_TRUE(res == ConvexCell::Clip::Cut || res == ConvexCell::Clip::Unchanged) << i;
    double v = c.volume();
    EXPECT_LE(v, last + 1e-12);
    last = v;
  }
  EXPECT_GT(last, 4.0 / 3.0 * M_PI);
  EXPECT_LT(last, 4.0 / 3.0 * M_PI * 1.05);
  // Every vertex lies on at least three faces and every face has at least 3 vertices.
  std::vector<ConvexCell::Names> names;
  ASSERT_TRUE(c.vertex_names(names));
  for (size_t v = 0; v < c.vertex_count(); ++v) EXPECT_GE(names[v].n, 3);
  for (size_t f = 0; f < c.face_count(); ++f) EXPECT_GE(c.face_size(f), 3u);
}

TEST(ConvexCell, MorePlanesThanItCanNameFailCleanly) {
  // 300 tangent planes all stay faces: past kMaxPlanes the cut must report failure.
  ConvexCell c;
  c.reset_cube(2);
  bool failed = false;
  for (int i = 0; i < 300 && !failed; ++i) {
    double z = 1 - 2 * (i + 0.5) / 300, phi = i * M_PI * (3 - std::sqrt(5.0));
    double s = std::sqrt(1 - z * z);
    failed = c.clip({s * std::cos(phi), s * std::sin(phi), z}, 1, i, kEps) == ConvexCell::Clip::Failed;
  }
  EXPECT_TRUE(failed);
}

}  // namespace
}  // namespace froth
