// libFuzzer target: any bytes as an STL file, through froth's STL reader.
#include "froth/domain.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path path = froth_fuzz::scratch_file(".stl", data, size);
  return froth_fuzz::expect_answer([&] { froth::read_stl(path); });
}
