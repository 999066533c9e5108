// Replays inputs through one fuzz target without libFuzzer (the regression corpus in ctest, in
// the ordinary and the sanitizer builds): every file named, or found under a folder named, once,
// printing what each got. Inputs named after --valid must be read, not refused.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int main(int argc, char** argv) {
  std::vector<std::pair<std::filesystem::path, bool>> files;  // (input, must be read)
  bool valid = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--valid") {
      valid = true;
      continue;
    }
    std::vector<std::filesystem::path> found;
    if (std::filesystem::is_directory(arg)) {
      for (const auto& e : std::filesystem::recursive_directory_iterator(arg))
        if (e.is_regular_file()) found.push_back(e.path());
    } else {
      found.push_back(arg);
    }
    std::sort(found.begin(), found.end());
    for (const auto& f : found) files.push_back({f, valid});
    valid = false;
  }
  int refused_valid = 0;
  for (const auto& [f, must_read] : files) {
    std::ifstream in(f, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    const std::string& got = froth_fuzz::last_refusal;
    std::printf("%s: %s\n", f.filename().c_str(), got.empty() ? "read" : got.substr(0, 160).c_str());
    if (must_read && !got.empty()) ++refused_valid;
  }
  std::printf("replayed %zu inputs; %d valid ones refused\n", files.size(), refused_valid);
  return files.empty() || refused_valid > 0 ? 1 : 0;
}
