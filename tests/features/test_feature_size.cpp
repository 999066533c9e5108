// Local feature size (thin walls, narrow gaps) on made shapes with known answers, and the rule
// that keeps a sharp wedge from being taken for a thin wall.
#include <gtest/gtest.h>

#include <cmath>

#include "common/test_support.hpp"
#include "features/feature_size.hpp"

namespace froth {
namespace {

void add_box(TriangleSurface& s, Vec3 lo, Vec3 hi) {
  const int32_t o = int32_t(s.vertices.size());
  for (int c = 0; c < 8; ++c) s.vertices.push_back({(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z});
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {1, 3, 7, 5}, {0, 4, 6, 2}};
  for (const auto& q : quads) {
    s.triangles.push_back({o + q[0], o + q[1], o + q[2]});
    s.triangles.push_back({o + q[0], o + q[2], o + q[3]});
  }
}

// A prism over the triangle with corner angle `degrees` at the origin, legs of length 2, height 1.
TriangleSurface wedge(double degrees) {
  const double a = degrees * M_PI / 180 / 2;
  TriangleSurface s;
  const Vec3 p[3] = {{0, 0, 0}, {2 * std::cos(a), -2 * std::sin(a), 0}, {2 * std::cos(a), 2 * std::sin(a), 0}};
  for (double z : {0.0, 1.0})
    for (Vec3 q : p) s.vertices.push_back({q.x, q.y, z});
  s.triangles = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}, {2, 0, 3}, {2, 3, 5}};
  return s;
}

TEST(FeatureSize, PlateThicknessIsMeasuredAwayFromItsRim) {
  TriangleSurface s;
  add_box(s, {0, 0, 0}, {4, 4, 0.1});
  const Domain d = domain_from_surface(s, "plate");
  const FeatureSize f = measure_feature_size(d, 1.0);
  EXPECT_NEAR(f.report.thickness.min, 0.1, 1e-12);
  // The two large faces (their centroids are far from the rim) are thin; the rim faces are not
  // (their rays cross the plate's 4 units).
  EXPECT_NEAR(f.report.thickness.area_below_cap, 32.0 / 33.6, 1e-9);
  EXPECT_NEAR(f.report.thickness.quantile_50, 0.1, 1e-12);
  EXPECT_FALSE(std::isfinite(f.report.gap.min));  // one convex body: no gap
}

TEST(FeatureSize, GapBetweenTwoBodies) {
  TriangleSurface s;
  add_box(s, {0, 0, 0}, {1, 1, 1});
  add_box(s, {1 + 1e-4, 0, 0}, {2, 1, 1});
  const FeatureSize two = measure_feature_size(domain_from_surface(s, "two bodies"), 0.5);
  EXPECT_NEAR(two.report.gap.min, 1e-4, 1e-12);
  EXPECT_NEAR(two.report.gap.where.x, 1 + 0.5e-4, 0.51e-4);  // on one of the facing sides
  EXPECT_FALSE(std::isfinite(two.report.thickness.min));      // nothing thinner than 0.5
}

TEST(FeatureSize, ThinWallsOfTheTubeModel) {
  const Domain d = load_domain(test::model("round.stl"));  // tube, wall 0.305
  const FeatureSize f = measure_feature_size(d, 1.0);
  EXPECT_GT(f.report.thickness.min, 0.28);
  EXPECT_LT(f.report.thickness.min, 0.306);
  EXPECT_GT(f.report.thickness.area_below_cap, 0.9);
}

// A wedge's two faces meet at its edge: for more than 27 degrees (atan(1 / kLocality)) they are
// a sharp feature and no thin wall is reported; a 10-degree wedge is thin near its edge.
TEST(FeatureSize, SharpWedgeIsNoThinWall) {
  const FeatureSize wide = measure_feature_size(domain_from_surface(wedge(40), "wedge 40"), 10);
  EXPECT_FALSE(std::isfinite(wide.report.thickness.min)) << wide.report.thickness.min;
  const FeatureSize narrow = measure_feature_size(domain_from_surface(wedge(10), "wedge 10"), 10);
  EXPECT_TRUE(std::isfinite(narrow.report.thickness.min));
}

}  // namespace
}  // namespace froth
