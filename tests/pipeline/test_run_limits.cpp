// Options resolved once, in the library (froth/mesh.hpp: resolve_options, check_mesh_options),
// and the limits a run is refused at before any work, each with a message that says what to do.
#include <gtest/gtest.h>

#include <string>

#include "froth/froth.hpp"

namespace froth {
namespace {

std::string usage_error_of(const Domain& d, const MeshOptions& opt) {
  try {
    check_mesh_options(d, opt);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Usage) << e.what();
    return e.what();
  }
  return "";
}

TEST(RunLimits, TheLibraryOwnsEveryDefault) {
  const Domain d = parse_box_spec("box:0,0,0,1,1,1");
  MeshOptions given;
  given.r = 0.1;
  const MeshOptions opt = resolve_options(d, given);
  ASSERT_TRUE(opt.weld.has_value());
  EXPECT_EQ(*opt.weld, default_weld_tolerance(0.1, d.bounds.diagonal()));
  EXPECT_TRUE(opt.quality);
  MeshOptions convex = given;
  convex.convex = true;
  EXPECT_EQ(*resolve_options(d, convex).weld, 0);  // convex cells need planar faces
  MeshOptions by_count;
  by_count.cells = 2000;
  const MeshOptions counted = resolve_options(d, by_count);
  EXPECT_EQ(counted.cells, 0);
  EXPECT_GT(counted.r, 0.05);
  EXPECT_LT(counted.r, 0.15);
  by_count.r = 0.1;
  EXPECT_NE(usage_error_of(d, by_count).find("not both"), std::string::npos);
}

TEST(RunLimits, GradingIsCheckedWhateverThePart) {
  // A box has no thin wall, so no sizing field is ever made: the check must not depend on it.
  const Domain d = parse_box_spec("box:0,0,0,1,1,1");
  MeshOptions opt;
  opt.r = 0.2;
  opt.grade = true;
  opt.grading = 0.3;
  EXPECT_NE(usage_error_of(d, opt).find("maximum grading must be in (0, 0.25)"), std::string::npos);
  opt.grading = 0.2;
  opt.min_r = 0.5;
  EXPECT_NE(usage_error_of(d, opt).find("min_r must be in (0, r]"), std::string::npos);
  opt.min_r = 0.05;
  EXPECT_EQ(usage_error_of(d, opt), "");
}

TEST(RunLimits, TheCubeIndexLimitSaysWhichRFits) {
  // 5e9 background cubes: more than the sampler's 32-bit index, with memory to spare.
  const Domain d = parse_box_spec("box:0,0,0,100,100,100");
  MeshOptions opt;
  opt.r = 0.1;
  opt.max_memory_bytes = 1e18;
  const std::string msg = usage_error_of(d, opt);
  EXPECT_NE(msg.find("32 bits"), std::string::npos) << msg;
  EXPECT_NE(msg.find("use r of"), std::string::npos) << msg;
  // The r it names does fit.
  const double fits = std::stod(msg.substr(msg.find("use r of") + 9));
  opt.r = fits;
  EXPECT_EQ(usage_error_of(d, opt), "");
  opt.threads = kMaxThreads + 1;
  EXPECT_NE(usage_error_of(d, opt).find("threads must be from 0"), std::string::npos);
}

}  // namespace
}  // namespace froth
