#include "cli_guards.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <new>
#include <system_error>

#include <fmt/format.h>

#include "froth/error.hpp"

namespace froth_cli {

namespace {

// Where a path leads: the file itself if it exists (links followed), else its would-be place.
std::filesystem::path resolved(const std::string& p) {
  std::error_code ec;
  std::filesystem::path out = std::filesystem::weakly_canonical(std::filesystem::absolute(p, ec), ec);
  return ec ? std::filesystem::path(p).lexically_normal() : out;
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec)) {
    const bool eq = std::filesystem::equivalent(a, b, ec);
    if (!ec) return eq;
  }
  return resolved(a) == resolved(b);
}

}  // namespace

void refuse_same_files(const std::vector<std::pair<std::string, std::string>>& paths) {
  for (size_t i = 0; i < paths.size(); ++i)
    for (size_t j = i + 1; j < paths.size(); ++j) {
      const auto& [what_a, a] = paths[i];
      const auto& [what_b, b] = paths[j];
      if (a.empty() || b.empty() || a.rfind("box:", 0) == 0 || b.rfind("box:", 0) == 0) continue;
      // Devices (/dev/null twice) are no data to lose.
      std::error_code ec;
      if (std::filesystem::exists(a, ec) && !std::filesystem::is_regular_file(a, ec) &&
          !std::filesystem::is_directory(a, ec))
        continue;
      if (same_file(a, b))
        froth::fail(froth::ErrorKind::Usage,
                    fmt::format("{} and {} are the same file ({}): writing one would destroy the other; give another "
                                "name",
                                what_a, what_b, b));
    }
}

void refuse_unwritable_outputs(const std::vector<std::pair<std::string, std::string>>& paths) {
  namespace fs = std::filesystem;
  for (const auto& [what, path] : paths) {
    std::error_code ec;
    if (path.empty() || (fs::exists(path, ec) && !fs::is_regular_file(path, ec) && !fs::is_directory(path, ec)))
      continue;  // a device (/dev/null) takes what it is given
    fs::path folder = fs::absolute(path, ec).parent_path();
    while (!folder.empty() && !fs::exists(folder, ec) && folder != folder.root_path()) folder = folder.parent_path();
    if (!fs::is_directory(folder, ec))
      froth::fail(froth::ErrorKind::Io, fmt::format("cannot write {} {}: {} is not a folder", what, path, folder.string()));
    const fs::path probe = folder / fmt::format(".froth-write-test{}", getpid());
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
    if (fd < 0)
      froth::fail(froth::ErrorKind::Io, fmt::format("cannot write {} {}: no file can be made in {} ({}); choose "
                                                    "another folder",
                                                    what, path, folder.string(), std::strerror(errno)));
    ::close(fd);
    ::unlink(probe.c_str());
  }
}

uint64_t parse_seed(const std::string& text) {
  uint64_t v = 0;
  const char* end = text.data() + text.size();
  const auto [at, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || at != end)
    froth::fail(froth::ErrorKind::Usage,
                fmt::format("--seed {}: not a whole number from 0 to 18446744073709551615 (2^64 - 1)", text));
  return v;
}

int run_with_exit_codes(const std::function<int()>& body, const std::string& where) {
  try {
    return body();
  } catch (const froth::Error& e) {
    fmt::print(stderr, "froth: error{}: {}\n", where, e.what());
    return e.exit_code();
  } catch (const std::filesystem::filesystem_error& e) {
    fmt::print(stderr, "froth: error{}: {}\n", where, e.what());
    return 4;
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "froth: error{}: out of memory\n", where);
    return 5;
  } catch (const std::exception& e) {
    fmt::print(stderr, "froth: internal error{}: {}\n", where, e.what());
    return 5;
  }
}

}  // namespace froth_cli
