// Input: STL reading, convexity validation and the errors bad input gets.
#include <gtest/gtest.h>

#include <fstream>

#include <fmt/format.h>

#include "common/test_support.hpp"

namespace froth {
namespace {

ErrorKind error_kind_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.kind();
  }
  ADD_FAILURE() << "no error";
  return ErrorKind::Internal;
}

std::string error_text_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Input, UnitCubeBinaryStlHasSixPlanesAndUnitVolume) {
  ConvexDomain d = load_domain(test::model("unit_cube.STL"));
  EXPECT_EQ(d.planes.size(), 6u);
  EXPECT_NEAR(d.volume, 1.0, 1e-12);
  EXPECT_NEAR(d.surface_area, 6.0, 1e-12);
  EXPECT_NEAR(d.bounds.lo.x, -0.5, 1e-12);
}

TEST(Input, IcosphereHasOnePlanePerTriangle) {
  TriangleSurface s = read_stl(test::model("unit_sphere.STL"));
  EXPECT_EQ(s.vertices.size(), 642u);
  EXPECT_EQ(s.triangles.size(), 1280u);
  ConvexDomain d = convex_domain_from_surface(s, "sphere");
  EXPECT_EQ(d.planes.size(), 1280u);
  EXPECT_GT(d.volume, 4.0);
  EXPECT_LT(d.volume, 4.0 / 3.0 * M_PI);
}

TEST(Input, AsciiStlWithTwoSolidsIsReadButRejectedAsTwoComponents) {
  TriangleSurface s = read_stl(test::model("two_objects_mixed_case_names.stl"));
  EXPECT_EQ(s.triangles.size(), 24u);
  EXPECT_EQ(s.vertices.size(), 16u);
  EXPECT_NE(error_text_of([&] { convex_domain_from_surface(s, "two"); }).find("more than one component"),
            std::string::npos);
}

TEST(Input, NonManifoldEdgeIsNamed) {
  std::string msg = error_text_of([] { load_domain(test::model("shared.STL")); });
  EXPECT_NE(msg.find("not manifold"), std::string::npos) << msg;
  EXPECT_NE(msg.find("shared by 4 triangles"), std::string::npos) << msg;
}

TEST(Input, OpenSurfaceIsNamed) {
  std::string msg = error_text_of([] { load_domain(test::model("featuretype.STL")); });
  EXPECT_NE(msg.find("not closed"), std::string::npos) << msg;
}

TEST(Input, InconsistentOrientationIsNamed) {
  std::string msg = error_text_of([] { load_domain(test::model("multibody.stl")); });
  EXPECT_NE(msg.find("inconsistent orientation"), std::string::npos) << msg;
}

TEST(Input, ReflexEdgeIsRejectedAsNonConvex) {
  std::string msg = error_text_of([] { load_domain(test::model("7_8ths_cube.stl")); });
  EXPECT_NE(msg.find("not convex"), std::string::npos) << msg;
  EXPECT_EQ(error_kind_of([] { load_domain(test::model("7_8ths_cube.stl")); }), ErrorKind::InvalidInput);
}

TEST(Input, MissingFileIsAnIoError) {
  EXPECT_EQ(error_kind_of([] { load_domain("/nonexistent/x.stl"); }), ErrorKind::Io);
}

TEST(Input, GarbageFileIsInvalidInput) {
  std::string path = testing::TempDir() + "/garbage.stl";
  std::ofstream(path) << "this is not an stl file at all";
  EXPECT_EQ(error_kind_of([&] { load_domain(path); }), ErrorKind::InvalidInput);
}

TEST(Input, NonFiniteCoordinateIsNamed) {
  std::string path = testing::TempDir() + "/nan.stl";
  std::ofstream(path) << "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex nan 0 0\nvertex 0 1 0\n"
                         "endloop\nendfacet\nendsolid x\n";
  std::string msg = error_text_of([&] { load_domain(path); });
  EXPECT_NE(msg.find("non-finite"), std::string::npos) << msg;
}

TEST(Input, BoxSpecs) {
  ConvexDomain d = parse_box_spec("box:0,0,0,1,2,3");
  EXPECT_DOUBLE_EQ(d.volume, 6);
  EXPECT_EQ(error_kind_of([] { parse_box_spec("box:0,0,0,1,2"); }), ErrorKind::Usage);
  EXPECT_EQ(error_kind_of([] { parse_box_spec("box:0,0,0,-1,2,3"); }), ErrorKind::Usage);
  EXPECT_EQ(error_kind_of([] { parse_box_spec("box:0,0,0,1,2,3,4"); }), ErrorKind::Usage);
}

}  // namespace
}  // namespace froth

namespace froth {
namespace {

// The icosphere written as ASCII STL (17 significant digits: an exact round trip of each
// coordinate) reads back to the same domain and meshes to the same volume.
TEST(Input, AsciiStlOfTheIcosphereMeshesLikeTheBinaryOne) {
  TriangleSurface s = read_stl(test::model("unit_sphere.STL"));
  std::string path = testing::TempDir() + "/sphere_ascii.stl";
  {
    std::ofstream out(path);
    out << "solid sphere\n";
    for (auto [a, b, c] : s.triangles) {
      out << "facet normal 0 0 0\nouter loop\n";
      for (int32_t v : {a, b, c})
        out << fmt::format("vertex {:.17g} {:.17g} {:.17g}\n", s.vertices[v].x, s.vertices[v].y, s.vertices[v].z);
      out << "endloop\nendfacet\n";
    }
    out << "endsolid sphere\n";
  }
  ConvexDomain bin = load_domain(test::model("unit_sphere.STL")), asc = load_domain(path);
  ASSERT_EQ(asc.planes.size(), bin.planes.size());
  EXPECT_DOUBLE_EQ(asc.volume, bin.volume);
  RunReport rb, ra;
  test::mesh_of(bin, 0.2, 3, 2, &rb);
  test::mesh_of(asc, 0.2, 3, 2, &ra);
  EXPECT_EQ(ra.cells, rb.cells);
  EXPECT_NEAR(ra.volume_sum, asc.volume, 1e-9 * asc.volume);
}

// unit_cube.STL is box:-0.5,-0.5,-0.5,0.5,0.5,0.5: the same seeds and cell volumes.
TEST(Input, CubeStlAndBoxSpecGiveTheSameMesh) {
  ConvexDomain stl = load_domain(test::model("unit_cube.STL"));
  ConvexDomain box = parse_box_spec("box:-0.5,-0.5,-0.5,0.5,0.5,0.5");
  PolyMesh a = test::mesh_of(stl, 0.15, 11, 2), b = test::mesh_of(box, 0.15, 11, 2);
  ASSERT_EQ(a.cell_count(), b.cell_count());
  for (size_t c = 0; c < a.cell_count(); ++c) {
    EXPECT_EQ(norm2(a.seeds[c] - b.seeds[c]), 0.0);
    EXPECT_NEAR(a.volumes[c], b.volumes[c], 1e-15);
  }
}

}  // namespace
}  // namespace froth
