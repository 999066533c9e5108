// What every fuzz target shares (issue 25): the bytes reach froth through its public readers, as
// a user's file would, and the only acceptable answers are a mesh or surface, or a froth::Error
// naming bad input, an I/O problem or a usage error. A crash, a sanitizer report, an exception of
// another type, or an ErrorKind::Internal is a bug: the target aborts so libFuzzer (or the
// regression replay in ctest) reports it.
#pragma once
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "froth/error.hpp"

namespace froth_fuzz {

// The bytes as a file named with `extension` (the readers choose the format by it), one per
// process, in memory where the system has /dev/shm.
inline std::filesystem::path scratch_file(const char* extension, const uint8_t* data, size_t size) {
  static const std::filesystem::path dir =
      std::filesystem::is_directory("/dev/shm") ? std::filesystem::path("/dev/shm") : std::filesystem::temp_directory_path();
  const std::filesystem::path path = dir / ("froth-fuzz-" + std::to_string(getpid()) + extension);
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || (size > 0 && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
  return path;
}

// What the last input got: empty if it was read, else the error's exit code and message (the
// replay prints it, and requires valid seeds to be read).
inline std::string last_refusal;

template <class Read>
int expect_answer(Read read) {
  last_refusal.clear();
  try {
    read();
  } catch (const froth::Error& e) {
    last_refusal = "exit " + std::to_string(e.exit_code()) + ": " + e.what();
    if (e.kind() == froth::ErrorKind::Internal) {
      std::fprintf(stderr, "fuzz: internal error on this input: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}

}  // namespace froth_fuzz
