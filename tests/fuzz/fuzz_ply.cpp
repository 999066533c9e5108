// libFuzzer target: any bytes as an PLY file, through froth's PLY reader.
#include "froth/domain.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path path = froth_fuzz::scratch_file(".ply", data, size);
  return froth_fuzz::expect_answer([&] { froth::read_polygon_file(path); });
}
