// libFuzzer target: any bytes as a VTU file, through the reader `froth quality` and
// `froth convert` use (ASCII, base64 and appended raw data, zlib-compressed or not).
#include "froth/io.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path path = froth_fuzz::scratch_file(".vtu", data, size);
  return froth_fuzz::expect_answer([&] { froth::read_vtu(path); });
}
