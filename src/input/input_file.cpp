#include "input/input_file.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>

#include <fmt/format.h>

#include "froth/error.hpp"
#include "froth/mesh.hpp"

namespace froth {

std::string quoted_text(std::string_view text) {
  constexpr size_t kMost = 60;
  std::string out;
  for (size_t i = 0; i < std::min(text.size(), kMost); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (std::isprint(c)) out += char(c);
    else out += fmt::format("\\x{:02x}", c);
  }
  if (text.size() > kMost) out += fmt::format("... ({} bytes)", text.size());
  return out;
}

void refuse_binary_text(const std::string& file, std::string_view head, const char* format, size_t text_end) {
  const size_t nul = head.substr(0, std::min(text_end, head.size())).find('\0');
  if (nul != std::string_view::npos)
    fail(ErrorKind::InvalidInput, fmt::format("{}: byte {} is a NUL byte, which {} text cannot hold (binary "
                                              "data or a zeroed file); it starts '{}'",
                                              file, nul + 1, format, quoted_text(head.substr(0, 24))));
}

std::string read_input_file(const std::filesystem::path& path, double max_memory_bytes, const SizeFromHead& size_from_head) {
  const std::string file = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(ErrorKind::Io, fmt::format("{}: cannot open for reading", file));
  const double memory = max_memory_bytes > 0 ? max_memory_bytes : available_memory();
  const size_t limit = memory > 0 ? size_t(memory / 4) : SIZE_MAX;
  std::error_code ec;
  const bool regular = std::filesystem::is_regular_file(path, ec);
  const uintmax_t size = regular ? std::filesystem::file_size(path, ec) : 0;
  if (regular && !ec && size > limit)
    fail(ErrorKind::Usage, fmt::format("{}: {:.3g} GB, more than a quarter of the {:.3g} GB of memory the run may take "
                                       "(the surface made from it and its checks need the rest): raise the memory "
                                       "limit, or use a machine with more memory",
                                       file, double(size) / 1e9, memory / 1e9));
  std::string bytes(4096, '\0');
  in.read(bytes.data(), std::streamsize(bytes.size()));
  bytes.resize(size_t(in.gcount()));
  // Read on until the format's bound (one byte past it, so that the reader names the excess)
  // or the memory's, whichever comes first.
  const size_t bound = size_from_head(bytes);
  const size_t most = std::min(bound == SIZE_MAX ? SIZE_MAX : bound + 1, limit);
  if (regular && !ec) bytes.reserve(size_t(std::min<uintmax_t>(size, most)));
  std::string chunk(1 << 20, '\0');
  while (in && bytes.size() < most) {
    in.read(chunk.data(), std::streamsize(std::min(chunk.size(), most - bytes.size())));
    bytes.append(chunk.data(), size_t(in.gcount()));
  }
  if (bytes.size() >= limit && in.peek() != std::char_traits<char>::eof())
    fail(ErrorKind::Usage, fmt::format("{}: more than {:.3g} GB, a quarter of the memory the run may take, and still "
                                       "not at its end (an endless stream such as /dev/zero?)",
                                       file, double(limit) / 1e9));
  return bytes;
}

}  // namespace froth
