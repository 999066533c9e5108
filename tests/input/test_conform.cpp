// Corefinement of touching solids (input/conform.hpp): after it, faces where two solids touch
// have the same triangles on both sides, and solids apart are left as they were.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "froth/domain.hpp"
#include "input/conform.hpp"

namespace froth {
namespace {

using Corners = std::array<std::array<double, 3>, 3>;

// The triangles of s lying in the plane coordinate `axis` = `at`, as sorted corner triples.
std::set<Corners> triangles_in_plane(const TriangleSurface& s, int axis, double at) {
  std::set<Corners> out;
  for (const auto& t : s.triangles) {
    Corners c;
    bool in = true;
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = s.vertices[size_t(t[k])];
      c[k] = {p.x, p.y, p.z};
      in &= p[axis] == at;
    }
    std::sort(c.begin(), c.end());
    if (in) out.insert(c);
  }
  return out;
}

double area_in_plane(const TriangleSurface& s, int axis, double at) {
  double a = 0;
  for (const Corners& c : triangles_in_plane(s, axis, at)) {
    const Vec3 p{c[0][0], c[0][1], c[0][2]}, q{c[1][0], c[1][1], c[1][2]}, w{c[2][0], c[2][1], c[2][2]};
    a += norm(cross(q - p, w - p)) / 2;
  }
  return a;
}

// box:... with each face split along its other diagonal.
TriangleSurface with_other_diagonals(TriangleSurface s) {
  // box:... lists the two triangles of each quad one after the other: (q0 q1 q2), (q0 q2 q3).
  for (size_t k = 0; k + 1 < s.triangles.size(); k += 2) {
    const auto a = s.triangles[k], b = s.triangles[k + 1];
    if (a[0] != b[0] || a[2] != b[1]) return {};
    s.triangles[k] = {a[0], a[1], b[2]}, s.triangles[k + 1] = {a[1], a[2], b[2]};
  }
  return s;
}

TEST(Conform, CubesWithOtherDiagonalsGetTheSameTrianglesOnTheSharedFace) {
  std::vector<TriangleSurface> solids{parse_box_spec("box:0,0,0,1,1,1").surface,
                                      with_other_diagonals(parse_box_spec("box:1,0,0,2,1,1").surface)};
  ASSERT_FALSE(solids[1].triangles.empty()) << "box:... no longer lists a quad's triangles together";
  ASSERT_NE(triangles_in_plane(solids[0], 0, 1.0), triangles_in_plane(solids[1], 0, 1.0));
  EXPECT_EQ(conform_touching_solids(solids), 2);
  const auto a = triangles_in_plane(solids[0], 0, 1.0), b = triangles_in_plane(solids[1], 0, 1.0);
  EXPECT_EQ(a, b);
  EXPECT_EQ(a.size(), 4u);  // the two diagonals cross at the face's centre
  EXPECT_DOUBLE_EQ(area_in_plane(solids[0], 0, 1.0), 1.0);
}

TEST(Conform, BlockOnAPlateMarksItsFootprintInThePlatesTopAndKeepsPatches) {
  TriangleSurface plate = parse_box_spec("box:0,0,0,2,2,0.5").surface;
  plate.patch_names = {"plate"};
  plate.triangle_patch.assign(plate.triangles.size(), 0);
  std::vector<TriangleSurface> solids{plate, parse_box_spec("box:0.5,0.7,0.5,1.3,1.4,1").surface};
  EXPECT_EQ(conform_touching_solids(solids), 2);  // the plate's diagonal crosses the block's foot
  const auto bottom = triangles_in_plane(solids[1], 2, 0.5), top = triangles_in_plane(solids[0], 2, 0.5);
  EXPECT_TRUE(std::includes(top.begin(), top.end(), bottom.begin(), bottom.end()));
  EXPECT_NEAR(area_in_plane(solids[1], 2, 0.5), 0.8 * 0.7, 1e-15);
  EXPECT_NEAR(area_in_plane(solids[0], 2, 0.5), 4.0, 1e-14);
  ASSERT_EQ(solids[0].triangle_patch.size(), solids[0].triangles.size());
  EXPECT_TRUE(std::all_of(solids[0].triangle_patch.begin(), solids[0].triangle_patch.end(), [](int32_t p) { return p == 0; }));
}

TEST(Conform, SolidsApartOrAlreadySharingTrianglesAreLeftAlone) {
  const TriangleSurface a = parse_box_spec("box:0,0,0,1,1,1").surface;
  for (const char* other : {"box:2,0,0,3,1,1", "box:1,0,0,2,1,1"}) {
    std::vector<TriangleSurface> solids{a, parse_box_spec(other).surface};
    const TriangleSurface b = solids[1];
    EXPECT_EQ(conform_touching_solids(solids), 0) << other;
    EXPECT_EQ(solids[0].triangles, a.triangles) << other;
    EXPECT_EQ(solids[1].triangles, b.triangles) << other;
  }
}

}  // namespace
}  // namespace froth
