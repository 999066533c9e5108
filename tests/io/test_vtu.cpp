// The VTU writer: deterministic bytes, atomic replacement, and errors for unwritable paths.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <thread>
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
  Domain d = make_box_domain({0, 0, 0}, {1, 1, 1});
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

// Renaming a temporary file over a device or pipe would replace it (it once replaced /dev/null).
TEST(Vtu, PipeTargetIsWrittenInPlaceAndStaysAPipe) {
  Domain d = make_box_domain({0, 0, 0}, {1, 1, 1});
  RunReport run;
  PolyMesh m = test::mesh_of(d, 0.3, 1, 1, &run);
  std::string fifo = testing::TempDir() + "/froth_test_fifo";
  std::filesystem::remove(fifo);
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  // Both ends are opened here, before froth writes: a read-write descriptor (never blocks on a
  // FIFO) and the reader's. Closing the former after froth is done gives the reader its
  // end-of-file, so the test fails rather than hangs if froth never writes to the pipe.
  int keep = open(fifo.c_str(), O_RDWR);
  ASSERT_GE(keep, 0);
  int rfd = open(fifo.c_str(), O_RDONLY);
  ASSERT_GE(rfd, 0);
  size_t received = 0;
  std::thread reader([&] {
    char buf[4096];
    ssize_t got;
    while ((got = read(rfd, buf, sizeof buf)) > 0) received += size_t(got);
    close(rfd);
  });
  try {
    write_vtu(m, run, fifo);
  } catch (...) {
  }
  close(keep);
  reader.join();
  EXPECT_GT(received, 1000u);
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
  std::filesystem::remove(fifo);
}

TEST(Vtu, SymlinkTargetIsReplacedAndTheLinkKept) {
  Domain d = make_box_domain({0, 0, 0}, {1, 1, 1});
  RunReport run;
  PolyMesh m = test::mesh_of(d, 0.3, 1, 1, &run);
  std::string dir = testing::TempDir(), target = dir + "/froth_link_target.vtu", link = dir + "/froth_link.vtu";
  std::filesystem::remove(link);
  std::ofstream(target) << "old";
  std::filesystem::create_symlink(target, link);
  write_vtu(m, run, link);
  EXPECT_TRUE(std::filesystem::is_symlink(link));
  EXPECT_GT(std::filesystem::file_size(target), 1000u);
  std::filesystem::remove(link);
  std::filesystem::remove(target);
}

TEST(Vtu, UnwritableDirectoryIsAnIoErrorAndLeavesNoFile) {
  Domain d = make_box_domain({0, 0, 0}, {1, 1, 1});
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
  Domain d = make_box_domain({0, 0, 0}, {1, 1, 1});
  RunReport run;
  test::mesh_of(d, 0.2, 1, 1, &run);
  std::string j = report_json_text(run);
  for (const char* key : {"\"cells\"", "\"relative_error\"", "\"sampling\"", "\"cells_sum\"", "\"peak_memory_bytes\"",
                          "\"maximal\": true"})
    EXPECT_NE(j.find(key), std::string::npos) << key;
}

}  // namespace
}  // namespace froth
