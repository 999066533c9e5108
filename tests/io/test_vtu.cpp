// The VTU writer: deterministic bytes, atomic replacement, and errors for unwritable paths.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/test_support.hpp"

namespace froth {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(Vtu, SameSeedGivesIdenticalBytesForOneAndTwoThreads) {
  ConvexDomain d = make_box_domain({0, 0, 0}, {1, 1, 1});
  std::string dir = testing::TempDir();
  RunReport ra, rb, rc;
  PolyMesh a = test::mesh_of(d, 0.1, 9, 1, &ra);
  PolyMesh b = test::mesh_of(d, 0.1, 9, 2, &rb);
  PolyMesh c = test::mesh_of(d, 0.1, 10, 2, &rc);
  write_vtu(a, ra, dir + "/a.vtu");
  write_vtu(b, rb, dir + "/b.vtu");
  write_vtu(c, rc, dir + "/c.vtu");
  std::string ba = slurp(dir + "/a.vtu");
  EXPECT_GT(ba.size(), 1000u);
  EXPECT_EQ(ba, slurp(dir + "/b.vtu"));
  EXPECT_NE(ba, slurp(dir + "/c.vtu"));
  EXPECT_NE(ba.find("type=\"UInt8\" Name=\"types\""), std::string::npos);
  EXPECT_NE(ba.find("Name=\"faceoffsets\""), std::string::npos);
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
}

TEST(Vtu, UnwritableDirectoryIsAnIoErrorAndLeavesNoFile) {
  ConvexDomain d = make_box_domain({0, 0, 0}, {1, 1, 1});
  RunReport run;
  PolyMesh m = test::mesh_of(d, 0.2, 1, 1, &run);
  try {
    write_vtu(m, run, "/nonexistent-dir/x.vtu");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Io);
  }
}

TEST(Report, JsonHasCountsVolumesAndStages) {
  ConvexDomain d = make_box_domain({0, 0, 0}, {1, 1, 1});
  RunReport run;
  test::mesh_of(d, 0.2, 1, 1, &run);
  std::string j = report_json_text(run);
  for (const char* key : {"\"cells\"", "\"relative_error\"", "\"sampling\"", "\"cells_sum\"", "\"peak_memory_bytes\"",
                          "\"maximal\": true"})
    EXPECT_NE(j.find(key), std::string::npos) << key;
}

}  // namespace
}  // namespace froth
