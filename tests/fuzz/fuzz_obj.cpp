// libFuzzer target: any bytes as an OBJ file, through froth's OBJ reader.
#include "froth/domain.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path path = froth_fuzz::scratch_file(".obj", data, size);
  return froth_fuzz::expect_answer([&] { froth::read_polygon_file(path); });
}
