// Crack sheets (input/cracks.hpp, issue 38's input): a sheet inside a box keeps its area and its
// front; one that pokes out is clipped at the box's faces, its cut edges on the boundary and
// its area what lies inside; sheets that cannot be cracks are refused naming the defect.
#include <gtest/gtest.h>

#include <cmath>

#include "froth/domain.hpp"
#include "froth/error.hpp"
#include "common/test_support.hpp"
#include "input/cracks.hpp"

namespace froth {
namespace {

TriangleSurface unit_box() { return parse_box_spec("box:0,0,0,1,1,1").surface; }

TriangleSurface square_sheet(double x0, double x1, double y0, double y1, double z, int n = 3) {
  return test::square_sheet(x0, x1, y0, y1, z, n);
}

double length(const CrackSheet& c, const std::vector<std::array<int32_t, 2>>& edges) {
  double sum = 0;
  for (const auto& e : edges) sum += norm(c.surface.vertices[size_t(e[1])] - c.surface.vertices[size_t(e[0])]);
  return sum;
}

TEST(Cracks, SheetInsideKeepsItsAreaAndFront) {
  const CrackSheet c = crack_from_surface(square_sheet(0.25, 0.75, 0.3, 0.7, 0.5), "penny", unit_box());
  EXPECT_NEAR(c.input_area, 0.5 * 0.4, 1e-15);
  EXPECT_NEAR(c.area, c.input_area, 1e-15);
  EXPECT_TRUE(c.on_boundary.empty());
  EXPECT_EQ(c.front.size(), 12u);
  EXPECT_NEAR(c.front_length, 2 * (0.5 + 0.4), 1e-14);
  EXPECT_TRUE(std::isnan(c.clipped_at.x));
}

TEST(Cracks, EdgeCrackIsClippedAtTheBoundary) {
  // From x = -0.5 (outside) to 0.6: the part in x < 0 is clipped; the cut lies on the face x = 0.
  const CrackSheet c = crack_from_surface(square_sheet(-0.5, 0.6, 0.2, 0.8, 0.45, 4), "edge", unit_box());
  EXPECT_NEAR(c.input_area, 1.1 * 0.6, 1e-14);
  EXPECT_NEAR(c.area, 0.6 * 0.6, 1e-12);
  EXPECT_NEAR(length(c, c.on_boundary), 0.6, 1e-12);
  EXPECT_NEAR(c.front_length, 0.6 + 2 * 0.6, 1e-12);
  EXPECT_LT(c.clipped_at.x, 0);
  for (const auto& e : c.on_boundary)
    for (int32_t v : e) EXPECT_NEAR(c.surface.vertices[size_t(v)].x, 0, 1e-15);
}

TEST(Cracks, ThroughCrackHasNoFrontInside) {
  // Across the whole section, poking out on four sides: a front nowhere, the boundary all round.
  const CrackSheet c = crack_from_surface(square_sheet(-0.2, 1.3, -0.1, 1.2, 0.5, 5), "through", unit_box());
  EXPECT_NEAR(c.area, 1.0, 1e-12);
  EXPECT_TRUE(c.front.empty());
  EXPECT_NEAR(length(c, c.on_boundary), 4.0, 1e-12);
}

TEST(Cracks, PiecesAreWoundOneWay) {
  TriangleSurface s = square_sheet(0.2, 0.8, 0.2, 0.8, 0.5, 2);
  std::swap(s.triangles[3][1], s.triangles[3][2]);  // one triangle the other way round
  const CrackSheet c = crack_from_surface(s, "flipped", unit_box());
  for (const auto& t : c.surface.triangles) {
    const Vec3 n = cross(c.surface.vertices[size_t(t[1])] - c.surface.vertices[size_t(t[0])],
                         c.surface.vertices[size_t(t[2])] - c.surface.vertices[size_t(t[0])]);
    EXPECT_GT(n.z, 0);
  }
}

// The message of the Error the sheet is refused with (InvalidInput), or "" if it is accepted.
std::string refusal(const TriangleSurface& s) {
  try {
    crack_from_surface(s, "bad", unit_box());
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
    return e.what();
  }
  return "";
}

TEST(Cracks, SheetsThatCannotBeCracksAreRefused) {
  EXPECT_NE(refusal(square_sheet(2, 3, 2, 3, 0.5)).find("lies outside the solid"), std::string::npos);
  EXPECT_NE(refusal(square_sheet(0.2, 0.8, 0.2, 0.8, 1.0)).find("lies on the solid's boundary"), std::string::npos);
  // Two squares crossing each other along x = 0.5 as one sheet.
  TriangleSurface crossing = square_sheet(0.2, 0.8, 0.2, 0.8, 0.5, 2);
  const TriangleSurface upright = [] {
    TriangleSurface u = square_sheet(0.3, 0.7, 0.3, 0.7, 0, 1);
    for (Vec3& p : u.vertices) p = {0.5, p.x, p.y};  // the plane x = 0.5, z from 0.3 to 0.7
    return u;
  }();
  const int32_t base = int32_t(crossing.vertices.size());
  crossing.vertices.insert(crossing.vertices.end(), upright.vertices.begin(), upright.vertices.end());
  for (auto t : upright.triangles) crossing.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  EXPECT_NE(refusal(crossing).find("intersects itself"), std::string::npos);
  // Three triangles on one edge.
  TriangleSurface fin = square_sheet(0.2, 0.8, 0.2, 0.8, 0.5, 1);
  fin.vertices.push_back({0.5, 0.5, 0.7});
  fin.triangles.push_back({0, 3, int32_t(fin.vertices.size() - 1)});  // on the diagonal 0-3
  EXPECT_NE(refusal(fin).find("shared by 3 triangles"), std::string::npos);
  // A zero-area triangle.
  TriangleSurface flat = square_sheet(0.2, 0.8, 0.2, 0.8, 0.5, 1);
  flat.vertices.push_back({0.5, 0.2, 0.5});
  flat.triangles.push_back({0, 1, int32_t(flat.vertices.size() - 1)});
  EXPECT_NE(refusal(flat).find("zero area"), std::string::npos);
}

}  // namespace
}  // namespace froth

namespace froth {
namespace {

TEST(Cracks, ClippedByACavity) {
  // A square through the middle of the hollow sphere (radii 0.4 and 0.5): what is kept is the
  // annulus between the two tessellated spheres, cut along both, with no front.
  const TriangleSurface solid = load_domain(FROTH_MODELS_DIR "/hollow_sphere.off").surface;
  const CrackSheet c = crack_from_surface(square_sheet(-0.7, 0.7, -0.7, 0.7, 0.013, 4), "annulus", solid);
  const double annulus = M_PI * (0.5 * 0.5 - 0.4 * 0.4);
  EXPECT_NEAR(c.area, annulus, 0.03 * annulus);  // the spheres' facets cut a little off
  EXPECT_TRUE(c.front.empty());
  EXPECT_NEAR(length(c, c.on_boundary), 2 * M_PI * (0.5 + 0.4), 0.03 * 2 * M_PI * 0.9);
}

}  // namespace
}  // namespace froth

namespace froth {
namespace {

TEST(Cracks, CrossingSheetsShareTheirCrossing) {
  // A horizontal square and an upright one crossing it along x = 0.5, y from 0.3 to 0.7.
  std::vector<CrackSheet> sheets;
  sheets.push_back(crack_from_surface(square_sheet(0.2, 0.8, 0.2, 0.8, 0.5, 3), "flat", unit_box()));
  TriangleSurface upright = square_sheet(0.3, 0.7, 0.3, 0.7, 0, 2);
  for (Vec3& p : upright.vertices) p = {0.5, p.x, p.y};  // x = 0.5, y and z from 0.3 to 0.7
  sheets.push_back(crack_from_surface(upright, "upright", unit_box()));
  const double flat_area = sheets[0].area, upright_area = sheets[1].area;
  conform_crack_sheets(sheets, unit_box());
  EXPECT_NEAR(sheets[0].area, flat_area, 1e-15);
  EXPECT_NEAR(sheets[1].area, upright_area, 1e-15);
  for (const CrackSheet& c : sheets) {
    EXPECT_NEAR(length(c, c.on_sheets), 0.4, 1e-12) << c.name;
    for (const auto& e : c.on_sheets)
      for (int32_t v : e) {
        EXPECT_EQ(c.surface.vertices[size_t(v)].x, 0.5);
        EXPECT_EQ(c.surface.vertices[size_t(v)].z, 0.5);
      }
  }
  EXPECT_NEAR(sheets[0].front_length, 2.4, 1e-12);
  EXPECT_NEAR(length(sheets[0], sheets[0].front), 2.4, 1e-12);  // split edges still the front
}

TEST(Cracks, OverlappingSheetsAreRefused) {
  std::vector<CrackSheet> sheets{crack_from_surface(square_sheet(0.2, 0.6, 0.2, 0.6, 0.5), "one", unit_box()),
                                 crack_from_surface(square_sheet(0.4, 0.8, 0.4, 0.8, 0.5), "two", unit_box())};
  try {
    conform_crack_sheets(sheets, unit_box());
    ADD_FAILURE() << "overlapping sheets were accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("overlap in a plane"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace froth
