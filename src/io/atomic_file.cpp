#include "io/atomic_file.hpp"

#include <unistd.h>

#include <fmt/format.h>

#include "froth/error.hpp"

namespace froth {

namespace {

// Devices and pipes (e.g. /dev/null, /dev/stdout) are written in place: renaming a file over
// them would replace the device.
void write_in_place(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  std::ofstream out(path, std::ios::binary);
  if (!out) fail(ErrorKind::Io, fmt::format("{}: cannot open for writing", path.string()));
  write(out);
  out.flush();
  if (!out) fail(ErrorKind::Io, fmt::format("{}: write failed", path.string()));
}

}  // namespace

void write_atomically(const std::filesystem::path& requested, const std::function<void(std::ostream&)>& write) {
  std::error_code ec;
  // A symbolic link stays a link: its target is what gets replaced.
  std::filesystem::path path = std::filesystem::is_symlink(requested, ec) ? std::filesystem::canonical(requested, ec)
                                                                          : requested;
  if (ec) path = requested;
  const auto status = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    return write_in_place(path, write);
  std::filesystem::path tmp = path;
  tmp += fmt::format(".tmp{}", ::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) fail(ErrorKind::Io, fmt::format("{}: cannot open for writing", tmp.string()));
    try {
      write(out);
    } catch (...) {
      out.close();
      std::filesystem::remove(tmp, ec);
      throw;
    }
    out.flush();
    if (!out) {
      out.close();
      std::filesystem::remove(tmp, ec);
      fail(ErrorKind::Io, fmt::format("{}: write failed (disk full?)", path.string()));
    }
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    fail(ErrorKind::Io, fmt::format("{}: cannot rename the finished file into place", path.string()));
  }
}

}  // namespace froth
