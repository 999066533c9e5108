// libFuzzer target: any bytes as a surface file of extension FROTH_FUZZ_EXTENSION (".stl",
// ".off", ".obj" or ".ply", one target each), through the reader load_domain picks for it.
#include <cstring>

#include "froth/domain.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path path = froth_fuzz::scratch_file(FROTH_FUZZ_EXTENSION, data, size);
  return froth_fuzz::expect_answer([&] {
    if (std::strcmp(FROTH_FUZZ_EXTENSION, ".stl") == 0) froth::read_stl(path);
    else froth::read_polygon_file(path);
  });
}
