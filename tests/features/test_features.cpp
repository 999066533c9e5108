// Feature edges of the input surface: flat, convex and reflex edges, curves and corners, on the
// shared models with known answers.
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "features/features.hpp"

namespace froth {
namespace {

TEST(Features, UnitCubeHasTwelveConvexCurvesAndEightCorners) {
  const SurfaceFeatures f = classify_features(read_stl(test::model("unit_cube.STL")), kDefaultFeatureAngle);
  EXPECT_EQ(f.convex_edges, 12u);
  EXPECT_EQ(f.reflex_edges, 0u);
  EXPECT_EQ(f.flat_edges, 6u);  // the face diagonals
  EXPECT_EQ(f.curves.size(), 12u);
  EXPECT_EQ(f.corners.size(), 8u);
  for (const FeatureCurve& c : f.curves) EXPECT_EQ(c.vertices.size(), 2u);
}

// The Fichera corner: 40^3 cube minus one octant. Three reflex edges meet at the reflex corner
// (0, 0, 0); the float32 noise on the coordinates must not make flat edges sharp.
TEST(Features, SevenEighthsCubeHasThreeReflexEdgesMeetingAtTheOrigin) {
  const TriangleSurface s = read_stl(test::model("7_8ths_cube.stl"));
  const SurfaceFeatures f = classify_features(s, kDefaultFeatureAngle);
  EXPECT_EQ(f.reflex_edges, 3u);
  EXPECT_EQ(f.convex_edges, 18u);
  size_t reflex_curves = 0;
  for (const FeatureCurve& c : f.curves) {
    if (c.cls != EdgeClass::Reflex) continue;
    ++reflex_curves;
    const bool at_origin = norm(s.vertices[c.vertices.front()]) < 1e-3 || norm(s.vertices[c.vertices.back()]) < 1e-3;
    EXPECT_TRUE(at_origin);
  }
  EXPECT_EQ(reflex_curves, 3u);
}

TEST(Features, CurvedSurfacesAreFlatAtTheDefaultAngle) {
  for (const char* model : {"unit_sphere.STL", "torus.STL"}) {
    const SurfaceFeatures f = classify_features(read_stl(test::model(model)), kDefaultFeatureAngle);
    EXPECT_EQ(f.convex_edges + f.reflex_edges, 0u) << model;
    EXPECT_TRUE(f.curves.empty()) << model;
  }
  // The icosphere's facets turn by 3.1 to 5.8 degrees at their edges: at 2 degrees every edge
  // is a feature, at 6 none.
  EXPECT_EQ(classify_features(read_stl(test::model("unit_sphere.STL")), 6).flat_edges, 1920u);
  const SurfaceFeatures f = classify_features(read_stl(test::model("unit_sphere.STL")), 2);
  EXPECT_EQ(f.convex_edges, 1920u);
  EXPECT_EQ(f.flat_edges, 0u);
}

// A torus's inner half is saddle-shaped: at a small angle, the inner edges that bend inward are
// reflex, and the closed feature loops have no corner.
TEST(Features, TorusAtASmallAngleHasReflexEdges) {
  const SurfaceFeatures f = classify_features(read_stl(test::model("torus.STL")), 1);
  EXPECT_GT(f.reflex_edges, 0u);
  EXPECT_GT(f.convex_edges, f.reflex_edges);
}

TEST(Features, DomainsCarryTheirFeatureCounts) {
  const Domain box = load_domain("box:0,0,0,2,1,1");
  EXPECT_EQ(box.features.convex_edges, 12u);
  EXPECT_EQ(box.features.corners, 8u);
  EXPECT_EQ(box.features.curves, 12u);
  const Domain sphere = load_domain(test::model("unit_sphere.STL"), {.feature_angle = 2});
  EXPECT_EQ(sphere.features.angle_degrees, 2);
  EXPECT_EQ(sphere.features.convex_edges, 1920u);
  EXPECT_THROW(load_domain("box:0,0,0,1,1,1", {.feature_angle = 0}), Error);
  EXPECT_THROW(load_domain("box:0,0,0,1,1,1", {.feature_angle = 180}), Error);
}

}  // namespace
}  // namespace froth
