// Input: STL reading, convexity validation and the errors bad input gets.
#include <cmath>
#include <gtest/gtest.h>

#include <bit>

#include <fstream>
#include <set>

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
  Domain d = load_domain(test::model("unit_cube.STL"));
  EXPECT_EQ(d.planes.size(), 6u);
  EXPECT_NEAR(d.volume, 1.0, 1e-12);
  EXPECT_NEAR(d.surface_area, 6.0, 1e-12);
  EXPECT_NEAR(d.bounds.lo.x, -0.5, 1e-12);
}

TEST(Input, IcosphereHasOnePlanePerTriangle) {
  TriangleSurface s = read_stl(test::model("unit_sphere.STL"));
  EXPECT_EQ(s.vertices.size(), 642u);
  EXPECT_EQ(s.triangles.size(), 1280u);
  Domain d = domain_from_surface(s, "sphere");
  EXPECT_EQ(d.planes.size(), 1280u);
  EXPECT_GT(d.volume, 4.0);
  EXPECT_LT(d.volume, 4.0 / 3.0 * M_PI);
}

// A surface built in memory is made a domain as a file is: the same features and the same reflex
// curves for the protection seeds (the Fichera corner's three reflex edges).
TEST(Input, SurfaceInMemoryGetsTheFileFeatures) {
  const Domain from_file = load_domain(test::model("7_8ths_cube.stl"));
  const Domain in_memory = domain_from_surface(read_stl(test::model("7_8ths_cube.stl")), "corner");
  EXPECT_EQ(in_memory.features.reflex_edges, 3u);
  EXPECT_EQ(in_memory.reflex_curves, from_file.reflex_curves);
  EXPECT_FALSE(in_memory.reflex_curves.empty());
  EXPECT_EQ(error_kind_of([&] { domain_from_surface(in_memory.surface, "corner", {.feature_angle = 0}); }),
            ErrorKind::Usage);
}

TEST(Input, AsciiStlWithTwoSolidsGivesTwoShells) {
  TriangleSurface s = read_stl(test::model("two_objects_mixed_case_names.stl"));
  EXPECT_EQ(s.triangles.size(), 24u);
  EXPECT_EQ(s.vertices.size(), 16u);
  Domain d = domain_from_surface(s, "two");
  EXPECT_EQ(d.shells, 2u);
  EXPECT_EQ(d.cavities, 0u);
  EXPECT_FALSE(d.convex);
  EXPECT_NEAR(d.volume, 2.0, 1e-12);
  EXPECT_TRUE(d.contains({0.5, 0.5, 0.5}));
  EXPECT_TRUE(d.contains({5.5, 0.5, 0.5}));
  EXPECT_FALSE(d.contains({3, 0.5, 0.5}));
}

// Both shells of hollow_sphere.off face outward in the file; the inner one bounds a cavity
// because it is nested, and is turned to face into it.
TEST(Input, CavityComesFromNestingNotFromTheFile) {
  Domain d = load_domain(test::model("hollow_sphere.off"));
  EXPECT_EQ(d.shells, 2u);
  EXPECT_EQ(d.cavities, 1u);
  EXPECT_NEAR(d.volume, 0.506 - 0.259, 0.01);
  EXPECT_TRUE(d.contains({0.45, 0, 0}));
  EXPECT_FALSE(d.contains({0, 0, 0}));
  EXPECT_FALSE(d.contains({0.6, 0, 0}));
}

TEST(Input, ReflexEdgesMakeANonConvexDomain) {
  Domain d = load_domain(test::model("7_8ths_cube.stl"));
  EXPECT_FALSE(d.convex);
  EXPECT_NEAR(d.volume, 7.0 / 8 * 40 * 40 * 40, 1e-6 * d.volume);
  EXPECT_EQ(d.features.reflex_edges, 3u);
  EXPECT_TRUE(d.contains({-10, -10, -10}));
  EXPECT_FALSE(d.contains({10, 10, 10}));
  EXPECT_TRUE(load_domain(test::model("unit_sphere.STL")).convex);
}

TEST(Input, SelfIntersectionIsNamed) {
  // Two tetrahedra that pierce each other.
  TriangleSurface s;
  s.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}, {0.5, 0.5, 0.5}, {3, 0.5, 0.5}, {0.5, 3, 0.5}, {0.5, 0.5, 3}};
  for (int32_t o : {0, 4}) {
    s.triangles.push_back({o + 0, o + 2, o + 1});
    s.triangles.push_back({o + 0, o + 1, o + 3});
    s.triangles.push_back({o + 0, o + 3, o + 2});
    s.triangles.push_back({o + 1, o + 2, o + 3});
  }
  std::string msg = error_text_of([&] { domain_from_surface(s, "pierced"); });
  EXPECT_NE(msg.find("intersects itself"), std::string::npos) << msg;
  EXPECT_NE(msg.find("triangles"), std::string::npos) << msg;
}

TEST(Input, RepairReorientsInconsistentShells) {
  TriangleSurface s = read_stl(test::model("multibody.stl"));
  EXPECT_NE(error_text_of([&] { domain_from_surface(s, "multibody"); }).find("repair option"), std::string::npos);
  Domain d = domain_from_surface(s, "multibody", {.repair = true});
  EXPECT_GT(d.reoriented_triangles, 0u);
  EXPECT_EQ(d.shells, 2u);
  EXPECT_GT(d.volume, 0);
  // Every edge now runs both ways.
  std::set<std::pair<int32_t, int32_t>> directed;
  for (auto [a, b, c] : d.surface.triangles)
    for (auto e : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) EXPECT_TRUE(directed.insert(e).second);
  for (auto [a, b] : directed) EXPECT_TRUE(directed.count({b, a}));
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
  Domain d = parse_box_spec("box:0,0,0,1,2,3");
  EXPECT_DOUBLE_EQ(d.volume, 6);
  EXPECT_EQ(error_kind_of([] { parse_box_spec("box:0,0,0,1,2"); }), ErrorKind::Usage);
  EXPECT_EQ(error_kind_of([] { parse_box_spec("box:0,0,0,-1,2,3"); }), ErrorKind::Usage);
  EXPECT_EQ(error_kind_of([] { parse_box_spec("box:0,0,0,1,2,3,4"); }), ErrorKind::Usage);
}

// Hostile polygon files (issue 25: CGAL 5.5's readers crashed or allocated gigabytes on these):
// each is refused as invalid input with a message, at once, or read as what it is.
TEST(Input, HostilePolygonFilesAreRefusedOrRead) {
  const std::string dir = testing::TempDir();
  struct Case {
    const char* name;
    std::string bytes;
    const char* message;  // nullptr: reads as the unit cube's surface would (8 vertices)
  };
  const std::string cube_vertices = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n";
  const std::string cube_faces = "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n";
  const std::vector<Case> cases = {
      {"property_first.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n", "a property before any element"},
      {"negative.ply", "ply\nformat ascii 1.0\nelement vertex -1\nproperty float x\nend_header\n", "negative"},
      {"huge_count.off", "OFF\n3 69900000 0\n0 0 0\n1 0 0\n0 1 0\n", "more than its"},
      {"coff_word.off", "COFF\n8 6 0\n0 0 0 255 0 0\nx y z\n" + cube_vertices + cube_faces, "is not a number"},
      {"short_list.ply", "ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
                         "end_header\n\xff",
       "a list of"},
      {"truncated.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty double x\nproperty double y\n"
                        "property double z\nend_header\n\x01\x02",
       "more than its"},
      {"index0.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "vertex index 0"},
      {"int_coords.ply", "ply\nformat ascii 1.0\nelement vertex 8\nproperty int x\nproperty int y\nproperty int z\n"
                         "element face 6\nproperty list uchar int vertex_indices\nend_header\n" + cube_vertices + cube_faces,
       nullptr},
      {"coff.off", "COFF\n8 6 0\n" + [&] {
         std::string v;
         for (const char* line : {"0 0 0", "1 0 0", "1 1 0", "0 1 0", "0 0 1", "1 0 1", "1 1 1", "0 1 1"})
           v += std::string(line) + " 200 10 10 255\n";
         return v;
       }() + cube_faces,
       nullptr},
  };
  for (const Case& c : cases) {
    const std::string path = dir + "/" + c.name;
    std::ofstream(path, std::ios::binary) << c.bytes;
    if (c.message) {
      EXPECT_EQ(error_kind_of([&] { load_domain(path); }), ErrorKind::InvalidInput) << c.name;
      EXPECT_NE(error_text_of([&] { load_domain(path); }).find(c.message), std::string::npos)
          << c.name << ": " << error_text_of([&] { load_domain(path); });
    } else {
      const Domain d = load_domain(path);
      EXPECT_EQ(d.surface.vertices.size(), 8u) << c.name;
      EXPECT_NEAR(d.volume, 1.0, 1e-12) << c.name;
    }
  }
  // The same cube as a big-endian binary PLY.
  std::string be = "ply\nformat binary_big_endian 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 6\nproperty list uchar int vertex_indices\nend_header\n";
  auto put_be = [&](uint32_t u, int bytes) {
    for (int k = bytes - 1; k >= 0; --k) be.push_back(char(u >> (8 * k) & 0xff));
  };
  const float corners[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (const auto& v : corners)
    for (float x : v) put_be(std::bit_cast<uint32_t>(x), 4);
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  for (const auto& q : quads) {
    put_be(4, 1);
    for (int i : q) put_be(uint32_t(i), 4);
  }
  std::ofstream(dir + "/cube_be.ply", std::ios::binary) << be;
  EXPECT_NEAR(load_domain(dir + "/cube_be.ply").volume, 1.0, 1e-12);
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
  Domain bin = load_domain(test::model("unit_sphere.STL")), asc = load_domain(path);
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
  Domain stl = load_domain(test::model("unit_cube.STL"));
  Domain box = parse_box_spec("box:-0.5,-0.5,-0.5,0.5,0.5,0.5");
  PolyMesh a = test::mesh_of(stl, 0.15, 11, 2), b = test::mesh_of(box, 0.15, 11, 2);
  ASSERT_EQ(a.cell_count(), b.cell_count());
  for (size_t c = 0; c < a.cell_count(); ++c) {
    EXPECT_EQ(norm2(a.seeds[c] - b.seeds[c]), 0.0);
    EXPECT_NEAR(a.volumes[c], b.volumes[c], 1e-15);
  }
}


// The unit cube [0, 1]^3 in OFF (quads), OBJ (quads, `o` and normals), ASCII PLY and binary PLY:
// all read to the box's six planes and volume.
const double kCube[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
const int kQuads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};

void expect_unit_cube(const std::string& path) {
  const Domain d = load_domain(path);
  EXPECT_EQ(d.planes.size(), 6u) << path;
  EXPECT_NEAR(d.volume, 1, 1e-15) << path;
  EXPECT_NEAR(d.surface_area, 6, 1e-14) << path;
}

TEST(Input, CubeAsOffObjAndPly) {
  const std::string dir = testing::TempDir();
  {
    std::ofstream off(dir + "/cube.off");
    off << "OFF\n8 6 0\n";
    for (auto& v : kCube) off << v[0] << " " << v[1] << " " << v[2] << "\n";
    for (auto& q : kQuads) off << "4 " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << "\n";
  }
  {
    std::ofstream obj(dir + "/cube.obj");
    obj << "o cube\n";
    for (auto& v : kCube) obj << "v " << v[0] << " " << v[1] << " " << v[2] << "\n";
    obj << "vn 0 0 1\n";
    for (auto& q : kQuads) obj << "f " << q[0] + 1 << "//1 " << q[1] + 1 << "//1 " << q[2] + 1 << "//1 " << q[3] + 1 << "//1\n";
  }
  const std::string header = "element vertex 8\nproperty double x\nproperty double y\nproperty double z\n"
                             "element face 6\nproperty list uchar int vertex_indices\nend_header\n";
  {
    std::ofstream ply(dir + "/cube_ascii.ply");
    ply << "ply\nformat ascii 1.0\n" << header;
    for (auto& v : kCube) ply << v[0] << " " << v[1] << " " << v[2] << "\n";
    for (auto& q : kQuads) ply << "4 " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << "\n";
  }
  {
    std::ofstream ply(dir + "/cube_binary.ply", std::ios::binary);
    ply << "ply\nformat binary_little_endian 1.0\n" << header;
    for (auto& v : kCube) ply.write(reinterpret_cast<const char*>(v), sizeof v);
    for (auto& q : kQuads) {
      const uint8_t n = 4;
      ply.write(reinterpret_cast<const char*>(&n), 1);
      ply.write(reinterpret_cast<const char*>(q), sizeof q);
    }
  }
  for (const char* name : {"cube.off", "cube.obj", "cube_ascii.ply", "cube_binary.ply"}) expect_unit_cube(dir + "/" + name);
}

TEST(Input, SharedModelsInOtherFormatsGetTheirOwnMessages) {
  auto message = [](const char* model) { return error_text_of([&] { load_domain(test::model(model)); }); };
  // Two tetrahedra listing their shared face twice, opposite ways: two regions.
  const Domain joined = load_domain(test::model("joined_tetrahedra.obj"));
  ASSERT_TRUE(joined.regions);
  EXPECT_EQ(joined.regions->size(), 2u);
  EXPECT_EQ(joined.regions->interfaces.size(), 1u);
  EXPECT_NEAR(joined.regions->interfaces[0].area, 1.5 * 0.8660254, 1e-12);  // the file's base triangle
  EXPECT_NE(message("rook.stl").find("not manifold"), std::string::npos);
  EXPECT_FALSE(load_domain(test::model("step.off")).convex);
}

TEST(Input, BrokenOffIsInvalidInput) {
  const std::string dir = testing::TempDir();
  std::ofstream(dir + "/broken.off") << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
  std::ofstream(dir + "/garbage.ply") << "this is not a ply file";
  EXPECT_EQ(error_kind_of([&] { load_domain(dir + "/broken.off"); }), ErrorKind::InvalidInput);
  EXPECT_EQ(error_kind_of([&] { load_domain(dir + "/garbage.ply"); }), ErrorKind::InvalidInput);
  EXPECT_EQ(error_kind_of([&] { load_domain(dir + "/missing.obj"); }), ErrorKind::Io);
  EXPECT_EQ(error_kind_of([&] { load_domain(dir + "/cube.vtk"); }), ErrorKind::Usage);
}

}  // namespace
}  // namespace froth
