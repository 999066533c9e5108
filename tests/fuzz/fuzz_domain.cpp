// libFuzzer target: read and validate, as `froth mesh` does before it samples. The first byte
// picks the format; the rest is the file. load_domain reads the surface, welds its vertices,
// checks it is closed, manifold, consistently oriented and free of self-intersections, finds its
// shells, cavities, features and patches.
#include "froth/domain.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const extensions[] = {".stl", ".off", ".obj", ".ply"};
  const std::filesystem::path path = froth_fuzz::scratch_file(extensions[data[0] % 4], data + 1, size - 1);
  return froth_fuzz::expect_answer([&] { froth::load_domain(path.string()); });
}
