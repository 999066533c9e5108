// Crack protection (sampling/protect_cracks.hpp, issue 38's step 1): on a penny crack and on two
// crossing sheets, the seeds keep their disks (r/2 on curves, r/sqrt(2) on the sheets), cover
// every sheet point (maximal: each point within r/sqrt(2) of a seed), and lie on their sheets.
#include <gtest/gtest.h>

#include <cmath>

#include "common/random.hpp"
#include "common/test_support.hpp"
#include "froth/domain.hpp"
#include "input/cracks.hpp"
#include "sampling/protect_cracks.hpp"

namespace froth {
namespace {

using test::square_sheet;

// Checks the disks, the coverage of the sheets by a grid of points, and that seeds lie on them.
void check_protection(const std::vector<CrackSheet>& sheets, double r, uint64_t seed) {
  InterfaceProtectionStats stats;
  const ProtectionSeeds p = protect_cracks(sheets, r, seed, {}, &stats);
  ASSERT_GT(stats.edge_seeds, 0u);
  ASSERT_GT(stats.face_seeds, 0u);
  EXPECT_EQ(stats.uncovered, 0u);
  EXPECT_EQ(p.points.size(), stats.edge_seeds + stats.face_seeds);
  // Empty disks: a seed lies outside every earlier seed's disk, r/2 for curve seeds (edge
  // seeds come first) and r/sqrt(2) for facet seeds (corner seeds sit 1e-7 r off their vertex).
  const double rc = r / 2, rf = r / std::sqrt(2.0);
  for (size_t i = 0; i < p.points.size(); ++i)
    for (size_t j = 0; j < i; ++j) {
      const double d = norm(p.points[i] - p.points[j]);
      if (i < stats.edge_seeds) EXPECT_GE(d, rc * (1 - 1e-6)) << i << " " << j;
      else EXPECT_GE(d, rf * (1 - 1e-9)) << i << " " << j;
    }
  // Maximal: every point of every sheet within r/sqrt(2) of a seed.
  const CounterRng rng(7, RandomStream::Sampling);
  size_t probes = 0;
  for (const CrackSheet& c : sheets)
    for (size_t t = 0; t < c.surface.triangles.size(); ++t)
      for (uint64_t k = 0; k < 40; ++k) {
        const auto w = rng.words(t, k, probes, 0);
        double u = CounterRng::unit(w[0]), v = CounterRng::unit(w[1]);
        if (u + v > 1) u = 1 - u, v = 1 - v;
        const auto& tri = c.surface.triangles[t];
        const Vec3 a = c.surface.vertices[size_t(tri[0])], b = c.surface.vertices[size_t(tri[1])],
                   d = c.surface.vertices[size_t(tri[2])];
        const Vec3 x = a + u * (b - a) + v * (d - a);
        double nearest = INFINITY;
        for (Vec3 s : p.points) nearest = std::min(nearest, norm(s - x));
        EXPECT_LE(nearest, rf * (1 + 1e-9)) << c.name << " triangle " << t;
        ++probes;
      }
  EXPECT_GT(probes, 100u);
  // On the sheets: each seed within 1e-6 r of some sheet's plane here (the sheets are planar).
  for (Vec3 s : p.points) {
    bool on = false;
    for (const CrackSheet& c : sheets) {
      const auto& t = c.surface.triangles[0];
      const Vec3 a = c.surface.vertices[size_t(t[0])];
      const Vec3 n = cross(c.surface.vertices[size_t(t[1])] - a, c.surface.vertices[size_t(t[2])] - a);
      on |= std::abs(dot(n, s - a)) / norm(n) < 1e-6 * r;
    }
    EXPECT_TRUE(on) << s.x << " " << s.y << " " << s.z;
  }
}

TEST(ProtectCracks, PennyCrackIsCoveredWithItsDisksEmpty) {
  const TriangleSurface box = parse_box_spec("box:0,0,0,1,1,1").surface;
  for (uint64_t seed : {1u, 2u})
    check_protection({crack_from_surface(square_sheet(0.2, 0.8, 0.25, 0.75, 0.5, 4), "penny", box)}, 0.1, seed);
}

TEST(ProtectCracks, CrossingSheetsAreCoveredAndTheirCrossingIsACurve) {
  const TriangleSurface box = parse_box_spec("box:0,0,0,1,1,1").surface;
  std::vector<CrackSheet> sheets{crack_from_surface(square_sheet(0.2, 0.8, 0.2, 0.8, 0.5, 3), "flat", box)};
  TriangleSurface upright = square_sheet(0.3, 0.7, 0.3, 0.7, 0, 2);
  for (Vec3& p : upright.vertices) p = {0.5, p.x, p.y};
  sheets.push_back(crack_from_surface(upright, "upright", box));
  conform_crack_sheets(sheets, box);
  check_protection(sheets, 0.08, 3);
  // The crossing (x = 0.5, z = 0.5) holds curve seeds.
  InterfaceProtectionStats stats;
  const ProtectionSeeds p = protect_cracks(sheets, 0.08, 3, {}, &stats);
  size_t on_crossing = 0;
  for (size_t i = 0; i < stats.edge_seeds; ++i)
    on_crossing += std::abs(p.points[i].x - 0.5) < 1e-6 && std::abs(p.points[i].z - 0.5) < 1e-6;
  EXPECT_GE(on_crossing, 4u);  // 0.4 long, disks of 0.04: at least 0.4 / (2 * 0.04) - 1 inside
}

}  // namespace
}  // namespace froth
