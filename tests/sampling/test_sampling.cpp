// The sampler: empty disk, maximality, determinism, and the saturation density of random
// sequential addition that only an unbiased maximal sampler reaches.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "common/test_support.hpp"
#include "sampling/mps.hpp"

namespace froth {
namespace {

TEST(Sampling, EmptyDiskAndMaximalOnABox) {
  Domain d = make_box_domain({0, 0, 0}, {1, 1.5, 0.7});
  for (uint64_t seed : {1u, 2u, 3u}) {
    Sample s = sample_maximal_poisson_disk(d, 0.1, seed);
    EXPECT_EQ(s.stats.uncovered_cubes, 0u);
    EXPECT_GE(test::min_seed_distance(s.seeds, 0.1), 0.1);
    for (Vec3 p : s.seeds) EXPECT_TRUE(d.contains(p));
    // Maximal: random probe points all lie within r of a seed.
    std::mt19937_64 gen(seed);
    std::uniform_real_distribution<double> ux(0, 1), uy(0, 1.5), uz(0, 0.7);
    size_t uncovered = 0;
    for (int k = 0; k < 20000; ++k) {
      Vec3 p{ux(gen), uy(gen), uz(gen)};
      double best = INFINITY;
      for (Vec3 q : s.seeds) best = std::min(best, norm(p - q));
      uncovered += best >= 0.1;
    }
    EXPECT_EQ(uncovered, 0u);
  }
}

// The grid's margin: every seed's cube, protection seeds on the surface included, is at least
// kMargin cubes from the grid's sides, so the sampler's and the cells' stencils around it (two
// and four cubes) are read without bounds checks.
TEST(Sampling, EverySeedIsAMarginAwayFromTheGridSides) {
  for (const std::string& model : {std::string("box"), std::string("plate_holes.STL")}) {
    Domain d = model == "box" ? make_box_domain({0, 0, 0}, {1, 1.5, 0.7}) : load_domain(test::model(model));
    const double r = d.bounds.diagonal() / 20;
    Sample s = sample_maximal_poisson_disk(d, r, 5);
    const BackgroundGrid& g = s.grid;
    const int m = BackgroundGrid::kMargin;
    EXPECT_GE(m, int(std::ceil(2 * r / g.side))) << "the cells' stencil reaches past the margin";
    ASSERT_FALSE(s.seeds.empty());
    for (Vec3 p : s.seeds) {
      const Vec3 q = p - g.origin;
      const double i = q.x / g.side, j = q.y / g.side, k = q.z / g.side;
      ASSERT_TRUE(i >= m && i < g.nx - m && j >= m && j < g.ny - m && k >= m && k < g.nz - m)
          << model << ": seed (" << p.x << ", " << p.y << ", " << p.z << ") in cube (" << i << ", " << j << ", " << k
          << ") of " << g.nx << " x " << g.ny << " x " << g.nz;
    }
  }
}

TEST(Sampling, SameSeedSameSampleForAnyThreadCount) {
  Domain d = load_domain(test::model("unit_sphere.STL"));
  omp_set_num_threads(1);
  Sample a = sample_maximal_poisson_disk(d, 0.15, 42);
  omp_set_num_threads(2);
  Sample b = sample_maximal_poisson_disk(d, 0.15, 42);
  ASSERT_EQ(a.seeds.size(), b.seeds.size());
  for (size_t i = 0; i < a.seeds.size(); ++i) {
    EXPECT_EQ(a.seeds[i].x, b.seeds[i].x);
    EXPECT_EQ(a.seeds[i].y, b.seeds[i].y);
    EXPECT_EQ(a.seeds[i].z, b.seeds[i].z);
  }
  Sample c = sample_maximal_poisson_disk(d, 0.15, 43);
  EXPECT_NE(a.seeds[0].x, c.seeds[0].x);
}

TEST(Sampling, SeedsLieInsideTheSphereAndFillItsBoundaryCubes) {
  Domain d = load_domain(test::model("unit_sphere.STL"));
  Sample s = sample_maximal_poisson_disk(d, 0.1, 7);
  size_t near_boundary = 0;
  for (Vec3 p : s.seeds) {
    ASSERT_TRUE(d.contains(p));
    double gap = INFINITY;
    for (const Plane& pl : d.planes) gap = std::min(gap, -pl.signed_distance(p));
    near_boundary += gap < 0.1 / std::sqrt(3.0);
  }
  // Cubes cut by the boundary get seeds too: no seed-free layer along the boundary.
  EXPECT_GT(near_boundary, s.seeds.size() / 10);
}

// Zhang & Torquato (PRE 88, 053312, 2013): saturated 3D RSA of hard spheres covers 0.3841 of
// space. Seeds r apart are hard spheres of diameter r, so the bulk fraction N (pi/6) r^3 / V
// must match it; a biased or non-maximal sampler misses it.
TEST(Sampling, BulkPackingFractionIsTheRsaSaturationDensity) {
  const double r = 1, side = 36;
  Domain d = make_box_domain({0, 0, 0}, {side, side, side});
  const double margin = 3 * r, inner = side - 2 * margin;
  double sum = 0;
  const int runs = 3;
  for (int k = 0; k < runs; ++k) {
    Sample s = sample_maximal_poisson_disk(d, r, 1000 + k);
    size_t n = 0;
    for (Vec3 p : s.seeds)
      n += p.x > margin && p.y > margin && p.z > margin && p.x < side - margin && p.y < side - margin &&
           p.z < side - margin;
    sum += n * (M_PI / 6) * r * r * r / (inner * inner * inner);
  }
  double phi = sum / runs;
  RecordProperty("bulk_packing_fraction", std::to_string(phi));
  std::printf("bulk packing fraction over %d runs: %.4f (RSA saturation 0.3841)\n", runs, phi);
  EXPECT_NEAR(phi, 0.3841, 0.01 * 0.3841) << "bulk packing fraction " << phi;
}

}  // namespace
}  // namespace froth
