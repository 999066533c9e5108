// Text formats' lines formatted by all threads and written in order: number formatting is most
// of an ASCII writer's time.
#pragma once
#include <algorithm>
#include <ostream>
#include <vector>

#include <fmt/format.h>

namespace froth {

// Writes line(buffer, i) for i in [0, count), in order; `line` appends to a fmt::memory_buffer.
template <class Line>
void write_lines(std::ostream& out, size_t count, const Line& line) {
  constexpr size_t kLinesPerBlock = 1 << 14, kBlocksPerBatch = 64;  // about 64 MB in memory at most
  const size_t blocks = (count + kLinesPerBlock - 1) / kLinesPerBlock;
  std::vector<fmt::memory_buffer> text(kBlocksPerBatch);
  for (size_t first = 0; first < blocks; first += kBlocksPerBatch) {
    const size_t last = std::min(blocks, first + kBlocksPerBatch);
#pragma omp parallel for schedule(dynamic, 1)
    for (size_t b = first; b < last; ++b) {
      fmt::memory_buffer& buf = text[b - first];
      buf.clear();
      for (size_t i = b * kLinesPerBlock; i < std::min(count, (b + 1) * kLinesPerBlock); ++i) line(buf, i);
    }
    for (size_t b = first; b < last; ++b) out.write(text[b - first].data(), std::streamsize(text[b - first].size()));
  }
}

}  // namespace froth
